"""Files that appear whole or not at all.

A plot, map or report written straight to its name leaves a truncated file
behind when the disk fills or the process is killed mid-write. Writing to a
temporary name in the same folder and renaming it (atomic on POSIX) means the
name only ever holds a complete file.
"""

from __future__ import annotations

import contextlib
import errno
import os
import tempfile
from pathlib import Path
from typing import Iterator, Union


@contextlib.contextmanager
def atomic_path(target: Union[str, os.PathLike]) -> Iterator[Path]:
    """Yield a temporary path beside ``target``; on success rename it to ``target``.

    On any exception the temporary file is removed and ``target`` is left as it was.
    The temporary name keeps ``target``'s suffix, so writers that pick a format
    from the suffix (matplotlib, Pillow) still work.

    Examples
    --------
    >>> with atomic_path("out.png") as tmp:          # doctest: +SKIP
    ...     fig.savefig(tmp)
    """
    target = Path(target)
    if target.is_symlink():
        target = Path(os.path.realpath(target))  # replace the file the link points to, keep the link
    if target.exists() and not target.is_file():
        # a device, a FIFO, a socket or a folder: renaming over it would replace it with a plain file
        raise IsADirectoryError(errno.EISDIR, "is a folder", str(target)) if target.is_dir() else \
            OSError(errno.EEXIST, "exists and is not a regular file (navlab writes files only)", str(target))
    fd, tmp_name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=target.suffix or ".tmp",
                                    dir=target.parent if str(target.parent) else ".")
    try:  # (from the file's creation on: a Ctrl-C before the try left an empty one behind: attack, session 29)
        os.close(fd)
        tmp = Path(tmp_name)
        yield tmp
        os.chmod(tmp, _public_mode(tmp))
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp_name)
        raise


def _public_mode(path: Path) -> int:
    """The mode a plain ``open()`` (or, for an executable, a linker) would have given.

    mkstemp makes the file private (0600). A writer that made it executable (a
    compiler writing a binary to the temporary name) keeps its execute bits:
    stripping them made the benchmarks' compiled OMPL driver fail with
    ``PermissionError`` on a fresh machine.
    """
    umask = os.umask(0)
    os.umask(umask)
    executable = os.stat(path).st_mode & 0o111
    return (0o666 | (0o111 if executable else 0)) & ~umask


def write_text_atomic(target: Union[str, os.PathLike], text: str) -> None:
    """Write ``text`` to ``target`` through :func:`atomic_path`."""
    with atomic_path(target) as tmp:
        tmp.write_text(text)
