"""Moving AI scenario files (``.scen``)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import List

from ..limits import check_path, shown
from .mapio import MapFormatError


@dataclass(frozen=True)
class Scenario:
    """One row: bucket, map name, size, start and goal (x = column, y = row), optimum."""

    bucket: int
    map_name: str
    width: int
    height: int
    start: tuple
    goal: tuple
    optimal: float
    optimal_text: str  #: as printed, to compare at the printed precision

    def tolerance(self) -> float:
        """One unit in the last printed digit."""
        return 10.0 ** -printed_decimals(self.optimal_text)


def printed_decimals(text: str) -> int:
    """How many digits a number printed as ``text`` has after its point."""
    return len(text.split(".")[1]) if "." in text else 0


def read_scen(path) -> List[Scenario]:
    p = check_path("path", path)
    try:
        lines = p.read_text(encoding="utf-8").splitlines()
    except OSError as exc:
        raise MapFormatError(f"{p}: cannot read: {exc.strerror}") from None
    except UnicodeDecodeError as exc:
        raise MapFormatError(f"{p}: not a text file (byte {exc.start} is not UTF-8)") from None
    if not lines or not lines[0].startswith("version"):
        raise MapFormatError(f"{p}: not a Moving AI scenario file (first line must be 'version ...')")
    version = lines[0][len("version"):].strip()
    if version not in ("1", "1.0"):
        raise MapFormatError(f"{p}: line 1: scenario format version {shown(version, 30)} is not one navlab reads "
                             "(version 1: bucket, map, width, height, start x, y, goal x, y, optimal length)")
    out = []
    for n, line in enumerate(lines[1:], start=2):
        if not line.strip():
            continue
        parts = line.split("\t") if "\t" in line else line.split()
        if len(parts) != 9:
            raise MapFormatError(f"{p}: line {n}: expected 9 fields, got {len(parts)}")
        try:
            out.append(Scenario(int(parts[0]), parts[1], int(parts[2]), int(parts[3]),
                                (int(parts[4]), int(parts[5])), (int(parts[6]), int(parts[7])),
                                float(parts[8]), parts[8].strip()))
        except ValueError:
            raise MapFormatError(f"{p}: line {n}: bad number in {line!r}") from None
        optimal = out[-1].optimal
        if not (math.isfinite(optimal) and optimal >= 0):
            raise MapFormatError(f"{p}: line {n}: the optimal length must be a finite number >= 0, "
                                 f"got {parts[8].strip()!r}")
    return out
