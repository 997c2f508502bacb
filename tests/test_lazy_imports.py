"""`navlab --help` and `import navlab` load none of the heavy modules (numba, scipy,
matplotlib, the bench), and `navlab plan clutter` none that a tree planner on a
built-in scene does not use: tests on the import graph, not on time
(benchmarks/bench_startup.py measures the time)."""

import json
import subprocess
import sys

import pytest

HEAVY = ("numba", "scipy", "matplotlib", "shapely", "navlab.bench", "navlab.sampling", "navlab.grid", "rclpy", "yaml")
#: what `navlab plan clutter` (rrt_star on a built-in scene) never calls: the grid search and its kernels, the
#: map readers, the pose planners and their curves, plotting, the bench, ROS, OMPL, and the scipy.linalg package
#: that numba's BLAS check would import (navlab.numba_start hands numba the one extension module it needs), and
#: shapely (a built-in scene's polygons are constants known simple: shapes.Polygon._known_simple)
NOT_FOR_A_TREE_QUERY = ("shapely", "scipy.linalg", "scipy.spatial", "scipy.ndimage", "matplotlib", "navlab.bench", "navlab.viz",
                        "navlab.grid.planner", "navlab.grid.kernels", "navlab.grid.mapio", "navlab.grid.rasterize",
                        "navlab.grid.hybrid_astar", "navlab.sampling.reeds_shepp", "navlab.sampling.dubins",
                        "navlab.sampling.curves", "navlab.sampling.se2_planners",
                        "navlab.sim", "navlab.ros", "rclpy", "ompl", "PIL",
                        "yaml")  # numba's configuration imports PyYAML for a file the working folder lacks


def loaded_after(code):
    out = subprocess.run([sys.executable, "-c", code + "\nimport sys, json; print(json.dumps(sorted(sys.modules)))"],
                         capture_output=True, text=True, check=True)
    return set(json.loads(out.stdout.strip().splitlines()[-1]))


def heavy(modules, names=HEAVY):
    return sorted(m for m in modules if any(m == h or m.startswith(h + ".") for h in names))


def test_import_navlab_is_light():
    assert heavy(loaded_after("import navlab")) == []


def test_navlab_help_loads_no_verb():
    code = ("from navlab.cli import main\n"
            "try:\n    main(['--help'])\nexcept SystemExit:\n    pass")
    modules = loaded_after(code)
    assert heavy(modules) == []
    assert not [m for m in modules if m.startswith("navlab.cli.") and m != "navlab.cli.common"]


def test_bench_help_loads_no_statistics():
    """`navlab bench --help` reads the suites' descriptions only: it took 1.4 s importing scipy.stats through
    navlab.bench's runner (newcomer run, session 19)."""
    code = ("from navlab.cli import main\n"
            "try:\n    main(['bench', '--help'])\nexcept SystemExit:\n    pass")
    modules = loaded_after(code)
    assert "navlab.bench.suites" in modules and heavy(modules, ("scipy", "numba", "navlab.bench.runner")) == []
    import navlab.bench
    from navlab.bench.runner import run_experiment

    assert navlab.bench.run_experiment is run_experiment and set(navlab.bench._LAZY) <= set(dir(navlab.bench))


def test_the_lazy_names_are_the_real_ones():
    import navlab
    from navlab.planning import plan
    from navlab.world import load_world

    assert navlab.plan is plan and navlab.load_world is load_world and "plan" in dir(navlab)
    import navlab.grid  # noqa: F401  (a loaded subpackage is listed, as dir() would)

    public = set(dir(navlab)) - {name for name in dir(navlab) if name.startswith("__")}
    extra = public - set(navlab._LAZY)
    assert set(navlab._LAZY) <= public and "grid" in extra
    # besides the public names only loaded submodules: no helpers (importlib, lazy_attributes)
    assert all(getattr(navlab, name).__name__ == f"navlab.{name}" for name in extra), extra
    with pytest.raises(AttributeError, match="no_such_name"):
        navlab.no_such_name


def test_every_verb_is_reachable_and_documented_lazily():
    from navlab.cli import VERBS, main

    for name in VERBS:
        command = main.get_command(None, name)
        assert command is not None and command.name == name


def test_plan_clutter_loads_only_what_a_tree_query_uses():
    code = ("from navlab.cli import main\n"
            "try:\n    main(['plan', 'clutter', '--max-iter', '50'])\nexcept SystemExit:\n    pass")
    loaded_after(code)  # a cold numba cache compiles here, and compiling loads numba's registries
    modules = loaded_after(code)
    assert "navlab.sampling.tree_kernel" in modules and "scipy.linalg.cython_blas" in modules  # it did plan
    assert heavy(modules - {"scipy.linalg.cython_blas"}, NOT_FOR_A_TREE_QUERY) == []  # loaded alone, not its package
    # the cached kernels loaded without numba's typing and lowering registries (numba_cached_loads.cached_loads_without_registries)
    assert heavy(modules, ("numba.np.arraymath", "numba.np.linalg", "numba.np.npyimpl", "numba.typed.typeddict")) == []
    # nor the modules their environments name (numba_start._environments_without_imports)
    assert heavy(modules, ("numba.np.arrayobj", "numba.cpython.unicode", "numba.cpython.charseq")) == []


def test_plan_clutter_defers_the_entry_points_reader():
    """numba imports importlib.metadata for its extensions' entry points; the command never reads them
    (numba_start.import_numba_lean), so the module is there but its code never ran."""
    code = ("import sys\nfrom navlab.cli import main\n"
            "try:\n    main(['plan', 'clutter', '--max-iter', '50'])\n"
            "except SystemExit:\n    pass\n"
            "module = sys.modules['importlib.metadata']\n"
            "print('deferred' if 'entry_points' not in object.__getattribute__(module, '__dict__') else 'ran')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip().splitlines()[-1] == "deferred"


def test_a_grid_planner_still_finds_the_grid_search():
    # the other side of answering tree planners' names without the grid package
    from navlab.planning import is_grid_planner, planner_names
    from navlab.queries import is_grid_planner as is_grid_planner_in_queries
    from navlab.registry import UnknownNameError

    for name in planner_names():
        if name != "hybrid_astar":  # a pose planner, routed before either is asked
            assert is_grid_planner(name) == is_grid_planner_in_queries(name), name
    assert is_grid_planner("astar") and not is_grid_planner("rrt_star")
    try:
        is_grid_planner("rrt_starr")
    except UnknownNameError as exc:
        assert "astar" in str(exc) and "rrt_star" in str(exc)  # both lists, and the hint
    else:
        raise AssertionError("an unknown planner must raise")


def test_tree_and_grid_planners_share_no_name():
    # navlab.planning.is_grid_planner answers a tree planner's name without asking the grid registry
    from navlab.grid import GRID_ALGORITHMS
    from navlab.sampling import PLANNERS

    assert set(PLANNERS.names()) & set(GRID_ALGORITHMS.names()) == set()
    assert PLANNERS.names() and GRID_ALGORITHMS.names()


def test_the_grid_package_loads_its_parts_on_first_use():
    code = "import navlab.grid.occupancy"
    modules = loaded_after(code)
    assert heavy(modules, ("numba", "navlab.grid.planner", "navlab.grid.kernels", "navlab.grid.mapio")) == []
    import importlib

    import navlab.grid as grid

    assert sorted(grid.__all__) == sorted(grid._LAZY) and set(grid.__all__) <= set(dir(grid))
    for name in grid.__all__:  # the lazy names are the real ones
        assert getattr(grid, name) is getattr(importlib.import_module(f"navlab.grid.{grid._LAZY[name]}"), name), name
    with pytest.raises(AttributeError, match="no_such_name"):
        grid.no_such_name
