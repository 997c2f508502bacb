"""The BARN protocol: start, goal, judging, the challenge's score and its published baseline.

BARN (Benchmark for Autonomous Robot Navigation; Perille et al., "Benchmarking
Metric Ground Navigation", IEEE SSRR 2020; Xiao et al., "Autonomous Ground
Navigation in Highly Constrained Spaces", IEEE RA-M 2022) is 300 worlds of
0.075 m cylinders. Its ``run.py`` (the-barn-challenge at bf5a226) fixes the
protocol this module restates:

- the robot starts at (−2, 3) facing +y (1.57 rad); the goal is (−2, 13);
- the clock starts when the robot has moved 0.1 m from the start;
- it succeeds on coming within 1 m of the goal with no collision in under 100 s;
- the score is ``1[success] · OT / clip(AT, 2·OT, 8·OT)``, AT the time taken and
  OT the optimal time: the reference path (start, the world's path file, goal)
  at 2 m/s. The best possible score is therefore 0.5.

The published move_base DWA baseline (``res/dwa_out.txt``, one run a line:
``world succeeded collided timeout time_s old_score``) is read by
:func:`read_runs` and summarised by :func:`challenge_means` the way the
challenge's ``report_test.py`` does: each world's mean first, then the mean
over worlds (the time over succeeded runs only). Its last column came from an
older score formula, so scores are recomputed from the path files.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, Iterable, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from ..limits import shown
from .experiment import ExperimentError

START = (-2.0, 3.0, 1.57)  #: [m, m, rad] the start pose of every run
GOAL = (-2.0, 13.0)  #: [m] 10 m ahead of the start
GOAL_RADIUS = 1.0  #: [m] success: this close to the goal
TIME_LIMIT = 100.0  #: [s] a run still going after this long timed out
MOVE_THRESHOLD = 0.1  #: [m] the clock starts when the robot has moved this far
REFERENCE_SPEED = 2.0  #: [m/s] the speed the optimal time is counted at
PATH_CELL = 0.15  #: [m] the world generator's grid (twice the cylinder radius)
WORLD_COUNT = 300
TEST_WORLDS = tuple(range(0, WORLD_COUNT, 6))  #: the challenge's 50 test worlds
#: the largest world number --worlds takes (a range is listed in memory: 10**400 overflowed it)
MAX_WORLD_NUMBER = 10 ** 6
STATUSES = ("succeeded", "collided", "timeout")


def path_to_world(cells: np.ndarray) -> np.ndarray:
    """Path-file cells (x, y) to world metres, as ``run.py`` converts them
    (``x·0.15 − 0.075 − 4.5``, ``y·0.15 + 0.075 + 5``)."""
    cells = np.asarray(cells, dtype=float)
    if cells.ndim != 2 or cells.shape[1] != 2 or not np.isfinite(cells).all():
        raise ExperimentError(f"a BARN path must be an (N, 2) array of cells, got shape {cells.shape}")
    half = PATH_CELL / 2
    return np.column_stack([cells[:, 0] * PATH_CELL - half - 30 * PATH_CELL,
                            cells[:, 1] * PATH_CELL + half + 5.0])


def reference_path(path_file) -> np.ndarray:
    """The reference polyline of one world: start, the path file's cells, goal [m]."""
    path_file = Path(path_file)
    try:
        cells = np.load(path_file, allow_pickle=False)
    except (OSError, ValueError) as exc:
        raise ExperimentError(f"{path_file}: not a BARN path file ({exc})") from None
    return np.vstack([START[:2], path_to_world(cells), GOAL])


def polyline_length(points: np.ndarray) -> float:
    return float(np.hypot(*np.diff(np.asarray(points, dtype=float), axis=0).T).sum())


def optimal_time(path_file=None) -> float:
    """OT [s]: the reference path's length at 2 m/s; without a path file, the
    straight line from start to goal (10 m, so 5 s)."""
    points = reference_path(path_file) if path_file is not None else np.array([START[:2], GOAL])
    return polyline_length(points) / REFERENCE_SPEED


def score(succeeded: bool, actual_time: float, optimal: float) -> float:
    """The challenge's score: ``1[success] · OT / clip(AT, 2·OT, 8·OT)``."""
    if not succeeded:
        return 0.0
    return optimal / min(max(actual_time, 2.0 * optimal), 8.0 * optimal)


@dataclass(frozen=True)
class BarnRun:
    """One run's outcome, as the challenge logs it."""

    world: int
    status: str  #: 'succeeded', 'collided' or 'timeout'
    time_s: float  #: AT: from the robot's first 0.1 m to the end of the run [s]

    @property
    def succeeded(self) -> bool:
        return self.status == "succeeded"


def judge(times: np.ndarray, positions: np.ndarray, collided_at: Optional[float] = None) -> BarnRun:
    """Judge one simulated run by the protocol.

    Parameters
    ----------
    times : (M,) array
        Simulated time of each recorded pose [s].
    positions : (M, 2) array
        The robot's true position at those times [m].
    collided_at : float, optional
        When the robot first touched an obstacle [s], if it did.

    Returns
    -------
    BarnRun
        With ``world=-1`` (the caller knows the world). A run that never moved
        0.1 m timed out with AT = 0 when it ended after the time limit.
    """
    times = np.asarray(times, dtype=float)
    positions = np.asarray(positions, dtype=float)[:, :2]
    moved = np.hypot(*(positions - START[:2]).T) >= MOVE_THRESHOLD
    if not moved.any():
        return BarnRun(-1, "collided" if collided_at is not None else "timeout", 0.0)
    t0 = times[np.argmax(moved)]
    near = np.hypot(*(positions - GOAL).T) <= GOAL_RADIUS
    reached_at = times[np.argmax(near)] if near.any() else math.inf
    if collided_at is not None and collided_at <= reached_at:
        return BarnRun(-1, "collided", max(0.0, collided_at - t0))
    if reached_at - t0 < TIME_LIMIT:
        return BarnRun(-1, "succeeded", reached_at - t0)
    return BarnRun(-1, "timeout", min(times[-1] - t0, TIME_LIMIT) if math.isinf(reached_at) else reached_at - t0)


def read_runs(path) -> List[BarnRun]:
    """Runs from a challenge log (``world succeeded collided timeout time_s [score]`` a line)."""
    runs = []
    path = Path(path)
    for number, line in enumerate(path.read_text().splitlines(), 1):
        fields = line.split()
        if not fields:
            continue
        try:
            world, succeeded, collided = int(fields[0]), int(fields[1]), int(fields[2])
            time_s = float(fields[4])
        except (IndexError, ValueError):
            raise ExperimentError(f"{path}, line {number}: expected 'world succeeded collided timeout time_s', "
                                  f"got {line!r}") from None
        status = "succeeded" if succeeded else "collided" if collided else "timeout"
        runs.append(BarnRun(world, status, time_s))
    return runs


def challenge_means(runs: Iterable[BarnRun], optimal_times: Optional[Mapping[int, float]] = None) -> Dict[str, float]:
    """The challenge's five figures: each world's mean first, then the mean over worlds.

    ``time`` is over succeeded runs only (worlds with none are left out, as
    ``report_test.py`` does); ``score`` is recomputed with :func:`score` from
    ``optimal_times`` (world → OT), and is NaN without them. Worlds missing
    from a given ``optimal_times`` raise, naming them.
    """
    by_world: Dict[int, List[BarnRun]] = {}
    for run in runs:
        by_world.setdefault(run.world, []).append(run)
    missing = sorted(set(by_world) - set(optimal_times)) if optimal_times is not None else []
    if missing:
        raise ExperimentError(f"no optimal time (path file) for BARN world(s) {_ranges(missing)}")
    means = {"success": [], "collision": [], "timeout": [], "time": [], "score": []}
    for world, world_runs in sorted(by_world.items()):
        means["success"].append(np.mean([r.succeeded for r in world_runs]))
        means["collision"].append(np.mean([r.status == "collided" for r in world_runs]))
        means["timeout"].append(np.mean([r.status == "timeout" for r in world_runs]))
        if optimal_times is not None:
            means["score"].append(np.mean([score(r.succeeded, r.time_s, optimal_times[world]) for r in world_runs]))
        done = [r.time_s for r in world_runs if r.succeeded]
        if done:
            means["time"].append(np.mean(done))
    out = {k: float(np.mean(v)) if v else math.nan for k, v in means.items()}
    out["worlds"] = len(by_world)
    out["runs"] = sum(len(v) for v in by_world.values())
    return out


def find_worlds(folder) -> Dict[int, Tuple[Path, Optional[Path]]]:
    """The BARN worlds in ``folder`` (``world_N.world``) with their path files
    (``path_files/path_N.npy`` beside them, or None when missing)."""
    folder = Path(folder)
    if not folder.is_dir():
        raise ExperimentError(f"--data {folder}: not a folder (give a checkout's jackal_helper/worlds/BARN, "
                              "or any folder of world_N.world files with path_files/ beside them)")
    found = {}
    for world in folder.glob("world_*.world"):
        match = re.fullmatch(r"world_(\d+)\.world", world.name)
        if match:
            index = int(match.group(1))
            path = folder / "path_files" / f"path_{index}.npy"
            found[index] = (world, path if path.is_file() else None)
    if not found:
        raise ExperimentError(f"--data {folder}: no world_N.world files there")
    return dict(sorted(found.items()))


def select_worlds(text: Optional[str], available: Sequence[int]) -> List[int]:
    """Worlds named by ``--worlds``: ``0,6,12``, a range ``0-49``, a stepped range
    ``0-299:6``, or ``test`` (the challenge's 50 test worlds); None means all available."""
    if text is None or text == "":
        return sorted(available)
    chosen: List[int] = []
    for part in str(text).split(","):
        part = part.strip()
        if part == "test":
            chosen.extend(TEST_WORLDS)
            continue
        match = re.fullmatch(r"(\d+)(?:-(\d+)(?::(\d+))?)?", part)
        if not match:
            raise ExperimentError(f"--worlds: {part!r} is not a world number, a range like 0-49, "
                                  "a stepped range like 0-299:6, or 'test'")
        first, last, step = (_selection_number(number, part) if number else None for number in match.groups())
        last = first if last is None else last
        step = 1 if step is None else step
        if last < first or step < 1:
            raise ExperimentError(f"--worlds: {part!r} is an empty range")
        chosen.extend(range(first, last + 1, step))
    missing = sorted(set(chosen) - set(available))
    if missing:
        raise ExperimentError(f"--worlds: no world file for {_ranges(missing)} in the data folder; "
                              f"it has {_ranges(available)}")
    return sorted(set(chosen))


def _selection_number(digits: str, part: str) -> int:
    """One number of a ``--worlds`` part, at most :data:`MAX_WORLD_NUMBER` (leading zeros aside): a range is
    listed in memory, and 10**400 overflowed it (int() refuses 4 300 digits and more outright)."""
    digits = digits.lstrip("0") or "0"
    if len(digits) > len(str(MAX_WORLD_NUMBER)) or int(digits) > MAX_WORLD_NUMBER:
        raise ExperimentError(f"--worlds: {shown(part, 40)}: its numbers go up to {MAX_WORLD_NUMBER}")
    return int(digits)


def _ranges(numbers: Sequence[int], most: int = 12) -> str:
    """``0, 6, 7, 8, 12`` as ``0, 6-8, 12``; past ``most`` runs, the first ones and how many numbers."""
    parts: List[str] = []
    for n in sorted(numbers):
        if parts and parts[-1].split("-")[-1] == str(n - 1):
            parts[-1] = f"{parts[-1].split('-')[0]}-{n}"
        else:
            parts.append(str(n))
    if len(parts) > most:
        return ", ".join(parts[:most]) + f", ... ({len(numbers)} in all)"
    return ", ".join(parts)
