"""The navigation-function wavefront shared by navfn and global_planner (numba kernels).

navfn's "priority block" propagation: cells wait in three buffers (current, next, overflow); a
cell whose new potential is below the threshold pushes its improvable 4-neighbours to ``next``,
otherwise to ``overflow``; when current and next are empty the threshold rises by ``increment``
and the overflow becomes current. The update is navfn's quadratic (planar-wave) one or the plain
``min(4 neighbours) + cost``.

Deliberate differences from the C++ (the first three fix real faults; none changes a converged
value):

* The buffers hold the whole map, so no push is ever dropped (ROS caps them at 10000 and silently
  loses cells on large open maps).
* A cell waiting in the overflow buffer is also queued for the current band when a cell below the
  threshold can lower it (ROS leaves it waiting, so the band can end with it unfinished).
* The search stops when a threshold band is exhausted with the target's potential below it, not at
  the first cycle that touches the target. Every update only raises potential (by at least 0.704
  of a cell cost), so all cells below a finished band are final: the target's potential is the
  converged (for the plain update: the exact Dijkstra) value, not a first-touch estimate.
* A queue filled as ``next`` has its cells' flags cleared one by one as they come up, not all at
  the start of the cycle, so a cell lowered earlier in the same cycle is not queued again.

Costs reach the kernel as the raw uint8 costmap plus a 256-entry float32 lookup table (the
planner's cost transform), so no transformed copy of the map is made per plan. Cells whose
``pending`` flag is 4 (the outer border) are never queued: that is navfn's border of COST_OBS and
global_planner's ``outline_map`` without writing into the shared costmap.

A* (``hkind``) is navfn's ``calcNavFnAstar``: the band of a cell is chosen by potential plus
heuristic. Maps of ``TILED_MIN_CELLS`` or more run on a copy in 8x8 tiles (``run_wavefront``):
same visiting order, so the same potentials, with far fewer cache misses along the front.

Performance notes (CPU time, office maps; see bench/bench_planners.py). The quadratic update is
not monotone (its factor jumps from 1.0046 to 1 at ``dc == hf``), so its potentials depend on the
visiting order: a strided order moved the 1000^2 goal potential by 0.6 %. Optimisations here keep
the order. Measured without gain: a per-plan float32 cost array instead of the uint8 map + table,
interleaved potential/cost pairs, FMA contraction, a premultiplied push table, OR-ed flags.
Dropping the pending flags altogether (duplicates allowed) saves ~25 % per update but costs 55 %
more updates. In cache the kernel needs ~24 ns per update, ~37 ns at 2000^2 row-major.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

POT_HIGH = np.float32(1.0e10)
INVSQRT2 = 0.707106781

_QA = np.float32(-0.2301)
_QB = np.float32(0.5307)
_QC = np.float32(0.7040)
_INVSQRT2 = np.float32(INVSQRT2)


HEURISTIC_NONE = 0
HEURISTIC_MANHATTAN = 1
HEURISTIC_EUCLIDEAN = 2


@njit(cache=True, inline="always")
def _heuristic(x: int, y: int, tx: int, ty: int, hkind: int, hscale: float) -> float:
    dx = abs(x - tx)
    dy = abs(y - ty)
    if hkind == HEURISTIC_MANHATTAN:
        return hscale * (dx + dy)
    return hscale * math.sqrt(dx * dx + dy * dy)


# Tiled layout: the map in TILE x TILE blocks, row-major inside a block and block by block in
# row-major order, so a cache line of potentials covers a 2-D patch instead of a piece of one row.
# The wave front is a curve; row-major, each of its cells drags in three rows' worth of lines and
# on big maps these no longer stay in cache from one cycle to the next.
TILE_SHIFT = 3
TILE = 1 << TILE_SHIFT
TILED_MIN_CELLS = 3_000_000  # measured: no gain below about 2000^2 once the layout change counts


@njit(cache=True, inline="always")
def tile_index(x: int, y: int, ntx: int) -> int:
    """Index of cell (x, y) in the tiled layout of a map ``ntx`` tiles wide."""
    return (((y >> TILE_SHIFT) * ntx + (x >> TILE_SHIFT)) << (2 * TILE_SHIFT)) \
        + ((y & (TILE - 1)) << TILE_SHIFT) + (x & (TILE - 1))


@njit(cache=True, inline="always")
def _cell_xy(n: int, nx: int, ntx: int, tiled: bool) -> tuple:
    if not tiled:
        y = n // nx
        return n - y * nx, y
    b = n >> (2 * TILE_SHIFT)
    by = b // ntx
    return ((b - by * ntx) << TILE_SHIFT) + (n & (TILE - 1)), \
        (by << TILE_SHIFT) + ((n >> TILE_SHIFT) & (TILE - 1))


@njit(cache=True)
def _to_tiled(cells: np.ndarray, nx: int, ns: int, ntx: int) -> np.ndarray:
    """Row-major cell indices to tiled ones (out-of-map ones become -1)."""
    out = np.empty(cells.shape[0], np.int64)
    for i in range(cells.shape[0]):
        c = cells[i]
        out[i] = tile_index(c % nx, c // nx, ntx) if 0 <= c < ns else -1
    return out


@njit(cache=True)
def tile_map(costs: np.ndarray, nx: int, ny: int, out: np.ndarray, pad: int) -> None:
    """Row-major uint8 map (flat) into the tiled layout; cells past the map edge get ``pad``."""
    ntx = (nx + TILE - 1) // TILE
    nty = (ny + TILE - 1) // TILE
    full = nx // TILE  # tiles wholly inside the map's width: a fixed-length copy each
    for y in range(nty * TILE):
        base = tile_index(0, y, ntx)
        if y >= ny:
            for bx in range(ntx):
                for lx in range(TILE):
                    out[base + (bx << (2 * TILE_SHIFT)) + lx] = pad
            continue
        row = y * nx
        for bx in range(full):
            o = base + (bx << (2 * TILE_SHIFT))
            r = row + bx * TILE
            for lx in range(TILE):
                out[o + lx] = costs[r + lx]
        if full < ntx:
            o = base + (full << (2 * TILE_SHIFT))
            for lx in range(TILE):
                x = full * TILE + lx
                out[o + lx] = costs[row + x] if x < nx else pad


@njit(cache=True)
def untile_pot(tpot: np.ndarray, nx: int, ny: int, out: np.ndarray) -> None:
    """Tiled potential back to the row-major flat ``out``."""
    ntx = (nx + TILE - 1) // TILE
    full = nx // TILE
    for y in range(ny):
        row = y * nx
        base = tile_index(0, y, ntx)
        for bx in range(full):
            o = base + (bx << (2 * TILE_SHIFT))
            r = row + bx * TILE
            for lx in range(TILE):
                out[r + lx] = tpot[o + lx]
        if full < ntx:
            o = base + (full << (2 * TILE_SHIFT))
            for lx in range(nx - full * TILE):
                out[row + full * TILE + lx] = tpot[o + lx]


@njit(cache=True)
def _reset_tiled(tpot: np.ndarray, tpending: np.ndarray, nx: int, ny: int) -> None:
    """POT_HIGH everywhere; pending 0 inside, 4 (never queued) on the border and the padding."""
    ntx = (nx + TILE - 1) // TILE
    nty = (ny + TILE - 1) // TILE
    tpot[:] = POT_HIGH
    tpending[:] = 0
    for x in range(ntx * TILE):
        tpending[tile_index(x, 0, ntx)] = 4
        for y in range(ny - 1, nty * TILE):
            tpending[tile_index(x, y, ntx)] = 4
    for y in range(ny):
        tpending[tile_index(0, y, ntx)] = 4
        for x in range(nx - 1, ntx * TILE):
            tpending[tile_index(x, y, ntx)] = 4


@njit(cache=True)
def _grown(buf: np.ndarray, need: int) -> np.ndarray:
    big = np.empty(max(2 * buf.shape[0], need), buf.dtype)
    big[: buf.shape[0]] = buf
    return big


# The push rule (navfn's, plus the overflow upgrade), applied to each neighbour m (old potential
# pm) of a cell that just got potential p, written out inline in ``propagate``: queue m when
# pm > p + cost(m)/sqrt(2) (cost +inf: impassable). It is branch-free within a neighbour (at the
# wave front the outcome is a coin flip, and mispredictions dominated the run time): m is always
# stored at the end of the queue and only the count advances when it belongs there. pending is
# 0 idle, 1 queued in current/next, 2 queued in overflow, 4 border (never queued). Below the
# threshold m goes to next, also when it waits in overflow (so the band finishes it; ROS leaves
# it waiting, and its overflow entry becomes a harmless repeat); above it, to overflow.


@njit(cache=True)
def propagate(costs: np.ndarray, lut: np.ndarray, lut_hf: np.ndarray, lut_inv: np.ndarray,
              nx: int, ny: int, pot: np.ndarray, pending: np.ndarray, buf_a: np.ndarray,
              buf_b: np.ndarray, buf_c: np.ndarray, seed_cells: np.ndarray, seed_pots: np.ndarray,
              push_cells: np.ndarray, target: int, threshold: float, increment: float,
              max_cycles: int, quadratic: bool, hkind: int = 0, hscale: float = 0.0,
              tiled: bool = False) -> tuple:
    """Spread potential from the seeds until ``target`` is final or nothing is left to update.

    ``costs`` is the flat uint8 costmap; ``lut[c]`` the cell cost, +inf where impassable (so the
    push test ``old > new + cost / sqrt(2)`` also rejects impassable cells); ``lut_hf[c]`` the cost
    the update adds (global_planner truncates it to an integer) and ``lut_inv[c]`` its reciprocal.
    Use ``kernel_tables`` to make the three.
    ``pot`` (float32, flat) must hold POT_HIGH everywhere and ``pending`` 0 inside, 4 on the
    border. Seeds get ``seed_pots``; ``push_cells`` start the wave. Returns
    ``(reached, cell_updates, cycles)``.

    With ``hkind`` HEURISTIC_MANHATTAN or HEURISTIC_EUCLIDEAN this is A* in navfn's
    ``calcNavFnAstar`` manner: a cell's band is decided by potential + ``hscale`` x its distance
    to ``target`` instead of the potential alone (the stored potential has no heuristic). With a
    consistent heuristic every cell whose key is below a finished band is final, as above.

    With ``tiled`` the map arrays (``costs``, ``pot``, ``pending``) are in the tiled layout of
    ``tile_index`` (see ``Workspace``) while seeds, pushes and target stay row-major indices; the
    cells are visited in exactly the same order, so the potential is the same.
    """
    ns = nx * ny
    ntx = (nx + TILE - 1) // TILE
    tx = target % nx
    ty = target // nx
    if tiled:
        seed_cells = _to_tiled(seed_cells, nx, ns, ntx)
        push_cells = _to_tiled(push_cells, nx, ns, ntx)
        target = tile_index(tx, ty, ntx)
        ns = pot.shape[0]
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
        if 0 <= m < ns and pending[m] == 0 and lut[costs[m]] < np.inf:
            cur[ncur] = m
            ncur += 1
            pending[m] = 1
    if hkind != HEURISTIC_NONE and seed_cells.shape[0] > 0:
        # the first band starts at the seed's key, not at its potential
        sx, sy = _cell_xy(seed_cells[0], nx, ntx, tiled)
        threshold += _heuristic(sx, sy, tx, ty, hkind, hscale)
    t = np.float32(threshold)
    inc = np.float32(increment)
    unx = np.uintp(nx)
    one = np.uintp(1)
    tsize = np.uintp(TILE)
    tmask = np.uintp(TILE - 1)
    tshift = np.uintp(TILE_SHIFT)
    hjump = np.uintp(TILE * TILE - TILE)  # left/right across a tile edge: +-(TILE^2 - TILE + 1)
    vjump = np.uintp(ntx * TILE * TILE - TILE * TILE)  # up/down across a tile row edge
    updates = 0
    cycle = 0
    reached = False
    from_over = False
    while cycle < max_cycles:
        if ncur == 0:
            break
        # every update may store 4 entries past the end of the overflow queue (see the push
        # rule), and overflow repeats can outgrow the map: keep room for them
        if nover + 4 * ncur + 8 > over.shape[0]:
            over = _grown(over, nover + 4 * ncur + 8)
        if from_over:
            # a former overflow queue may hold a cell twice: clear all flags first, as navfn does
            for i in range(ncur):
                pending[cur[i]] = 0
        for i in range(ncur):
            # unsigned indices: numba then skips its negative-index wraparound test
            n = np.uintp(cur[i])
            if tiled:
                # neighbour offsets: +-1 and +-TILE inside a tile, jumps to the next tile at
                # its edges (computed without branches: the edge test is a coin flip)
                lx = n & tmask
                ly = (n >> tshift) & tmask
                ol = one + ((tsize - lx) >> tshift) * hjump
                orr = one + ((lx + one) >> tshift) * hjump
                od = tsize + ((tsize - ly) >> tshift) * vjump
                ou = tsize + ((ly + one) >> tshift) * vjump
            else:
                ol = one
                orr = one
                od = unx
                ou = unx
            if not from_over:
                # a queue filled as ``next`` holds each cell once, so its flag can be cleared
                # as the cell comes up: a cell lowered earlier in this cycle that is still to come
                # is then not queued a second time
                pending[n] = 0
            cn = costs[n]
            updates += 1
            hf = lut_hf[cn]  # queued cells are passable: every push checks it
            l = pot[n - ol]
            r = pot[n + orr]
            u = pot[n - od]
            d = pot[n + ou]
            tc = min(l, r)
            ta0 = min(u, d)
            ta = min(ta0, tc)
            if quadratic:
                # navfn's planar-wave update, computed without branches (both sides, then select)
                dc = abs(tc - ta0)
                q = dc * lut_inv[cn]
                pq = ta + hf * (_QA * q * q + _QB * q + _QC)
                p = ta + hf if dc >= hf else pq
            else:
                p = ta + hf
            if not p < pot[n]:
                continue
            pot[n] = p
            if hkind == HEURISTIC_NONE:
                tn = np.intp(p < t)
            else:
                hx, hy = _cell_xy(np.intp(n), nx, ntx, tiled)
                tn = np.intp(p + _heuristic(hx, hy, tx, ty, hkind, hscale) < t)
            # the push rule above, per neighbour (left, right, -nx, +nx), written out: passing
            # the arrays to a helper costs reference counting in this loop. Below the threshold
            # (nearly always, so well predicted) only next is touched, else only overflow.
            if tn:
                m = n - ol
                pq = np.intp(pending[m])
                okn = np.intp(l > p + _INVSQRT2 * lut[costs[m]]) & np.intp((pq & 5) == 0)
                pending[m] = np.uint8(pq + okn * (1 - pq))
                nxt[nnext] = m
                nnext += okn
                m = n + orr
                pq = np.intp(pending[m])
                okn = np.intp(r > p + _INVSQRT2 * lut[costs[m]]) & np.intp((pq & 5) == 0)
                pending[m] = np.uint8(pq + okn * (1 - pq))
                nxt[nnext] = m
                nnext += okn
                m = n - od
                pq = np.intp(pending[m])
                okn = np.intp(u > p + _INVSQRT2 * lut[costs[m]]) & np.intp((pq & 5) == 0)
                pending[m] = np.uint8(pq + okn * (1 - pq))
                nxt[nnext] = m
                nnext += okn
                m = n + ou
                pq = np.intp(pending[m])
                okn = np.intp(d > p + _INVSQRT2 * lut[costs[m]]) & np.intp((pq & 5) == 0)
                pending[m] = np.uint8(pq + okn * (1 - pq))
                nxt[nnext] = m
                nnext += okn
            else:
                m = n - ol
                pq = np.intp(pending[m])
                oko = np.intp(l > p + _INVSQRT2 * lut[costs[m]]) & np.intp(pq == 0)
                pending[m] = np.uint8(pq + 2 * oko)
                over[nover] = m
                nover += oko
                m = n + orr
                pq = np.intp(pending[m])
                oko = np.intp(r > p + _INVSQRT2 * lut[costs[m]]) & np.intp(pq == 0)
                pending[m] = np.uint8(pq + 2 * oko)
                over[nover] = m
                nover += oko
                m = n - od
                pq = np.intp(pending[m])
                oko = np.intp(u > p + _INVSQRT2 * lut[costs[m]]) & np.intp(pq == 0)
                pending[m] = np.uint8(pq + 2 * oko)
                over[nover] = m
                nover += oko
                m = n + ou
                pq = np.intp(pending[m])
                oko = np.intp(d > p + _INVSQRT2 * lut[costs[m]]) & np.intp(pq == 0)
                pending[m] = np.uint8(pq + 2 * oko)
                over[nover] = m
                nover += oko
        tmp = cur
        cur = nxt
        nxt = tmp
        ncur = nnext
        nnext = 0
        from_over = False
        if ncur == 0:
            # band below t is exhausted: every cell under t is final
            if pot[target] < t:
                reached = True
                break
            t += inc
            tmp = cur
            cur = over
            over = tmp
            ncur = nover
            nover = 0
            from_over = True
        cycle += 1
    if not reached and pot[target] < POT_HIGH:
        reached = True
    return reached, updates, cycle


def kernel_tables(lut: np.ndarray, block: float, truncate: bool) -> tuple:
    """``(lut, lut_hf, lut_inv)`` for ``propagate`` from a planner's cost table (float32[256]):
    impassable (>= block) becomes +inf, ``lut_hf`` is the added cost (truncated for
    global_planner), ``lut_inv`` its reciprocal (1 where impassable, never read)."""
    lut = np.asarray(lut, np.float32)
    passable = lut < block
    k = np.where(passable, lut, np.float32(np.inf)).astype(np.float32)
    hf = (np.floor(lut) if truncate else lut).astype(np.float32)
    inv = np.where(passable & (hf > 0), 1.0 / np.where(hf > 0, hf, 1.0), 1.0).astype(np.float32)
    return k, hf, inv


def reset_buffers(pot: np.ndarray, pending: np.ndarray, nx: int, ny: int) -> None:
    """POT_HIGH everywhere, pending 0 inside and 4 (never queued) on the outer border."""
    pot.fill(POT_HIGH)
    pending.fill(0)
    p2 = pending.reshape(ny, nx)
    p2[0, :] = 4
    p2[-1, :] = 4
    p2[:, 0] = 4
    p2[:, -1] = 4


class Workspace:
    """Per-map-size buffers reused from plan to plan (ROS reallocates them on every plan).

    ``tiled`` None picks the tiled layout for maps of ``TILED_MIN_CELLS`` or more; the row-major
    potential ``pot`` is there either way after ``run_wavefront``.
    """

    def __init__(self, tiled: bool | None = None) -> None:
        self.shape: tuple[int, int] = (0, 0)
        self.want_tiled = tiled
        self.tiled = False

    def ensure(self, nx: int, ny: int) -> None:
        if self.shape == (nx, ny):
            return
        ns = nx * ny
        self.shape = (nx, ny)
        self.tiled = ns >= TILED_MIN_CELLS if self.want_tiled is None else self.want_tiled
        self.pot = np.empty(ns, np.float32)
        # Whole-map queues: current and next hold a cell at most once, so they cannot overflow;
        # the overflow queue grows itself in the rare case its repeats outgrow the map.
        # np.empty does not touch the pages, so unused queue space costs no time.
        self.buf_a = np.empty(ns, np.int32)
        self.buf_b = np.empty(ns, np.int32)
        self.buf_c = np.empty(ns, np.int32)
        if self.tiled:
            nt = ((nx + TILE - 1) // TILE) * ((ny + TILE - 1) // TILE) * TILE * TILE
            self.tcosts = np.empty(nt, np.uint8)
            self.tpot = np.empty(nt, np.float32)
            self.pending = np.empty(nt, np.uint8)
        else:
            self.pending = np.empty(ns, np.uint8)


def run_wavefront(ws: Workspace, costs: np.ndarray, tables: tuple, nx: int, ny: int,
                  seed_cells: np.ndarray, seed_pots: np.ndarray, push_cells: np.ndarray,
                  target: int, threshold: float, increment: float, max_cycles: int,
                  quadratic: bool, hkind: int = HEURISTIC_NONE, hscale: float = 0.0) -> tuple:
    """``propagate`` on the workspace (``ensure`` it first) from a fresh start, in the tiled
    layout when the workspace uses it; the row-major potential ends in ``ws.pot``. ``costs`` is
    the flat row-major uint8 costmap, ``tables`` the ``kernel_tables``."""
    if not ws.tiled:
        reset_buffers(ws.pot, ws.pending, nx, ny)
        return propagate(costs, *tables, nx, ny, ws.pot, ws.pending, ws.buf_a, ws.buf_b,
                         ws.buf_c, seed_cells, seed_pots, push_cells, target, threshold,
                         increment, max_cycles, quadratic, hkind, hscale, False)
    tile_map(costs, nx, ny, ws.tcosts, 254)  # padding is also never queued (pending 4)
    _reset_tiled(ws.tpot, ws.pending, nx, ny)
    out = propagate(ws.tcosts, *tables, nx, ny, ws.tpot, ws.pending, ws.buf_a, ws.buf_b,
                    ws.buf_c, seed_cells, seed_pots, push_cells, target, threshold, increment,
                    max_cycles, quadratic, hkind, hscale, True)
    untile_pot(ws.tpot, nx, ny, ws.pot)
    return out
