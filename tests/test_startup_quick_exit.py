"""The navlab command ends the process at once after `navlab plan` (navlab.cli._exit_now): the
output, the files and the exit status stay whole, atexit handlers still run, and only the
interpreter's teardown is skipped. Each case is a fresh process run the way a user runs it
(python -m navlab); the truth is navlab.plan called in this process, the PNG format's own
structure, and an object whose __del__ runs only in an ordinary teardown."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import navlab

PLAN = ["plan", "clutter", "--max-iter", "300", "--json"]


def navlab_command(args, **kwargs):
    return subprocess.run([sys.executable, "-m", "navlab", *args], timeout=300, **kwargs)


@pytest.fixture(scope="module")
def truth():
    return navlab.plan("clutter", max_iter=300)


def check_json(text, truth):
    got = json.loads(text)  # one whole JSON document: nothing cut off at the exit
    assert got["status"] == truth.status.name == "EXACT"
    assert got["cost"] == pytest.approx(truth.cost, rel=1e-12)
    np.testing.assert_allclose(got["path"], truth.path, rtol=1e-12)


def test_plan_output_is_whole_through_a_pipe(truth):
    out = navlab_command(PLAN, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    check_json(out.stdout, truth)


def test_plan_output_is_whole_in_a_file_and_so_is_the_plot(tmp_path, truth):
    png = tmp_path / "plan.png"
    with open(tmp_path / "out.json", "w") as stdout:
        code = navlab_command([*PLAN, "--plot", str(png)], stdout=stdout, stderr=subprocess.PIPE).returncode
    assert code == 0
    check_json((tmp_path / "out.json").read_text(), truth)
    data = png.read_bytes()
    # PNG's signature first and its IEND chunk last: the file was closed whole before the exit
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and data[-12:] == b"\x00\x00\x00\x00IEND\xaeB`\x82"


def test_exit_statuses_and_messages_survive():
    failed = navlab_command(["plan", "clutter", "--max-iter", "1"], capture_output=True, text=True)
    assert failed.returncode == 1  # answered without reaching the goal
    assert failed.stdout.startswith("clutter: rrt_star + uniform, seed 0: FAILED")
    closed = navlab_command(["plan", "clutter", "--max-iter", "50"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            text=True, preexec_fn=lambda: os.close(1))  # started without a stdout (sys.stdout is None)
    assert closed.returncode == 0 and closed.stderr == ""
    bad = navlab_command(["plan", "clutter", "--seed", "-1"], capture_output=True, text=True)
    assert bad.returncode == 2 and bad.stdout == ""
    assert bad.stderr.startswith("Error: ") and bad.stderr.count("\n") == 1


TEARDOWN = """
import atexit, os, sys

class Witness:
    def __del__(self, write=os.write):  # its own reference to os.write: teardown may have cleared the globals
        write(2, b"TEARDOWN\\n")

sys.modules["navlab_test_witness"] = Witness()  # an ordinary exit may drop it while emptying sys.modules
atexit.register(lambda: sys.stderr.write("ATEXIT\\n"))
sys.argv = ["navlab", *ARGS]
import navlab.cli
exit_now = navlab.cli._exit_now

def spy(code):
    sys.stderr.write("QUICK\\n")
    exit_now(code)
    sys.stderr.write("RETURNED\\n")  # left to the ordinary exit

navlab.cli._exit_now = spy
navlab.cli.main()  # bare, as the console script calls it
"""


@pytest.mark.parametrize("args, quick", [(["plan", "clutter", "--max-iter", "50"], True),
                                         (["list", "scenes"], False)])
def test_only_a_verb_that_says_so_skips_the_teardown_and_atexit_still_runs(args, quick, tmp_path):
    script = tmp_path / "navlab"  # run as the console script is: a file named navlab
    script.write_text(TEARDOWN.replace("ARGS", repr(args)))
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    lines = out.stderr.splitlines()
    assert "ATEXIT" in lines  # atexit handlers run either way
    assert ("QUICK" in lines) is quick
    if quick:
        assert "RETURNED" not in lines
        # gone at once: no object destroyed in a teardown (whether an ordinary exit reaches this one depends
        # on the hash seed, as objects frozen at exit in reference cycles are never freed: asserted one way only)
        assert "TEARDOWN" not in lines


PROGRAM = """
import sys
sys.argv = ["prog", "plan", "clutter", "--max-iter", "50", "--json"]
import navlab.cli
try:
    navlab.cli.main()  # bare, from a program of its own: not the navlab command
except SystemExit as exc:
    print("CAUGHT", exc.code, file=sys.stderr)
print("STILL RUNNING", file=sys.stderr)
"""


def test_a_program_calling_main_bare_keeps_its_process(tmp_path):
    script = tmp_path / "prog.py"
    script.write_text(PROGRAM)
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stderr.splitlines()[-2:] == ["CAUGHT 0", "STILL RUNNING"]
    assert json.loads(out.stdout.splitlines()[0])["status"] == "EXACT"


EXIT_NOW = """
import sys, threading, time
from navlab.cli import _exit_now

def late():
    time.sleep(0.2)
    print("JOINED", flush=True)

CASE
print("RETURNED", flush=True)
"""


@pytest.mark.parametrize("case, printed, code", [
    ("threading.Thread(target=late).start(); _exit_now(3)", ["RETURNED", "JOINED"], 0),  # a live thread: joined
    ("_exit_now('a message')", ["RETURNED"], 0),  # not a number: Python prints it
    ("print('WRITTEN', end='')\n_exit_now(3)", ["WRITTEN"], 3),  # buffered output flushed, then gone at once
])
def test_exit_now_leaves_the_cases_it_cannot_take_to_the_ordinary_exit(case, printed, code):
    out = subprocess.run([sys.executable, "-c", EXIT_NOW.replace("CASE", case)], capture_output=True, text=True,
                         timeout=60)
    assert out.stdout.split() == printed and out.returncode == code


NO_RUN_EXITFUNCS = """
import atexit, os, sys
del atexit._run_exitfuncs  # CPython's private function: a Python without it must still exit as it should
atexit.register(lambda: sys.stderr.write("ATEXIT\\n"))
real_exit = os._exit
os._exit = lambda code: (sys.stderr.write("QUICK\\n"), real_exit(code))
sys.argv = ["navlab", *ARGS]
import navlab.cli
navlab.cli.main()  # bare, as the console script calls it
"""


@pytest.mark.parametrize("args, code", [(PLAN, 0), (["plan", "clutter", "--max-iter", "1", "--json"], 1)])
def test_without_run_exitfuncs_the_ordinary_exit_flushes_and_keeps_the_status(args, code, tmp_path, truth):
    script = tmp_path / "navlab"
    script.write_text(NO_RUN_EXITFUNCS.replace("ARGS", repr(args)))
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=300)
    assert out.returncode == code, out.stderr
    lines = out.stderr.splitlines()
    assert lines.count("ATEXIT") == 1 and "QUICK" not in lines  # the ordinary exit ran the handlers, once
    got = json.loads(out.stdout)  # whole, flushed by the ordinary exit
    if code == 0:
        check_json(out.stdout, truth)
    else:
        assert got["status"] == "FAILED"


COUNTED = """
import sys
sys.argv = ["navlab", "list", "scenes"]
import navlab.cli
asked = navlab.cli._is_the_command
calls = []
navlab.cli._is_the_command = lambda: calls.append(1) or asked()
try:
    navlab.cli.main()
finally:
    sys.stderr.write(f"ASKED {len(calls)}\\n")
"""


def test_the_command_asks_whether_it_is_the_command_once(tmp_path):
    script = tmp_path / "navlab"
    script.write_text(COUNTED)
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stderr.splitlines()[-1] == "ASKED 1" and "clutter" in out.stdout


CTRL_C_WHILE_IMPORTING = """
import sys

class Interrupting:  # Ctrl-C while the command's modules import: navlab.cli's import is interrupted
    def find_spec(self, name, path=None, target=None):
        if name == "navlab.cli":
            raise KeyboardInterrupt
        return None

sys.meta_path.insert(0, Interrupting())
from navlab.command import main
main()
"""


def test_ctrl_c_while_the_command_imports_is_one_line_and_130():
    """The console script imports its entry point outside any handler: a Ctrl-C in the first tenth of a
    second printed a KeyboardInterrupt traceback (attack, session 29). navlab.command's own import is
    guarded."""
    out = subprocess.run([sys.executable, "-c", CTRL_C_WHILE_IMPORTING], capture_output=True, text=True, timeout=60)
    assert (out.returncode, out.stderr) == (130, "Interrupted.\n")


def test_the_console_script_is_the_guarded_entry_point():
    import tomllib
    from pathlib import Path

    scripts = tomllib.loads((Path(__file__).resolve().parents[1] / "pyproject.toml").read_text())["project"]["scripts"]
    assert scripts["navlab"] == "navlab.command:main"


AFTER_THE_LAST_LINE = """
import atexit, os, signal, sys
from navlab.cli import main
atexit.register(lambda: os.kill(os.getpid(), signal.SIGINT))  # Ctrl-C while the interpreter shuts down
atexit.register(lambda: print("EXITING", flush=True))
main.main(ARGS, the_command=THE_COMMAND)
"""


@pytest.mark.parametrize("args, status", [(["--version"], 0), (["plan", "trap", "--max-iter", "-1"], 2)])
def test_once_the_command_is_done_ctrl_c_ends_it_with_its_own_status(args, status):
    """A Ctrl-C while the interpreter shut down, after the command's last line, ended the process by the
    signal with no message and no status of its own (attack, session 29): once the navlab command is done,
    it ends the process with the command's status, output flushed."""
    code = AFTER_THE_LAST_LINE.replace("ARGS", repr(args)).replace("THE_COMMAND", "True")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert out.returncode == status and out.stdout.splitlines()[-1] == "EXITING", out.stdout + out.stderr
    assert "KeyboardInterrupt" not in out.stderr and "Traceback" not in out.stderr, out.stderr


def test_a_program_calling_main_keeps_its_own_ctrl_c():
    code = AFTER_THE_LAST_LINE.replace("ARGS", '["--version"]').replace("THE_COMMAND", "False")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert out.returncode == -2 or "KeyboardInterrupt" in out.stderr, (out.returncode, out.stderr)
