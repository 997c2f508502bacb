"""The navlab command runs numpy's BLAS on one thread unless the user set a thread count
(navlab.cli._one_blas_thread); the library never touches the environment. Each case runs in a
fresh process; the truth is the process's own thread list (/proc/self/task, Linux), read after
numpy has loaded OpenBLAS, which starts its threads when it loads."""

import json
import os
import subprocess
import sys
import tempfile

import pytest

SETTINGS = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS", "GOTO_NUM_THREADS")

SCRIPT = """
import atexit, json, os, sys
BEFORE

def report():  # registered before the command: atexit runs it after navlab's own handlers
    import numpy  # loads OpenBLAS (if the command did not): its threads start now, from the environment
    tasks = len(os.listdir("/proc/self/task")) if os.path.isdir("/proc/self/task") else None
    print(json.dumps({"env": {k: os.environ.get(k) for k in SETTINGS}, "threads": tasks}), file=sys.stderr)

atexit.register(report)
COMMAND
"""
COMMAND = "from navlab.cli import main\nmain(['list', 'scenes'])"


def run(env=None, before="", command=COMMAND, name="navlab"):
    """The script run as a file called ``name``: ``navlab`` is how the console script runs (the command),
    any other name a program of the user's."""
    clean = {k: v for k, v in os.environ.items() if k not in SETTINGS}
    clean.update(env or {})
    script = SCRIPT.replace("BEFORE", before).replace("COMMAND", command).replace("SETTINGS", repr(SETTINGS))
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, name)
        with open(path, "w") as f:
            f.write(script)
        out = subprocess.run([sys.executable, path], capture_output=True, text=True, env=clean, timeout=120)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stderr.strip().splitlines()[-1])


def linux_with_cores():
    return os.path.isdir("/proc/self/task") and (os.cpu_count() or 1) >= 2


def test_the_command_sets_one_blas_thread():
    got = run()
    assert got["env"]["OPENBLAS_NUM_THREADS"] == "1" and got["env"]["MKL_NUM_THREADS"] == "1"
    assert got["env"]["OMP_NUM_THREADS"] is None  # governs more than BLAS: never set
    if linux_with_cores():
        assert got["threads"] == 1  # no OpenBLAS worker thread in the process


def test_a_users_blas_setting_wins():
    got = run({"OPENBLAS_NUM_THREADS": "2"})
    assert got["env"]["OPENBLAS_NUM_THREADS"] == "2" and got["env"]["MKL_NUM_THREADS"] is None
    if linux_with_cores():
        assert got["threads"] >= 2  # OpenBLAS started its worker thread, as the user asked


@pytest.mark.parametrize("name", ["OMP_NUM_THREADS", "MKL_NUM_THREADS", "GOTO_NUM_THREADS"])
def test_any_thread_setting_of_the_user_leaves_the_others_alone(name):
    got = run({name: "2"})
    assert got["env"] == {k: ("2" if k == name else None) for k in SETTINGS}


def test_nothing_changes_when_numpy_was_imported_first_or_for_the_library():
    assert run(before="import numpy")["env"] == dict.fromkeys(SETTINGS)  # BLAS started already: env left as is
    program = run(name="prog.py")  # a program calling main(['list', 'scenes']) keeps its environment
    assert program["env"] == dict.fromkeys(SETTINGS)
    library = run(command="import navlab, navlab.cli\nnavlab.plan('clutter', max_iter=50)")
    assert library["env"] == dict.fromkeys(SETTINGS)
    if linux_with_cores():
        assert library["threads"] >= 2  # import navlab keeps OpenBLAS's own default
