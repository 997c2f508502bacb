"""save_figure: a figure file appears whole or not at all, and errors name the real file."""

import errno
import os

import matplotlib.pyplot as plt
import pytest

from navlab.viz import save_figure


@pytest.fixture
def fig():
    f, ax = plt.subplots(figsize=(2, 2))
    ax.plot([0, 1], [0, 1])
    yield f
    plt.close(f)


@pytest.mark.parametrize("name, magic", [("out.png", b"\x89PNG"), ("out.pdf", b"%PDF"), ("out.svg", b"<?xml")])
def test_writes_the_format_of_the_suffix(tmp_path, fig, name, magic):
    assert save_figure(fig, tmp_path / name).read_bytes().startswith(magic)
    assert os.listdir(tmp_path) == [name]  # no temporary file left beside it


def test_failure_mid_write_keeps_the_old_file(tmp_path, fig, monkeypatch):
    target = tmp_path / "plot.png"
    target.write_bytes(b"old")

    def full_disk(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(fig, "savefig", full_disk)
    with pytest.raises(OSError) as err:
        save_figure(fig, target)
    assert err.value.filename == str(target) and err.value.errno == errno.ENOSPC
    assert target.read_bytes() == b"old" and os.listdir(tmp_path) == ["plot.png"]


def test_missing_folder_names_the_file(tmp_path, fig):
    with pytest.raises(FileNotFoundError) as err:
        save_figure(fig, tmp_path / "nowhere" / "plot.png")
    assert err.value.filename == str(tmp_path / "nowhere" / "plot.png")
