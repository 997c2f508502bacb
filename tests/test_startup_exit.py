"""The navlab command's exit skips the final garbage collections over numba's objects
(navlab.cli._quick_exit): checked on what the interpreter holds at exit, not on time
(benchmarks/bench_startup.py measures the time)."""

import json
import subprocess
import sys

SCRIPT = """
import atexit, gc, json, sys
# registered before the command: atexit runs last-in first-out, so this runs after navlab's handler
atexit.register(lambda: sys.stderr.write("FROZEN " + str(gc.get_freeze_count()) + "\\n"))
from navlab.cli import main
try:
    main(ARGS)
except SystemExit as exc:
    code = exc.code
sys.stderr.write("DURING " + str(gc.get_freeze_count()) + " CODE " + str(code) + "\\n")
"""


def run_command(args):
    out = subprocess.run([sys.executable, "-c", SCRIPT.replace("ARGS", repr(args))], capture_output=True,
                         text=True, check=True)
    lines = dict(line.split(" ", 1) for line in out.stderr.splitlines() if line.startswith(("FROZEN", "DURING")))
    return out.stdout, lines


def test_objects_are_frozen_only_at_exit_and_the_output_is_whole():
    stdout, lines = run_command(["plan", "clutter", "--max-iter", "300", "--json"])
    during, code = lines["DURING"].split(" CODE ")
    assert int(during) == 0  # nothing frozen while the command runs: its garbage is collected as usual
    assert code == "0"
    assert int(lines["FROZEN"]) > 10_000  # at exit: numba's registries and the rest, skipped by the collector
    result = json.loads(stdout)  # the JSON written before exit arrives complete
    assert result["status"] == "EXACT" and result["params"]["max_iter"] == 300


def test_frozen_once_however_often_main_runs():
    script = """
import sys, types
import navlab.cli
from navlab.cli import main

def freeze():
    sys.stderr.write("FREEZE\\n")

navlab.cli.gc = types.SimpleNamespace(freeze=freeze)  # counts what would run at exit
for _ in range(3):
    try:
        main(["--version"])
    except SystemExit:
        pass
"""
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True)
    assert out.stderr.splitlines().count("FREEZE") == 1


def test_the_plan_verb_pauses_the_collector_only_for_its_query(monkeypatch):
    import gc

    from click.testing import CliRunner

    import navlab.planning
    from navlab.cli import main

    seen = []
    real_plan = navlab.planning.plan

    def spy(*args, **kwargs):
        seen.append(gc.isenabled())
        return real_plan(*args, **kwargs)

    monkeypatch.setattr(navlab.planning, "plan", spy)
    assert gc.isenabled()
    try:
        out = CliRunner().invoke(main, ["plan", "clutter", "--max-iter", "100"])
        assert out.exit_code == 0, out.output
        assert seen == [False] and gc.isenabled()  # paused during the query, on again after
        gc.disable()
        out = CliRunner().invoke(main, ["plan", "no_such_scene"])  # an error inside the block
        assert out.exit_code == 2 and not gc.isenabled()  # a collector that was off stays off
        gc.enable()
        out = CliRunner().invoke(main, ["plan", "no_such_scene"])
        assert out.exit_code == 2 and gc.isenabled()  # and on, after an error
    finally:
        gc.enable()
        import atexit

        import navlab.cli

        atexit.unregister(navlab.cli._freeze_at_exit)  # main registered it: this test process exits as usual


def test_a_process_that_loaded_ompl_exits_without_nanobinds_leak_list():
    """Frozen at exit, OMPL's module objects outlive the interpreter and nanobind lists them as
    leaked (25 lines after `navlab bench ... --planner ompl:RRTstar`, and in every CI log)."""
    import pytest

    pytest.importorskip("ompl.base")
    script = """
import ompl.base, ompl.geometric
from navlab.cli import main
try:
    main(["--version"])
except SystemExit:
    pass
"""
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True)
    assert "leaked" not in out.stderr and "version" in out.stdout
