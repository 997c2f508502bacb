"""Run a Moving AI scenario file and compare with the stored optimal lengths."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional

import numpy as np

from . import kernels as K
from .mapio import MapFormatError, load_map
from .planner import OWN_HEURISTIC, plan
from .scen import Scenario, read_scen

#: The benchmark's generator priced a diagonal at 1.414213562 (√2 cut to 9
#: decimals): over all 9,861 scenarios in shared/data, the stored lengths equal
#: straight + 1.414213562 · diagonal rounded to the printed digits (worst
#: difference 0.49 units), while exact √2 drifts by ~3.7e-10 per diagonal step.
MOVINGAI_SQRT2 = 1.414213562

#: Algorithms whose paths are not 8-connected grid paths: the stored octile
#: optimum is an upper bound for them (any-angle paths are shorter by design).
ANY_ANGLE = ("theta_star",)

WORST = 5  #: rows listed in the summary


def benchmark_length(cells: np.ndarray) -> float:
    """A path's length as the Moving AI generator computes it."""
    straight, diagonal, rest = K.step_counts(np.ascontiguousarray(cells, dtype=np.int64))
    return straight + diagonal * MOVINGAI_SQRT2 + rest


def resolve_map(scen_path: Path, scenario: Scenario, map_path: Optional[str]) -> Path:
    if map_path:
        return Path(map_path)
    candidate = scen_path.parent / Path(scenario.map_name).name
    if not candidate.exists():
        raise MapFormatError(f"{scen_path}: its map '{scenario.map_name}' is not at {candidate}; pass --map")
    return candidate


def compare(sc: Scenario, result, any_angle: bool) -> Dict[str, Any]:
    """One row: the path's length against the stored optimum.

    Grid algorithms match when the length computed the benchmark's way
    (:data:`MOVINGAI_SQRT2`) equals the optimum to one unit of its last
    printed digit. Any-angle algorithms match when their exact length is at
    most the optimum (plus that unit): lower is fine. ``excess`` is the
    length minus the optimum (signed; what the worst rows are ranked by).
    """
    row: Dict[str, Any] = {"start": list(sc.start), "goal": list(sc.goal), "optimal": sc.optimal,
                           "optimal_text": sc.optimal_text, "status": result.status.name, "length": None,
                           "exact_length": None, "excess": None,
                           "match": False, "expanded": result.stats["expanded"], "time_s": result.stats["time_s"]}
    if not result.success:
        return row
    exact = float(result.stats["cost_cells"])
    length = exact if any_angle else benchmark_length(result.cells)
    tol = sc.tolerance() * (1 + 1e-9)
    excess = length - sc.optimal
    row.update(length=length, exact_length=exact, excess=excess,
               match=bool(excess <= tol if any_angle else abs(excess) <= tol))
    return row


def run_scenarios(scen_path, map_path: Optional[str] = None, algorithm: str = "astar",
                  heuristic: str = "octile", limit: Optional[int] = None, every: int = 1,
                  progress: Optional[Callable[[int], None]] = None) -> Dict[str, Any]:
    """Plan every scenario (8-connected, no corner cutting) and compare lengths.

    A scenario whose start or goal is blocked or outside the map is planned
    like any other and counted by its status (``INVALID_START`` /
    ``INVALID_GOAL``) under ``invalid``, apart from the mismatches.
    ``progress(n)`` is called after each scenario with the number done (for a
    progress bar). Returns ``{"summary": ..., "rows": [...]}``, each row's ``index``
    its scenario's place in the file (from 0, with ``every``); the summary
    counts matches, mismatches, invalid rows and every status, and lists the
    five worst rows (failed first, then by distance from the optimum; for
    any-angle algorithms, by how far they exceed it).
    """
    scen_path = Path(scen_path)
    scenarios = read_scen(scen_path)[::every]
    if limit is not None:
        scenarios = scenarios[:limit]
    if not scenarios:
        raise MapFormatError(f"{scen_path}: no scenarios")
    grid = load_map(resolve_map(scen_path, scenarios[0], map_path))
    if (grid.width, grid.height) != (scenarios[0].width, scenarios[0].height):
        raise MapFormatError(f"{scen_path}: scenarios are for a {scenarios[0].width}x{scenarios[0].height} map, "
                             f"the map is {grid.width}x{grid.height}")
    any_angle = algorithm in ANY_ANGLE
    plan(grid, scenarios[0].start, scenarios[0].goal, algorithm=algorithm, heuristic=heuristic)  # warm up
    rows: List[Dict[str, Any]] = []
    for i, sc in enumerate(scenarios):
        r = plan(grid, sc.start, sc.goal, algorithm=algorithm, heuristic=heuristic)
        # the scenario's place in the file (--every K showed file scenario 10 as #1: newcomer, session 22)
        rows.append({"index": i * every, **compare(sc, r, any_angle)})
        if progress is not None:
            progress(i + 1)
    return {"summary": summarize(rows, grid.name, algorithm, heuristic), "rows": rows}


def summarize(rows: List[Dict[str, Any]], map_name: str, algorithm: str, heuristic: str) -> Dict[str, Any]:
    any_angle = algorithm in ANY_ANGLE
    invalid = [row for row in rows if row["status"].startswith("INVALID")]
    statuses: Dict[str, int] = {}
    for row in rows:
        statuses[row["status"]] = statuses.get(row["status"], 0) + 1
    times = np.array([row["time_s"] for row in rows])

    def badness(row):
        if row["excess"] is None:
            return math.inf
        return row["excess"] if any_angle else abs(row["excess"])

    ranked = sorted((row for row in rows if not row["status"].startswith("INVALID")), key=badness, reverse=True)
    summary = {
        # the heuristic searched with: Dijkstra, JPS and Theta* have their own (the setting is not used)
        "map": map_name, "scenarios": len(rows), "algorithm": algorithm,
        "heuristic": OWN_HEURISTIC.get(algorithm, heuristic),
        "comparison": "at most the octile optimum" if any_angle else "equal to the octile optimum",
        "matches": sum(row["match"] for row in rows),
        "mismatches": sum(not row["match"] for row in rows) - len(invalid),
        "invalid": len(invalid), "statuses": statuses,
        "worst": [{k: row[k] for k in ("index", "start", "goal", "optimal", "optimal_text", "length", "excess",
                                       "status", "match")}
                  for row in ranked[:WORST]],
        "time_median_ms": float(np.median(times) * 1000), "time_p95_ms": float(np.percentile(times, 95) * 1000),
        "time_total_s": float(times.sum()),
    }
    if any_angle:
        ratios = [row["length"] / row["optimal"] for row in rows if row["length"] is not None and row["optimal"] > 0]
        summary["length_over_optimal_median"] = float(np.median(ratios)) if ratios else None
    return summary
