"""Inflation: costmap_2d's decaying cost around lethal cells, from an exact Euclidean distance.

costmap_2d's InflationLayer spreads costs with a priority-queue brushfire that approximates the
distance to the nearest lethal cell. We compute the exact distance instead (as Nav2's newest
inflation layer does), separably, and map squared cell distance to cost through a lookup table
built with the costmap_2d formula. Costs only depend on distances up to the inflation radius r
(in cells), so a transform truncated there is enough (proof at ``_inflate_block``): a column
pass of vertical distances capped at r + 1, then per row d^2(x) = min over |dx| <= r of
g(x + dx)^2 + dx^2. Both passes go row after row over contiguous memory in the narrowest integer
type that holds the numbers (uint8 at the usual radii), so numba vectorises them, and a large
window is done in blocks of rows that stay in cache. For very large radii the row pass uses the
lower envelope of parabolas instead (Felzenszwalb-Huttenlocher), which costs O(1) per cell
whatever r. Cells farther than the radius keep their cost, exactly as costmap_2d leaves them
unvisited.
"""

from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from numba import njit

from navcore.costmap.cost_values import (INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE,
                                         NO_INFORMATION)
from navcore.params import Param, Parameters


def compute_cost(distance_cells: float, resolution: float, inscribed_radius: float,
                 cost_scaling_factor: float) -> int:
    """costmap_2d computeCost: the cost of a cell ``distance_cells`` cells from a lethal cell."""
    if distance_cells == 0:
        return LETHAL_OBSTACLE
    d = distance_cells * resolution
    if d <= inscribed_radius:
        return INSCRIBED_INFLATED_OBSTACLE
    factor = math.exp(-1.0 * cost_scaling_factor * (d - inscribed_radius))
    return int((INSCRIBED_INFLATED_OBSTACLE - 1) * factor)


def cell_inflation_radius(inflation_radius: float, resolution: float) -> int:
    """costmap_2d cellDistance(inflation_radius): whole cells covering the radius."""
    return max(0, int(math.ceil(inflation_radius / resolution)))


def cost_table(resolution: float, inscribed_radius: float, inflation_radius: float,
               cost_scaling_factor: float) -> np.ndarray:
    """Cost by squared cell distance: ``table[dx*dx + dy*dy]`` for distances up to the cell radius.

    uint8, length R*R + 1 with R = cell_inflation_radius; cells farther than R get no cost, as in
    costmap_2d, which never visits them.
    """
    r = cell_inflation_radius(inflation_radius, resolution)
    d2 = np.arange(r * r + 1, dtype=np.float64)
    d = np.sqrt(d2)
    table = np.empty(r * r + 1, dtype=np.uint8)
    for i in range(len(table)):
        table[i] = compute_cost(float(d[i]), resolution, inscribed_radius, cost_scaling_factor)
    return table


@njit(cache=True, nogil=True)
def _column_pass_down(costs: np.ndarray, g: np.ndarray, sx0: int, sy0: int, sxn: int, syn: int,
                      cap: int) -> None:
    """g[j - sy0, i - sx0] = cell distance up to the nearest lethal cell at or above row j in
    column i, capped at ``cap``. Row after row, so every step is a contiguous vector operation."""
    t = g.dtype.type
    w = sxn - sx0
    c = t(cap)
    zero = t(0)
    one = t(1)
    row = costs[sy0, sx0:sxn]
    gj = g[0]
    for i in range(w):
        gj[i] = zero if row[i] == LETHAL_OBSTACLE else c
    for j in range(1, syn - sy0):
        row = costs[sy0 + j, sx0:sxn]
        gp = g[j - 1]
        gj = g[j]
        for i in range(w):
            v = min(t(gp[i] + one), c)  # (t's arithmetic: g's type holds cap + 1)
            gj[i] = zero if row[i] == LETHAL_OBSTACLE else v


@njit(cache=True, nogil=True)
def _finish_row(g: np.ndarray, j: int, rows: int, w: int, r: int, pad: np.ndarray) -> None:
    """The up sweep for row j (from the finished row j + 1 below it), and the row's squared
    column distances into ``pad[r:r + w]``, clamped at r^2 + 1 ("out of reach")."""
    gj = g[j]
    one = g.dtype.type(1)
    if j + 1 < rows:
        gn = g[j + 1]
        for i in range(w):
            gj[i] = min(gj[i], g.dtype.type(gn[i] + one))
    # narrow arithmetic so that it vectorises: the row type holds (r + 1)^2 (see _row_type)
    t = pad.dtype.type
    beyond = t(r * r + 1)
    sq = pad[r:r + w]
    for i in range(w):
        gi = t(gj[i])
        sq[i] = min(t(gi * gi), beyond)


@njit(cache=True, nogil=True)
def _row_pass_window(pad: np.ndarray, ox: int, nx: int, r: int, d2: np.ndarray) -> None:
    """d2[x] = min over |dx| <= r of pad[r + ox + x + dx] + dx^2.

    ``pad`` holds a row's clamped squared column distances with r out-of-reach cells on either
    side, so every tap is a contiguous, branch-free pass; the taps +dx and -dx share one. Sums
    stay below 2 r^2 + 2, so the buffers' type can be as narrow as uint8 for the usual radii
    (32 cells per instruction).
    """
    t = pad.dtype.type
    base = ox + r
    mid = pad[base:base + nx]
    for x in range(nx):
        d2[x] = mid[x]
    for dx in range(1, r + 1):
        c = np.int64(dx * dx)
        left = pad[base - dx:base - dx + nx]
        right = pad[base + dx:base + dx + nx]
        for x in range(nx):
            d2[x] = min(d2[x], t(min(left[x], right[x]) + c))


@njit(cache=True, nogil=True)
def _row_pass_envelope(pad: np.ndarray, ox: int, nx: int, r: int, v: np.ndarray,
                       fv: np.ndarray, z: np.ndarray, d2: np.ndarray) -> None:
    """What ``_row_pass_window`` computes wherever it is at most r^2 (elsewhere only "beyond r^2"
    is guaranteed), in O(width) whatever the radius: the lower envelope of the parabolas
    (x - q)^2 + g[q]^2 of the sites q closer than the cap (Felzenszwalb-Huttenlocher); farther
    sites cannot give a distance within the radius."""
    beyond = r * r + 1
    w = pad.shape[0] - 2 * r
    k = -1
    for q in range(w):
        fq = np.int64(pad[r + q])
        if fq >= beyond:
            continue
        if k < 0:
            k = 0
            v[0] = q
            fv[0] = fq
            z[0] = -1e300
            z[1] = 1e300
            continue
        while True:
            p = v[k]
            s = ((fq + q * q) - (fv[k] + p * p)) / (2.0 * (q - p))
            if s <= z[k]:
                k -= 1
            else:
                break
        k += 1
        v[k] = q
        fv[k] = fq
        z[k] = s
        z[k + 1] = 1e300
    if k < 0:
        for x in range(nx):
            d2[x] = beyond
        return
    j = 0
    for x in range(nx):
        xo = x + ox
        while z[j + 1] < xo:
            j += 1
        dx = xo - v[j]
        d2[x] = min(dx * dx + fv[j], beyond)


# The first cell radius whose window-pass sums (up to 2 r^2 + 1) overflow uint16. Below it the
# 2r + 1 vector taps of ``_row_pass_window`` win even at large radii; from it on they run at half
# the lanes (int32) and the envelope's O(1) per cell is faster. Measured on the 2000x2000 office
# map, ms for window / envelope: r = 11: 12.6 / 52; r = 180: 52 / 87; r = 182: 129 / 59.
ENVELOPE_FROM_RADIUS = 182


def _row_type(r: int) -> type:
    """The row buffers' dtype for cell radius r: the narrowest that holds 2 r^2 + 1 (and so
    (r + 1)^2, the largest square ``_finish_row`` forms)."""
    if 2 * r * r + 1 <= 255:
        return np.uint8
    if 2 * r * r + 1 <= 65535:
        return np.uint16
    return np.int32


@njit(cache=True, nogil=True)
def _inflate_block(costs: np.ndarray, x0: int, y0: int, xn: int, yn: int, sx0: int, sy0: int,
                   sxn: int, syn: int, cost_by_d2: np.ndarray, unknown_takes: int, r: int,
                   envelope: bool, g: np.ndarray, pad: np.ndarray, d2: np.ndarray) -> None:
    """Write inflated costs into ``costs`` over [x0, xn) x [y0, yn), from the lethal cells of the
    source window [sx0, sxn) x [sy0, syn) (the update window grown by the cell radius r).

    Why distances capped at r + 1 are enough: with G the exact vertical distance, the squared
    distance is D(x) = min over q of (x - q)^2 + G(q)^2. The row pass computes
    E(x) = min over |x - q| <= r of (x - q)^2 + g(q)^2 with g = min(G, r + 1). Each of its terms
    is either a term of D (g = G) or at least (r + 1)^2 (g = r + 1), so E >= min(D, (r + 1)^2).
    If D <= r^2, its best site q* has |x - q*| <= r and G(q*) <= r, so g(q*) = G(q*), the term
    is in E's range and E <= D: E = D. If D > r^2, E > r^2 too. So E is exact wherever a cost is
    due, and beyond the radius both say "out of reach". Lethal cells outside the source window
    are more than r away from the update window in x or y, so they never matter.

    ``cost_by_d2[d2]`` is the cost at squared distance d2 <= r^2, and 0 (which changes nothing)
    at r^2 + 1; an unknown cell takes costs from ``unknown_takes`` up. ``g`` is a scratch of at
    least the source window's shape; ``pad`` and ``d2`` are row scratch of the dtype
    ``_row_type`` gives.
    ``envelope`` picks the row pass (both give the same costs; see ENVELOPE_FROM_RADIUS).
    Squared distances are clamped at r^2 + 1: that changes no value up to r^2 and keeps larger
    ones larger.
    """
    cap = r + 1
    r2 = r * r
    _column_pass_down(costs, g, sx0, sy0, sxn, syn, cap)
    w = sxn - sx0
    rows = syn - sy0
    far = pad.dtype.type(r2 + 1)
    beyond = d2.dtype.type(r2 + 1)
    takes = np.uint8(unknown_takes)
    unknown = np.uint8(NO_INFORMATION)
    for i in range(r):
        pad[i] = far
        pad[r + w + i] = far
    padw = pad[:w + 2 * r]
    ox = x0 - sx0
    nx = xn - x0
    if envelope:
        v = np.empty(w, dtype=np.int64)
        fv = np.empty(w, dtype=np.int64)
        z = np.empty(w + 1, dtype=np.float64)
    for y in range(syn - 1, y0 - 1, -1):
        j = y - sy0
        _finish_row(g, j, rows, w, r, pad)  # the up sweep, row by row, while in cache
        if y >= yn:
            continue
        if envelope:
            _row_pass_envelope(padw, ox, nx, r, v, fv, z, d2)
        else:
            _row_pass_window(padw, ox, nx, r, d2)
        # costs: a scalar lookup alone (branch-free, the only part that cannot vectorise),
        # then the merge as a vector pass
        for x in range(nx):
            d2[x] = cost_by_d2[min(d2[x], beyond)]
        row = costs[y, x0:xn]
        for x in range(nx):
            old = row[x]
            c = np.uint8(d2[x])
            row[x] = (c if c >= takes else unknown) if old == unknown else max(old, c)


@njit(cache=True, nogil=True)
def _inflate_kernel(costs: np.ndarray, x0: int, y0: int, xn: int, yn: int, sx0: int, sy0: int,
                    sxn: int, syn: int, cost_by_d2: np.ndarray, unknown_takes: int, r: int,
                    envelope: bool, block_rows: int, g: np.ndarray, pad: np.ndarray,
                    d2: np.ndarray) -> None:
    """``_inflate_block`` over [y0, yn) in blocks of ``block_rows`` rows, each from its own
    source rows (r more on either side, within [sy0, syn)), so that the column distances of a
    block stay in cache; ``g`` needs block_rows + 2r rows."""
    for a in range(y0, yn, block_rows):
        b = min(a + block_rows, yn)
        _inflate_block(costs, x0, a, xn, b, sx0, max(sy0, a - r), sxn, min(syn, b + r),
                       cost_by_d2, unknown_takes, r, envelope, g, pad, d2)


def _block_rows(r: int, width: int) -> int:
    """Rows per block: column distances of about 128 KB (L2-resident), and enough rows that the
    2r rows of overlap stay a small part of the column pass."""
    return max(BLOCK_BYTES // max(width, 1), 8 * r, 16)


BLOCK_BYTES = 1 << 17  # measured: 10-15% faster than unblocked at 2000^2 and 4000^2

_POOL: ThreadPoolExecutor | None = None
_POOL_SIZE = 0
MIN_ROWS_PER_THREAD = 128  # below this a thread costs more than it saves


def _pool(n: int) -> ThreadPoolExecutor:
    global _POOL, _POOL_SIZE
    if _POOL is None or _POOL_SIZE < n:
        _POOL = ThreadPoolExecutor(max_workers=n, thread_name_prefix="inflation")
        _POOL_SIZE = n
    return _POOL


_KERNEL_TABLES: dict = {}  # table bytes -> the kernel's table


def _kernel_table(table: np.ndarray) -> np.ndarray:
    """``table`` (uint8) with a 0 appended for "beyond the radius", remembered (a local costmap
    inflates every cycle with the same table)."""
    key = table.tobytes()
    out = _KERNEL_TABLES.get(key)
    if out is None:
        out = np.zeros(len(table) + 1, dtype=np.uint8)
        out[:-1] = table
        if len(_KERNEL_TABLES) >= 16:
            _KERNEL_TABLES.clear()
        _KERNEL_TABLES[key] = out
    return out


def _buffers(r: int, shape: tuple[int, int], nx: int, old: tuple | None) -> tuple:
    """Scratch for one band: column distances ``g`` (uint8 when the cap r + 1 fits), the padded
    row and the row of squared distances (of ``_row_type``)."""
    g_type = np.uint8 if r + 2 <= 255 else np.int32  # holds the cap r + 1, plus one
    d_type = _row_type(r)
    g, pad, d2 = old if old is not None else (None, None, None)
    if (g is None or g.dtype != g_type or g.shape[0] < shape[0] or g.shape[1] < shape[1]):
        g = np.empty(shape, dtype=g_type)
    if pad is None or pad.dtype != d_type or len(pad) < shape[1] + 2 * r:
        pad = np.empty(shape[1] + 2 * r, dtype=d_type)
    if d2 is None or d2.dtype != d_type or len(d2) < nx:
        d2 = np.empty(nx, dtype=d_type)
    return g, pad, d2


def inflate(costs: np.ndarray, table: np.ndarray, x0: int = 0, y0: int = 0, xn: int | None = None,
            yn: int | None = None, inflate_unknown: bool = False,
            scratch: list | None = None, num_threads: int = 1) -> list:
    """Inflate the lethal cells of ``costs`` (uint8 [my, mx]) in place over [x0, xn) x [y0, yn).

    Obstacles up to the table's radius outside the window count too. Merge as costmap_2d: an
    unknown cell takes the new cost only if it is inscribed or lethal (any nonzero cost with
    ``inflate_unknown``), others keep the max. With ``num_threads`` > 1 large windows are cut
    into bands of rows inflated concurrently (the kernel releases the GIL); the result is the
    same, since inflation never creates or removes a lethal cell. Returns the scratch buffers,
    which may be passed back in to save allocations.
    """
    scratch = list(scratch) if scratch else []
    h, w = costs.shape
    xn = w if xn is None else min(int(xn), w)
    yn = h if yn is None else min(int(yn), h)
    x0, y0 = max(0, int(x0)), max(0, int(y0))
    if xn <= x0 or yn <= y0:
        return scratch
    r = int(round(math.sqrt(len(table) - 1)))
    cost_by_d2 = _kernel_table(table)
    # costmap_2d: an unknown cell takes an inscribed or lethal cost, any nonzero one with
    # inflate_unknown
    unknown_takes = 1 if inflate_unknown else INSCRIBED_INFLATED_OBSTACLE
    bands = max(1, min(int(num_threads), (yn - y0) // MIN_ROWS_PER_THREAD))
    edges = [y0 + (yn - y0) * i // bands for i in range(bands + 1)]
    jobs = []
    for i in range(bands):
        a, b = edges[i], edges[i + 1]
        sx0, sy0 = max(0, x0 - r), max(0, a - r)
        sxn, syn = min(w, xn + r), min(h, b + r)
        if len(scratch) <= i:
            scratch.append(None)
        block = _block_rows(r, sxn - sx0)
        rows = min(syn - sy0, block + 2 * r)
        scratch[i] = _buffers(r, (rows, sxn - sx0), xn - x0, scratch[i])
        jobs.append((costs, x0, a, xn, b, sx0, sy0, sxn, syn, cost_by_d2, unknown_takes, r,
                     r >= ENVELOPE_FROM_RADIUS, block) + scratch[i])
    if bands == 1:
        _inflate_kernel(*jobs[0])
    else:
        for f in [_pool(bands).submit(_inflate_kernel, *job) for job in jobs]:
            f.result()
    return scratch


INFLATION_PARAMS = (
    Param("enabled", True, bool, "whether the layer contributes"),
    Param("inflation_radius", 0.55, float, "radius (m) to which costs are spread", min=0.0,
          max=50.0),
    Param("cost_scaling_factor", 10.0, float, "exponential decay rate (1/m) of the inflated cost",
          min=0.0, max=100.0),
    Param("inflate_unknown", False, bool, "also write inflated costs into unknown cells"),
    Param("num_threads", 1, int, "threads for large updates (Nav2's parameter)", min=1, max=64),
)


class InflationLayer:
    """costmap_2d::InflationLayer: inflates the master grid's lethal cells in place.

    Its bounds grow the update window by ``inflation_radius`` around the union of this update's
    and the previous update's windows, so that costs fade where obstacles disappeared. Only that
    window is re-inflated. Parameter changes (or a new footprint) force a full re-inflation.
    """

    kind = "inflation"
    clearable = False

    def __init__(self, name: str, params: dict | None = None, inscribed_radius: float = 0.0,
                 resolution: float = 0.05) -> None:
        self.name = name
        self.params = Parameters(INFLATION_PARAMS, params or {}, where=name)
        self.current = True
        self._inscribed = float(inscribed_radius)
        self._resolution = float(resolution)
        self._table: np.ndarray | None = None
        self._table_key: tuple | None = None
        self._scratch: list = []
        self._last: tuple[float, float, float, float] | None = None
        self._applied: tuple | None = None  # the parameter values of the last inflation
        self.need_reinflation = True

    @property
    def enabled(self) -> bool:
        return bool(self.params.enabled)

    def set_parameters(self, values: dict) -> dict:
        """Change parameters at run time (dynamic_reconfigure); forces a full re-inflation."""
        prev = self.params.set(values)
        self.need_reinflation = True
        return prev

    def on_footprint_changed(self, inscribed_radius: float, circumscribed_radius: float) -> None:
        self._inscribed = float(inscribed_radius)
        self.need_reinflation = True

    def match_size(self, size_x: int, size_y: int, resolution: float, origin_x: float,
                   origin_y: float) -> None:
        if resolution != self._resolution:
            self._resolution = float(resolution)
            self.need_reinflation = True

    def update_origin(self, origin_x: float, origin_y: float) -> None:
        """The master moved; the inflation layer keeps no grid of its own."""

    def reset(self) -> None:
        self.need_reinflation = True
        self._last = None

    def table(self) -> np.ndarray:
        """The cost lookup table for the current parameters (rebuilt when they change)."""
        key = (self._resolution, self._inscribed, self.params.inflation_radius,
               self.params.cost_scaling_factor)
        # (num_threads and inflate_unknown do not change the table)
        if self._table is None or key != self._table_key:
            self._table = cost_table(*key)
            self._table_key = key
        return self._table

    def update_bounds(self, robot_x: float, robot_y: float, robot_yaw: float,
                      bounds: list[float]) -> None:
        """Grow ``bounds`` ([min_x, min_y, max_x, max_y], metres) as costmap_2d does."""
        if not self.enabled:
            self._applied = None
            return
        # a parameter changed (even straight through ``params.set``): inflate everything again
        applied = (self.params.inflation_radius, self.params.cost_scaling_factor,
                   self.params.inflate_unknown, self._inscribed, self._resolution)
        if applied != self._applied:
            self.need_reinflation = True
            self._applied = applied
        if self.need_reinflation:
            self._last = (bounds[0], bounds[1], bounds[2], bounds[3])
            bounds[0] = bounds[1] = -1e30
            bounds[2] = bounds[3] = 1e30
            self.need_reinflation = False
            return
        last = self._last if self._last is not None else (bounds[0], bounds[1], bounds[2],
                                                           bounds[3])
        self._last = (bounds[0], bounds[1], bounds[2], bounds[3])
        r = self.params.inflation_radius
        bounds[0] = min(last[0], bounds[0]) - r
        bounds[1] = min(last[1], bounds[1]) - r
        bounds[2] = max(last[2], bounds[2]) + r
        bounds[3] = max(last[3], bounds[3]) + r

    def update_costs(self, master, x0: int, y0: int, xn: int, yn: int) -> None:
        """Inflate ``master`` (a Costmap2D) over the cell window [x0, xn) x [y0, yn)."""
        if not self.enabled or xn <= x0 or yn <= y0:
            return
        self._resolution = master.resolution
        self._scratch = inflate(master.costs, self.table(), x0, y0, xn, yn,
                                self.params.inflate_unknown, self._scratch,
                                self.params.num_threads)
