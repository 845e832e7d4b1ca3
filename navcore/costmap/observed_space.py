"""Observed space: a short-term memory of the cells the robot's sensors saw free or occupied, and
when, kept apart from the costmaps (a costmap clear does not erase it).

A motion that reverses into the laser's blind sector drives into space nobody looked at: right
after a clear the costmap says "free" for cells that only mean "forgotten". This grid answers the
other question, "was this cell *seen* free within the last T seconds?". Each laser beam stamps
the time on every cell it crosses (free) and on the cell it ends in (occupied); every cycle the
cells under the robot's padded footprint are stamped free and forget any occupied stamp, as the
costmaps' footprint clearing frees them (the body is there; range noise near it is not an
obstacle). A cell is observed free when its newest stamp is a free one no older than T (a beam
that ended in it in the same scan wins: occupied). Cells no beam reached (behind a 240-degree
laser, say) stay unknown.

The grid is a rolling window around the robot on the world lattice, so it keeps what it saw
while the robot moves inside it. The ray walk visits the cells costmap_2d's does
(``raytrace_line``, the obstacle layer's clearing walk; walked here on the flat store, two beams
at a time), clipped to the window with ``navcore.raycast``'s slab clip; the body is
freed with costmap_2d's convex fill (``Costmap2D.set_convex_polygon_cost``'s kernel); how much of
a cell a motion's footprint covers outside where the robot stands is exact polygon clipping.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from navcore.costmap.costmap2d import _fill_convex_cells
from navcore.costmap.footprint import _place, _square_meets_polygon, parse_footprint
from navcore.raycast import _clip_to_grid
from navcore.types import LaserScan, Pose2D

NEVER = -np.inf  # the stamp of a cell never observed


@njit(cache=True, nogil=True, inline="always")
def _walk_on(flat: np.ndarray, i: int, e: int, steps: int, major_step: int, minor_step: int,
             major: int, minor: int, value: float) -> None:
    """``raytrace_line``'s walk on a flattened C-contiguous grid: ``steps`` more cells from
    index ``i``, ``major_step`` apart plus ``minor_step`` whenever the error term overflows,
    then the last cell. ``e`` is raytrace_line's error term less ``major``, so it overflows
    when it turns non-negative: the sign bit makes the step without a branch (a branch that
    goes either way by the line's slope is often mispredicted; docs/performance.md)."""
    for _ in range(steps):
        flat[np.uint64(i)] = value  # unsigned: no negative-index test per cell
        i += major_step
        e += minor
        over = ~(e >> 63)  # all ones when e >= 0, else 0
        i += minor_step & over
        e -= major & over
    flat[np.uint64(i)] = value


@njit(cache=True, nogil=True, inline="always")
def _walk_two(flat: np.ndarray, i: int, a: np.ndarray, b: np.ndarray, value: float) -> None:
    """``raytrace_line``'s walks ``a`` and ``b`` (major step, minor step, major, minor) from
    index ``i``, each error term starting at ``major // 2`` (less ``major``, as ``_walk_on``
    counts it), in lockstep while both last: two independent chains keep the core busy."""
    ia = ib = i
    ea = a[2] // 2 - a[2]
    eb = b[2] // 2 - b[2]
    both = min(a[2], b[2])
    for _ in range(both):
        flat[np.uint64(ia)] = value
        flat[np.uint64(ib)] = value
        ia += a[0]
        ib += b[0]
        ea += a[3]
        eb += b[3]
        over_a = ~(ea >> 63)
        over_b = ~(eb >> 63)
        ia += a[1] & over_a
        ib += b[1] & over_b
        ea -= a[2] & over_a
        eb -= b[2] & over_b
    _walk_on(flat, ia, ea, a[2] - both, a[0], a[1], a[2], a[3], value)
    _walk_on(flat, ib, eb, b[2] - both, b[0], b[1], b[2], b[3], value)


@njit(cache=True, nogil=True)
def _stamp(free: np.ndarray, occupied: np.ndarray, start: int, w: int, h: int, gx: float,
           gy: float, angles: np.ndarray, ranges: np.ndarray, range_min: float,
           range_max: float, resolution: float, now: float) -> int:
    """``stamp_scan`` on grids stored flat: the h x w grid starts at index ``start`` of ``free``
    and ``occupied``; the laser at (gx, gy) cells lies on the grid.

    Each beam is ``raytrace_line`` from the laser's cell to its end cell; as both lie on the
    grid, the ray is shorter than its ``max_length`` (w + h) and every cell it visits is on the
    grid, so the walk needs neither the length scale nor a bounds test. Every stamp is ``now``,
    so the order the cells are written in does not matter: the beams are walked two at a time.
    A beam no longer than the laser's distance to the nearest edge of the grid (``near``) is
    not clipped: the slab clip would give (0, t_end), as each exit parameter is a distance to
    an edge divided by |cos| or |sin| <= 1, which rounds to no less than that distance."""
    x0 = int(gx)
    y0 = int(gy)
    walks = np.empty((angles.shape[0], 4), dtype=np.int64)
    m = 0
    near = min(gx, w - gx, gy, h - gy)
    for k in range(angles.shape[0]):
        r = float(ranges[k])
        if not r >= range_min:  # NaN too
            continue
        hit = r < range_max
        length = r if hit else range_max
        dx = math.cos(angles[k])
        dy = math.sin(angles[k])
        t_end = length / resolution
        if t_end <= near and dx == dx:  # not NaN: a finite angle
            t0, t1 = 0.0, t_end
        else:
            t0, t1 = _clip_to_grid(gx, gy, dx, dy, w, h, t_end)
        if t0 > t1:
            continue
        inside = hit and t1 >= t_end  # the end point lies in the grid
        # a range is where the beam enters the obstacle's cell: a hair further is inside it
        t = t_end + 1e-6 if inside else t1 - 1e-9
        x1 = min(max(int(math.floor(gx + t * dx)), 0), w - 1)
        y1 = min(max(int(math.floor(gy + t * dy)), 0), h - 1)
        if inside:
            occupied[start + y1 * w + x1] = now
        adx = abs(x1 - x0)
        ady = abs(y1 - y0)
        sx = 1 if x1 > x0 else (-1 if x1 < x0 else 0)
        sy = w if y1 > y0 else (-w if y1 < y0 else 0)
        if adx >= ady:
            walks[m, 0], walks[m, 1], walks[m, 2], walks[m, 3] = sx, sy, adx, ady
        else:
            walks[m, 0], walks[m, 1], walks[m, 2], walks[m, 3] = sy, sx, ady, adx
        m += 1
    i = start + y0 * w + x0
    for k in range(0, m, 2):  # an odd last beam goes with itself (the same cells twice)
        _walk_two(free, i, walks[k], walks[min(k + 1, m - 1)], now)
    return m


@njit(cache=True, nogil=True)
def stamp_scan(free: np.ndarray, occupied: np.ndarray, origin_x: float, origin_y: float,
               resolution: float, ox: float, oy: float, angles: np.ndarray, ranges: np.ndarray,
               range_min: float, range_max: float, now: float) -> int:
    """Stamp ``now`` on the cells each beam from the laser at (ox, oy) crosses (``free``) and on
    the cell a beam ends in when it hit something inside the grid (``occupied``); both grids
    C-contiguous.

    ``angles`` are world beam angles. A NaN reading or one below ``range_min`` is skipped; inf or
    at least ``range_max`` means nothing within ``range_max``: the beam clears that far. Rays are
    clipped to the grid and walked as ``raytrace_line`` walks them (the obstacle layer's
    clearing). Returns the beams used (0 when the laser is off the grid)."""
    h, w = free.shape
    gx = (ox - origin_x) / resolution
    gy = (oy - origin_y) / resolution
    if not (0.0 <= gx < w and 0.0 <= gy < h):
        return 0
    return _stamp(free.reshape(h * w), occupied.reshape(h * w), 0, w, h, gx, gy, angles, ranges,
                  range_min, range_max, resolution, now)


@njit(cache=True, nogil=True)
def fan_angles(angle_min: float, increment: float, theta: float, n: int) -> np.ndarray:
    """World angles of a scan's ``n`` beams from a laser heading ``theta``: the same floats as
    ``scan.angles() + theta`` (the same two roundings per beam, in the same order)."""
    out = np.empty(n)
    for k in range(n):
        out[k] = angle_min + increment * float(k) + theta
    return out


@njit(cache=True, nogil=True)
def free_body(free: np.ndarray, occupied: np.ndarray, footprint: np.ndarray, x: float, y: float,
              c: float, s: float, origin_x: float, origin_y: float, resolution: float,
              now: float) -> bool:
    """Stamp ``now`` free and forget the occupied stamp on the cells under ``footprint`` placed at
    (x, y) with cos/sin (c, s): the convex fill of its vertex cells (costmap_2d's footprint
    clearing). False, touching nothing, when a vertex cell is off the grid."""
    h, w = free.shape
    n = footprint.shape[0]
    cells = np.empty((n, 2), dtype=np.int64)
    for k in range(n):
        fi = np.floor((x + c * footprint[k, 0] - s * footprint[k, 1] - origin_x) / resolution)
        fj = np.floor((y + s * footprint[k, 0] + c * footprint[k, 1] - origin_y) / resolution)
        if not (0.0 <= fi < w and 0.0 <= fj < h):  # NaN too
            return False
        cells[k, 0] = int(fi)
        cells[k, 1] = int(fj)
    _fill_convex_cells(free, cells, now)
    _fill_convex_cells(occupied, cells, NEVER)
    return True


@njit(cache=True, nogil=True, inline="always")
def _point_in_polygon(footprint: np.ndarray, x: float, y: float, c: float, s: float,
                      origin_x: float, origin_y: float, inv: float, u: float, v: float) -> bool:
    """Whether the point (u, v) (cell units) lies inside the footprint placed at the pose (even-odd
    rule, as the corner test of ``_square_meets_polygon``)."""
    n = footprint.shape[0]
    inside = False
    au, av = _place(footprint[n - 1, 0], footprint[n - 1, 1], x, y, c, s, origin_x, origin_y, inv)
    for k in range(n):
        bu, bv = _place(footprint[k, 0], footprint[k, 1], x, y, c, s, origin_x, origin_y, inv)
        if (av <= v) != (bv <= v):
            if au + (v - av) * (bu - au) / (bv - av) > u:
                inside = not inside
        au, av = bu, bv
    return inside


@njit(cache=True, nogil=True)
def _square_inside(footprint: np.ndarray, x: float, y: float, c: float, s: float,
                   origin_x: float, origin_y: float, inv: float, i: int, j: int) -> bool:
    """Whether the whole cell square [i, i+1] x [j, j+1] lies under the footprint at the pose
    (its four corners inside: exact for a convex footprint)."""
    for corner in range(4):
        if not _point_in_polygon(footprint, x, y, c, s, origin_x, origin_y, inv,
                                 i + (corner & 1), j + (corner >> 1)):
            return False
    return True


@njit(cache=True, nogil=True)
def _cell_box(footprint: np.ndarray, x: float, y: float, c: float, s: float, origin_x: float,
              origin_y: float, inv: float) -> tuple[int, int, int, int]:
    """The cells (i0, j0, i1, j1), inclusive, of the bounding box of the placed footprint."""
    u0 = v0 = 1e300
    u1 = v1 = -1e300
    for k in range(footprint.shape[0]):
        u, v = _place(footprint[k, 0], footprint[k, 1], x, y, c, s, origin_x, origin_y, inv)
        u0, u1 = min(u0, u), max(u1, u)
        v0, v1 = min(v0, v), max(v1, v)
    return (int(math.floor(u0)), int(math.floor(v0)), int(math.floor(u1)), int(math.floor(v1)))


@njit(cache=True, nogil=True)
def _place_all(footprint: np.ndarray, x: float, y: float, theta: float, origin_x: float,
               origin_y: float, inv: float) -> np.ndarray:
    """The footprint's vertices at the pose, in cell units (N, 2)."""
    c = math.cos(theta)
    s = math.sin(theta)
    out = np.empty((footprint.shape[0], 2))
    for k in range(footprint.shape[0]):
        out[k, 0], out[k, 1] = _place(footprint[k, 0], footprint[k, 1], x, y, c, s, origin_x,
                                      origin_y, inv)
    return out


@njit(cache=True, nogil=True)
def _clip_square(poly: np.ndarray, i: int, j: int, inset: float, a: np.ndarray,
                 b: np.ndarray) -> int:
    """Clip the cell square [i, i+1] x [j, j+1], shrunk by ``inset`` on every side, to the
    convex counter-clockwise polygon ``poly`` (Sutherland-Hodgman); the vertices land in ``a``
    (scratch ``b``, both (4 + N + 1, 2)). Returns their count (0: no overlap)."""
    a[0, 0], a[0, 1] = i + inset, j + inset
    a[1, 0], a[1, 1] = i + 1.0 - inset, j + inset
    a[2, 0], a[2, 1] = i + 1.0 - inset, j + 1.0 - inset
    a[3, 0], a[3, 1] = i + inset, j + 1.0 - inset
    m = 4
    n = poly.shape[0]
    for e in range(n):
        ax, ay = poly[e - 1, 0], poly[e - 1, 1]
        ex, ey = poly[e, 0] - ax, poly[e, 1] - ay
        k = 0
        qx, qy = a[m - 1, 0], a[m - 1, 1]
        dq = ex * (qy - ay) - ey * (qx - ax)
        for v in range(m):
            px, py = a[v, 0], a[v, 1]
            dp = ex * (py - ay) - ey * (px - ax)
            if (dp >= 0.0) != (dq >= 0.0):  # the side q -> p crosses the edge's line
                t = dq / (dq - dp)
                b[k, 0], b[k, 1] = qx + t * (px - qx), qy + t * (py - qy)
                k += 1
            if dp >= 0.0:
                b[k, 0], b[k, 1] = px, py
                k += 1
            qx, qy, dq = px, py, dp
        for v in range(k):
            a[v, 0], a[v, 1] = b[v, 0], b[v, 1]
        m = k
        if m == 0:
            return 0
    return m


@njit(cache=True, nogil=True)
def _area(a: np.ndarray, m: int) -> float:
    """Area of the polygon a[:m] (shoelace)."""
    s = 0.0
    q = m - 1
    for v in range(m):
        s += a[q, 0] * a[v, 1] - a[v, 0] * a[q, 1]
        q = v
    return 0.5 * s


@njit(cache=True, nogil=True)
def _within(poly: np.ndarray, a: np.ndarray, m: int, tol: float) -> bool:
    """Whether the points a[:m] lie in the convex counter-clockwise polygon ``poly`` (up to
    ``tol`` cells outside an edge: shared edges of two placements round differently)."""
    n = poly.shape[0]
    for e in range(n):
        ax, ay = poly[e - 1, 0], poly[e - 1, 1]
        ex, ey = poly[e, 0] - ax, poly[e, 1] - ay
        lim = -tol * math.sqrt(ex * ex + ey * ey)
        for v in range(m):
            if ex * (a[v, 1] - ay) - ey * (a[v, 0] - ax) < lim:
                return False
    return True


# cells^2: a footprint's overlap with a cell smaller than this is a touch, not a cover
SLIVER = 1e-6
# m: a footprint this little outside the start footprint stays on it (the flats of a polygon
# approximating a round robot turning on the spot reach ~4 mm out; shared edges round)
START_TOLERANCE = 0.01
# m: a footprint reaching no deeper than this into a cell does not cover it (the numerical
# slack navcore.motion.collision allows a tight-spot motion against a lethal cell)
DEPTH_TOLERANCE = 0.002


@njit(cache=True, nogil=True)
def first_unobserved(free: np.ndarray, occupied: np.ndarray, origin_x: float, origin_y: float,
                     resolution: float, footprint: np.ndarray, convex: bool, poses: np.ndarray,
                     start: np.ndarray, since: float, tolerance: float = START_TOLERANCE,
                     allow_unknown: bool = False, depth: float = DEPTH_TOLERANCE
                     ) -> tuple[int, int, int]:
    """The first of ``poses`` (N, 3) whose footprint reaches into a cell not observed free since
    ``since`` (free stamp >= since and newer than its occupied stamp), with that cell (i, j),
    counting only the part of the footprint more than ``tolerance`` m outside the footprint at
    ``start`` (3,): the robot stands there, and only cells it reaches more than ``depth`` m
    into. Cells off the grid are unobserved. (-1, 0, 0) when
    every pose keeps to observed-free space. With ``allow_unknown`` only a cell whose newest
    observation is occupied (at any age) counts: never seen, or seen free long ago, will do (a
    last resort when nothing around was seen).

    ``convex`` (the footprint counter-clockwise): a cell counts when the footprint covers some
    of it outside the start footprint (exact polygon clipping). Otherwise, conservatively, every
    cell the footprint meets counts unless it lies wholly under the start footprint."""
    h, w = free.shape
    inv = 1.0 / resolution
    sc = math.cos(start[2])
    ss = math.sin(start[2])
    home = _place_all(footprint, start[0], start[1], start[2], origin_x, origin_y, inv)
    tol = tolerance * inv
    inset = depth * inv
    a = np.empty((footprint.shape[0] + 5, 2))
    b = np.empty((footprint.shape[0] + 5, 2))
    for p in range(poses.shape[0]):
        x = poses[p, 0]
        y = poses[p, 1]
        c = math.cos(poses[p, 2])
        s = math.sin(poses[p, 2])
        placed = _place_all(footprint, x, y, poses[p, 2], origin_x, origin_y, inv)
        i0, j0, i1, j1 = _cell_box(footprint, x, y, c, s, origin_x, origin_y, inv)
        for j in range(j0, j1 + 1):
            for i in range(i0, i1 + 1):
                if convex:
                    m = _clip_square(placed, i, j, inset, a, b)
                    if m < 3 or _area(a, m) <= SLIVER or _within(home, a, m, tol):
                        continue
                else:
                    if not _square_meets_polygon(footprint, x, y, c, s, origin_x, origin_y, inv,
                                                 i, j):
                        continue
                    if _square_inside(footprint, start[0], start[1], sc, ss, origin_x,
                                      origin_y, inv, i, j):
                        continue
                if not (0 <= i < w and 0 <= j < h):
                    if allow_unknown:
                        continue
                    return p, i, j
                f = free[j, i]
                o = occupied[j, i]
                if allow_unknown:
                    if o > NEVER and o >= f:
                        return p, i, j
                elif not (f >= since and f > o):
                    return p, i, j
    return -1, 0, 0


@njit(cache=True, nogil=True)
def _roll(free: np.ndarray, occupied: np.ndarray, start: int, w: int, h: int, dx: int,
          dy: int) -> int:
    """Move the h x w window that starts at ``start`` in the stores ``free`` and ``occupied``
    (each three windows long) by (dx, dy) cells: costmap2d.shift_grid of both grids, cell (r, c)
    takes what was at (r + dy, c + dx), NEVER where that lies outside the window. Moving the
    start by dy * w + dx moves every cell at once (no copy); only the cells that came into view
    are set. Returns the new start. (Plain loops: numpy slice assignments here took seconds to
    compile on a cold start.)"""
    n = h * w
    if dx == 0 and dy == 0:
        return start
    if abs(dx) >= w or abs(dy) >= h:  # nothing stays in view
        for k in range(n, 2 * n):
            free[k] = NEVER
            occupied[k] = NEVER
        return n
    moved = start + dy * w + dx
    if not 0 <= moved <= 2 * n:  # the store runs out: move the window to its middle first
        # (overlapping ranges: copy from the end when moving up, from the start when down)
        order = range(n - 1, -1, -1) if start < n else range(n)
        for k in order:
            free[n + k] = free[start + k]
            occupied[n + k] = occupied[start + k]
        moved = n + dy * w + dx
    # the cells that came into view: the columns (a cell whose source column lies outside the
    # window reads the row next to it), then the rows
    c0 = w - dx if dx > 0 else 0
    r0 = h - dy if dy > 0 else 0
    for r in range(h):
        row = moved + r * w
        if r0 <= r < r0 + abs(dy):
            first, last = row, row + w
        else:
            first, last = row + c0, row + c0 + abs(dx)
        for k in range(first, last):
            free[k] = NEVER
            occupied[k] = NEVER
    return moved


@njit(cache=True, nogil=True)
def _observe(free: np.ndarray, occupied: np.ndarray, start: int, w: int, h: int, dx: int,
             dy: int, origin_x: float, origin_y: float, resolution: float, lx: float, ly: float,
             ltheta: float, angle_min: float, increment: float, ranges: np.ndarray,
             range_min: float, range_max: float, footprint: np.ndarray, x: float, y: float,
             c: float, s: float, now: float) -> int:
    """One cycle of ``ObservedSpace.update`` in one call (each Python-side step cost more than
    its kernel): move the window by (dx, dy), stamp the scan (no beams: no scan), free the body
    at (x, y) with cos/sin (c, s). Returns the window's new start."""
    start = _roll(free, occupied, start, w, h, dx, dy)
    gx = (lx - origin_x) / resolution
    gy = (ly - origin_y) / resolution
    if 0.0 <= gx < w and 0.0 <= gy < h:  # else the laser is off the window: no beam stamped
        _stamp(free, occupied, start, w, h, gx, gy,
               fan_angles(angle_min, increment, ltheta, ranges.shape[0]), ranges, range_min,
               range_max, resolution, now)
    n = h * w
    free_body(free[start:start + n].reshape((h, w)), occupied[start:start + n].reshape((h, w)),
              footprint, x, y, c, s, origin_x, origin_y, resolution, now)
    return start


# no scan this cycle: no beam to stamp. float32 as a LaserScan's ranges, so that _observe
# compiles once (a float64 array would be a second specialisation, seconds of cold start)
_NO_RANGES = np.empty(0, dtype=np.float32)


def _ranges(scan: LaserScan) -> np.ndarray:
    """The scan's ranges as an array (a LaserScan's are float32 already: read as they are)."""
    r = scan.ranges
    if isinstance(r, np.ndarray) and r.dtype == np.float32:
        return r
    return np.asarray(r, dtype=np.float64)


def _convex_ccw(fp: np.ndarray) -> tuple[np.ndarray, bool]:
    """The footprint counter-clockwise, and whether it is convex."""
    x, y = fp[:, 0], fp[:, 1]
    if float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)) < 0.0:
        fp = fp[::-1].copy()
    d = np.roll(fp, -1, axis=0) - fp
    cross = d[:, 0] * np.roll(d[:, 1], -1) - d[:, 1] * np.roll(d[:, 0], -1)
    return np.ascontiguousarray(fp), bool(np.all(cross >= -1e-12))


class ObservedSpace:
    """A rolling ``size_x`` x ``size_y`` cell window of observation stamps around the robot.

    ``footprint``: the robot's outline (robot frame), which motions are checked with;
    ``clearing_footprint`` (default: the same): the outline whose cells each cycle frees, the
    costmaps' padded footprint. ``update(pose, scan, laser_pose, now)`` is the whole per-cycle
    input; queries read ``free_since`` / ``first_unobserved``."""

    def __init__(self, resolution: float, size_x: int, size_y: int, footprint: object,
                 clearing_footprint: object = None) -> None:
        if not resolution > 0:
            raise ValueError(f"ObservedSpace: resolution must be > 0, got {resolution}")
        if size_x <= 0 or size_y <= 0:
            raise ValueError(f"ObservedSpace: size must be positive, got {size_x} x {size_y}")
        self.resolution = float(resolution)
        self.footprint, self.convex = _convex_ccw(parse_footprint(footprint))
        self.clearing_footprint = parse_footprint(
            footprint if clearing_footprint is None else clearing_footprint)
        self._shape = (int(size_y), int(size_x))
        n = self._shape[0] * self._shape[1]
        # Each grid is a window into a store three windows long, starting at ``_start``: moving
        # the window by (dx, dy) cells moves its start by dy * size_x + dx and sets the cells
        # that came into view (every shift_grid copied the whole window, ~40 us per step).
        self._stores = (np.full(3 * n, NEVER), np.full(3 * n, NEVER))
        self._start = n
        self._show()
        self._half_width = self._shape[1] * self.resolution / 2.0
        self._half_height = self._shape[0] * self.resolution / 2.0
        self.origin_x = 0.0
        self.origin_y = 0.0
        self._placed = False

    def _show(self) -> None:
        """Point ``free`` and ``occupied`` at the window (C-contiguous views of the stores)."""
        s, n = self._start, self._shape[0] * self._shape[1]
        self.free = self._stores[0][s:s + n].reshape(self._shape)
        self.occupied = self._stores[1][s:s + n].reshape(self._shape)

    @classmethod
    def around(cls, resolution: float, width: float, height: float, footprint: object,
               clearing_footprint: object = None) -> ObservedSpace:
        """A window of ``width`` x ``height`` metres."""
        return cls(resolution, max(1, int(round(width / resolution))),
                   max(1, int(round(height / resolution))), footprint, clearing_footprint)

    @property
    def size_x(self) -> int:
        return int(self.free.shape[1])

    @property
    def size_y(self) -> int:
        return int(self.free.shape[0])

    def _follow(self, x: float, y: float) -> tuple[int, int]:
        """Place the window so (x, y) is near its centre, on the world lattice (whole cells, as
        costmap_2d's rolling window): sets the origin and returns the move (dx, dy) in cells
        that the stores must follow."""
        res = self.resolution
        nx = math.floor((x - self._half_width) / res)
        ny = math.floor((y - self._half_height) / res)
        if not self._placed:
            self.origin_x, self.origin_y, self._placed = nx * res, ny * res, True
            return 0, 0
        dx = nx - int(round(self.origin_x / res))
        dy = ny - int(round(self.origin_y / res))
        if dx != 0 or dy != 0:
            self.origin_x, self.origin_y = nx * res, ny * res
        return dx, dy

    def _moved_to(self, start: int) -> None:
        if start != self._start:
            self._start = start
            self._show()

    def recentre(self, x: float, y: float) -> None:
        """Move the window so (x, y) is near its centre: what it holds keeps its world
        position."""
        dx, dy = self._follow(x, y)
        if dx != 0 or dy != 0:
            h, w = self._shape
            self._moved_to(_roll(self._stores[0], self._stores[1], self._start, w, h, dx, dy))

    def add_scan(self, scan: LaserScan, laser_pose: Pose2D, now: float) -> int:
        """Stamp what one scan saw from ``laser_pose`` (in the same frame as the window)."""
        ranges = _ranges(scan)
        angles = fan_angles(float(scan.angle_min), float(scan.angle_increment),
                            laser_pose.theta, ranges.shape[0])
        return stamp_scan(self.free, self.occupied, self.origin_x, self.origin_y,
                          self.resolution, laser_pose.x, laser_pose.y, angles, ranges,
                          float(scan.range_min), float(scan.range_max), float(now))

    def add_body(self, pose: Pose2D, now: float) -> bool:
        """Free the cells under the clearing footprint at ``pose`` (costmap_2d's footprint
        clearing: the convex fill of its vertex cells): stamped free, occupied forgotten. False,
        touching nothing, when a vertex is off the window."""
        return free_body(self.free, self.occupied, self.clearing_footprint, pose.x, pose.y,
                         math.cos(pose.theta), math.sin(pose.theta), self.origin_x,
                         self.origin_y, self.resolution, float(now))

    def update(self, pose: Pose2D, scan: LaserScan | None, laser_pose: Pose2D | None,
               now: float) -> None:
        """One cycle: follow the robot, stamp a new scan (if any), then free its body (after
        the scan, as costmap_2d clears the footprint last). The same stamps as ``recentre``,
        ``add_scan`` and ``add_body`` in turn, in one kernel call."""
        c, s = math.cos(pose.theta), math.sin(pose.theta)  # first: an infinite heading raises
        dx, dy = self._follow(pose.x, pose.y)  # before anything moved
        h, w = self._shape
        if scan is None or laser_pose is None:
            start = _observe(self._stores[0], self._stores[1], self._start, w, h, dx, dy,
                             self.origin_x, self.origin_y, self.resolution, 0.0, 0.0, 0.0, 0.0,
                             0.0, _NO_RANGES, 0.0, 0.0, self.clearing_footprint, pose.x, pose.y,
                             c, s, float(now))
        else:
            start = _observe(self._stores[0], self._stores[1], self._start, w, h, dx, dy,
                             self.origin_x, self.origin_y, self.resolution, laser_pose.x,
                             laser_pose.y, laser_pose.theta, float(scan.angle_min),
                             float(scan.angle_increment), _ranges(scan),
                             float(scan.range_min), float(scan.range_max),
                             self.clearing_footprint, pose.x, pose.y, c, s, float(now))
        self._moved_to(start)

    def free_since(self, since: float) -> np.ndarray:
        """Boolean grid [my, mx]: observed free at or after ``since``."""
        return (self.free >= since) & (self.free > self.occupied)

    def first_unobserved(self, poses: list[Pose2D], start: Pose2D, since: float,
                         allow_unknown: bool = False) -> tuple[int, tuple[float, float]] | None:
        """The index of the first of ``poses`` whose footprint reaches a cell not observed free
        since ``since`` (beyond what the robot covers at ``start``) and that cell's centre;
        None when the whole motion stays on observed-free space. ``allow_unknown``: only
        cells last seen occupied count (see the kernel ``first_unobserved``)."""
        if not poses:
            return None
        arr = np.array([[p.x, p.y, p.theta] for p in poses], dtype=np.float64)
        k, i, j = first_unobserved(self.free, self.occupied, self.origin_x, self.origin_y,
                                   self.resolution, self.footprint, self.convex, arr,
                                   np.array([start.x, start.y, start.theta]), float(since),
                                   START_TOLERANCE, bool(allow_unknown), DEPTH_TOLERANCE)
        if k < 0:
            return None
        return int(k), (self.origin_x + (i + 0.5) * self.resolution,
                        self.origin_y + (j + 0.5) * self.resolution)
