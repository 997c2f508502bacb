"""navlab.jit: a navlab kernel's cache goes stale when navlab code or constants it compiles in change, not only
when its own file does, and stays valid when only Python code around the kernels changes.

numba keys a cache on the function's own source file; a compiled function holds the navlab code it calls and
the constants it reads, so after a change to a callee's module alone (``git pull`` in an editable install)
numba ran the old code. Each check runs in fresh processes sharing one cache folder, on a small package of
navlab modules written for the test (added to ``navlab.__path__``) and edited between runs."""

import json
import os
import pathlib
import re
import subprocess
import sys
import textwrap

import pytest

from navlab import jit

CALLEE = '''
from .jit import njit

K = {k}  # frozen into the caller's machine code


@njit(cache=True)
def twice(x):
    return {factor} * x
'''

# each in a module of its own, which nothing else of the kernel's reaches
CONSTANT = "K2 = {k2}  # re-exported by jitfake_reexport, read there through a module alias\n"
REEXPORT = "from .jitfake_constant import K2  # noqa: F401\n"
ENUM = "import enum\n\n\nclass Mode(enum.IntEnum):\n    A = 0\n    B = {b}\n"
SCALE = "SCALE = {scale}  # a default value's\n"

AROUND = '''
def message(x):
    return "{text}"  # Python code around a kernel: no kernel compiles it in
'''

CALLER = '''
from . import jitfake_reexport as R
from .jit import njit
from .jitfake_around import message  # noqa: F401
from .jitfake_callee import K, twice
from .jitfake_enum import Mode
from .jitfake_scale import SCALE


@njit(cache=True)
def kernel(x, s=SCALE):
    return twice(x) + K + R.K2 + Mode.B + s
'''

RUN = textwrap.dedent('''
    import json, sys
    import navlab
    navlab.__path__.append(sys.argv[1])
    from navlab import jitfake_caller as caller
    value = caller.kernel(1)
    stats = caller.kernel.stats
    print(json.dumps({"value": value, "loaded": sum(stats.cache_hits.values()),
                      "compiled": sum(stats.cache_misses.values())}))
''')


def write(folder, k=10, factor=2, k2=100, b=1000, scale=10000, text="hello"):
    for name, text_ in (("callee", CALLEE.format(k=k, factor=factor)), ("constant", CONSTANT.format(k2=k2)),
                        ("reexport", REEXPORT), ("enum", ENUM.format(b=b)), ("scale", SCALE.format(scale=scale)),
                        ("around", AROUND.format(text=text)), ("caller", CALLER)):
        (folder / f"jitfake_{name}.py").write_text(text_)


def run(folder):
    # no bytecode cache: a module rewritten at the same size within the same second (K = 10 -> 20) would
    # be read from its stale .pyc (Python checks size and whole-second mtime), running the old code
    env = {**os.environ, "NUMBA_CACHE_DIR": str(folder / "cache"), "PYTHONDONTWRITEBYTECODE": "1"}
    out = subprocess.run([sys.executable, "-c", RUN, str(folder)], env=env, capture_output=True, text=True,
                         timeout=600)
    assert out.returncode == 0, out.stderr
    result = json.loads(out.stdout.splitlines()[-1])
    return result["value"], "loaded" if result["loaded"] else "compiled"


def test_a_kernel_compiles_again_when_code_or_constants_it_holds_change_and_only_then(tmp_path):
    write(tmp_path)
    assert run(tmp_path) == (11112, "compiled")
    assert run(tmp_path) == (11112, "loaded")
    write(tmp_path, k=20)  # a constant the kernel reads, imported by name from another module
    assert run(tmp_path) == (11122, "compiled")
    write(tmp_path, k=20, factor=3)  # a function it calls, in another module
    assert run(tmp_path) == (11123, "compiled")
    # (review, session 21: these three were missed) a constant re-exported by a module read through an alias,
    # an IntEnum member, a default value
    write(tmp_path, k=20, factor=3, k2=200)
    assert run(tmp_path) == (11223, "compiled")
    write(tmp_path, k=20, factor=3, k2=200, b=2000)
    assert run(tmp_path) == (12223, "compiled")
    write(tmp_path, k=20, factor=3, k2=200, b=2000, scale=20000)
    assert run(tmp_path) == (22223, "compiled")
    write(tmp_path, k=20, factor=3, k2=200, b=2000, scale=20000, text="changed")  # a module it compiles nothing of
    assert run(tmp_path) == (22223, "loaded")
    write(tmp_path)  # back: compiled again, not the other version's code
    assert run(tmp_path) == (11112, "compiled")


def test_what_hybrid_a_star_search_compiles_in():
    """The case that ran stale (a change to reeds_shepp_length.py alone, session 20), and what it does not hold
    (the checks and messages of errors.py and limits.py, which Python code around it uses)."""
    from navlab.grid import hybrid_search

    reached = set(jit.compiled_in(hybrid_search.search.py_func))
    assert {"navlab.sampling.reeds_shepp_length", "navlab.sampling.dubins", "navlab.grid.hybrid_field",
            "navlab.grid.floor_cells", "navlab.sampling.curves"} <= reached
    assert not reached & {"navlab.errors", "navlab.limits", "navlab.grid.hybrid_search", "navlab.grid.hybrid_astar"}


def test_the_stamp_needs_none_of_numbas_private_hashing(monkeypatch):
    """(review, session 21: numba's _hash_source_file exists only from 0.68, and navlab takes numba >= 0.59)"""
    from numba.core import caching

    from navlab.sampling import reeds_shepp

    monkeypatch.delattr(caching, "_hash_source_file", raising=False)
    hashes = dict(jit.dependency_hashes(reeds_shepp.solve.py_func))
    assert "navlab.sampling.curves" in hashes and len(hashes["navlab.sampling.curves"]) == 32


def test_a_navlab_kernel_that_cannot_be_cached_gets_numbas_warning(tmp_path, monkeypatch):
    """(session 26: numba's warning reads the locator's ``_py_file``, which the dependency locator lacked, so
    a kernel numba cannot cache, here one calling C through ctypes, raised AttributeError at its first call)"""
    import importlib.util

    from numba.core.errors import NumbaWarning

    path = tmp_path / "jitfake_ctypes.py"
    path.write_text("import ctypes\n\nfrom navlab.jit import njit\n\nlabs = ctypes.CDLL(None).labs\n"
                    "labs.restype = ctypes.c_long\nlabs.argtypes = [ctypes.c_long]\n\n\n"
                    "@njit(cache=True)\ndef absolute(x):\n    return labs(x)\n")
    spec = importlib.util.spec_from_file_location("navlab.jitfake_ctypes", path)
    module = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(sys.modules, spec.name, module)
    spec.loader.exec_module(module)
    with pytest.warns(NumbaWarning, match="Cannot cache compiled function \"absolute\""):
        assert module.absolute(-7) == 7
    assert isinstance(module.absolute._cache._impl.locator, jit.DependencyStampLocator)


def test_only_navlab_functions_get_the_dependency_stamp():
    import numba

    from navlab.sampling import dubins

    @numba.njit(cache=True)
    def elsewhere(x):
        return x + 1

    assert jit.install()
    assert isinstance(dubins.length._cache._impl.locator, jit.DependencyStampLocator)
    assert not isinstance(elsewhere._cache._impl.locator, jit.DependencyStampLocator)


def test_every_navlab_kernel_module_takes_njit_from_navlab_jit():
    """One imported straight from numba, before anything imported navlab.jit, would be keyed on its own file."""
    src = pathlib.Path(jit.__file__).parent
    offenders = [str(path.relative_to(src)) for path in src.rglob("*.py") if path.name != "jit.py"
                 and re.search(r"^\s*(from numba import .*\bnjit\b|.*\bnumba\.(njit|jit)\()", path.read_text(), re.M)]
    assert offenders == []


@pytest.mark.parametrize("text, expected", [
    ("from .curves import NOP, LEFT\n", {"NOP": "navlab.sampling.curves", "LEFT": "navlab.sampling.curves"}),
    ("from ..grid.floor_cells import (floor_div,\n    floor_cells)  # a comment\n",
     {"floor_div": "navlab.grid.floor_cells", "floor_cells": "navlab.grid.floor_cells"}),
    ("from numpy import pi\nfrom . import dubins as d\n", {"d": "navlab.sampling"}),
    ('"""\nfrom the start, scaled by r)\n"""\nfrom .curves import NOP\n', {"NOP": "navlab.sampling.curves"}),
    ("from .curves import NOP\n\n\ndef f():\n    pass\n\n\nfrom .dubins import length\n",
     {"NOP": "navlab.sampling.curves"}),  # (navlab imports at the top: the scan stops at the first definition)
])
def test_names_imported_by_name_are_traced_to_their_module(tmp_path, monkeypatch, text, expected):
    path = tmp_path / "jitfake_names.py"
    path.write_text(text)
    module = type(sys)("navlab.sampling.jitfake_names")
    module.__file__ = str(path)
    monkeypatch.setitem(sys.modules, module.__name__, module)
    jit._imported_names.cache_clear()
    assert jit._imported_names(module.__name__) == expected
