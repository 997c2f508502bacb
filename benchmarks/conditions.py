"""What the machine was doing while a benchmark ran, printed beside its figures.

The machine is shared and noisy: a table of medians means little without the
load it was measured under and the spread of the runs behind each median.
"""

from __future__ import annotations

import os
import platform
from typing import Sequence


def load_line(when: str) -> str:
    """One line with the 1/5/15-minute load averages and the core count."""
    one, five, fifteen = os.getloadavg()
    return (f"load {when}: {one:.2f} / {five:.2f} / {fifteen:.2f} (1/5/15 min) on {os.cpu_count()} cores, "
            f"{platform.processor() or platform.machine()}")


def spread(values: Sequence[float], digits: int = 1, unit: str = "") -> str:
    """``min–max`` of the runs behind a median, e.g. ``8.1–17.9x``."""
    return f"{min(values):.{digits}f}–{max(values):.{digits}f}{unit}"
