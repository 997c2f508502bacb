"""The BARN suite's report: the challenge's five means per navigator beside the
published move_base DWA baseline, and a per-world figure."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Dict, List

from ..atomic import write_text_atomic


def disclaimer(lidar: str = "exact") -> str:
    """What every BARN report says first (its sensors as the study ran them)."""
    sensors = ("a noise-free LiDAR at the robot's centre, no wheel slip" if lidar == "exact" else
               "a noisy LiDAR at the robot's centre, 2 % wheel-speed noise and 1 % slip (--lidar rplidar_a1)")
    return ("navlab's BARN runs are a 2D kinematic simulation: the Jackal's exact rectangular footprint moving "
            f"along exact arcs among the worlds' cylinders, {sensors}; no inertia beyond the acceleration limits, "
            "no ROS timing. The published move_base figures come from Gazebo's physics with ROS in the loop; they "
            "are the field's reference, not a like-for-like measurement.")


def _fmt(value: Any, digits: int = 3) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "–"
    return f"{value:.{digits}f}" if isinstance(value, float) else str(value)


def means_table(summary: Dict[str, Any]) -> List[str]:
    lines = ["| navigator | worlds | runs | success | collision | timeout | time [s] | score |",
             "|---|---|---|---|---|---|---|---|"]
    rows = [(label, nav["means"]) for label, nav in summary["navigators"].items()]
    published = summary.get("published")
    if published:
        rows.append(("move_base DWA, Gazebo (published, same worlds)", published["means"]))
    for label, m in rows:
        if not m:
            lines.append(f"| {label} | – | 0 | – | – | – | – | – |")
            continue
        lines.append(f"| {label} | {m['worlds']} | {m['runs']} | {_fmt(m['success'])} | {_fmt(m['collision'])} | "
                     f"{_fmt(m['timeout'])} | {_fmt(m['time'], 2)} | {_fmt(m['score'])} |")
    return lines


def _laser(study) -> str:
    if study.lidar == "rplidar_a1":
        return ("rplidar_a1 (a noisy laser, 2 % wheel-speed noise, 1 % slip: the runs of a world differ by "
                "their seed, as the challenge's Gazebo runs do)")
    return "exact (every run of a world sees the same scans: runs differ only by a controller's own sampling)"


def write_barn_report(study, rows: List[Dict[str, Any]], summary: Dict[str, Any], folder: Path,
                      plots: bool = True) -> None:
    lines = [f"# BARN: {len(study.worlds)} worlds × {len(study.navigators)} navigator(s) × {study.runs} run(s)", "",
             disclaimer(study.lidar), "",
             "Protocol (the-barn-challenge's run.py): start (−2, 3) facing +y, goal (−2, 13); success within 1 m of "
             "the goal with no collision within 100 s of the robot's first 0.1 m; score = 1[success] · OT / "
             "clip(AT, 2·OT, 8·OT), OT the reference path (start, path file, goal) at 2 m/s, so at most 0.5. "
             "Means per world first, then over worlds (the challenge's report_test.py); time over succeeded runs.",
             "", f"Laser: {_laser(study)}.", "", *means_table(summary), ""]
    if summary.get("published"):
        lines.append(f"Published baseline: {summary['published']['file']}, the {len(summary['published']['worlds'])}"
                     " of its worlds in this study, 10 runs each, scores recomputed with the formula above.")
    errors = [r for r in rows if r["status"] == "ERROR"]
    if errors:
        lines += ["", f"{len(errors)} run(s) ended in an internal error (first: {errors[0]['reason']})."]
    failed = [r for r in rows if r["status"] in ("collided", "timeout")]
    if failed:
        lines += ["", "## Runs that did not succeed", "", "| navigator | world | status | why |", "|---|---|---|---|"]
        for r in failed[:60]:
            lines.append(f"| {r['label']} | {r['world']} | {r['status']} | {str(r.get('reason', ''))[:160]} |")
        if len(failed) > 60:
            lines.append(f"| … | | | {len(failed) - 60} more in results.jsonl |")
    if plots and rows:
        name = _plot(study, summary, folder)
        lines += ["", f"![score per world]({name})"]
    write_text_atomic(folder / "report.md", "\n".join(lines) + "\n")


def _plot(study, summary: Dict[str, Any], folder: Path) -> str:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_s, ax_c) = plt.subplots(2, 1, figsize=(max(6.0, 0.12 * len(study.worlds) + 3), 6.0), sharex=True)
    for label, nav in summary["navigators"].items():
        worlds = sorted(nav["per_world"])
        ax_s.plot(worlds, [nav["per_world"][w]["score"] for w in worlds], "o-", ms=3, lw=0.8, label=label)
        ax_c.plot(worlds, [nav["per_world"][w]["success"] for w in worlds], "o-", ms=3, lw=0.8, label=label)
    published = summary.get("published")
    if published:
        for ax, key in ((ax_s, "score"), (ax_c, "success")):
            ax.axhline(published["means"][key], color="k", ls="--", lw=1,
                       label=f"move_base DWA (published) mean {key}")
    ax_s.axhline(0.5, color="0.6", lw=0.6)
    ax_s.set_ylabel("mean score")
    ax_c.set_ylabel("success rate")
    ax_c.set_xlabel("BARN world")
    ax_s.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax_s.set_title("BARN, per world (2D kinematic simulation)")
    name = "barn_per_world.png"
    (folder / "plots").mkdir(exist_ok=True)
    # the figure grows to hold the legend beside the axes, however long a navigator's label (tight_layout
    # could not make room for a long one and printed a UserWarning: newcomer, session 23)
    fig.savefig(folder / "plots" / name, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return f"plots/{name}"
