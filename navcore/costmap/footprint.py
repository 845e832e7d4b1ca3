"""Robot footprints (costmap_2d footprint.cpp semantics) and the footprint cost of a pose.

A footprint is an (N, 2) float64 polygon in the robot frame. ``footprint_cost`` is a numba kernel
meant to be called from other kernels (the local planner scores hundreds of thousands of poses per
cycle): it reads each covered cell once and allocates only two small scratch arrays.

Two compiled variants of it (``footprint_cost_plain`` and ``footprint_cost_vector``) differ only
in how they take the max of a row span: cell by cell, or 16 cells per masked vector load (LLVM
IR, ``_lanes_max``). ``footprint_cost`` is the vector one unless NUMBA_DISABLE_JIT=1 or
NAVBT_PLAIN_KERNELS=1 (docs/performance.md, "Footprint cost": what each buys).
"""

from __future__ import annotations

import ast
import math
import os
from typing import Any, Callable

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic

NUM_RADIUS_VERTICES = 16  # makeFootprintFromRadius uses a 16-gon


def _sign0(v: float) -> float:
    return 1.0 if v > 0 else (-1.0 if v < 0 else 0.0)


def parse_footprint(footprint: Any) -> np.ndarray:
    """An (N, 2) float64 polygon from a list of [x, y] pairs or its ROS string form "[[x,y],...]".

    Raises ValueError naming what is wrong (fewer than 3 points, a non-pair, a non-number).
    """
    if isinstance(footprint, str):
        try:
            footprint = ast.literal_eval(footprint.strip())
        except (ValueError, SyntaxError) as e:
            raise ValueError(f"footprint: cannot parse {footprint!r} as [[x, y], ...]: {e}"
                             ) from None
    try:
        fp = np.asarray(footprint, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"footprint: expected a list of [x, y] pairs, got {footprint!r}") from None
    if fp.ndim != 2 or fp.shape[1] != 2:
        raise ValueError(f"footprint: expected a list of [x, y] pairs, got shape {fp.shape}")
    if fp.shape[0] < 3:
        raise ValueError(f"footprint: a polygon needs at least 3 points, got {fp.shape[0]}")
    if not np.all(np.isfinite(fp)):
        raise ValueError("footprint: every coordinate must be finite")
    return fp


def make_footprint(footprint: Any = None, robot_radius: float = 0.46,
                   footprint_padding: float = 0.01) -> np.ndarray:
    """The padded footprint polygon, (N, 2) float64, as Costmap2DROS builds it.

    A given ``footprint`` polygon wins; otherwise ``robot_radius`` gives a 16-gon. Padding then
    moves each vertex outward per axis (x += sign0(x) * pad, y += sign0(y) * pad), like padFootprint.
    An empty list or string counts as "not given", as in ROS.
    """
    given = footprint is not None
    if isinstance(footprint, str):
        given = footprint.strip() not in ("", "[]")
    elif isinstance(footprint, (list, tuple)):
        given = len(footprint) > 0
    if given:
        fp = parse_footprint(footprint).copy()
    else:
        if not robot_radius > 0:
            raise ValueError(f"robot_radius: must be > 0 without a footprint, got {robot_radius}")
        a = np.arange(NUM_RADIUS_VERTICES) * (2.0 * math.pi / NUM_RADIUS_VERTICES)
        fp = np.stack([robot_radius * np.cos(a), robot_radius * np.sin(a)], axis=1)
    pad = float(footprint_padding)
    fp[:, 0] += np.sign(fp[:, 0]) * pad
    fp[:, 1] += np.sign(fp[:, 1]) * pad
    return np.ascontiguousarray(fp, dtype=np.float64)


def _min_max_distances(fp: np.ndarray) -> tuple[float, float]:
    """costmap_2d calculateMinAndMaxDistances: over every edge, the vertex distance and the
    distance from the origin to the edge segment; min and max of all of them."""
    fp = np.asarray(fp, dtype=np.float64)
    lo, hi = math.inf, -math.inf
    n = len(fp)
    for i in range(n):
        x0, y0 = fp[i]
        x1, y1 = fp[(i + 1) % n]
        vertex = math.hypot(x0, y0)
        dx, dy = x1 - x0, y1 - y0
        seg2 = dx * dx + dy * dy
        t = 0.0 if seg2 == 0.0 else min(1.0, max(0.0, -(x0 * dx + y0 * dy) / seg2))
        edge = math.hypot(x0 + t * dx, y0 + t * dy)
        lo = min(lo, vertex, edge)
        hi = max(hi, vertex, edge)
    return lo, hi


def inscribed_radius(fp: np.ndarray) -> float:
    """Radius of the largest origin-centred circle inside the footprint (costmap_2d definition)."""
    return _min_max_distances(fp)[0]


def circumscribed_radius(fp: np.ndarray) -> float:
    """Radius of the smallest origin-centred circle holding the footprint."""
    return _min_max_distances(fp)[1]


@njit(cache=True, nogil=True, inline="always")
def _place(fx: float, fy: float, x: float, y: float, c: float, s: float, origin_x: float,
           origin_y: float, inv: float) -> tuple[float, float]:
    """Robot-frame point (fx, fy) at pose (x, y, c = cos, s = sin), in cell units from the grid
    origin.

    Scalars only, like every helper of the kernel: an inlined helper that takes an array costs an
    atomic reference count increment and decrement per call, more than all the arithmetic here.
    """
    return ((x + c * fx - s * fy - origin_x) * inv, (y + s * fx + c * fy - origin_y) * inv)


@njit(cache=True, nogil=True)
def _square_meets_polygon(footprint: np.ndarray, x: float, y: float, c: float, s: float,
                          origin_x: float, origin_y: float, inv: float, i: int, j: int) -> bool:
    """Whether the closed cell square [i, i+1] x [j, j+1] meets the footprint placed at the pose
    (cell units): a vertex inside the square, a square corner inside the polygon, or an edge
    crossing it. Vertices are placed on the fly: no scratch array."""
    n = footprint.shape[0]
    for k in range(n):
        u, v = _place(footprint[k, 0], footprint[k, 1], x, y, c, s, origin_x, origin_y, inv)
        if i <= u <= i + 1 and j <= v <= j + 1:
            return True
    for corner in range(4):
        cx = i + (corner & 1)
        cy = j + (corner >> 1)
        inside = False
        au, av = _place(footprint[n - 1, 0], footprint[n - 1, 1], x, y, c, s, origin_x, origin_y,
                        inv)
        for k in range(n):
            bu, bv = _place(footprint[k, 0], footprint[k, 1], x, y, c, s, origin_x, origin_y, inv)
            if (av <= cy) != (bv <= cy):
                if au + (cy - av) * (bu - au) / (bv - av) > cx:
                    inside = not inside
            au, av = bu, bv
        if inside:
            return True
    au, av = _place(footprint[n - 1, 0], footprint[n - 1, 1], x, y, c, s, origin_x, origin_y, inv)
    for k in range(n):  # clip each edge to the square (Liang-Barsky)
        bu, bv = _place(footprint[k, 0], footprint[k, 1], x, y, c, s, origin_x, origin_y, inv)
        du, dv = bu - au, bv - av
        t0, t1 = 0.0, 1.0
        ok = True
        for side in range(4):
            if side == 0:
                p, q = -du, au - i
            elif side == 1:
                p, q = du, i + 1 - au
            elif side == 2:
                p, q = -dv, av - j
            else:
                p, q = dv, j + 1 - av
            if p == 0.0:
                if q < 0.0:
                    ok = False
                    break
            elif p < 0.0:
                t0 = max(t0, q / p)
            else:
                t1 = min(t1, q / p)
            if t0 > t1:
                ok = False
                break
        if ok:
            return True
        au, av = bu, bv
    return False


LANES = 16  # cells read per vector load when taking the max of a row span


@intrinsic
def _lanes_max(typingctx, arr, row, start, skip, count, width):  # type: ignore[no-untyped-def]
    """Max of arr[row, start + i] over the lanes skip <= i < skip + count of one ``width``-cell
    (a literal) unaligned vector load, others masked to 0. The caller keeps start + width
    within the row and the row contiguous. A loop over a short span runs scalar (the loop
    vectoriser wants far longer rows, and numba leaves LLVM's SLP vectoriser off); this reads
    up to ``width`` cells without a branch."""
    if not (isinstance(arr, types.Array) and arr.ndim == 2 and arr.dtype == types.uint8
            and isinstance(width, types.IntegerLiteral)):
        return None
    w = width.literal_value

    def codegen(context, builder, sig, args):  # type: ignore[no-untyped-def]
        a = context.make_array(sig.args[0])(context, builder, args[0])
        ptr = cgutils.get_item_pointer(context, builder, sig.args[0], a, [args[1], args[2]],
                                       wraparound=False)
        i8, i32 = ir.IntType(8), ir.IntType(32)
        vec = ir.VectorType(i8, w)

        def splat(value):  # type: ignore[no-untyped-def]  # the low byte of an int64, every lane
            one = builder.insert_element(ir.Constant(vec, ir.Undefined),
                                         builder.trunc(value, i8), i32(0))
            return builder.shuffle_vector(one, ir.Constant(vec, ir.Undefined),
                                          ir.Constant(ir.VectorType(i32, w), [0] * w))
        cells = builder.load(builder.bitcast(ptr, vec.as_pointer()), align=1)
        lane = ir.Constant(vec, [i8(i) for i in range(w)])
        # lane - skip < count, unsigned: lanes before skip wrap to large values
        keep = builder.icmp_unsigned("<", builder.sub(lane, splat(args[3])), splat(args[4]))
        cells = builder.select(keep, cells, ir.Constant(vec, [i8(0)] * w))
        fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(i8, [vec]),
                                            f"llvm.vector.reduce.umax.v{w}i8")
        return builder.call(fn, [cells])
    return types.uint8(arr, row, start, skip, count, width), codegen


def _make_footprint_cost(vector_rows: bool) -> Callable[..., int]:
    """``footprint_cost`` compiled with (``vector_rows``) or without the vector row max: the
    flag is a constant of the closure, so each variant carries only its own code and has its
    own numba cache entry."""

    @njit(cache=True, nogil=True)
    def footprint_cost(costs: np.ndarray, origin_x: float, origin_y: float, resolution: float,
                       footprint: np.ndarray, x: float, y: float, theta: float) -> int:
        """Max cost of the cells the footprint covers at pose (x, y, theta): every cell its
        outline passes through and every cell inside it (a conservative rasterisation: no cell
        the robot overlaps is missed). -1 if any vertex is off the map. ``costs``: a uint8 cost
        grid [my, mx].

        Row band by row band (cell rows), the parts of the edges within a band give its x
        extent. Edge by edge, each edge widens the extents of the bands it crosses: short loops
        with few data-dependent branches. For a convex footprint the covered cells of a row are
        that one span; a non-convex one checks each cell of the span exactly.
        """
        n = footprint.shape[0]
        size_y = costs.shape[0]
        size_x = costs.shape[1]
        c = math.cos(theta)
        s = math.sin(theta)
        inv = 1.0 / resolution
        vert = np.empty((2, n))
        vmin = 1e300
        vmax = -1e300
        on_map = True
        for k in range(n):
            u, v = _place(footprint[k, 0], footprint[k, 1], x, y, c, s, origin_x, origin_y, inv)
            # False for NaN too
            on_map &= u >= 0.0 and v >= 0.0 and u < size_x and v < size_y
            vert[0, k] = u
            vert[1, k] = v
            vmin = min(vmin, v)
            vmax = max(vmax, v)
        if not on_map:
            return -1
        r0 = int(vmin)
        rows = int(vmax) - r0 + 1
        # convex iff the turns never change sign (collinear vertices do not count)
        left = False
        right = False
        au, av = vert[0, n - 2], vert[1, n - 2]
        bu, bv = vert[0, n - 1], vert[1, n - 1]
        for k in range(n):
            cu, cv = vert[0, k], vert[1, k]
            cross = (bu - au) * (cv - bv) - (bv - av) * (cu - bu)
            left |= cross > 0.0
            right |= cross < 0.0
            au, av, bu, bv = bu, bv, cu, cv
        convex = not (left and right)
        ext = np.empty((2, rows))
        for r in range(rows):
            ext[0, r] = 1e300
            ext[1, r] = -1e300
        # edge k - 1 -> k widens every band it meets by its part inside (a horizontal
        # edge whole)
        au, av = vert[0, n - 1], vert[1, n - 1]
        for k in range(n):
            bu, bv = vert[0, k], vert[1, k]
            e0 = min(av, bv)
            e1 = max(av, bv)
            if e0 == e1:
                r = int(e0) - r0
                ext[0, r] = min(ext[0, r], min(au, bu))
                ext[1, r] = max(ext[1, r], max(au, bu))
            else:
                slope = (bu - au) / (bv - av)
                xa = au + (e0 - av) * slope
                for row in range(int(e0), int(e1) + 1):
                    xb = au + (min(e1, row + 1.0) - av) * slope
                    r = row - r0
                    ext[0, r] = min(ext[0, r], min(xa, xb))
                    ext[1, r] = max(ext[1, r], max(xa, xb))
                    xa = xb  # where the edge leaves this band it enters the next
            au, av = bu, bv
        best = 0
        wide_rows = size_x >= LANES and costs.strides[1] == 1  # a whole load fits in a row
        for r in range(rows):
            row = r0 + r
            m0 = int(ext[0, r])
            m1 = min(int(ext[1, r]), size_x - 1)
            if convex:
                rb = np.uint8(0)
                if vector_rows and wide_rows:
                    # written out here: a helper taking the array costs a refcount
                    start = m0
                    left_over = m1 - m0 + 1
                    while left_over > LANES:
                        rb = max(rb, _lanes_max(costs, row, start, 0, LANES, LANES))
                        start += LANES
                        left_over -= LANES
                    at = min(start, size_x - LANES)  # the last load ends inside the row
                    rb = max(rb, _lanes_max(costs, row, at, start - at, left_over, LANES))
                else:
                    # unsigned column indices: no negative-index wraparound, so plain loads
                    for mx in range(np.uint64(m0), np.uint64(m1 + 1)):
                        rb = max(rb, costs[row, mx])
                if rb > best:
                    best = np.int64(rb)
                    if best == 255:  # nothing can be higher
                        return best
            else:
                for mx in range(m0, m1 + 1):
                    if costs[row, mx] > best and _square_meets_polygon(
                            footprint, x, y, c, s, origin_x, origin_y, inv, mx, row):
                        best = np.int64(costs[row, mx])
        return best
    
    
    return footprint_cost


footprint_cost_plain = _make_footprint_cost(False)
footprint_cost_vector = _make_footprint_cost(True)
# the variant the costmaps and controllers call (an intrinsic has no Python form: plain without
# the JIT). Kernels that call it are cached with the variant they were compiled with: after
# switching NAVBT_PLAIN_KERNELS, run on a fresh NUMBA_CACHE_DIR.
VECTOR_ROWS = not (os.environ.get("NUMBA_DISABLE_JIT", "0") not in ("", "0")
                   or os.environ.get("NAVBT_PLAIN_KERNELS") == "1")
footprint_cost = footprint_cost_vector if VECTOR_ROWS else footprint_cost_plain


@njit(cache=True, nogil=True)
def reach_of(radius: float, resolution: float) -> int:
    """Half-width in cells of the square around a pose's cell that holds every cell a footprint
    within ``radius`` of the pose can cover, at any heading: a vertex lies less than
    radius / resolution cells (plus rounding, far below the 1e-9 allowed) from a centre that
    lies in the cell."""
    return int(radius / resolution * (1.0 + 1e-9) + 1e-9) + 1


def bound_reach(footprint: np.ndarray, resolution: float, scale: float = 1.0) -> int:
    """``reach_of`` the footprint grown by ``scale``."""
    return reach_of(float(np.max(np.hypot(footprint[:, 0], footprint[:, 1]))) * scale, resolution)


@njit(cache=True, nogil=True)
def square_max(costs: np.ndarray, reach: int) -> np.ndarray:
    """For each cell, the max cost over the square of half-width ``reach`` cells around it
    (clipped at the map edge). With ``reach = bound_reach(footprint, resolution)`` it bounds the
    footprint cost of any pose in that cell from above: where it is no higher than what a
    caller already knows, the footprint cannot add anything and needs no rasterising."""
    size_y, size_x = costs.shape
    w = np.uint64(size_x)  # unsigned indices: no wraparound, so the row loops vectorise
    cols = np.empty((size_y, size_x), dtype=np.uint8)
    for my in range(size_y):  # max over the column neighbours, a whole row at a time
        lo = max(0, my - reach)
        for mx in range(w):
            cols[my, mx] = costs[lo, mx]
        for j in range(lo + 1, min(size_y - 1, my + reach) + 1):
            for mx in range(w):
                cols[my, mx] = max(cols[my, mx], costs[j, mx])
    out = cols.copy()
    for my in range(size_y):  # then over the row neighbours: the row against itself shifted
        for d in range(np.uint64(1), np.uint64(min(reach, size_x - 1) + 1)):
            for mx in range(w - d):
                out[my, mx] = max(out[my, mx], cols[my, mx + d])
            for mx in range(d, w):
                out[my, mx] = max(out[my, mx], cols[my, mx - d])
    return out


@njit(cache=True, nogil=True)
def footprint_costs(costs: np.ndarray, origin_x: float, origin_y: float, resolution: float,
                    footprint: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """``footprint_cost`` of each (x, y, theta) row of ``poses`` (N, 3), as an int64 array."""
    out = np.empty(poses.shape[0], dtype=np.int64)
    for i in range(poses.shape[0]):
        out[i] = footprint_cost(costs, origin_x, origin_y, resolution, footprint, poses[i, 0],
                                poses[i, 1], poses[i, 2])
    return out


def transform_footprint(fp: np.ndarray, x: float, y: float, theta: float) -> np.ndarray:
    """The footprint polygon placed at pose (x, y, theta) in the world frame, (N, 2)."""
    return _placed_polygon(fp, x, y, math.cos(theta), math.sin(theta))


@njit(cache=True, nogil=True)
def _placed_polygon(fp: np.ndarray, x: float, y: float, c: float, s: float) -> np.ndarray:
    # a kernel, not four numpy expressions: the costmaps place the footprint twice a cycle
    out = np.empty((fp.shape[0], 2))
    for i in range(fp.shape[0]):
        out[i, 0] = x + c * fp[i, 0] - s * fp[i, 1]
        out[i, 1] = y + s * fp[i, 0] + c * fp[i, 1]
    return out
