"""A* on a costmap, the way Nav2's grid planners weigh cost (Smac 2D, NavFn).

A cell's centre may be visited when its cost is below ``INSCRIBED`` (253):
lethal and inscribed cells are blocked, as in Nav2, and so are
``NO_INFORMATION`` cells unless ``allow_unknown``. Moves go to the eight
neighbours (a diagonal only when both cells beside it are passable, so the
path never cuts a blocked corner). A move of length ℓ (one or √2 cells) into
a cell of cost c costs

    ℓ · (1 + cost_travel_multiplier · c / 252)

so a path pays for the metres it spends near obstacles. Smac 2D adds
``cost_travel_multiplier · c / 252`` to each step (its default multiplier is
2.0); navlab scales that penalty by the step's length so a diagonal step is
not cheaper per metre than a straight one. The octile distance is a lower
bound of this cost (every factor is ≥ 1), so A* returns the cheapest path.

Search state belongs to the call (thread-safe).
"""

from __future__ import annotations

import math
from typing import Optional

import numpy as np
from ..errors import ParameterError
from ..jit import njit

SQRT2 = math.sqrt(2.0)
#: Nav2 Smac 2D's default
DEFAULT_COST_TRAVEL_MULTIPLIER = 2.0


@njit(cache=True, inline="always")
def _push(heap_f, heap_v, size, f, v):
    k = size
    while k > 0:
        p = (k - 1) >> 1
        if f < heap_f[p]:
            heap_f[k] = heap_f[p]
            heap_v[k] = heap_v[p]
            k = p
        else:
            break
    heap_f[k] = f
    heap_v[k] = v


@njit(cache=True, inline="always")
def _pop(heap_f, heap_v, size):
    top = heap_v[0]
    size -= 1
    f, v = heap_f[size], heap_v[size]
    k = 0
    while True:
        c = 2 * k + 1
        if c >= size:
            break
        if c + 1 < size and heap_f[c + 1] < heap_f[c]:
            c += 1
        if heap_f[c] < f:
            heap_f[k] = heap_f[c]
            heap_v[k] = heap_v[c]
            k = c
        else:
            break
    if size > 0:
        heap_f[k] = f
        heap_v[k] = v
    return top, size


@njit(cache=True, nogil=True)
def costmap_astar(costs, passable, start, goal, multiplier, parent):
    """Cheapest 8-connected path cost (in cells) from cell ``start`` to ``goal``
    (flat indices ``y·W + x``) over ``passable`` cells, filling ``parent``;
    inf when the goal cannot be reached. ``goal = -1`` searches the whole map
    (Dijkstra); then ``parent`` and the returned g array hold every cell's.
    Returns (cost, g, cells expanded)."""
    h, w = costs.shape
    n = h * w
    g = np.full(n, np.inf)
    closed = np.zeros(n, np.bool_)
    heap_f = np.empty(8 * n + 8)
    heap_v = np.empty(8 * n + 8, np.int64)
    gx, gy = (goal % w, goal // w) if goal >= 0 else (0, 0)
    g[start] = 0.0
    parent[start] = start
    size = 0
    _push(heap_f, heap_v, size, 0.0, start)
    size += 1
    expanded = 0
    while size > 0:
        v, size = _pop(heap_f, heap_v, size)
        if closed[v]:
            continue
        closed[v] = True
        expanded += 1
        if v == goal:
            return g[v], g, expanded
        vx, vy = v % w, v // w
        for dy in range(-1, 2):
            for dx in range(-1, 2):
                if dx == 0 and dy == 0:
                    continue
                nx, ny = vx + dx, vy + dy
                if nx < 0 or ny < 0 or nx >= w or ny >= h or not passable[ny, nx]:
                    continue
                if dx != 0 and dy != 0 and not (passable[vy, nx] and passable[ny, vx]):
                    continue
                u = ny * w + nx
                if closed[u]:
                    continue
                step = SQRT2 if dx != 0 and dy != 0 else 1.0
                cand = g[v] + step * (1.0 + multiplier * costs[ny, nx] / 252.0)
                if cand < g[u]:
                    g[u] = cand
                    parent[u] = v
                    hx, hy = abs(nx - gx), abs(ny - gy)
                    hval = (max(hx, hy) + (SQRT2 - 1.0) * min(hx, hy)) if goal >= 0 else 0.0
                    _push(heap_f, heap_v, size, cand + hval, u)
                    size += 1
    return np.inf, g, expanded


def plan_on_costmap(costmap, start_xy, goal_xy, cost_travel_multiplier: float = DEFAULT_COST_TRAVEL_MULTIPLIER,
                    allow_unknown: bool = False, stats: Optional[dict] = None):
    """The cheapest path over a :class:`~navlab.world.costmap.Costmap` between two points.

    Returns
    -------
    path : (N, 2) array or None
        Cell centres [m] from the start's cell to the goal's, the start and goal
        points themselves at the ends; None when no path exists.
    cost : float
        The path's cost in metres (each metre weighted by its cells' costs).
    reason : str
        Why there is no path ('' when there is one).

    ``stats``, if given, receives ``expanded``: the cells the search expanded
    (0 when it did not run: an end outside the costmap or on a blocked cell).
    """
    from ..world.costmap import INSCRIBED_INFLATED_OBSTACLE, NO_INFORMATION

    if not (math.isfinite(cost_travel_multiplier) and cost_travel_multiplier >= 0):
        raise ParameterError(f"cost_travel_multiplier must be ≥ 0, got {cost_travel_multiplier!r}")
    costs = costmap.costs
    h, w = costs.shape
    passable = costs < INSCRIBED_INFLATED_OBSTACLE
    if allow_unknown:
        passable = passable | (costs == NO_INFORMATION)
    work = np.where(costs == NO_INFORMATION, 0, costs).astype(np.float64)
    cells = costmap.world_to_cell(np.array([start_xy[:2], goal_xy[:2]], float))
    for label, (cx, cy) in zip(("start", "goal"), cells):
        if not (0 <= cx < w and 0 <= cy < h):
            return None, math.inf, f"the {label} is outside the costmap"
        if not passable[cy, cx]:
            return None, math.inf, (f"the {label} is on a cell of cost {costs[cy, cx]} (lethal, inscribed or "
                                    "unknown): the robot's body would touch an obstacle there")
    start, goal = int(cells[0, 1] * w + cells[0, 0]), int(cells[1, 1] * w + cells[1, 0])
    parent = np.full(h * w, -1, np.int64)
    total, _, expanded = costmap_astar(work, passable, start, goal, float(cost_travel_multiplier), parent)
    if stats is not None:
        stats["expanded"] = int(expanded)
    if not math.isfinite(total):
        unknown = 0 if allow_unknown else int(np.count_nonzero(costs == NO_INFORMATION))
        closed = f"; the costmap's {unknown} unknown cells were closed to it: allow_unknown=true opens them" \
            if unknown else ""
        return None, math.inf, "no path through cells below INSCRIBED cost" + closed
    chain = [goal]
    while chain[-1] != start:
        chain.append(int(parent[chain[-1]]))
    flat = np.array(chain[::-1])
    centres = costmap.cell_to_world(np.column_stack((flat % w, flat // w)))
    path = np.vstack([np.asarray(start_xy[:2], float), centres[1:-1], np.asarray(goal_xy[:2], float)]) \
        if len(centres) > 2 else np.array([start_xy[:2], goal_xy[:2]], float)
    if len(path) == 2 and np.array_equal(path[0], path[1]):  # start == goal: one point, no zero-length leg
        path = path[:1]
    return path, total * costmap.resolution, ""


def plan_poses_on_costmap(costmap, footprint, start_pose, goal_pose, turning_radius: float,
                          allow_unknown: bool = False, max_expansions: int = 200_000):
    """A forward path of poses for the footprint itself on a costmap (Hybrid A*, Dubins motion).

    Where the costmap A* path (planned for the centre, its cells below
    ``INSCRIBED``) leads a rectangle into a gap its inscribed disc fits and its
    corners do not at the path's heading, the footprint needs a path planned
    between poses: :func:`~navlab.grid.hybrid_astar.plan_hybrid` on the
    costmap's ``LETHAL`` cells (and ``NO_INFORMATION`` ones unless
    ``allow_unknown``), forward only (a Dubins car with a small
    ``turning_radius``: a differential drive can follow any such curve), its
    footprint certified clear of every blocked cell along the way.

    Parameters
    ----------
    costmap : Costmap
    footprint : Footprint
    start_pose, goal_pose : (x, y, θ)
        [m, m, rad].
    turning_radius : float
        [m] the tightest curve of the path.
    allow_unknown : bool
        Treat unknown cells as free.
    max_expansions : int
        Hybrid A*'s search budget.

    Returns
    -------
    Result
        Hybrid A*'s: ``path`` (N, 3) poses, ``status`` and ``reason``.
    """
    from ..world.costmap import LETHAL_OBSTACLE
    from .hybrid_astar import plan_hybrid
    from .occupancy import OccupancyGrid

    costs = costmap.costs
    blocked = (costs == LETHAL_OBSTACLE) if allow_unknown else (costs >= LETHAL_OBSTACLE)
    grid = OccupancyGrid(blocked, costmap.resolution, (costmap.origin[0], costmap.origin[1], 0.0))
    return plan_hybrid(grid, tuple(float(v) for v in start_pose[:3]), tuple(float(v) for v in goal_pose[:3]),
                       turning_radius, "dubins", footprint=footprint, max_expansions=max_expansions)
