"""Microseconds per Reeds–Shepp length solve: the full solver (every word, segments kept) against the
length-only branch and bound (:mod:`navlab.sampling.reeds_shepp_length`), and Dubins for scale.

Pose pairs are uniform in a square of side ``2 span`` (in turning radii) with uniform headings; small
spans are the near-neighbour queries of a tree in a narrow aisle, large ones the Hybrid A* heuristic
far from the goal. Each round times every solver once on the same pairs, in turn (interleaved, so a
change of load hits them alike); the table shows medians over rounds and the median of the per-round
ratios full / length-only.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from conditions import load_line, spread
from navlab.sampling import dubins, reeds_shepp, reeds_shepp_length

SOLVERS = {"reeds_shepp.distances": reeds_shepp.distances,
           "reeds_shepp_length.lengths": reeds_shepp_length.lengths,
           "dubins.distances": dubins.distances}


def pairs(n: int, span: float, seed: int):
    rng = np.random.default_rng(seed)
    a = np.column_stack([rng.uniform(-span, span, (n, 2)), rng.uniform(-np.pi, np.pi, n)])
    b = np.column_stack([rng.uniform(-span, span, (n, 2)), rng.uniform(-np.pi, np.pi, n)])
    return a, b


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pairs", type=int, default=100_000)
    ap.add_argument("--rounds", type=int, default=9)
    ap.add_argument("--spans", default="0.5,2,10", help="half-sides of the square, in turning radii")
    args = ap.parse_args()
    print(load_line("at start"))
    print(f"{args.pairs} pairs per round, {args.rounds} rounds, turning radius 1")
    print(f"{'span':>6s} {'solver':28s} {'us/solve':>9s} {'spread':>16s} {'full/length-only':>17s}")
    for span in map(float, args.spans.split(",")):
        a, b = pairs(args.pairs, span, seed=0)
        for f in SOLVERS.values():
            f(a[:2], b[:2], 1.0)  # compile or load outside the clock
        times = {name: [] for name in SOLVERS}
        for _ in range(args.rounds):
            for name, f in SOLVERS.items():
                t = time.perf_counter()
                f(a, b, 1.0)
                times[name].append((time.perf_counter() - t) / args.pairs * 1e6)
        ratio = statistics.median(o / n for o, n in zip(times["reeds_shepp.distances"],
                                                        times["reeds_shepp_length.lengths"]))
        for name, ts in times.items():
            extra = f"{ratio:16.2f}x" if name == "reeds_shepp_length.lengths" else ""
            print(f"{span:6.1f} {name:28s} {statistics.median(ts):9.3f} {spread(ts, 3):>16s} {extra}")
    print(load_line("at end"))


if __name__ == "__main__":
    main()
