"""The command that installs one of navlab's optional extras, for the copy of navlab installed here.

navlab is installed from its repository (``pip install .`` or ``pip install -e .``), not from PyPI,
so ``pip install 'navlab[ros2]'``, which the error messages used to give, finds no such package
(newcomer run, session 29). pip records where an installed copy came from in its
``direct_url.json`` (PEP 610): the command names that folder, with ``-e`` for an editable install,
and for the ros2 extra the ROS 2 message package PyPI lacks, built from ``ros_interfaces/tf2_msgs``
beside it. Without that record (a wheel, or an installer that keeps none) it says the generic form,
run in the repository's folder.

References
----------
PEP 610, "Recording the Direct URL Origin of installed distributions".
"""

from __future__ import annotations

import json
import shlex
from typing import Optional, Tuple
from urllib.parse import unquote, urlparse

#: what the ros2 extra needs beside its PyPI wheels: the message package built from the repository
ROS_MESSAGES = "ros_interfaces/tf2_msgs"


def _installed_from() -> Tuple[Optional[str], bool]:
    """(the folder this navlab was installed from, or None; whether the install is editable)."""
    from importlib import metadata

    try:
        text = metadata.distribution("navlab").read_text("direct_url.json")
        record = json.loads(text) if text else {}
    except (metadata.PackageNotFoundError, OSError, ValueError):
        return None, False
    url = record.get("url", "") if isinstance(record, dict) else ""
    info = record.get("dir_info") if isinstance(record, dict) else None
    editable = isinstance(info, dict) and info.get("editable") is True
    if not isinstance(url, str) or not url.startswith("file://"):
        return None, editable
    return unquote(urlparse(url).path) or None, editable


def install_command(extra: str) -> str:
    """``pip install ...`` adding ``extra`` (``ros2``, ``dask``, ``ompl``, ``parquet``, ``bench``) to this
    installation of navlab."""
    folder, editable = _installed_from()
    base = folder if folder is not None else "."
    command = "pip install " + ("-e " if editable else "") + shlex.quote(f"{base}[{extra}]")
    if extra == "ros2":
        command += " " + shlex.quote(f"{base}/{ROS_MESSAGES}")
    return command if folder is not None else command + " (in the navlab repository's folder)"
