"""move_base's default global planner, ROS 1 ``navfn`` (``NavfnROS``), as the BARN challenge runs it.

navfn spreads a navigation function (a potential) over the costmap from the
robot's cell until it reaches the goal's, then descends its gradient from
the goal back to the robot (``navfn.cpp``):

1. **Costs** (``NavFn::setCostmap``): a cell of cost c < ``INSCRIBED`` (253)
   costs ``COST_NEUTRAL + COST_FACTOR · c`` = 50 + 0.8 · c; ``INSCRIBED``,
   ``LETHAL`` (and unknown, unless ``allow_unknown``, then 253) are walls
   (``COST_OBS`` 254), and so is the map's outer ring of cells. The robot's
   own cell is cleared first (``clearRobotCell``).
2. **Potential** (``propNavFnDijkstra``): a Dijkstra-like wave over the 4
   neighbours, in priority bands (``curT`` from 254 in steps of
   ``2 · COST_NEUTRAL``); a cell's potential comes from its lowest
   horizontal and vertical neighbours by navfn's quadratic interpolation
   (``updateCell``: ``ta + hf`` when they differ by ``hf`` or more, else
   ``ta + hf · (−0.2301 d² + 0.5307 d + 0.7040)``, ``d = Δ/hf``), which makes
   it close to the cost-weighted Euclidean distance rather than a grid
   distance. The wave stops once the goal's cell has a potential.
3. **Path** (``calcPath``): from the goal, steps of half a cell along the
   bilinearly interpolated normalised gradient (``gradCell``); next to
   unreached cells, or when the path oscillates, a step to the lowest of
   the 8 neighbours instead; done within ``COST_NEUTRAL`` of the robot.
   ``NavfnROS::mapToWorld`` turns cell coordinates into metres with no half
   cell added (``origin + c · resolution``: a whole cell index is the cell's
   corner; global_planner's ``convert_offset`` 0.5 is not navfn's), runs the
   path robot → goal and appends the goal itself.

References
----------
ROS 1 navigation, ``navfn/src/navfn.cpp`` and ``navfn_ros.cpp`` (Brian
Gerkey, Kurt Konolige); K. Konolige, "A Gradient Method for Realtime Robot
Control", IROS 2000.
"""

from __future__ import annotations

import math
from typing import Optional

import numpy as np

from ..jit import njit
from ..world.costmap import INSCRIBED_INFLATED_OBSTACLE, NO_INFORMATION

#: navfn.h: a free cell's cost, the cost per unit of costmap cost, a wall, and an unassigned potential
COST_NEUTRAL, COST_FACTOR, COST_OBS, POT_HIGH = 50, 0.8, 254, 1.0e10
#: navfn.h: the size of each of the three priority buffers (cells beyond it are dropped, as in navfn)
PRIORITYBUFSIZE = 10000
#: [cells] calcPath's step along the gradient
PATH_STEP = 0.5
INVSQRT2 = 0.707106781


def navfn_costs(costs: np.ndarray, allow_unknown: bool) -> np.ndarray:
    """(H+2, W+2) uint8 navfn costs of a costmap (``setCostmap``, ROS costs), with navfn's outer ring of
    walls as one extra cell round the map (navfn walls off its map's border cells; the challenge's 40 m
    global costmap has its border far from the course, navlab's ends at the world's edge)."""
    out = np.full((costs.shape[0] + 2, costs.shape[1] + 2), COST_OBS, np.uint8)
    inner = np.full(costs.shape, COST_OBS, np.int64)
    free = costs < INSCRIBED_INFLATED_OBSTACLE
    inner[free] = np.minimum((COST_NEUTRAL + COST_FACTOR * costs[free]).astype(np.int64), COST_OBS - 1)
    if allow_unknown:
        inner[costs == NO_INFORMATION] = COST_OBS - 1
    out[1:-1, 1:-1] = inner
    return out


@njit(cache=True)
def _push(buf, size, pending, costarr, n):
    if 0 <= n < costarr.size and not pending[n] and costarr[n] < COST_OBS and size < PRIORITYBUFSIZE:
        buf[size] = n
        pending[n] = True
        size += 1
    return size


@njit(cache=True)
def _push_neighbours(buf, size, pending, costarr, n, nx, p32, l, r, u, d, le, re, ue, de):
    """navfn's updateCell tail: each neighbour whose potential the new value ``p32`` plus its edge
    would lower goes on ``buf`` (left, right, up, down, in navfn's order)."""
    if l > p32 + le:
        size = _push(buf, size, pending, costarr, n - 1)
    if r > p32 + re:
        size = _push(buf, size, pending, costarr, n + 1)
    if u > p32 + ue:
        size = _push(buf, size, pending, costarr, n - nx)
    if d > p32 + de:
        size = _push(buf, size, pending, costarr, n + nx)
    return size


@njit(cache=True)
def navfn_potential(costarr, nx, robot, goal, cycles):
    """navfn's potential (flat float32 array) spread from cell ``robot`` (0) over the flat costs
    ``costarr`` (row length ``nx``) until cell ``goal`` is reached or ``cycles`` bands are spent
    (``setupNavFn`` + ``propNavFnDijkstra``, atStart)."""
    ns = costarr.size
    pot = np.full(ns, np.float32(POT_HIGH), np.float32)
    pending = np.zeros(ns, np.bool_)
    cur = np.empty(PRIORITYBUFSIZE, np.int64)
    nxt = np.empty(PRIORITYBUFSIZE, np.int64)
    over = np.empty(PRIORITYBUFSIZE, np.int64)
    cur_n, nxt_n, over_n = 0, 0, 0
    cur_t = float(COST_OBS)
    pri_inc = 2.0 * COST_NEUTRAL
    pot[robot] = 0.0  # initCost
    for n in (robot + 1, robot - 1, robot - nx, robot + nx):
        cur_n = _push(cur, cur_n, pending, costarr, n)
    for _ in range(cycles):
        if cur_n == 0 and nxt_n == 0:
            break
        for i in range(cur_n):
            pending[cur[i]] = False
        for i in range(cur_n):
            n = cur[i]
            # updateCell: the lowest neighbour on each axis, navfn's interpolation between them
            l, r, u, d = pot[n - 1], pot[n + 1], pot[n - nx], pot[n + nx]
            tc = l if l < r else r
            ta = u if u < d else d
            if costarr[n] >= COST_OBS:
                continue
            hf = float(costarr[n])
            dc = tc - ta
            if dc < 0:
                dc, ta = -dc, tc
            if dc >= hf:
                p = ta + hf
            else:
                q = dc / hf
                p = ta + hf * (-0.2301 * q * q + 0.5307 * q + 0.7040)
            p32 = np.float32(p)
            if p32 < pot[n]:
                le, re = INVSQRT2 * costarr[n - 1], INVSQRT2 * costarr[n + 1]
                ue, de = INVSQRT2 * costarr[n - nx], INVSQRT2 * costarr[n + nx]
                pot[n] = p32
                # below the band's threshold the neighbours go on the next list, else on the overflow
                if p32 < cur_t:
                    nxt_n = _push_neighbours(nxt, nxt_n, pending, costarr, n, nx, p32, l, r, u, d, le, re, ue, de)
                else:
                    over_n = _push_neighbours(over, over_n, pending, costarr, n, nx, p32, l, r, u, d, le, re, ue, de)
        cur, nxt = nxt, cur
        cur_n, nxt_n = nxt_n, 0
        if cur_n == 0:  # this band is done: the overflow is next
            cur_t += pri_inc
            cur, over = over, cur
            cur_n, over_n = over_n, 0
        if pot[goal] < POT_HIGH:
            break
    return pot


@njit(cache=True)
def _grad(pot, gx, gy, nx, n):
    """gradCell: the normalised gradient at cell ``n`` (cached in gx, gy as navfn does)."""
    if gx[n] + gy[n] > 0.0:
        return
    if n < nx or n > pot.size - nx:
        return
    cv = pot[n]
    dx, dy = 0.0, 0.0
    if cv >= POT_HIGH:
        if pot[n - 1] < POT_HIGH:
            dx = -float(COST_OBS)
        elif pot[n + 1] < POT_HIGH:
            dx = float(COST_OBS)
        if pot[n - nx] < POT_HIGH:
            dy = -float(COST_OBS)
        elif pot[n + nx] < POT_HIGH:
            dy = float(COST_OBS)
    else:
        if pot[n - 1] < POT_HIGH:
            dx += pot[n - 1] - cv
        if pot[n + 1] < POT_HIGH:
            dx += cv - pot[n + 1]
        if pot[n - nx] < POT_HIGH:
            dy += pot[n - nx] - cv
        if pot[n + nx] < POT_HIGH:
            dy += cv - pot[n + nx]
    norm = math.hypot(dx, dy)
    if norm > 0:
        gx[n] = np.float32(dx / norm)
        gy[n] = np.float32(dy / norm)


@njit(cache=True)
def navfn_path(pot, nx, start, robot, max_steps):
    """(N, 2) float cell coordinates (x, y) from cell ``start`` down the potential to cell ``robot``
    (``calcPath``); an empty array when it fails."""
    ns = pot.size
    gx = np.zeros(ns, np.float32)
    gy = np.zeros(ns, np.float32)
    px = np.empty(max_steps + 1)
    py = np.empty(max_steps + 1)
    npath = 0
    stc = start
    dx, dy = 0.0, 0.0
    for _ in range(max_steps):
        nearest = max(0, min(ns - 1, stc + int(round(dx)) + nx * int(round(dy))))
        if pot[nearest] < COST_NEUTRAL:
            px[npath], py[npath] = robot % nx, robot // nx
            return np.column_stack((px[:npath + 1], py[:npath + 1]))
        if stc < nx or stc > ns - nx:
            break
        px[npath], py[npath] = stc % nx + dx, stc // nx + dy
        npath += 1
        oscillating = npath > 2 and px[npath - 1] == px[npath - 3] and py[npath - 1] == py[npath - 3]
        up, down = stc + nx, stc - nx
        if (pot[stc] >= POT_HIGH or pot[stc + 1] >= POT_HIGH or pot[stc - 1] >= POT_HIGH
                or pot[up] >= POT_HIGH or pot[up + 1] >= POT_HIGH or pot[up - 1] >= POT_HIGH
                or pot[down] >= POT_HIGH or pot[down + 1] >= POT_HIGH or pot[down - 1] >= POT_HIGH
                or oscillating):
            # follow the grid: the lowest of the 8 neighbours (navfn keeps the potential as an int here)
            minc = stc
            minp = int(pot[stc])
            for sti in (down - 1, down, down + 1, stc - 1, stc + 1, up - 1, up, up + 1):
                if pot[sti] < minp:
                    minp = int(pot[sti])
                    minc = sti
            stc = minc
            dx, dy = 0.0, 0.0
            if pot[stc] >= POT_HIGH:
                break
        else:
            _grad(pot, gx, gy, nx, stc)
            _grad(pot, gx, gy, nx, stc + 1)
            _grad(pot, gx, gy, nx, up)
            _grad(pot, gx, gy, nx, up + 1)
            x1 = (1.0 - dx) * gx[stc] + dx * gx[stc + 1]
            x2 = (1.0 - dx) * gx[up] + dx * gx[up + 1]
            x = (1.0 - dy) * x1 + dy * x2
            y1 = (1.0 - dx) * gy[stc] + dx * gy[stc + 1]
            y2 = (1.0 - dx) * gy[up] + dx * gy[up + 1]
            y = (1.0 - dy) * y1 + dy * y2
            if x == 0.0 and y == 0.0:
                break
            ss = PATH_STEP / math.hypot(x, y)
            dx += x * ss
            dy += y * ss
            if dx > 1.0:
                stc += 1
                dx -= 1.0
            if dx < -1.0:
                stc -= 1
                dx += 1.0
            if dy > 1.0:
                stc += nx
                dy -= 1.0
            if dy < -1.0:
                stc -= nx
                dy += 1.0
    return np.zeros((0, 2))


def plan_navfn(costmap, start_xy, goal_xy, allow_unknown: bool = True) -> Optional[np.ndarray]:
    """NavfnROS::makePlan on a :class:`~navlab.world.costmap.Costmap` (default_tolerance 0): (N, 2)
    points [m] from the robot to the goal, the goal itself last; None when navfn finds no path."""
    costs = navfn_costs(costmap.costs, allow_unknown)
    ny, nx = costs.shape
    cells = costmap.world_to_cell(np.array([start_xy[:2], goal_xy[:2]], float)) + 1  # the ring of walls
    h, w = costmap.costs.shape
    if not all(1 <= cx <= w and 1 <= cy <= h for cx, cy in cells):
        return None
    robot, goal = (int(cy * nx + cx) for cx, cy in cells)
    costs[cells[0, 1], cells[0, 0]] = COST_NEUTRAL  # clearRobotCell: FREE_SPACE, i.e. navfn's 50
    flat = costs.ravel().astype(np.int64)
    pot = navfn_potential(flat, nx, robot, goal, max(nx * ny // 20, nx + ny))
    if not pot[goal] < POT_HIGH:
        return None
    cells_path = navfn_path(pot, nx, goal, robot, 4 * max(nx, ny))
    if not len(cells_path):
        return None
    # the path runs goal → robot: NavfnROS reverses it, maps it with no half-cell offset, appends the goal
    world = np.asarray(costmap.origin) + (cells_path[::-1] - 1) * costmap.resolution
    return np.vstack((world, np.asarray(goal_xy[:2], float)))
