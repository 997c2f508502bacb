"""--scheduler that is not a Dask scheduler: one line within a few seconds (loopback servers only)."""

import socket
import threading
import time

import pytest

from navlab.bench.executors import DASK_CONNECT_TIMEOUT, check_executor
from navlab.bench.experiment import ExperimentError

pytest.importorskip("distributed")


def serve(reply):
    """A one-connection server on 127.0.0.1 that sends ``reply`` (or nothing) and holds the line open."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(4)
    stop = threading.Event()

    def run():
        server.settimeout(0.2)
        held = []
        while not stop.is_set():
            try:
                conn, _ = server.accept()
            except OSError:
                continue
            held.append(conn)
            if reply:
                try:
                    conn.sendall(reply)
                except OSError:
                    pass
        for c in held:
            c.close()
        server.close()

    threading.Thread(target=run, daemon=True).start()
    return f"tcp://127.0.0.1:{server.getsockname()[1]}", stop


@pytest.mark.parametrize("reply", [b"SSH-2.0-OpenSSH_9.2p1 Debian-2\r\n", b"", b"HTTP/1.1 400 Bad Request\r\n\r\n"])
def test_a_port_that_is_not_a_dask_scheduler_is_one_line_within_seconds(reply):
    address, stop = serve(reply)
    t0 = time.monotonic()
    try:
        with pytest.raises(ExperimentError, match=f"--scheduler {address}: ") as err:
            check_executor("dask", address)
    finally:
        stop.set()
    assert time.monotonic() - t0 < DASK_CONNECT_TIMEOUT + 3
    assert "\n" not in str(err.value) and "EiB" not in str(err.value)


def test_a_closed_port_is_one_line():
    sock = socket.socket()
    sock.bind(("127.0.0.1", 0))
    port = sock.getsockname()[1]
    sock.close()
    with pytest.raises(ExperimentError, match="not a Dask scheduler, or not reachable|no Dask scheduler answered"):
        check_executor("dask", f"tcp://127.0.0.1:{port}")


def test_the_command_ends_after_its_line_while_the_far_end_still_holds_the_connection(tmp_path):
    """The connection attempt is abandoned, not waited for at exit: an outside check found the process alive
    after its error line for as long as an HTTP server kept the socket open (a thread pool's worker is joined
    when Python exits)."""
    import subprocess
    import sys

    address, stop = serve(b"")  # accepts and never answers, nor closes, until stopped below
    study = tmp_path / "study.yaml"
    study.write_text("name: dask-hang\nworlds: [clutter]\nplanners: [rrt]\ntrials: 1\n")
    try:
        done = subprocess.run([sys.executable, "-m", "navlab", "bench", str(study), "--executor", "dask",
                               "--scheduler", address, "--out", str(tmp_path / "out")],
                              capture_output=True, text=True, timeout=180)  # a hang detector, not a speed limit
    finally:
        stop.set()
    assert done.returncode == 2 and f"--scheduler {address}: no Dask scheduler answered" in done.stderr + done.stdout
    assert len((done.stderr + done.stdout).strip().splitlines()) == 1
