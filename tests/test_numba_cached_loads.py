"""navlab.numba_cached_loads.cached_loads_without_registries: a cached kernel loads and runs without numba's typing
and lowering registries, the modules its environments name (numba.np.arrayobj) or the third-party extensions'
entry points, and whatever compiles afterwards in the same process still gets all of them, extensions first.
Each check runs in fresh processes (a cache written by one, read by the next); the truth is numpy's, and a
numba extension installed for the test (an entry point in a .dist-info folder) that records when it ran."""

import json
import os
import subprocess
import sys
import textwrap

import numpy as np

KERNELS = '''
import numba
import numpy as np

@numba.njit(cache=True)
def cumulative(x):  # allocates (numba's runtime) and loops: what navlab's kernels do
    out = np.empty(x.size + 1)
    out[0] = 0.0
    for i in range(x.size):
        out[i + 1] = out[i] + x[i]
    return out
'''

LOAD = '''
import json, os, sys
sys.path.insert(0, {folder!r})
lean = {lean!r}
import numba
if lean:
    from navlab.numba_cached_loads import cached_loads_without_registries
    switched = cached_loads_without_registries()
    again = cached_loads_without_registries()
else:
    switched = again = None
import numpy as np
from kernels import cumulative
got = cumulative(np.arange(5.0))
registries_after_load = "numba.np.arraymath" in sys.modules
arrayobj_after_load = "numba.np.arrayobj" in sys.modules  # the module np.empty's helpers' environment names
linking_parsed_after_load = next(iter(cumulative.overloads.values())).library._shared_module is not None
extension_after_load = os.path.exists({marker!r})

@numba.njit
def sorted_norms(a):  # compiled now: needs the array registries (np.sort, np.linalg.norm)
    return np.sort(np.array([np.linalg.norm(row) for row in a]))

norms = sorted_norms(np.array([[3.0, 4.0], [1.0, 0.0], [6.0, 8.0]]))

@numba.njit
def last_of_cumulative(x):  # compiled now, calling the cached kernel: links its library's bitcode in
    return cumulative(x)[-1]

linked = last_of_cumulative(np.arange(5.0))
print(json.dumps({{"switched": switched, "again": again, "got": got.tolist(),
                  "registries_after_load": registries_after_load, "norms": norms.tolist(),
                  "registries_after_compile": "numba.np.arraymath" in sys.modules,
                  "arrayobj_after_load": arrayobj_after_load, "extension_after_load": extension_after_load,
                  "linking_parsed_after_load": linking_parsed_after_load, "linked": linked,
                  "extension_ran": open({marker!r}).read() if os.path.exists({marker!r}) else None,
                  "loaded_from_cache": len(cumulative.stats.cache_hits) == 1}}))
'''


#: a numba extension as a distribution installs one: an ``init`` entry point in group ``numba_extensions``
EXTENSION = '''
import os, sys

def init():  # numba runs it once per process, before the first typing (or, lean, the first compile)
    with open({marker!r}, "w") as f:
        f.write("numba.np.arraymath" if "numba.np.arraymath" in sys.modules else "before the registries")
'''


def install_extension(folder, marker):
    (folder / "fake_numba_ext.py").write_text(EXTENSION.format(marker=str(marker)))
    info = folder / "fake_numba_ext-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: fake-numba-ext\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text("[numba_extensions]\ninit = fake_numba_ext:init\n")


def run(folder, lean):
    marker = folder / "extension-ran"
    if marker.exists():
        marker.unlink()
    out = subprocess.run([sys.executable, "-c", LOAD.format(folder=str(folder), lean=lean, marker=str(marker))],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_this_numba_is_one_the_switches_were_checked_against():
    """A new numba release turns the lean loads off (numba_cached_loads.CHECKED_NUMBA); this says so, so that
    someone reads numba's new loading code, runs these tests and adds the release, rather than start-up silently
    losing a third of its speed."""
    import numba

    from navlab.numba_cached_loads import CHECKED_NUMBA

    assert numba.__version__.startswith(CHECKED_NUMBA), (numba.__version__, CHECKED_NUMBA)


def test_a_cached_kernel_loads_without_the_registries_and_later_compiles_get_them(tmp_path):
    (tmp_path / "kernels.py").write_text(textwrap.dedent(KERNELS))
    install_extension(tmp_path, tmp_path / "extension-ran")
    first = run(tmp_path, lean=True)  # nothing cached yet: it compiles, and compiling loads the registries
    assert first["loaded_from_cache"] is False and first["registries_after_load"] is True
    plain = run(tmp_path, lean=False)  # numba's own load, for comparison
    assert plain["loaded_from_cache"] is True and plain["registries_after_load"] is True
    lean = run(tmp_path, lean=True)
    assert lean["switched"] is True and lean["again"] is True
    assert lean["loaded_from_cache"] is True
    assert lean["registries_after_load"] is False  # what the switch saves
    assert lean["arrayobj_after_load"] is False and plain["arrayobj_after_load"] is True
    # numba runs the extensions before its first call's typing; lean, at the first compile (and before it)
    assert plain["extension_after_load"] is True and lean["extension_after_load"] is False
    # the library's linking bitcode is parsed when a compile links it in (last_of_cumulative), not at its load
    assert plain["linking_parsed_after_load"] is True and lean["linking_parsed_after_load"] is False
    for got in (first, plain, lean):
        np.testing.assert_array_equal(got["got"], np.concatenate([[0.0], np.cumsum(np.arange(5.0))]))
        assert got["norms"] == [1.0, 5.0, 10.0]  # a compile after the lean load still has np.sort and np.linalg
        assert got["registries_after_compile"] is True
        assert got["extension_ran"] is not None  # every process ran the extension before it compiled
        assert got["linked"] == 10.0


RUNTIME = '''
import glob, json, os, sys
sys.path.insert(0, {folder!r})
import numba
from navlab.numba_cached_loads import cached_loads_without_registries
cached_loads_without_registries()
import numpy as np
from numba.core.runtime import nrtdynmod, rtsys
from kernels import cumulative
got = cumulative(np.arange(5.0))

@numba.njit
def grown(n):  # compiled now, linked against the runtime library: allocates, copies, frees
    out = np.zeros(0)
    for i in range(n):
        out = np.append(out, float(i))
    return out

total = grown(50).sum()
stats = rtsys.get_allocation_stats()
print(json.dumps({{"loaded_from": nrtdynmod.compile_nrt_functions.loaded_from, "got": got.tolist(), "total": total,
                  "allocs_minus_frees": stats.alloc - stats.free,
                  "files": sorted(os.path.basename(p) for p in glob.glob(os.path.join({cache!r}, "**", "*.nbo"),
                                                                          recursive=True))}}))
'''


def test_the_runtime_module_is_compiled_once_then_loaded_and_frees_what_it_allocates(tmp_path):
    """numba's runtime module from navlab's file (_runtime_from_cache): the second process loads what the first
    compiled; kernels loaded or compiled with it allocate and free in balance (NRT's own counters); a damaged
    file is compiled over."""
    (tmp_path / "kernels.py").write_text(textwrap.dedent(KERNELS))
    cache = tmp_path / "cache"
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), NUMBA_NRT_STATS="1")
    code = RUNTIME.format(folder=str(tmp_path), cache=str(cache))

    def run_once():
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
        return json.loads(out.stdout.strip().splitlines()[-1])

    first, second = run_once(), run_once()
    assert first["loaded_from"] is None and len(first["files"]) == 1  # compiled, and written for the next process
    assert second["loaded_from"] is not None and second["loaded_from"].endswith(first["files"][0])
    for got in (first, second):
        np.testing.assert_array_equal(got["got"], [0.0, 0.0, 1.0, 3.0, 6.0, 10.0])
        assert got["total"] == sum(range(50))
        assert got["allocs_minus_frees"] <= 1  # at most `got`'s buffer, still alive: every temporary was freed
    with open(second["loaded_from"], "wb") as f:
        f.write(b"not a pickle")
    damaged = run_once()
    assert damaged["loaded_from"] is None and damaged["total"] == sum(range(50))
    assert run_once()["loaded_from"] == second["loaded_from"]  # written again, whole


SYMBOLS = '''
import glob, json, os, pickle, sys
sys.path.insert(0, {folder!r})
import numpy as np
import llvmlite.binding as ll
from kernels import cumulative, sorted_rows
cumulative(np.arange(3.0)), sorted_rows(np.ones((2, 2)))
from navlab.numba_cached_loads import _elf_defined_symbols
out = []
for path in sorted(glob.glob(os.path.join({cache!r}, "**", "*.nbc"), recursive=True)):
    name, kind, (object_code, bitcode) = pickle.loads(open(path, "rb").read())[0]
    module = ll.parse_bitcode(bitcode)  # numba's own record: every function and global the module defines
    walked = {{g.name for group in (module.functions, module.global_variables) for g in group if not g.is_declaration}}
    out.append([sorted(walked), sorted(_elf_defined_symbols(object_code))])
print(json.dumps(out))
'''


def test_the_object_codes_symbol_table_lists_what_numbas_walk_of_the_bitcode_lists(tmp_path):
    """_elf_defined_symbols, against numba's own record of a library's symbols (the bitcode's defined functions
    and globals, walked through llvmlite), on kernels with numba's helpers inlined (np.empty, np.sort)."""
    (tmp_path / "kernels.py").write_text(textwrap.dedent(KERNELS) + textwrap.dedent('''
        @numba.njit(cache=True)
        def sorted_rows(a):
            out = np.empty_like(a)
            for i in range(a.shape[0]):
                out[i] = np.sort(a[i])
            return out
        '''))
    cache = tmp_path / "cache"
    out = subprocess.run([sys.executable, "-c", SYMBOLS.format(folder=str(tmp_path), cache=str(cache))],
                         env=dict(os.environ, NUMBA_CACHE_DIR=str(cache)), capture_output=True, text=True, check=True)
    libraries = json.loads(out.stdout.strip().splitlines()[-1])
    assert len(libraries) == 2
    for walked, listed in libraries:
        assert len(walked) > 3 and walked == listed


def test_object_code_that_is_not_elf64_little_endian_is_left_to_numba():
    from navlab.numba_cached_loads import _elf_defined_symbols

    for data in (b"", b"\xcf\xfa\xed\xfe" + bytes(60), b"\x7fELF\x01\x01" + bytes(60), b"\x7fELF\x02\x01" + bytes(10),
                 b"\x7fELF\x02\x01" + bytes(0x3A) + b"\xff\xff"):  # Mach-O, 32-bit, truncated, absurd count
        assert _elf_defined_symbols(data) is None
