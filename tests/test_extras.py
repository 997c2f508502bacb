"""The install command an error gives for a missing extra names this copy of navlab's own source."""

import json

import pytest

import navlab.extras as extras


class Distribution:
    def __init__(self, record):
        self.record = record

    def read_text(self, name):
        assert name == "direct_url.json"
        return None if self.record is None else json.dumps(self.record)


@pytest.mark.parametrize("record, extra, command", [
    ({"url": "file:///home/me/navlab", "dir_info": {"editable": True}}, "ros2",
     "pip install -e '/home/me/navlab[ros2]' /home/me/navlab/ros_interfaces/tf2_msgs"),
    ({"url": "file:///home/me/navlab", "dir_info": {}}, "dask", "pip install '/home/me/navlab[dask]'"),
    ({"url": "file:///home/me/my%20robots/navlab", "dir_info": {}}, "ompl",
     "pip install '/home/me/my robots/navlab[ompl]'"),
    (None, "parquet", "pip install '.[parquet]' (in the navlab repository's folder)"),
    ({"url": "https://example.org/navlab.whl", "archive_info": {}}, "ompl",
     "pip install '.[ompl]' (in the navlab repository's folder)"),
    ("not a mapping", "dask", "pip install '.[dask]' (in the navlab repository's folder)"),
])
def test_the_command_names_where_navlab_was_installed_from(record, extra, command, monkeypatch):
    """pip's PEP 610 record says where the installed copy came from; 'navlab[ros2]' is no PyPI package
    (newcomer run, session 29)."""
    from importlib import metadata

    monkeypatch.setattr(metadata, "distribution", lambda name: Distribution(record))
    assert extras.install_command(extra) == command


def test_this_installation_is_named():
    """The test run's own navlab was installed from this repository (.ci/run: pip install -e '.[test,ros2]')."""
    from pathlib import Path

    command = extras.install_command("dask")
    assert command.startswith("pip install ") and "'navlab[dask]'" not in command
    folder, _ = extras._installed_from()
    if folder is not None:  # (an installer that keeps no PEP 610 record: the generic form, tested above)
        assert Path(folder).resolve() == Path(__file__).resolve().parents[1] and folder in command
