"""Saving figures whole or not at all (plots, maps, reports: every figure navlab writes)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Dict, Union

from ..atomic import atomic_path


def save_figure(fig: Any, target: Union[str, os.PathLike], **savefig_kwargs: Any) -> Path:
    """Write ``fig`` to ``target`` through a temporary file renamed into place.

    A full disk or a kill mid-write leaves ``target`` as it was (never a
    truncated image). The format follows ``target``'s suffix, as with
    ``fig.savefig``.

    Raises
    ------
    OSError
        The file cannot be written; ``filename`` is ``target``, so the CLI's
        one-line message names it (not the temporary name).
    """
    import matplotlib

    target = Path(target)
    savefig_kwargs.setdefault("format", target.suffix[1:].lower() or matplotlib.rcParams["savefig.format"])
    try:
        with atomic_path(target) as tmp:
            fig.savefig(tmp, **savefig_kwargs)
    except OSError as exc:
        raise OSError(exc.errno, exc.strerror or str(exc), str(target)) from None
    return target


def figure_formats() -> Dict[str, str]:
    """The file formats ``save_figure`` writes, by suffix (matplotlib's: png, pdf, svg, ...), each
    with its description."""
    from matplotlib.backend_bases import FigureCanvasBase

    return dict(FigureCanvasBase.get_supported_filetypes())
