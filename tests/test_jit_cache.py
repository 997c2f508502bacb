"""navlab.jit: a navlab kernel's cache goes stale when a navlab module it uses changes, not only its own file.

numba keys a cache on the function's own source file; a compiled function holds the navlab code it calls, so
after a change to a callee's module alone (``git pull`` in an editable install) numba ran the old code. Each
process below starts fresh and shares one cache folder; the change is simulated by replacing the hashes of
the dependencies (editing navlab's own files is not a test's to do)."""

import json
import os
import subprocess
import sys
import textwrap

from navlab import jit

RUN = textwrap.dedent('''
    import json, sys
    import navlab.jit as jit
    if sys.argv[1] == "changed":
        jit.dependency_hashes = lambda name: (("navlab.sampling.curves", b"another text"),)
    from navlab.sampling import dubins
    length = dubins.length(2.0, 0.5, 1.0)
    stats = dubins.length.stats
    print(json.dumps({"length": length, "hits": sum(stats.cache_hits.values()),
                      "misses": sum(stats.cache_misses.values())}))
''')


def run(tmp_path, how):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    out = subprocess.run([sys.executable, "-c", RUN, how], env=env, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.splitlines()[-1])


def test_a_change_in_a_module_a_kernel_uses_makes_its_cache_stale(tmp_path):
    first, again, changed, after = (run(tmp_path, how) for how in ("same", "same", "changed", "same"))
    assert (first["misses"], again["hits"], again["misses"]) == (1, 1, 0)  # compiled once, then loaded
    assert (changed["hits"], changed["misses"]) == (0, 1)  # a dependency changed: compiled again
    assert (after["hits"], after["misses"]) == (0, 1)  # and back: compiled again, not the other's code
    assert first["length"] == again["length"] == changed["length"] == after["length"]


def test_the_dependencies_reach_through_modules():
    """Hybrid A*'s search uses the Reeds–Shepp length through its own imports, and the field's module: the
    case that ran stale (a change to reeds_shepp_length.py alone, session 20)."""
    import navlab.grid.hybrid_search  # noqa: F401

    names = [name for name, _ in jit.dependency_hashes("navlab.grid.hybrid_search")]
    assert {"navlab.sampling.reeds_shepp_length", "navlab.sampling.dubins", "navlab.grid.hybrid_field",
            "navlab.grid.floor_cells", "navlab.sampling.curves"} <= set(names)
    assert "navlab.grid.hybrid_search" not in names and names == sorted(names)


def test_only_navlab_functions_get_the_dependency_stamp():
    import numba

    from navlab.sampling import dubins

    @numba.njit(cache=True)
    def elsewhere(x):
        return x + 1

    assert isinstance(dubins.length._cache._impl.locator, jit.DependencyStampLocator)
    assert not isinstance(elsewhere._cache._impl.locator, jit.DependencyStampLocator)
