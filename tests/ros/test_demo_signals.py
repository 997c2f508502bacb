"""``navlab ros demo --processes`` under Ctrl-C and SIGKILL, on real ROS 2
in a private network namespace: no traceback from any process, no node left
running, no temporary folder left outside the run's own output."""

import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

pytest.importorskip("rclpy", reason="rclpy cannot be imported: the ros2 extra is not installed")

from ros_helpers import DOMAIN_ID, alive, can_unshare, navlab_cmd, ros_env  # noqa: E402

#: bounds on waiting (a generous ceiling, never a measurement)
START_LIMIT, EXIT_LIMIT = 120.0, 60.0


class Demo:
    """A demo run in its own session (as a shell runs a foreground job),
    its stderr read line by line as it comes."""

    def __init__(self, tmp_path: Path, *args: str) -> None:
        cmd = navlab_cmd("ros", "demo", "--processes", "--maze-size", "3", "--rtf", "5", *args)
        env = ros_env(DOMAIN_ID)
        env["TMPDIR"] = str(tmp_path / "tmp")  # what the run leaves in the temporary folder shows here
        (tmp_path / "tmp").mkdir()
        if can_unshare():  # unshare execs the demo: the same pid
            cmd = ["unshare", "-n", "sh", "-c", 'ip link set lo up && exec "$@"', "sh", *cmd]
        else:
            env["ROS_DOMAIN_ID"] = str(100 + os.getpid() % 100)
        self.proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                                     start_new_session=True)
        self.lines, self.out = [], ""
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self) -> None:
        for line in self.proc.stderr:
            self.lines.append(line)

    def children(self):
        """pids of the demo's child processes that run a node's Python (past exec)."""
        path = Path(f"/proc/{self.proc.pid}/task/{self.proc.pid}/children")
        try:
            pids = [int(pid) for pid in path.read_text().split()]
            return [pid for pid in pids if b"run_child" in Path(f"/proc/{pid}/cmdline").read_bytes()]
        except OSError:
            return []

    def wait_for(self, condition, what: str) -> None:
        end = time.monotonic() + START_LIMIT
        while not condition():
            assert self.proc.poll() is None, f"the demo ended before {what}:\n{''.join(self.lines)[-4000:]}"
            assert time.monotonic() < end, f"no {what} in {START_LIMIT:g} s:\n{''.join(self.lines)[-4000:]}"
            time.sleep(0.05)

    def seen(self, text: str) -> bool:
        return any(text in line for line in self.lines)

    def finish(self) -> str:
        self.out = self.proc.communicate(timeout=EXIT_LIMIT)[0]
        self.reader.join(timeout=EXIT_LIMIT)
        return "".join(self.lines)


@pytest.mark.parametrize("moment", ["starting", "driving"])
def test_ctrl_c_ends_the_demo_and_its_nodes_without_a_traceback(tmp_path, moment):
    """Ctrl-C as a terminal sends it: SIGINT to the whole foreground job,
    while the nodes are still importing, and while the robot drives."""
    demo = Demo(tmp_path)
    if moment == "starting":
        demo.wait_for(lambda: len(demo.children()) == 4, "four node processes")
    else:
        demo.wait_for(lambda: demo.seen("[goto_waypoint]: following"), "robot driving")
    nodes = demo.children()
    os.killpg(demo.proc.pid, signal.SIGINT)
    err = demo.finish()
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err[-4000:]
    # the summary, or (interrupted before the run loop) the CLI's one line; exit 130 either way
    assert demo.out.startswith("INTERRUPTED: interrupted") or err.rstrip().endswith("Interrupted.")
    assert demo.proc.returncode == 130
    assert not any(alive(pid) for pid in nodes)
    assert list((tmp_path / "tmp").iterdir()) == []


def test_sigkill_of_the_demo_takes_its_nodes_along(tmp_path):
    """kill -9 of the launcher: every node process ends (SIGTERM from the
    kernel as its parent dies), and the run's files are all in --log-dir."""
    logs = tmp_path / "logs"
    demo = Demo(tmp_path, "--log-dir", str(logs))
    demo.wait_for(lambda: len(demo.children()) == 4 and (logs / "pathplanner.log").exists()
                  and "map 38x38" in (logs / "pathplanner.log").read_text(), "planner with its map")
    nodes = demo.children()
    assert len(nodes) == 4 and all(alive(pid) for pid in nodes)
    os.kill(demo.proc.pid, signal.SIGKILL)
    demo.finish()
    end = time.monotonic() + EXIT_LIMIT
    while any(alive(pid) for pid in nodes) and time.monotonic() < end:
        time.sleep(0.05)
    assert not [pid for pid in nodes if alive(pid)], "node processes outlived the demo"
    assert list((tmp_path / "tmp").iterdir()) == []  # nothing outside the run's own folder
    assert sorted(p.name for p in logs.iterdir()) == ["goto_waypoint.log", "map_server.log", "maze3x3.pgm",
                                                      "maze3x3.yaml", "pathplanner.log", "sim.log"]


def test_a_later_run_removes_the_temporary_folder_of_a_killed_one(tmp_path, monkeypatch):
    import tempfile

    from navlab.ros.demo import TEMP_PREFIX, run_folder

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    gone = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True,
                          text=True, check=True)
    dead_pid = int(gone.stdout)  # a process that has ended
    stale = tmp_path / f"{TEMP_PREFIX}{dead_pid}-abc"
    live = tmp_path / f"{TEMP_PREFIX}{os.getppid()}-abc"  # our parent runs
    other = tmp_path / "someone-else"
    for folder in (stale, live, other):
        folder.mkdir()
        (folder / "maze.yaml").write_text("x")
    with run_folder() as folder:
        assert folder.parent == tmp_path and folder.name.startswith(f"{TEMP_PREFIX}{os.getpid()}-")
        assert not stale.exists() and live.exists() and other.exists()
    assert not folder.exists()
    with run_folder(str(tmp_path / "out")) as folder:
        assert folder == tmp_path / "out"
    assert folder.is_dir()  # a run's own output folder stays


def test_ctrl_c_ends_a_pathplanner_node_that_has_loaded_its_kernels(tmp_path):
    """The node loads its kernels after rclpy.init: numba's compile-lock listener (navlab.compile_clock)
    set a Python SIGINT handler around each load, which replaced rclpy's for good, and the node then
    ignored Ctrl-C until killed (attack run, session 18)."""
    env = ros_env(DOMAIN_ID)
    cmd = navlab_cmd("ros", "pathplanner")
    if can_unshare():
        cmd = ["unshare", "-n", "sh", "-c", 'ip link set lo up && exec "$@"', "sh", *cmd]
    else:
        env["ROS_DOMAIN_ID"] = str(100 + os.getpid() % 100)
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                            start_new_session=True)
    lines = []
    reader = threading.Thread(target=lambda: lines.extend(proc.stderr), daemon=True)
    reader.start()
    end = time.monotonic() + START_LIMIT
    while not any("ready" in line for line in lines):
        assert proc.poll() is None, "".join(lines)[-4000:]
        assert time.monotonic() < end, f"no 'ready' in {START_LIMIT:g} s:\n{''.join(lines)[-4000:]}"
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGINT)
    try:
        proc.wait(timeout=EXIT_LIMIT)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        pytest.fail(f"the pathplanner node still ran {EXIT_LIMIT:g} s after Ctrl-C")
    reader.join(timeout=EXIT_LIMIT)
    assert proc.returncode in (0, 130) and "Traceback" not in "".join(lines), "".join(lines)[-4000:]


def test_ctrl_c_while_the_nodes_are_built_stops_after_the_one_being_built(tmp_path):
    """The in-process demo built every node before it looked at a Ctrl-C: 19 s on a first start, the
    pathplanner compiling its kernels (attack, session 30). Now it stops after the node being built, and
    says on stderr that it waits for it."""
    import json

    from ros_helpers import run_isolated

    proc = run_isolated([sys.executable, str(Path(__file__).with_name("demo_stop_scenario.py"))], timeout=120)
    assert proc.returncode == 0, proc.stderr[-4000:]
    seen = json.loads(proc.stdout.strip().splitlines()[-1])
    assert seen["built"] == ["map_server"] and seen["reason"] == "interrupted", seen
    assert "stopping once the map_server node is built" in proc.stderr, proc.stderr[-4000:]
