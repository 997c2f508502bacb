"""The command that installs one of navlab's optional extras, for the copy of navlab installed here.

navlab is installed from its repository (``pip install .`` or ``pip install -e .``), not from PyPI,
so ``pip install 'navlab[ros2]'``, which the error messages used to give, finds no such package
(newcomer run, session 29). pip records where an installed copy came from in its
``direct_url.json`` (PEP 610): the command names that folder, with ``-e`` for an editable
install, runs this interpreter's pip, and for the ros2 extra the ROS 2 message package PyPI lacks,
built from ``ros_interfaces/tf2_msgs`` beside it. Without that record (a wheel, or an installer that keeps none) it says the generic form,
run in the repository's folder.

References
----------
PEP 610, "Recording the Direct URL Origin of installed distributions".
"""

from __future__ import annotations

import json
import os
import shlex
import sys
from typing import Optional, Tuple
from urllib.parse import urlparse

#: what the ros2 extra needs beside its PyPI wheels: the message package built from the repository
ROS_MESSAGES = "ros_interfaces/tf2_msgs"
#: navlab's optional extras (pyproject.toml's optional-dependencies; a test keeps the two alike)
EXTRAS = ("ros2", "dask", "ompl", "parquet", "bench", "irsim", "test")


def _installed_from() -> Tuple[Optional[str], bool]:
    """(the folder this navlab was installed from, or None; whether the install is editable). None unless
    pip recorded a folder (``dir_info``: not a wheel or an archive, not a URL of another kind) and the
    navlab imported here lies in it, as an editable install's does (a copy run from another folder, with
    ``PYTHONPATH``, is not the one the record describes)."""
    from importlib import metadata
    from urllib.request import url2pathname

    try:
        text = metadata.distribution("navlab").read_text("direct_url.json")
        record = json.loads(text) if text else {}
    except (metadata.PackageNotFoundError, OSError, ValueError):
        return None, False
    if not isinstance(record, dict) or not isinstance(record.get("dir_info"), dict):
        return None, False
    url = record.get("url")
    parts = urlparse(url) if isinstance(url, str) else None
    if parts is None or parts.scheme != "file" or parts.netloc not in ("", "localhost"):
        return None, False
    folder = os.path.abspath(url2pathname(parts.path))  # (which undoes the URL's %-escapes)
    editable = record["dir_info"].get("editable") is True
    if editable and not _imported_from(folder):
        return None, False
    return folder, editable


def _imported_from(folder: str) -> bool:
    """Whether the navlab package imported here lies in ``folder``."""
    import navlab

    here = os.path.realpath(os.path.dirname(navlab.__file__))
    return os.path.commonpath([here, os.path.realpath(folder)]) == os.path.realpath(folder)


def install_command(extra: str) -> str:
    """``python -m pip install ...`` adding ``extra`` (``ros2``, ``dask``, ``ompl``, ``parquet``, ``bench``) to
    this installation of navlab, with this interpreter's pip (a bare ``pip`` may be another environment's:
    the README's venv is used as ``.venv/bin/navlab``, not activated)."""
    if extra not in EXTRAS:  # (None, 5 or 'nosuch' gave "pip install '.[None]'": API attack, session 29)
        from .errors import ParameterError

        raise ParameterError(f"extra must be one of {', '.join(EXTRAS)}, got {extra!r}")
    folder, editable = _installed_from()
    base = folder if folder is not None else "."
    command = f"{shlex.quote(sys.executable)} -m pip install " + ("-e " if editable else "") + \
        shlex.quote(f"{base}[{extra}]")
    if extra == "ros2":
        command += " " + shlex.quote(os.path.join(base, ROS_MESSAGES))
    return command if folder is not None else command + " (in the navlab repository's folder)"
