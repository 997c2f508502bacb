"""The grid search kernels take no array references inside their loops.

Numba reference-counts arrays. Around a call that numba inlines at its own
level (``inline="always"``), or a helper whose body branches, it can leave an
atomic ``NRT_incref``/``NRT_decref`` of each array argument that its pruning
pass does not remove; inside a search loop that is two locked adds per call
(JPS paid them per jump and per push: 1.2x its time on random4096,
kernels.py above ``_jump_straight``). A kernel whose loops are clean increments
each array argument at most once, on entry, so its LLVM IR holds at most as
many ``NRT_incref`` calls as it has array arguments. Checked on an uncached
compile of each kernel's Python source (cached code cannot be inspected).
"""

import re

import numpy as np
import pytest
from numba import njit, types

from navlab.grid import kernels as K
from navlab.grid.planner import GridSearcher, PaddedGrid


def incref_calls(py_func, args):
    """(NRT_incref calls, array arguments) of the compiled kernel, and of each helper LLVM kept as a function
    of its own, as a list of pairs: the kernel's first. (numba 0.68.1 keeps ``clear_touched``, which the kernel
    calls once on entry, out of line, with an incref of each of its own four arrays: counted against the
    kernel's ten, its fourteen looked like references taken in the loop.)"""
    fn = njit(py_func)
    fn(*args)
    (sig,) = fn.signatures
    arrays = sum(isinstance(t, types.Array) for t in sig)
    functions = [chunk for chunk in fn.inspect_llvm(sig).split("\ndefine ")[1:] if "@NRT_incref(" not in
                 chunk.split("\n", 1)[0]]
    counts = []
    for chunk in functions:
        header, body = chunk.split("\n", 1)
        # an array argument is passed as its fields, %arg.NAME.0 (meminfo) to %arg.NAME.6.k (strides)
        own_arrays = len(set(re.findall(r"%arg\.([A-Za-z_][A-Za-z_0-9]*)\.6\.0\b", header)))
        counts.append((body.count("call void @NRT_incref"), own_arrays))
    assert counts and counts[0][1] == arrays, (counts, arrays)  # the kernel itself comes first
    return counts


def clean(counts) -> bool:
    """Whether every function increments each array argument at most once (on entry: none in a loop)."""
    return all(calls <= arrays for calls, arrays in counts)


def small_query():
    grid = PaddedGrid(np.eye(8, dtype=bool)[::-1] & (np.arange(8) < 6))  # an anti-diagonal wall with a gap
    return grid, GridSearcher(grid), grid.index(0, 0), grid.index(7, 7)


def test_jps_takes_no_references_in_its_loop():
    grid, s, a, b = small_query()
    state = np.zeros(grid.moves.size, dtype=K.state_layout(False)[0])  # (the searcher allocates its own at first use)
    counts = incref_calls(K.make_jps(False).py_func, (grid.moves, grid.stride, a, b, state, s.lo, s.hi,
                                                      s.extent, s.key, s.cell, s.next, s.head, s.stack))
    assert clean(counts), counts


@pytest.mark.parametrize("conn, hcode, any_angle, wide", [
    (8, K.H_OCTILE, False, False), (8, K.H_ZERO, False, False), (4, K.H_MANHATTAN, False, False),
    (8, K.H_OCTILE, False, True), (8, K.H_EUCLIDEAN, True, False)])
def test_astar_variants_take_no_references_in_their_loops(conn, hcode, any_angle, wide):
    grid, s, a, b = small_query()
    parent = np.empty(grid.moves.size, dtype=np.int32)
    state = np.zeros(grid.moves.size, dtype=np.float64 if any_angle else K.state_layout(wide)[0])
    kernel = K.make_astar(conn, hcode, any_angle, wide)
    counts = incref_calls(kernel.py_func, (grid.free, grid.moves, grid.stride, a, b, 1.0, state, parent,
                                           s.lo, s.hi, s.extent, s.key, s.cell, s.next, s.head, s.stack))
    assert clean(counts), counts


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


def test_the_count_sees_a_reference_taken_in_a_loop():
    """The check above can fail: a loop that reassigns an array variable it passes to a helper holds more
    increments than it has arrays (4 for 2 with numba 0.68)."""
    values = np.linspace(0.0, 1.0, 10)
    assert not clean(incref_calls(_reassigns_in_its_loop, (values, values[::-1].copy())))
