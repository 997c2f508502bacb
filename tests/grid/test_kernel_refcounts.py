"""The grid search kernels take no array references inside their loops.

Numba reference-counts arrays. Around a call that numba inlines at its own
level (``inline="always"``), or a helper whose body branches, it can leave an
atomic ``NRT_incref``/``NRT_decref`` of each array argument that its pruning
pass does not remove; inside a search loop that is two locked adds per call
(JPS paid them per jump and per push: 1.2x its time on random4096,
kernels.py above ``_jump_straight``). A kernel whose loops are clean takes
its references on entry only: no ``NRT_incref`` call, and no call of a
function that makes one, lies in a basic block on a cycle of the control-flow
graph (:func:`loop_references`). Checked on an uncached compile of each
kernel's Python source (cached code cannot be inspected).
"""

import re

import numpy as np
import pytest
from numba import njit
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import connected_components

from navlab.grid import kernels as K
from navlab.grid.planner import GridSearcher, PaddedGrid


def kernel_ir(py_func, args) -> str:
    """The LLVM IR of ``py_func`` compiled afresh (not from numba's cache) for ``args``."""
    fn = njit(py_func)
    fn(*args)
    (sig,) = fn.signatures
    return fn.inspect_llvm(sig)


def loop_references(ir: str) -> list:
    """Every reference taken in a loop: an ``NRT_incref`` call, or a call of a function that takes one, in a
    basic block on a cycle of its function's control-flow graph, as (function, block, instruction).

    Counting increments against array arguments (this test until session 25) was a proxy: numba 0.68.1 keeps
    ``clear_touched`` (called once, on entry) out of line, whose own four increments then read as the loop's,
    while an A* variant with two unused array arguments had room for two increments in its loop, and a helper
    called in the loop was counted against its own arrays (review, session 25)."""
    functions = {}
    for chunk in ir.split("\ndefine ")[1:]:
        header, _, body = chunk.partition("\n")
        name = re.search(r"@([\w.$]+)\(", header).group(1)
        blocks, label = {"<entry>": []}, "<entry>"
        for line in body.split("\n"):
            if line == "}":
                break
            opened = re.match(r"^([\w.$-]+):", line)
            if opened:
                label = opened.group(1)
                blocks[label] = []
            else:
                blocks[label].append(line)
        functions[name] = blocks
    calls = {name: {callee for lines in blocks.values() for line in lines
                    for callee in re.findall(r"\bcall [^@]*@([\w.$]+)\(", line)} for name, blocks in functions.items()}
    taking = {"NRT_incref"}  # the functions that take a reference, directly or through a call
    while True:
        more = {name for name, callees in calls.items() if callees & taking and name != "NRT_incref"} - taking
        if not more:
            break
        taking |= more
    found = []
    for name, blocks in functions.items():
        labels = list(blocks)
        index = {label: i for i, label in enumerate(labels)}
        targets = [(i, target) for i, label in enumerate(labels) for line in blocks[label]
                   for target in re.findall(r"label %([\w.$-]+)", line)]
        # every branch target is a block read above: a label the parse missed would hide a loop (second review)
        unread = {target for _, target in targets if target not in index}
        assert not unread, f"{name}: branch targets not parsed as blocks: {sorted(unread)[:5]}"
        edges = [(i, index[target]) for i, target in targets]
        if not edges:
            continue
        rows, cols = zip(*edges)
        graph = csr_matrix((np.ones(len(edges)), (rows, cols)), shape=(len(labels), len(labels)))
        _, component = connected_components(graph, directed=True, connection="strong")
        sizes = np.bincount(component)
        cyclic = {labels[i] for i in range(len(labels)) if sizes[component[i]] > 1} | {labels[i] for i, j in edges
                                                                                       if i == j}
        for label in cyclic:
            for line in blocks[label]:
                if set(re.findall(r"\bcall [^@]*@([\w.$]+)\(", line)) & taking:
                    found.append((name, label, line.strip()[:200]))
    return found


def small_query():
    grid = PaddedGrid(np.eye(8, dtype=bool)[::-1] & (np.arange(8) < 6))  # an anti-diagonal wall with a gap
    return grid, GridSearcher(grid), grid.index(0, 0), grid.index(7, 7)


def test_jps_takes_no_references_in_its_loop():
    grid, s, a, b = small_query()
    state = np.zeros(grid.moves.size, dtype=K.state_layout(False)[0])  # (the searcher allocates its own at first use)
    ir = kernel_ir(K.make_jps(False).py_func, (grid.moves, grid.stride, a, b, state, s.lo, s.hi, s.extent, s.key,
                                               s.cell, s.next, s.head, s.stack))
    assert "call void @NRT_incref" in ir  # (on entry: what the check looks at is there)
    assert loop_references(ir) == []


@pytest.mark.parametrize("conn, hcode, any_angle, wide", [
    (8, K.H_OCTILE, False, False), (8, K.H_ZERO, False, False), (4, K.H_MANHATTAN, False, False),
    (8, K.H_OCTILE, False, True), (8, K.H_EUCLIDEAN, True, False)])
def test_astar_variants_take_no_references_in_their_loops(conn, hcode, any_angle, wide):
    grid, s, a, b = small_query()
    parent = np.empty(grid.strip_size, dtype=np.int32)
    state = np.zeros(grid.strip_size, dtype=np.float64 if any_angle else K.state_layout(wide)[0])
    kernel = K.make_astar(conn, hcode, any_angle, wide)
    ir = kernel_ir(kernel.py_func, (grid.free, grid.stride, grid.strip_moves, grid.strip_height, grid.bits,
                                    grid.strip_index(0, 0), grid.strip_index(7, 7), 1.0, state, parent, s.flags,
                                    s.key, s.cell, s.next, s.head, s.stack))
    assert "call void @NRT_incref" in ir
    assert loop_references(ir) == []


def test_hybrid_expansion_loop_never_replaces_an_array():
    """Hybrid A*'s loop (``hybrid_search._expand``) takes its arrays as arguments and never assigns to
    one: an array variable a loop may reassign costs numba's atomic reference counting on every pass
    (12 % of the PythonRobotics demo query before the loop moved there; its IR then held 40
    ``NRT_incref`` calls for 40 array arguments). Checked on the source, which costs no compile."""
    import ast
    import inspect
    import textwrap

    from navlab.grid import hybrid_search

    tree = ast.parse(textwrap.dedent(inspect.getsource(hybrid_search._expand.py_func)))
    function = tree.body[0]
    arguments = {a.arg for a in function.args.args}
    assigned = set()
    for node in ast.walk(function):
        targets = node.targets if isinstance(node, ast.Assign) else \
            [node.target] if isinstance(node, (ast.AugAssign, ast.AnnAssign, ast.For)) else []
        for target in targets:
            assigned |= {n.id for n in ast.walk(target) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store)}
    replaced = arguments & assigned
    assert not replaced, f"_expand reassigns array arguments: {sorted(replaced)}"
    # nor takes a slice: a view is a new reference, counted with the same atomics on every pass (its LLVM
    # held 43 NRT_incref calls for 41 array arguments with prim_kind[j:j + 1] in the loop; 44 for 44 without)
    slices = [ast.unparse(n) for n in ast.walk(function) if isinstance(n, ast.Subscript) and
              isinstance(n.slice, ast.Slice)]
    assert not slices, f"_expand slices arrays in its loop: {slices}"
    assert {"nx", "hkey", "swept", "fcells", "blocks"} <= arguments


@njit
def _branchy_sum(values, n):
    total = 0.0
    for j in range(n):
        if values[j] > 0.5:
            total += values[j]
    return total


def _reassigns_in_its_loop(a, b):
    total = 0.0
    chosen = a
    for i in range(a.shape[0]):
        total += _branchy_sum(chosen, i)
        chosen = b if i % 2 else a  # an array variable reassigned in the loop: counted on every pass
    return total


@njit
def _span_total(lo, hi, extent, stride):
    """The review's helper (session 25): LLVM keeps it out of line, with an increment of each array on entry."""
    total = 0
    for row in range(extent[0], extent[1] + 1):
        first, last = K.touched_span(row, lo, hi, extent, stride)
        total += last - first
    return total


def _calls_a_referencing_helper_in_its_loop(lo, hi, extent):
    total = 0
    for i in range(lo.shape[0]):
        total += _span_total(lo, hi, extent, i + 3)
    return total


def test_the_check_sees_a_reference_taken_in_a_loop():
    """The check above can fail: a loop that reassigns an array variable it passes to a helper takes a
    reference on every pass; so does one that calls a helper taking references (the review's mutant of A*
    that the per-function count passed, session 25)."""
    values = np.linspace(0.0, 1.0, 10)
    assert loop_references(kernel_ir(_reassigns_in_its_loop, (values, values[::-1].copy())))
    lo, hi = np.zeros(6, dtype=np.int64), np.full(6, 2, dtype=np.int64)
    found = loop_references(kernel_ir(_calls_a_referencing_helper_in_its_loop, (lo, hi, np.array([0, 5]))))
    assert any("calls_a_referencing_helper" in function and "_span_total" in call for function, _, call in found), \
        found
