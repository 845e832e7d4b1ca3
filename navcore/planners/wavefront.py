"""The navigation-function wavefront shared by navfn and global_planner (numba kernels).

navfn's "priority block" propagation: cells wait in three buffers (current, next, overflow); a
cell whose new potential is below the threshold pushes its improvable 4-neighbours to ``next``,
otherwise to ``overflow``; when current and next are empty the threshold rises by ``increment``
and the overflow becomes current. The update is navfn's quadratic (planar-wave) one or the plain
``min(4 neighbours) + cost``.

Two deliberate differences from the C++ (both fix real faults, neither changes a converged value):

* The buffers hold the whole map, so no push is ever dropped (ROS caps them at 10000 and silently
  loses cells on large open maps).
* A cell waiting in the overflow buffer is also queued for the current band when a cell below the
  threshold can lower it (ROS leaves it waiting, so the band can end with it unfinished).
* The search stops when a threshold band is exhausted with the target's potential below it, not at
  the first cycle that touches the target. Every update only raises potential (by at least 0.704
  of a cell cost), so all cells below a finished band are final: the target's potential is the
  converged (for the plain update: the exact Dijkstra / A*) value, not a first-touch estimate.

Costs reach the kernel as the raw uint8 costmap plus a 256-entry float32 lookup table (the
planner's cost transform), so no transformed copy of the map is made per plan. Cells whose
``pending`` flag is 3 (the outer border) are never queued: that is navfn's border of COST_OBS and
global_planner's ``outline_map`` without writing into the shared costmap.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

POT_HIGH = np.float32(1.0e10)
INVSQRT2 = 0.707106781

HEURISTIC_NONE = 0
HEURISTIC_MANHATTAN = 1
HEURISTIC_EUCLIDEAN = 2


@njit(cache=True, inline="always")
def _heuristic(n, nx, kind, scale, tx, ty):
    x = np.int64(n) % nx
    y = np.int64(n) // nx
    if kind == HEURISTIC_MANHATTAN:
        return np.float32(scale * (abs(x - tx) + abs(y - ty)))
    return np.float32(scale * math.sqrt((x - tx) * (x - tx) + (y - ty) * (y - ty)))


_QA = np.float32(-0.2301)
_QB = np.float32(0.5307)
_QC = np.float32(0.7040)
_INVSQRT2 = np.float32(INVSQRT2)


@njit(cache=True)
def _grown(buf: np.ndarray) -> np.ndarray:
    big = np.empty(2 * buf.shape[0], buf.dtype)
    big[: buf.shape[0]] = buf
    return big


@njit(cache=True)
def propagate(costs: np.ndarray, lut: np.ndarray, block: float, nx: int, ny: int,
              pot: np.ndarray, pending: np.ndarray, buf_a: np.ndarray, buf_b: np.ndarray,
              buf_c: np.ndarray, seed_cells: np.ndarray, seed_pots: np.ndarray,
              push_cells: np.ndarray, target: int, threshold: float, increment: float,
              max_cycles: int, quadratic: bool, hkind: int, hscale: float) -> tuple:
    """Spread potential from the seeds until ``target`` is final or nothing is left to update.

    ``costs`` is the flat uint8 costmap, ``lut[c]`` the cell cost (>= ``block``: impassable).
    ``pot`` (float32, flat) must hold POT_HIGH everywhere and ``pending`` 0 inside, 3 on the
    border. Seeds get ``seed_pots``; ``push_cells`` start the wave. Returns
    ``(reached, cell_updates, cycles)``.
    """
    ns = nx * ny
    tx = target % nx
    ty = target // nx
    for i in range(seed_cells.shape[0]):
        k = seed_cells[i]
        if 0 <= k < ns:
            pot[k] = seed_pots[i]
    cur, nxt, over = buf_a, buf_b, buf_c
    ncur = 0
    nnext = 0
    nover = 0
    for i in range(push_cells.shape[0]):
        m = push_cells[i]
        if 0 <= m < ns and pending[m] == 0 and lut[costs[m]] < block:
            cur[ncur] = m
            ncur += 1
            pending[m] = 1
    t = np.float32(threshold)
    blk = np.float32(block)
    unx = np.uintp(nx)
    one = np.uintp(1)
    updates = 0
    cycle = 0
    reached = False
    while cycle < max_cycles:
        if ncur == 0:
            break
        for i in range(ncur):
            pending[cur[i]] = 0
        for i in range(ncur):
            # unsigned indices: numba then skips its negative-index wraparound test
            n = np.uintp(cur[i])
            c = lut[costs[n]]
            if c >= blk:
                continue
            updates += 1
            hf = np.float32(math.floor(c))  # global_planner passes the cost as unsigned char
            l = pot[n - one]
            r = pot[n + one]
            u = pot[n - unx]
            d = pot[n + unx]
            tc = l if l < r else r
            ta = u if u < d else d
            if quadratic:
                dc = tc - ta
                if dc < 0.0:
                    dc = -dc
                    ta = tc
                if dc >= hf:
                    p = ta + hf
                else:
                    q = dc / hf
                    p = ta + hf * (_QA * q * q + _QB * q + _QC)
            else:
                p = (ta if ta < tc else tc) + hf
            if not p < pot[n]:
                continue
            pot[n] = p
            if hkind == HEURISTIC_NONE:
                to_next = p < t
            else:
                to_next = p + _heuristic(n, nx, hkind, hscale, tx, ty) < t
            # navfn's push rule, neighbours in its order: left, right, -nx, +nx (unrolled by
            # hand: a helper taking the arrays costs refcounting in the hot loop). pending is
            # 0 idle, 1 queued in current/next, 2 queued in overflow, 3 border (never queued).
            # A cell waiting in overflow that a below-threshold cell can lower is queued in next
            # as well, so the band finishes it (ROS leaves it for the next band); its overflow
            # entry becomes a harmless repeat, the only way overflow can outgrow the map.
            if to_next:
                if l > p:  # cheap test first: neighbours behind the wave fail here
                    m = n - one
                    cm = lut[costs[m]]
                    if l > p + _INVSQRT2 * cm and (pending[m] & 1) == 0 and cm < blk:
                        pending[m] = 1
                        nxt[nnext] = m
                        nnext += 1
                if r > p:  # cheap test first: neighbours behind the wave fail here
                    m = n + one
                    cm = lut[costs[m]]
                    if r > p + _INVSQRT2 * cm and (pending[m] & 1) == 0 and cm < blk:
                        pending[m] = 1
                        nxt[nnext] = m
                        nnext += 1
                if u > p:  # cheap test first: neighbours behind the wave fail here
                    m = n - unx
                    cm = lut[costs[m]]
                    if u > p + _INVSQRT2 * cm and (pending[m] & 1) == 0 and cm < blk:
                        pending[m] = 1
                        nxt[nnext] = m
                        nnext += 1
                if d > p:  # cheap test first: neighbours behind the wave fail here
                    m = n + unx
                    cm = lut[costs[m]]
                    if d > p + _INVSQRT2 * cm and (pending[m] & 1) == 0 and cm < blk:
                        pending[m] = 1
                        nxt[nnext] = m
                        nnext += 1
            else:
                if l > p:  # cheap test first: neighbours behind the wave fail here
                    m = n - one
                    cm = lut[costs[m]]
                    if l > p + _INVSQRT2 * cm and pending[m] == 0 and cm < blk:
                        pending[m] = 2
                        if nover == over.shape[0]:
                            over = _grown(over)
                        over[nover] = m
                        nover += 1
                if r > p:  # cheap test first: neighbours behind the wave fail here
                    m = n + one
                    cm = lut[costs[m]]
                    if r > p + _INVSQRT2 * cm and pending[m] == 0 and cm < blk:
                        pending[m] = 2
                        if nover == over.shape[0]:
                            over = _grown(over)
                        over[nover] = m
                        nover += 1
                if u > p:  # cheap test first: neighbours behind the wave fail here
                    m = n - unx
                    cm = lut[costs[m]]
                    if u > p + _INVSQRT2 * cm and pending[m] == 0 and cm < blk:
                        pending[m] = 2
                        if nover == over.shape[0]:
                            over = _grown(over)
                        over[nover] = m
                        nover += 1
                if d > p:  # cheap test first: neighbours behind the wave fail here
                    m = n + unx
                    cm = lut[costs[m]]
                    if d > p + _INVSQRT2 * cm and pending[m] == 0 and cm < blk:
                        pending[m] = 2
                        if nover == over.shape[0]:
                            over = _grown(over)
                        over[nover] = m
                        nover += 1
        tmp = cur
        cur = nxt
        nxt = tmp
        ncur = nnext
        nnext = 0
        if ncur == 0:
            # band below t is exhausted: every cell under t is final
            if pot[target] < t:
                reached = True
                break
            t += np.float32(increment)
            tmp = cur
            cur = over
            over = tmp
            ncur = nover
            nover = 0
        cycle += 1
    if not reached and pot[target] < POT_HIGH:
        reached = True
    return reached, updates, cycle


def reset_buffers(pot: np.ndarray, pending: np.ndarray, nx: int, ny: int) -> None:
    """POT_HIGH everywhere, pending 0 inside and 3 (never queued) on the outer border."""
    pot.fill(POT_HIGH)
    pending.fill(0)
    p2 = pending.reshape(ny, nx)
    p2[0, :] = 3
    p2[-1, :] = 3
    p2[:, 0] = 3
    p2[:, -1] = 3


class Workspace:
    """Per-map-size buffers reused from plan to plan (ROS reallocates them on every plan)."""

    def __init__(self) -> None:
        self.shape: tuple[int, int] = (0, 0)

    def ensure(self, nx: int, ny: int) -> None:
        if self.shape == (nx, ny):
            return
        ns = nx * ny
        self.shape = (nx, ny)
        self.pot = np.empty(ns, np.float32)
        self.pending = np.empty(ns, np.uint8)
        # Whole-map queues: current and next hold a cell at most once, so they cannot overflow;
        # the overflow queue grows itself in the rare case its repeats outgrow the map.
        # np.empty does not touch the pages, so unused queue space costs no time.
        self.buf_a = np.empty(ns, np.int32)
        self.buf_b = np.empty(ns, np.int32)
        self.buf_c = np.empty(ns, np.int32)
        # gradient caches, kept all-zero between plans by the path kernel
        self.gradx = np.zeros(ns, np.float32)
        self.grady = np.zeros(ns, np.float32)
