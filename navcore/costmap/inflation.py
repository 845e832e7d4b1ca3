"""Inflation: costmap_2d's decaying cost around lethal cells, from an exact Euclidean distance.

costmap_2d's InflationLayer spreads costs with a priority-queue brushfire that approximates the
distance to the nearest lethal cell. Like Nav2's newest inflation layer we compute the exact
distance instead (Felzenszwalb-Huttenlocher lower envelope of parabolas, separable: a column pass
then a row pass) and map squared cell distance to cost through a lookup table built with the
costmap_2d formula. Distances are only needed up to the inflation radius: the column pass is
capped there (so its scratch fits in uint8), the row pass builds the envelope only from cells
near an obstacle and skips the stretches of a row that no obstacle reaches. Cells farther than
the radius keep their cost, exactly as costmap_2d leaves them unvisited.
"""

from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from numba import njit

from navcore.costmap.cost_values import (FREE_SPACE, INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE,
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
def _column_pass(costs: np.ndarray, g: np.ndarray, sx0: int, sy0: int, sxn: int, syn: int,
                 cap: int) -> None:
    """g[j - sy0, i - sx0] = vertical cell distance to the nearest lethal cell, capped at ``cap``.

    Two row-by-row sweeps (down then up) so that memory is read in order.
    """
    w = sxn - sx0
    row = costs[sy0, sx0:sxn]
    gj = g[0]
    for i in range(w):
        gj[i] = 0 if row[i] == LETHAL_OBSTACLE else cap
    for j in range(1, syn - sy0):
        row = costs[sy0 + j, sx0:sxn]
        gp = g[j - 1]
        gj = g[j]
        for i in range(w):
            if row[i] == LETHAL_OBSTACLE:
                gj[i] = 0
            else:
                v = gp[i] + 1
                gj[i] = v if v < cap else cap
    for j in range(syn - sy0 - 2, -1, -1):
        gn = g[j + 1]
        gj = g[j]
        for i in range(w):
            v = gn[i] + 1
            if v < gj[i]:
                gj[i] = v


@njit(cache=True, nogil=True)
def _inflate_kernel(costs: np.ndarray, x0: int, y0: int, xn: int, yn: int, sx0: int, sy0: int,
                    sxn: int, syn: int, table: np.ndarray, r: int, inflate_unknown: bool,
                    g: np.ndarray) -> None:
    """Write inflated costs into ``costs`` over [x0, xn) x [y0, yn), from the lethal cells of the
    source window [sx0, sxn) x [sy0, syn) (the update window grown by the cell radius).

    ``g`` is a scratch of at least the source window's shape (uint8 when the cap fits).
    """
    cap = r + 1
    r2 = r * r
    _column_pass(costs, g, sx0, sy0, sxn, syn, cap)
    w = sxn - sx0
    v = np.empty(w, dtype=np.int64)        # envelope sites (column offsets)
    fv = np.empty(w, dtype=np.int64)       # their squared vertical distances
    z = np.empty(w + 1, dtype=np.float64)  # envelope breakpoints
    for y in range(y0, yn):
        gr = g[y - sy0]
        # lower envelope of the parabolas (x - q)^2 + g[q]^2, only from sites closer than the
        # cap: farther ones cannot give a distance within the radius
        k = -1
        for q in range(w):
            gq = np.int64(gr[q])
            if gq >= cap:
                continue
            fq = gq * gq
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
            continue
        row = costs[y]
        j = 0
        lo = max(x0, sx0 + v[0] - r)
        hi = min(xn, sx0 + v[k] + r + 1)
        x = lo
        while x < hi:
            xo = x - sx0
            while z[j + 1] < xo:
                j += 1
            dx = xo - v[j]
            d2 = dx * dx + fv[j]
            if d2 > r2:
                # beyond the radius of every site; if even the horizontal distance to the
                # nearest site is, skip to where the next site comes within the radius
                if dx > r:
                    if j == k:
                        break
                    x = max(x + 1, sx0 + v[j + 1] - r)
                elif dx < -r:
                    x = max(x + 1, sx0 + v[j] - r)
                else:
                    x += 1
                continue
            cost = table[d2]
            old = row[x]
            if old == NO_INFORMATION:
                if inflate_unknown:
                    if cost > FREE_SPACE:
                        row[x] = cost
                elif cost >= INSCRIBED_INFLATED_OBSTACLE:
                    row[x] = cost
            elif cost > old:
                row[x] = cost
            x += 1


_POOL: ThreadPoolExecutor | None = None
_POOL_SIZE = 0
MIN_ROWS_PER_THREAD = 128  # below this a thread costs more than it saves


def _pool(n: int) -> ThreadPoolExecutor:
    global _POOL, _POOL_SIZE
    if _POOL is None or _POOL_SIZE < n:
        _POOL = ThreadPoolExecutor(max_workers=n, thread_name_prefix="inflation")
        _POOL_SIZE = n
    return _POOL


def _scratch_for(r: int, shape: tuple[int, int], scratch: np.ndarray | None) -> np.ndarray:
    dtype = np.uint8 if r + 1 <= 255 else np.int32  # distances are capped at r + 1
    if (scratch is None or scratch.dtype != dtype or scratch.shape[0] < shape[0]
            or scratch.shape[1] < shape[1]):
        scratch = np.empty(shape, dtype=dtype)
    return scratch


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
    inflate_unknown = bool(inflate_unknown)
    bands = max(1, min(int(num_threads), (yn - y0) // MIN_ROWS_PER_THREAD))
    edges = [y0 + (yn - y0) * i // bands for i in range(bands + 1)]
    jobs = []
    for i in range(bands):
        a, b = edges[i], edges[i + 1]
        sx0, sy0 = max(0, x0 - r), max(0, a - r)
        sxn, syn = min(w, xn + r), min(h, b + r)
        if len(scratch) <= i:
            scratch.append(None)
        scratch[i] = _scratch_for(r, (syn - sy0, sxn - sx0), scratch[i])
        jobs.append((costs, x0, a, xn, b, sx0, sy0, sxn, syn, table, r, inflate_unknown,
                     scratch[i]))
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
