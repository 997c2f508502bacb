"""`navlab --help` and `import navlab` load none of the heavy modules (numba, scipy,
matplotlib, the bench): a test on the import graph, not on time
(benchmarks/bench_startup.py measures the time)."""

import json
import subprocess
import sys

HEAVY = ("numba", "scipy", "matplotlib", "shapely", "navlab.bench", "navlab.sampling", "navlab.grid", "rclpy")


def loaded_after(code):
    out = subprocess.run([sys.executable, "-c", code + "\nimport sys, json; print(json.dumps(sorted(sys.modules)))"],
                         capture_output=True, text=True, check=True)
    return set(json.loads(out.stdout.strip().splitlines()[-1]))


def heavy(modules):
    return sorted(m for m in modules if any(m == h or m.startswith(h + ".") for h in HEAVY))


def test_import_navlab_is_light():
    assert heavy(loaded_after("import navlab")) == []


def test_navlab_help_loads_no_verb():
    code = ("from navlab.cli import main\n"
            "try:\n    main(['--help'])\nexcept SystemExit:\n    pass")
    modules = loaded_after(code)
    assert heavy(modules) == []
    assert not [m for m in modules if m.startswith("navlab.cli.") and m != "navlab.cli.common"]


def test_the_lazy_names_are_the_real_ones():
    import navlab
    from navlab.planning import plan
    from navlab.world import load_world

    assert navlab.plan is plan and navlab.load_world is load_world and "plan" in dir(navlab)
    try:
        navlab.no_such_name
    except AttributeError as exc:
        assert "no_such_name" in str(exc)
    else:
        raise AssertionError("an unknown attribute must raise AttributeError")


def test_every_verb_is_reachable_and_documented_lazily():
    from navlab.cli import VERBS, main

    for name in VERBS:
        command = main.get_command(None, name)
        assert command is not None and command.name == name
