"""Hybrid A*'s cost equals Dijkstra's on an obstacle-free lattice (issue 21).

Hybrid A* merges continuous poses per (cell, heading bin), so it is a graph
search over those states only where each state's successors do not depend on
which pose of the cell it holds. The form that is true:

- 4 heading bins, turning radius r = 7 cells, so every arc primitive is a
  quarter turn (k = 1: its chord r·√2 is at least √2 cells) that moves the
  car exactly 7 cells along its heading and 7 to the side;
- the straight primitive has the same length r·π/2 = 10.9956 cells, so it
  cannot land on a cell centre (π is irrational: no radius and cell size make
  both primitives close on the lattice). It lands 0.0044 cell short of 11; a
  path of n straights along one axis is n·0.0044 cell off the lattice point,
  so for n < 100 every pose stays in the cell of its lattice point and the
  successors of a state are the same for every pose it can hold;
- point robot on an obstacle-free map, analytic expansion and smoother off,
  change_penalty 0 (Hybrid A* does not keep the direction of arrival in the
  state, so a cost depending on it is not a graph cost).

Then Hybrid A* searches the graph of (cell, bin) with transitions straight
±11 cells and quarter arcs (±7, ±7) cells. Its heuristic (the larger of the
8-connected field and the Reeds–Shepp distance to the goal pose) overestimates
there only through the 0.0044-cell offsets: a straight is 0.0044 cell shorter
than the 11 orthogonal steps the field counts, and the end pose may be
0.0044·n cell beside the goal pose. Those overestimates, a fraction of a cell,
bound how much more than the optimum A* can return (consistent up to them);
every cost on this lattice is a multiple of 0.2·r·π/2 = 2.2 cells (penalties
1, 1.2, 2, 2.4), so the cost returned is the optimum exactly.

Only with Reeds–Shepp motion: the Reeds–Shepp distance is continuous, so a
pose a few thousandths of a cell off the goal pose is that little from it.
The Dubins distance is not: from a pose 0.0044 cell ahead of the goal pose a
forward-only car needs about a full loop (2πr), so with Dubins motion the
heuristic can overestimate by that much at the search's end poses and the
same query returns a dearer path (61.6 m against Dijkstra's 39.6 m for one
goal below). With analytic expansion off the search ends anywhere in the goal's
cell and bin while the heuristic measures to the goal pose itself; the
Reeds–Shepp form tolerates that, the Dubins form does not.

The reference is a plain Dijkstra over that graph with hand-derived moves
(below), with no map edge at all: the equality also shows the edge did not
matter. The queries end in cells reached by random sequences of primitives.
"""

import heapq
import math

import numpy as np
import pytest

from navlab.grid.hybrid_astar import plan_hybrid
from navlab.grid.occupancy import OccupancyGrid
from navlab.result import Status

RES = 1.0  # [m]
ARC = 7  # the turning radius in cells
SIZE = 160  # cells a side
START = (80, 80)  # cell


def moves(heading, non_straight=1.2, reverse=2.0):
    """(dx, dy, new heading, cost factor) of the six primitives at heading bin 0..3 (quarter turns).
    A left arc forward from heading e ends r along e and r to the left (e'), at e'; a right arc at e'' (the
    right); driving an arc backwards retraces it from its end: left backwards ends −r(e + e'') at e''."""
    unit = [(1, 0), (0, 1), (-1, 0), (0, -1)]
    e, left, right = unit[heading], unit[(heading + 1) % 4], unit[(heading - 1) % 4]
    straight = round(ARC * math.pi / 2)  # 11 cells (10.9956)
    return [
        (straight * e[0], straight * e[1], heading, 1.0),
        (ARC * (e[0] + left[0]), ARC * (e[1] + left[1]), (heading + 1) % 4, non_straight),
        (ARC * (e[0] + right[0]), ARC * (e[1] + right[1]), (heading - 1) % 4, non_straight),
        (-straight * e[0], -straight * e[1], heading, reverse),
        (-ARC * (e[0] + right[0]), -ARC * (e[1] + right[1]), (heading - 1) % 4, non_straight * reverse),
        (-ARC * (e[0] + left[0]), -ARC * (e[1] + left[1]), (heading + 1) % 4, non_straight * reverse),
    ]


def dijkstra(start, goal, length, reverse=True):
    """Least penalised cost [m] from state ``start`` to state ``goal`` (cell x, cell y, heading bin)."""
    dist = {start: 0.0}
    heap = [(0.0, start)]
    while heap:
        d, state = heapq.heappop(heap)
        if state == goal:
            return d
        if d > dist[state]:
            continue
        for dx, dy, h2, factor in moves(state[2]):
            if not reverse and factor >= 2.0:
                continue
            nxt = (state[0] + dx, state[1] + dy, h2)
            nd = d + length * factor
            if nd < dist.get(nxt, math.inf):
                dist[nxt] = nd
                heapq.heappush(heap, (nd, nxt))
    return math.inf


def random_goals(rng, count, reverse):
    goals = []
    while len(goals) < count:
        x, y, h = *START, 0
        for _ in range(rng.integers(2, 7)):
            choices = moves(h)[:6 if reverse else 3]
            dx, dy, h, _ = choices[rng.integers(len(choices))]
            x, y = x + dx, y + dy
        if 20 <= x < SIZE - 20 and 20 <= y < SIZE - 20 and (x, y, h) != (*START, 0):
            goals.append((x, y, h))
    return goals


def test_hybrid_astar_costs_what_dijkstra_costs_on_a_lattice_its_primitives_close_on():
    motion, reverse = "reeds_shepp", True
    radius = ARC * RES
    length = radius * math.pi / 2  # every primitive's length [m]
    assert abs(length / RES - round(length / RES)) * 99 < 0.5  # the offsets stay inside their cells
    grid = OccupancyGrid(np.zeros((SIZE, SIZE), bool), resolution=RES)
    centre = lambda cx, cy: ((cx + 0.5) * RES, (cy + 0.5) * RES)  # noqa: E731
    for goal in random_goals(np.random.default_rng(21), 10, reverse):
        result = plan_hybrid(grid, (*centre(*START), 0.0), (*centre(goal[0], goal[1]), goal[2] * math.pi / 2),
                             radius, motion=motion, heading_bins=4, change_penalty=0.0, analytic_expansion=False,
                             smooth=False)
        assert result.status == Status.EXACT
        expected = dijkstra((*START, 0), goal, length, reverse)
        assert result.stats["g"] == pytest.approx(expected, rel=1e-12), goal
        # the path ends in the goal's cell, a few thousandths of a cell from its centre
        assert np.hypot(*(np.array(result.path[-1, :2]) - centre(goal[0], goal[1]))) < 0.05 * RES


@pytest.mark.parametrize("weight", [1.25, 2.0, 5.0])
def test_a_weighted_search_costs_at_most_weight_times_dijkstra(weight):
    """Weighted A* (keys g + w·h) returns at most w times the optimum with a consistent heuristic (Pohl 1970;
    without re-expansions, Likhachev et al., ARA*, NIPS 2003); here the heuristic is consistent up to the
    0.0044-cell offsets above, a fraction of the 2.2-cell cost quantum. Never below the optimum, and on these
    queries the weight saves expansions overall."""
    radius = ARC * RES
    length = radius * math.pi / 2
    grid = OccupancyGrid(np.zeros((SIZE, SIZE), bool), resolution=RES)
    centre = lambda cx, cy: ((cx + 0.5) * RES, (cy + 0.5) * RES)  # noqa: E731
    plain = weighted = 0
    for goal in random_goals(np.random.default_rng(21), 10, True):
        common = dict(motion="reeds_shepp", heading_bins=4, change_penalty=0.0, analytic_expansion=False,
                      smooth=False)
        ends = ((*centre(*START), 0.0), (*centre(goal[0], goal[1]), goal[2] * math.pi / 2))
        result = plan_hybrid(grid, *ends, radius, weight=weight, **common)
        assert result.status == Status.EXACT
        expected = dijkstra((*START, 0), goal, length)
        assert expected * (1 - 1e-12) <= result.stats["g"] <= weight * expected + 0.1 * RES, goal
        weighted += result.stats["expansions"]
        plain += plan_hybrid(grid, *ends, radius, **common).stats["expansions"]
    assert weighted < plain
