"""Exact ray casting, compiled with numba.

Geometric worlds: analytic ray–circle (quadratic), ray–rectangle (slabs)
and ray–segment (for polygon edges) intersections. Occupancy grids: exact
cell traversal (Amanatides & Woo) in the grid's frame, returning the
distance at which the ray enters the first blocked cell.

References
----------
J. Amanatides, A. Woo, "A fast voxel traversal algorithm for ray tracing",
Eurographics 1987.
"""

from __future__ import annotations

import math

import numpy as np

from ..jit import njit

INF = np.inf


@njit(cache=True, inline="always")
def ray_circle(ox, oy, dx, dy, cx, cy, r):
    """Smallest t ≥ 0 with |o + t·d − c| = r (d a unit vector), else inf;
    0 when o is inside."""
    fx = ox - cx
    fy = oy - cy
    c = fx * fx + fy * fy - r * r
    if c <= 0.0:
        return 0.0
    b = fx * dx + fy * dy
    if b >= 0.0:
        return INF
    disc = b * b - c
    if disc < 0.0:
        return INF
    return -b - math.sqrt(disc)


@njit(cache=True, inline="always")
def _slab(o, d, lo, hi, t0, t1):
    """Clip the ray interval [t0, t1] to the slab lo ≤ o + t·d ≤ hi along
    one axis (an empty interval has t0 > t1)."""
    if d != 0.0:
        a = (lo - o) / d
        b = (hi - o) / d
        if a > b:
            a, b = b, a
        return max(t0, a), min(t1, b)
    if o < lo or o > hi:
        return 1.0, 0.0
    return t0, t1


@njit(cache=True, inline="always")
def ray_rect(ox, oy, dx, dy, xmin, ymin, xmax, ymax):
    """Entry distance of the ray into an axis-aligned box (slab method)."""
    t0, t1 = _slab(ox, dx, xmin, xmax, 0.0, INF)
    t0, t1 = _slab(oy, dy, ymin, ymax, t0, t1)
    return t0 if t0 <= t1 else INF


@njit(cache=True, inline="always")
def ray_segment(ox, oy, dx, dy, ax, ay, bx, by):
    """Distance along the ray to segment ab, inf if it misses."""
    ex = bx - ax
    ey = by - ay
    den = dx * ey - dy * ex
    if den == 0.0:
        return INF  # parallel: a grazing ray meets the neighbouring edges instead
    wx = ax - ox
    wy = ay - oy
    t = (wx * ey - wy * ex) / den
    u = (wx * dy - wy * dx) / den
    if t >= 0.0 and 0.0 <= u <= 1.0:
        return t
    return INF


@njit(cache=True)
def scan_shapes(pose, angles, range_max, circles, rects, verts, offsets, out):
    """Ranges of rays from ``pose`` at body-frame ``angles`` against
    un-inflated shapes; ``inf`` where nothing is hit within ``range_max``."""
    ox, oy, th = pose[0], pose[1], pose[2]
    nc = circles.shape[0]
    nr = rects.shape[0]
    npoly = offsets.shape[0] - 1
    # Cull per scan: shapes entirely beyond range_max are never hit.
    near_c = np.empty(nc, np.int64)
    k = 0
    for i in range(nc):
        if math.hypot(circles[i, 0] - ox, circles[i, 1] - oy) - circles[i, 2] <= range_max:
            near_c[k] = i
            k += 1
    for j in range(angles.shape[0]):
        a = th + angles[j]
        dx = math.cos(a)
        dy = math.sin(a)
        best = INF
        for m in range(k):
            i = near_c[m]
            t = ray_circle(ox, oy, dx, dy, circles[i, 0], circles[i, 1], circles[i, 2])
            if t < best:
                best = t
        for i in range(nr):
            t = ray_rect(ox, oy, dx, dy, rects[i, 0], rects[i, 1], rects[i, 2], rects[i, 3])
            if t < best:
                best = t
        for p in range(npoly):
            s = offsets[p]
            e = offsets[p + 1]
            for v in range(s, e):
                w = v + 1 if v + 1 < e else s
                t = ray_segment(ox, oy, dx, dy, verts[v, 0], verts[v, 1], verts[w, 0], verts[w, 1])
                if t < best:
                    best = t
        out[j] = best if best <= range_max else INF


@njit(cache=True)
def scan_grid(pose, angles, range_max, blocked, origin, resolution, out):
    """Ranges against an occupancy grid (``blocked[y, x]``; cells outside the
    grid are free). ``origin`` is (x, y, yaw) of the cell (0, 0) corner."""
    h, w = blocked.shape
    cy0 = math.cos(origin[2])
    sy0 = math.sin(origin[2])
    # the sensor in grid units (cells)
    rx = pose[0] - origin[0]
    ry = pose[1] - origin[1]
    gx = (cy0 * rx + sy0 * ry) / resolution
    gy = (-sy0 * rx + cy0 * ry) / resolution
    tmax_cells = range_max / resolution
    for j in range(angles.shape[0]):
        a = pose[2] + angles[j] - origin[2]
        dx = math.cos(a)
        dy = math.sin(a)
        ix = int(math.floor(gx))
        iy = int(math.floor(gy))
        step_x = 1 if dx > 0 else -1
        step_y = 1 if dy > 0 else -1
        t_dx = abs(1.0 / dx) if dx != 0.0 else INF
        t_dy = abs(1.0 / dy) if dy != 0.0 else INF
        if dx > 0:
            t_x = (ix + 1 - gx) * t_dx
        elif dx < 0:
            t_x = (gx - ix) * t_dx
        else:
            t_x = INF
        if dy > 0:
            t_y = (iy + 1 - gy) * t_dy
        elif dy < 0:
            t_y = (gy - iy) * t_dy
        else:
            t_y = INF
        t = 0.0
        hit = INF
        while t <= tmax_cells:
            if 0 <= ix < w and 0 <= iy < h:
                if blocked[iy, ix]:
                    hit = t
                    break
            elif (ix < 0 and step_x < 0) or (ix >= w and step_x > 0) or \
                    (iy < 0 and step_y < 0) or (iy >= h and step_y > 0):
                break  # left the grid for good
            if t_x < t_y:
                t = t_x
                t_x += t_dx
                ix += step_x
            else:
                t = t_y
                t_y += t_dy
                iy += step_y
        d = hit * resolution
        out[j] = d if d <= range_max else INF


@njit(cache=True)
def scan_points(pose, angles, ranges, out):
    """World points of finite readings (seed 004, eq. 18–19):
    X = x + d·cos(θn + θ), Y = y + d·sin(θn + θ). Returns how many."""
    n = 0
    for j in range(angles.shape[0]):
        d = ranges[j]
        if d > 0.0 and d < INF:
            a = pose[2] + angles[j]
            out[n, 0] = pose[0] + d * math.cos(a)
            out[n, 1] = pose[1] + d * math.sin(a)
            n += 1
    return n
