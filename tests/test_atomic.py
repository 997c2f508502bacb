"""navlab.atomic: a name holds a whole file or the old one, with ordinary permissions."""

import os

import pytest

from navlab.atomic import atomic_path, write_text_atomic


def test_a_written_file_has_the_mode_open_would_give(tmp_path):
    umask = os.umask(0o022)
    try:
        write_text_atomic(tmp_path / "a.txt", "x")
    finally:
        os.umask(umask)
    assert (tmp_path / "a.txt").stat().st_mode & 0o777 == 0o644


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path):
    target = tmp_path / "plot.png"
    target.write_text("old")
    with pytest.raises(OSError), atomic_path(target) as tmp:
        tmp.write_text("half")
        raise OSError(28, "No space left on device")
    assert target.read_text() == "old" and sorted(p.name for p in tmp_path.iterdir()) == ["plot.png"]


def test_a_fifo_is_refused_and_a_symlink_kept(tmp_path):
    """Renaming over a FIFO or a device would replace it with a plain file."""
    import errno
    import os

    import pytest

    from navlab.atomic import write_text_atomic

    fifo = tmp_path / "f.png"
    os.mkfifo(fifo)
    with pytest.raises(OSError) as err:
        write_text_atomic(fifo, "x")
    assert err.value.errno == errno.EEXIST and err.value.filename == str(fifo)
    assert fifo.is_fifo() and sorted(os.listdir(tmp_path)) == ["f.png"]
    real = tmp_path / "real.txt"
    real.write_text("old")
    (tmp_path / "link.txt").symlink_to(real)
    write_text_atomic(tmp_path / "link.txt", "new")
    assert (tmp_path / "link.txt").is_symlink() and real.read_text() == "new"


def test_a_file_the_writer_made_executable_stays_executable(tmp_path):
    """A compiler writing its binary to the temporary name sets execute bits:
    the rename must keep them (the benchmarks' OMPL driver, built this way, failed
    with PermissionError on a fresh machine when they were stripped)."""
    import os
    import stat

    from navlab.atomic import atomic_path

    target = tmp_path / "tool"
    with atomic_path(target) as tmp:
        tmp.write_text("#!/bin/sh\necho ok\n")
        os.chmod(tmp, 0o755)
    assert target.stat().st_mode & stat.S_IXUSR
    plain = tmp_path / "plain.txt"
    with atomic_path(plain) as tmp:
        tmp.write_text("x")
    assert not plain.stat().st_mode & 0o111


def test_a_ctrl_c_right_after_the_temporary_is_made_leaves_none(tmp_path, monkeypatch):
    """Ctrl-C between the temporary's creation and the writer's first byte left an empty
    .report.html.*.html in a bench folder (attack, session 29)."""
    import navlab.atomic as atomic

    def interrupted(fd):
        raise KeyboardInterrupt

    monkeypatch.setattr(atomic.os, "close", interrupted)
    with pytest.raises(KeyboardInterrupt), atomic_path(tmp_path / "report.html"):
        pass
    monkeypatch.undo()
    assert list(tmp_path.iterdir()) == []
