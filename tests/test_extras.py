"""The install command an error gives for a missing extra names this copy of navlab's own source."""

import json
import shlex
import sys
from pathlib import Path

import pytest

import navlab.extras as extras

PIP = f"{shlex.quote(sys.executable)} -m pip install "


class Distribution:
    def __init__(self, record):
        self.record = record

    def read_text(self, name):
        assert name == "direct_url.json"
        return self.record if self.record is None or isinstance(self.record, str) else json.dumps(self.record)


@pytest.mark.parametrize("record, extra, command", [
    ({"url": "file:///home/me/navlab", "dir_info": {"editable": True}}, "ros2",
     PIP + "-e '/home/me/navlab[ros2]' /home/me/navlab/ros_interfaces/tf2_msgs"),
    ({"url": "file:///home/me/navlab", "dir_info": {}}, "dask", PIP + "'/home/me/navlab[dask]'"),
    ({"url": "file:///home/me/my%20robots/50%25/navlab", "dir_info": {}}, "ompl",
     PIP + "'/home/me/my robots/50%/navlab[ompl]'"),
    # no folder recorded: the generic form, in the repository's folder
    (None, "parquet", PIP + "'.[parquet]' (in the navlab repository's folder)"),
    ("not json", "parquet", PIP + "'.[parquet]' (in the navlab repository's folder)"),
    ('"a string"', "dask", PIP + "'.[dask]' (in the navlab repository's folder)"),
    ({"url": "file:///home/me/navlab-0.1.0-py3-none-any.whl", "archive_info": {}}, "ompl",
     PIP + "'.[ompl]' (in the navlab repository's folder)"),
    ({"url": "https://example.org/navlab.git", "vcs_info": {"vcs": "git"}}, "ompl",
     PIP + "'.[ompl]' (in the navlab repository's folder)"),
    ({"url": "file://otherhost/share/navlab", "dir_info": {}}, "dask",
     PIP + "'.[dask]' (in the navlab repository's folder)"),
])
def test_the_command_names_where_navlab_was_installed_from(record, extra, command, monkeypatch):
    """pip's PEP 610 record says where the installed copy came from; 'navlab[ros2]' is no PyPI package
    (newcomer run, session 29). A folder only: not an archive, a VCS URL or another host's share."""
    from importlib import metadata

    monkeypatch.setattr(metadata, "distribution", lambda name: Distribution(record))
    monkeypatch.setattr(extras, "_imported_from", lambda folder: True)
    assert extras.install_command(extra) == command


def test_an_editable_record_of_another_copy_is_not_named(monkeypatch):
    """A copy run from another folder (PYTHONPATH=clone/src) is not the one pip's record describes."""
    from importlib import metadata

    record = {"url": "file:///somewhere/else/navlab", "dir_info": {"editable": True}}
    monkeypatch.setattr(metadata, "distribution", lambda name: Distribution(record))
    assert extras.install_command("dask") == PIP + "'.[dask]' (in the navlab repository's folder)"


def test_this_installation_is_named():
    """The test run's own navlab, installed from this repository (.ci/run: pip install -e '.[test,ros2]')."""
    command = extras.install_command("dask")
    assert command.startswith(PIP) and "'navlab[dask]'" not in command
    folder, _ = extras._installed_from()
    if folder is not None:  # (an installer that keeps no PEP 610 record, or another copy: the generic form)
        assert Path(folder).resolve() == Path(__file__).resolve().parents[1] and folder in command


def test_the_extras_are_pyprojects_and_no_other_is_named():
    import tomllib

    from navlab.errors import ParameterError

    extras_declared = tomllib.loads((Path(__file__).resolve().parents[1] / "pyproject.toml").read_text())["project"][
        "optional-dependencies"]
    assert set(extras.EXTRAS) == set(extras_declared)
    for bad in (None, 5, ["ros2"], "\n", "nosuch"):
        with pytest.raises(ParameterError, match="extra must be one of"):
            extras.install_command(bad)
