"""The navigation-function wavefront shared by navfn and global_planner (numba kernels).

navfn's "priority block" propagation: cells wait in three buffers (current, next, overflow); a
cell whose new potential is below the threshold pushes its improvable 4-neighbours to ``next``,
otherwise to ``overflow``; when current and next are empty the threshold rises by ``increment``
and the overflow becomes current. The update is navfn's quadratic (planar-wave) one or the plain
``min(4 neighbours) + cost``.

Deliberate differences from the C++ (the first three fix real faults; none but the band width
changes a converged value):

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
* The planners use bands ``BAND_NEUTRALS`` (10) neutral costs wide, not 2 (see there): fewer
  updates; the plain update's values do not depend on it, the quadratic one's move slightly.

Costs reach the kernel as the raw uint8 costmap plus a 256-entry float32 lookup table (the
planner's cost transform); the per-plan "gate" array (queue state and push cost in one float32,
see the push rule) is set from them. Cells on the outer border have a gate of +inf and are never
queued: that is navfn's border of COST_OBS and global_planner's ``outline_map`` without writing
into the shared costmap.

A* (``hkind``) is navfn's ``calcNavFnAstar``: the band of a cell is chosen by potential plus
heuristic. Maps of ``TILED_MIN_CELLS`` or more run on a copy in 8x8 tiles (``run_wavefront``):
same visiting order, so the same potentials, with far fewer cache misses along the front.

Performance notes (CPU time, office maps; see bench/bench_planners.py). The quadratic update is
not monotone (its factor jumps from 1.0046 to 1 at ``dc == hf``), so its potentials depend on the
visiting order: a strided order moved the 1000^2 goal potential by 0.6 %. Optimisations here keep
the order within a band. Measured without gain: a per-plan float32 cost array instead of the
uint8 map + table, interleaved potential/cost pairs, FMA contraction, a premultiplied push table,
OR-ed flags; later also the quadratic update in Horner form on per-cost coefficients, the queue
visited as two interleaved halves (to break the dependency of a front cell on its neighbour just
updated: slower, and it changes the potentials), and the band test and the no-change test made
branch-free (slower: more stores than the mispredictions cost). Dropping the queue flags
altogether (duplicates allowed) saves ~25 % per update but costs 55 % more updates. One kernel per
(update, search, layout) with the flags and the push costs in one gate array took 30 -> 26 ms at
1000^2 (navfn, same potentials); bands of ``BAND_NEUTRALS`` cut the updates by ~15 %.

A single-pass (Fast-Marching-style) order cannot do much better here: with 10-neutral bands the
kernel makes one update per passable cell (office maps, navfn: 809k updates for 805k passable
cells at 1000^2, 3.25M for 3.26M at 2000^2), each reading its four neighbours once and checking
four pushes. What is left is the cost of one update, ~25 ns at 1000^2, ~30 ns tiled at 2000^2
and 4000^2.

That cost was mostly waiting for memory: replaying the same updates in the recorded order without
the queue takes ~11 ns each, and the front's lines come from L3 or memory (potential and gate
are 8 bytes a cell, 8 MB at 1000^2 against a 1 MB L2). The kernel now prefetches (for writing)
the potential, gate and cost lines of the cell ``PREFETCH_AHEAD`` places ahead in the queue: same
visiting order, same potentials; CPU time of the whole wavefront at 1000^2 22.99 -> 17.10 ms
(navfn, interleaved A/B in one process, min of 9; 4 and 16 places ahead within 2 %). Row-major
with the prefetch then beats the tiled copy at 2000^2 (118 vs 134 ms tiled without it) but not
at 2800^2 (184 vs 174 ms) or 4000^2 (608 vs 547 ms), hence ``TILED_MIN_CELLS``.

With the memory waits hidden, the instructions count: the four push tests took ~48 of an
update's ~110. They now run as one 4-lane vector step (``_push4_next``, ``_push4_over``:
compare, write the gates back, append the pushed cells with one compressing store on AVX-512):
same pushes in the same order, same potentials; wavefront 16.83 -> 14.96 ms at 1000^2 and
79.0 -> 69.7 ms at 2000^2 (navfn, interleaved A/B, min of 11 / 5). Without the compressing store
(one store per neighbour, as on CPUs without AVX-512) the vector step gains nothing.

Around the kernel: the gate survives from plan to plan of one size (the kernel hands queued cells
their idle gate back on exit) and only cells whose cost changed are rewritten (``refresh_buffers``:
set-up 1.1 -> 0.35 ms at 1000^2, 5.3 -> 2.6 ms at 2000^2); the three per-cost tables are read as
one record (-1 % at 1000^2, -2..-5 % at 2000^2). Measured with the prefetch and without gain (in
one process, interleaved): the potential and gate interleaved in one 8-byte record (kernel -10 %
at 2000^2 but +5..35 % at 1000^2, and the path would have to read a strided potential); the
tiled layout at 1000^2 (+15 %) and 4x4 tiles (one line a tile) at 1000^2 and 2000^2; the buffers
on transparent huge pages (within 2 %); no costs prefetch (+4..6 %); the prefetch's bound test
replaced by a clamp (within 1 %).
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.core.extending import intrinsic

POT_HIGH = np.float32(1.0e10)
INVSQRT2 = 0.707106781

_QA = np.float32(-0.2301)
_QB = np.float32(0.5307)
_QC = np.float32(0.7040)
_INVSQRT2 = np.float32(INVSQRT2)


# Threshold bands this many neutral costs wide (navfn's priInc is 2): each band change re-queues
# the overflow, whose repeats are updates that lower nothing, while wider bands let the FIFO order
# within a band stray from Dijkstra's and redo cells. Measured on the 1000^2 office map: 2 x ->
# 10 x takes navfn's updates 960k -> 809k, global_planner's 994k -> 831k (plain update 855k ->
# 796k, its A* 449k -> 368k); at 2000^2 navfn 3.85M -> 3.25M; across the Willow Garage map navfn
# 1.48M -> 0.94M, global_planner 1.67M -> 0.95M. The plain update stays exact (the band stop
# holds for any width). The quadratic one is order-dependent: on those maps the goal's potential
# moves by at most 1.2e-4 (relative), cells below it by 1e-4 on average and up to 3 % for a few
# dozen cells within ~50 cells of the start; path lengths by at most 0.03 m.
BAND_NEUTRALS = 10

HEURISTIC_NONE = 0
HEURISTIC_MANHATTAN = 1
HEURISTIC_EUCLIDEAN = 2


@intrinsic
def _prefetch_write(typingctx, arr, i):  # type: ignore[no-untyped-def]
    """Hint the CPU to fetch element ``i`` of a 1-D array, for writing (``prefetchw``); a hint
    only: never faults, changes nothing."""
    if not (isinstance(arr, types.Array) and arr.ndim == 1):
        return None

    def codegen(context, builder, sig, args):  # type: ignore[no-untyped-def]
        a = context.make_array(sig.args[0])(context, builder, args[0])
        ptr = builder.gep(a.data, [args[1]])
        i8p = ir.IntType(8).as_pointer()
        i32 = ir.IntType(32)
        fn = cgutils.get_or_insert_function(
            builder.module, ir.FunctionType(ir.VoidType(), [i8p, i32, i32, i32]),
            "llvm.prefetch.p0i8")
        builder.call(fn, [builder.bitcast(ptr, i8p), i32(1), i32(3), i32(1)])
        return context.get_dummy_value()
    return types.none(arr, i), codegen


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
TILED_MIN_CELLS = 6_000_000  # with the prefetch, row-major wins at 2000^2 and tiled at 2800^2


@njit(cache=True, inline="always")
def tile_index(x: int, y: int, ntx: int) -> int:
    """Index of cell (x, y) in the tiled layout of a map ``ntx`` tiles wide."""
    return (((y >> TILE_SHIFT) * ntx + (x >> TILE_SHIFT)) << (2 * TILE_SHIFT)) \
        + ((y & (TILE - 1)) << TILE_SHIFT) + (x & (TILE - 1))


@njit(cache=True, inline="always")
def _cell_xy(n: int, nx: int, ntx: int, tiled: bool, inv_w: float) -> tuple:
    """(x, y) of cell ``n``; ``inv_w`` is 1/nx (row-major) or 1/ntx (tiled). A* asks this on every
    update, so the row (or tile row) comes from a multiply, not an integer division (~30 cycles):
    floor((a + 0.5) * inv_w) is exact while the double's error, below a/w x 2^-52, stays under
    0.5/w, i.e. for any map below 2^20 cells a side."""
    if not tiled:
        y = np.intp((n + 0.5) * inv_w)
        return n - y * nx, y
    b = n >> (2 * TILE_SHIFT)
    by = np.intp((b + 0.5) * inv_w)
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
def _reset_tiled(tpot: np.ndarray, tgate: np.ndarray, tcosts: np.ndarray, lut_push: np.ndarray,
                 nx: int, ny: int) -> None:
    """POT_HIGH everywhere; the gate idle inside, +inf (never queued) on the border and padding."""
    ntx = (nx + TILE - 1) // TILE
    nty = (ny + TILE - 1) // TILE
    tpot[:] = POT_HIGH
    for i in range(tgate.shape[0]):
        tgate[i] = lut_push[tcosts[i]]
    for x in range(ntx * TILE):
        tgate[tile_index(x, 0, ntx)] = np.inf
        for y in range(ny - 1, nty * TILE):
            tgate[tile_index(x, y, ntx)] = np.inf
    for y in range(ny):
        tgate[tile_index(0, y, ntx)] = np.inf
        for x in range(nx - 1, ntx * TILE):
            tgate[tile_index(x, y, ntx)] = np.inf


@njit(cache=True)
def _grown(buf: np.ndarray, need: int) -> np.ndarray:
    big = np.empty(max(2 * buf.shape[0], need), buf.dtype)
    big[: buf.shape[0]] = buf
    return big


# The push rule (navfn's, plus the overflow upgrade), applied to each neighbour m (old potential
# pm) of a cell that just got potential p: queue m when pm > p + cost(m)/sqrt(2). Below the
# threshold m goes to next, also when it waits in overflow (so the band finishes it; ROS leaves it
# waiting, and its overflow entry becomes a harmless repeat); above it, to overflow when idle.
#
# The queue state and the push cost share one float32 array, the "gate", so a push test is one
# load: idle cells hold cost/sqrt(2) (> 0), cells in overflow its negation, cells in current/next,
# impassable cells and the border +inf. Below the threshold ``pm > p + |gate|`` is the whole test,
# above it ``gate > 0`` joins it. The pushes are branch-free (at the wave front the outcome is a
# coin flip, and mispredictions dominated the run time), and the four neighbours are tested as one
# 4-lane vector (``_push4``): one compare, the four gates written back, and the pushed cells
# appended in neighbour order (left, right, up, down) with one compressing store where the CPU has
# one (AVX-512), else one store per neighbour with the count advancing only for pushed ones.


def _push4_codegen(above: bool):  # type: ignore[no-untyped-def]
    def codegen(context, builder, sig, args):  # type: ignore[no-untyped-def]
        gate = context.make_array(sig.args[0])(context, builder, args[0])
        queue = context.make_array(sig.args[1])(context, builder, args[1])
        count, p, pms, cells = args[2], args[3], args[4:8], args[8:12]
        f32, i32, i64 = ir.FloatType(), ir.IntType(32), ir.IntType(64)
        v4f, v4i = ir.VectorType(f32, 4), ir.VectorType(i32, 4)
        g = pm = ir.Constant(v4f, None)
        idx = ir.Constant(v4i, None)
        ptrs = []
        for k in range(4):
            ptrs.append(builder.gep(gate.data, [cells[k]]))
            g = builder.insert_element(g, builder.load(ptrs[k]), i32(k))
            pm = builder.insert_element(pm, pms[k], i32(k))
            idx = builder.insert_element(idx, builder.trunc(cells[k], i32), i32(k))
        pv = builder.shuffle_vector(builder.insert_element(ir.Constant(v4f, None), p, i32(0)),
                                    ir.Constant(v4f, None), ir.Constant(v4i, [0, 0, 0, 0]))
        zero = ir.Constant(v4f, [0.0] * 4)
        if above:  # to overflow when idle: the gate turns negative
            ok = builder.and_(builder.fcmp_ordered(">", pm, builder.fadd(pv, g)),
                              builder.fcmp_ordered(">", g, zero))
            g = builder.select(ok, builder.fsub(zero, g), g)
        else:  # to next, also from overflow: the gate turns +inf
            fabs = cgutils.get_or_insert_function(builder.module, ir.FunctionType(v4f, [v4f]),
                                                  "llvm.fabs.v4f32")
            ok = builder.fcmp_ordered(">", pm, builder.fadd(pv, builder.call(fabs, [g])))
            g = builder.select(ok, ir.Constant(v4f, [float("inf")] * 4), g)
        for k in range(4):
            builder.store(builder.extract_element(g, i32(k)), ptrs[k])
        if "+avx512vl" in getattr(context.codegen(), "_tm_features", ""):
            v4b = ir.VectorType(ir.IntType(1), 4)
            fn = cgutils.get_or_insert_function(
                builder.module, ir.FunctionType(ir.VoidType(), [v4i, i32.as_pointer(), v4b]),
                "llvm.masked.compressstore.v4i32")
            builder.call(fn, [idx, builder.gep(queue.data, [count]), ok])
            pop = cgutils.get_or_insert_function(
                builder.module, ir.FunctionType(ir.IntType(4), [ir.IntType(4)]), "llvm.ctpop.i4")
            return builder.add(count, builder.zext(
                builder.call(pop, [builder.bitcast(ok, ir.IntType(4))]), i64))
        # elsewhere LLVM would expand the compressing store into a branch per lane
        for k in range(4):
            builder.store(builder.extract_element(idx, i32(k)), builder.gep(queue.data, [count]))
            count = builder.add(count, builder.zext(builder.extract_element(ok, i32(k)), i64))
        return count
    return codegen


def _push4_typing(above: bool):  # type: ignore[no-untyped-def]
    def typer(typingctx, gate, queue, count, p, l, r, u, d, ml, mr, mu, md):  # type: ignore
        """Apply the push rule to the four neighbours (old potentials l, r, u, d; cells ml, mr, mu,
        md) of a cell that got potential p: update their gates and append the pushed ones to
        ``queue`` (int32) at ``count``; returns the new count (uintp)."""
        ok = (isinstance(gate, types.Array) and gate.dtype == types.float32
              and isinstance(queue, types.Array) and queue.dtype == types.int32
              and count == types.uintp and p == types.float32
              and all(v == types.float32 for v in (l, r, u, d))
              and all(m == types.uintp for m in (ml, mr, mu, md)))
        if not ok:
            return None
        return (types.uintp(gate, queue, count, p, l, r, u, d, ml, mr, mu, md),
                _push4_codegen(above))
    return typer


_push4_next = intrinsic(_push4_typing(False))
_push4_over = intrinsic(_push4_typing(True))


# How many queue places ahead the kernel prefetches a cell's lines (measured: see the notes above).
PREFETCH_AHEAD = 8


@njit(cache=True, inline="always")
def _make_idle(gate: np.ndarray, costs: np.ndarray, lut_push: np.ndarray, queue: np.ndarray,
               count: int) -> None:
    for i in range(count):
        m = queue[i]
        gate[m] = lut_push[costs[m]]


def _make_propagate(quadratic: bool, astar: bool, tiled: bool):
    """``propagate`` compiled for one update kind, search kind and layout: the flags are
    constants of the closure, so each variant carries only its own code (a single generic kernel
    spent a third of its instructions on flag tests and on spilled registers)."""

    @njit(cache=True)
    def propagate(costs: np.ndarray, lut_push: np.ndarray, lut_hf: np.ndarray,
                  lut_inv: np.ndarray, nx: int, ny: int, pot: np.ndarray, gate: np.ndarray,
                  buf_a: np.ndarray, buf_b: np.ndarray, buf_c: np.ndarray,
                  seed_cells: np.ndarray, seed_pots: np.ndarray, push_cells: np.ndarray,
                  target: int, threshold: float, increment: float, max_cycles: int, hkind: int,
                  hscale: float) -> tuple:
        ns = nx * ny
        # the three per-cost tables as one record per cost: one base register, one line
        cost_rec = np.empty(4 * lut_push.shape[0], np.float32)
        for c in range(lut_push.shape[0]):
            cost_rec[4 * c] = lut_push[c]
            cost_rec[4 * c + 1] = lut_hf[c]
            cost_rec[4 * c + 2] = lut_inv[c]
            cost_rec[4 * c + 3] = 0.0
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
        zero = np.uintp(0)
        ncur = zero
        nnext = zero
        nover = zero
        for i in range(push_cells.shape[0]):
            m = push_cells[i]
            if 0 <= m < ns and 0.0 < gate[m] < np.inf:
                cur[ncur] = m
                ncur += np.uintp(1)
                gate[m] = np.inf
        inv_w = 1.0 / ntx if tiled else 1.0 / nx
        if astar and seed_cells.shape[0] > 0:
            # the first band starts at the seed's key, not at its potential
            sx, sy = _cell_xy(seed_cells[0], nx, ntx, tiled, inv_w)
            threshold += _heuristic(sx, sy, tx, ty, hkind, hscale)
        t = np.float32(threshold)
        inc = np.float32(increment)
        inf = np.float32(np.inf)
        unx = np.uintp(nx)
        one = np.uintp(1)
        tsize = np.uintp(TILE)
        tmask = np.uintp(TILE - 1)
        tshift = np.uintp(TILE_SHIFT)
        hjump = np.uintp(TILE * TILE - TILE)  # left/right across a tile edge: +-(TILE^2-TILE+1)
        vjump = np.uintp(ntx * TILE * TILE - TILE * TILE)  # up/down across a tile row edge
        updates = 0
        cycle = 0
        reached = False
        from_over = False
        while cycle < max_cycles:
            if ncur == zero:
                break
            # every update may store 4 entries past the end of the overflow queue (see the push
            # rule), and overflow repeats can outgrow the map: keep room for them
            need = np.intp(nover + np.uintp(4) * ncur + np.uintp(8))
            if need > over.shape[0]:
                over = _grown(over, need)
            if from_over:
                # a former overflow queue may hold a cell twice: make all idle first, as navfn
                # clears its flags
                for i in range(ncur):
                    m = cur[i]
                    gate[m] = lut_push[costs[m]]
            ahead = np.uintp(PREFETCH_AHEAD)  # unsigned like i: an int/uint mix compares as float
            for i in range(ncur):
                # unsigned indices: numba then skips its negative-index wraparound test
                n = np.uintp(cur[i])
                if i + ahead < ncur:
                    # the front's lines come from L3 or memory: ask for those of a cell a few
                    # places ahead in the queue while this one is updated (same results)
                    f = np.uintp(cur[i + ahead])
                    if tiled:
                        fy = (f >> tshift) & tmask
                        fd = tsize + ((tsize - fy) >> tshift) * vjump
                        fu = tsize + ((fy + one) >> tshift) * vjump
                    else:
                        fd = unx
                        fu = unx
                    _prefetch_write(pot, f - fd)
                    _prefetch_write(pot, f)
                    _prefetch_write(pot, f + fu)
                    _prefetch_write(gate, f - fd)
                    _prefetch_write(gate, f)
                    _prefetch_write(gate, f + fu)
                    _prefetch_write(costs, f)
                if tiled:
                    # neighbour offsets: +-1 and +-TILE inside a tile, jumps to the next tile
                    # at its edges (computed without branches: the edge test is a coin flip)
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
                cn = np.uintp(costs[n]) << np.uintp(2)
                if not from_over:
                    # a queue filled as ``next`` holds each cell once, so it turns idle as it
                    # comes up: a cell lowered earlier in this cycle that is still to come is
                    # then not queued a second time
                    gate[n] = cost_rec[cn]
                updates += 1
                hf = cost_rec[cn + one]  # queued cells are passable: every push checks it
                l = pot[n - ol]
                r = pot[n + orr]
                u = pot[n - od]
                d = pot[n + ou]
                tc = min(l, r)
                ta0 = min(u, d)
                ta = min(ta0, tc)
                if quadratic:
                    # navfn's planar-wave update (both sides computed, then selected)
                    dc = abs(tc - ta0)
                    q = dc * cost_rec[cn + np.uintp(2)]
                    pq = ta + hf * (_QA * q * q + _QB * q + _QC)
                    p = ta + hf if dc >= hf else pq
                else:
                    p = ta + hf
                if not p < pot[n]:
                    continue
                pot[n] = p
                if astar:
                    hx, hy = _cell_xy(np.intp(n), nx, ntx, tiled, inv_w)
                    below = p + _heuristic(hx, hy, tx, ty, hkind, hscale) < t
                else:
                    below = p < t
                # the push rule above, all four neighbours at once
                if below:
                    nnext = _push4_next(gate, nxt, nnext, p, l, r, u, d, n - ol, n + orr, n - od,
                                        n + ou)
                else:
                    nover = _push4_over(gate, over, nover, p, l, r, u, d, n - ol, n + orr, n - od,
                                        n + ou)
            tmp = cur
            cur = nxt
            nxt = tmp
            ncur = nnext
            nnext = zero
            from_over = False
            if ncur == zero:
                # band below t is exhausted: every cell under t is final
                if pot[target] < t:
                    reached = True
                    break
                t += inc
                tmp = cur
                cur = over
                over = tmp
                ncur = nover
                nover = zero
                from_over = True
            cycle += 1
        # cells still queued get their idle gate back, so the gate ends as a fresh reset left
        # it: the next plan of the same size rewrites only the cells whose cost changed
        _make_idle(gate, costs, lut_push, cur, ncur)
        _make_idle(gate, costs, lut_push, nxt, nnext)
        _make_idle(gate, costs, lut_push, over, nover)
        if not reached and pot[target] < POT_HIGH:
            reached = True
        return reached, updates, cycle

    return propagate


_PROPAGATE = {(q, a, t): _make_propagate(q, a, t)
              for q in (False, True) for a in (False, True) for t in (False, True)}


def propagate(costs: np.ndarray, tables: tuple, nx: int, ny: int, pot: np.ndarray,
              gate: np.ndarray, buf_a: np.ndarray, buf_b: np.ndarray, buf_c: np.ndarray,
              seed_cells: np.ndarray, seed_pots: np.ndarray, push_cells: np.ndarray,
              target: int, threshold: float, increment: float, max_cycles: int,
              quadratic: bool, hkind: int = HEURISTIC_NONE, hscale: float = 0.0,
              tiled: bool = False) -> tuple:
    """Spread potential from the seeds until ``target`` is final or nothing is left to update.

    ``costs`` is the flat uint8 costmap and ``tables`` its ``kernel_tables``. ``pot`` (float32,
    flat) must hold POT_HIGH everywhere and ``gate`` (float32) the push costs with +inf on the
    border (``reset_buffers``). Seeds get ``seed_pots``; ``push_cells`` start the wave. Returns
    ``(reached, cell_updates, cycles)``.

    With ``hkind`` HEURISTIC_MANHATTAN or HEURISTIC_EUCLIDEAN this is A* in navfn's
    ``calcNavFnAstar`` manner: a cell's band is decided by potential + ``hscale`` x its distance
    to ``target`` instead of the potential alone (the stored potential has no heuristic). With a
    consistent heuristic every cell whose key is below a finished band is final, as above.

    With ``tiled`` the map arrays (``costs``, ``pot``, ``gate``) are in the tiled layout of
    ``tile_index`` (see ``Workspace``) while seeds, pushes and target stay row-major indices; the
    cells are visited in exactly the same order, so the potential is the same.
    """
    kernel = _PROPAGATE[(bool(quadratic), hkind != HEURISTIC_NONE, bool(tiled))]
    return kernel(costs, *tables, nx, ny, pot, gate, buf_a, buf_b, buf_c, seed_cells, seed_pots,
                  push_cells, target, threshold, increment, max_cycles, hkind, hscale)


def kernel_tables(lut: np.ndarray, block: float, truncate: bool) -> tuple:
    """``(lut_push, lut_hf, lut_inv)`` for ``propagate`` from a planner's cost table
    (float32[256]): ``lut_push`` the push cost cost/sqrt(2), +inf where impassable (>= block),
    ``lut_hf`` the added cost (truncated for global_planner), ``lut_inv`` its reciprocal (1 where
    impassable, never read)."""
    lut = np.asarray(lut, np.float32)
    passable = lut < block
    k = np.where(passable, lut, np.float32(np.inf)).astype(np.float32)
    push = (np.float32(INVSQRT2) * k).astype(np.float32)
    hf = (np.floor(lut) if truncate else lut).astype(np.float32)
    inv = np.where(passable & (hf > 0), 1.0 / np.where(hf > 0, hf, 1.0), 1.0).astype(np.float32)
    return push, hf, inv


@njit(cache=True, inline="always")
def _close_border(gate: np.ndarray, nx: int, ny: int) -> None:
    for x in range(nx):
        gate[x] = np.inf
        gate[(ny - 1) * nx + x] = np.inf
    for y in range(ny):
        gate[y * nx] = np.inf
        gate[y * nx + nx - 1] = np.inf


@njit(cache=True)
def reset_buffers(pot: np.ndarray, gate: np.ndarray, costs: np.ndarray, lut_push: np.ndarray,
                  nx: int, ny: int) -> None:
    """POT_HIGH everywhere; the gate idle inside, +inf (never queued) on the outer border."""
    pot[:] = POT_HIGH
    for i in range(gate.shape[0]):
        gate[i] = lut_push[costs[i]]
    _close_border(gate, nx, ny)


@njit(cache=True)
def refresh_buffers(pot: np.ndarray, gate: np.ndarray, gate_costs: np.ndarray,
                    costs: np.ndarray, lut_push: np.ndarray, nx: int, ny: int) -> None:
    """``reset_buffers`` for a gate left idle by the last run on ``gate_costs`` (with the same
    ``lut_push``): only cells whose cost changed since get a new gate (and ``gate_costs`` their
    cost). On an unchanged map this is a compare of 64-cell blocks instead of the gather
    ``lut_push[costs]`` of a full reset."""
    pot[:] = POT_HIGH
    ns = costs.shape[0]
    # compared as 8-byte words, 8 words (64 cells) a block: uint8 arithmetic would widen
    end = ns - ns % 64
    words = costs[:end].view(np.uint64)
    last_words = gate_costs[:end].view(np.uint64)
    changed = False
    for b in range(0, end // 8, 8):
        diff = np.uint64(0)
        for w in range(b, b + 8):
            diff |= words[w] ^ last_words[w]
        if diff != 0:
            changed = True
            for i in range(8 * b, 8 * b + 64):
                gate_costs[i] = costs[i]
                gate[i] = lut_push[costs[i]]
    for i in range(end, ns):
        if costs[i] != gate_costs[i]:
            changed = True
            gate_costs[i] = costs[i]
            gate[i] = lut_push[costs[i]]
    if changed:  # a border cell may have been rewritten
        _close_border(gate, nx, ny)


class Workspace:
    """Per-map-size buffers reused from plan to plan (ROS reallocates them on every plan).

    ``tiled`` None picks the tiled layout for maps of ``TILED_MIN_CELLS`` or more; after
    ``run_wavefront`` the potential is in ``pot`` (row-major) unless the run kept it tiled
    (``last_potential``).
    """

    def __init__(self, tiled: bool | None = None) -> None:
        self.shape: tuple[int, int] = (0, 0)
        self.want_tiled = tiled
        self.tiled = False
        self.pot_tiled = False  # the last run left its potential in tpot only

    def ensure(self, nx: int, ny: int) -> None:
        if self.shape == (nx, ny):
            return
        ns = nx * ny
        self.shape = (nx, ny)
        self.tiled = ns >= TILED_MIN_CELLS if self.want_tiled is None else self.want_tiled
        self.pot_tiled = False
        # row-major: the costs and push table the idle gate was built from (None: rebuild it)
        self.gate_lut: np.ndarray | None = None
        self.gate_costs = np.empty(ns if not self.tiled else 0, np.uint8)
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
            self.gate = np.empty(nt, np.float32)
        else:
            self.gate = np.empty(ns, np.float32)

    def last_potential(self) -> tuple[np.ndarray, bool]:
        """The last run's potential (flat) and whether it is in the tiled layout."""
        return (self.tpot, True) if self.pot_tiled else (self.pot, False)


def layout_index(cells: np.ndarray | int, nx: int, tiled: bool) -> np.ndarray | int:
    """Row-major flat cell indices as indices into a flat grid in the row-major or the tiled
    (``tile_index``) layout."""
    if not tiled:
        return cells
    x, y = cells % nx, cells // nx
    ntx = (nx + TILE - 1) // TILE
    return ((((y >> TILE_SHIFT) * ntx + (x >> TILE_SHIFT)) << (2 * TILE_SHIFT))
            + ((y & (TILE - 1)) << TILE_SHIFT) + (x & (TILE - 1)))


def run_wavefront(ws: Workspace, costs: np.ndarray, tables: tuple, nx: int, ny: int,
                  seed_cells: np.ndarray, seed_pots: np.ndarray, push_cells: np.ndarray,
                  target: int, threshold: float, increment: float, max_cycles: int,
                  quadratic: bool, hkind: int = HEURISTIC_NONE, hscale: float = 0.0,
                  row_major: bool = True) -> tuple:
    """``propagate`` on the workspace (``ensure`` it first) from a fresh start, in the tiled
    layout when the workspace uses it. The potential ends in ``ws.pot`` (row-major); with
    ``row_major`` false a tiled run leaves it in ``ws.tpot`` instead (converting it back costs
    ~5 % of a 4000^2 plan), see ``last_potential``. ``costs`` is the flat row-major uint8
    costmap, ``tables`` the ``kernel_tables``."""
    ws.pot_tiled = False
    if not ws.tiled:
        lut_push = tables[0]
        if ws.gate_lut is not None and np.array_equal(ws.gate_lut, lut_push):
            refresh_buffers(ws.pot, ws.gate, ws.gate_costs, costs, lut_push, nx, ny)
        else:
            reset_buffers(ws.pot, ws.gate, costs, lut_push, nx, ny)
            ws.gate_costs[:] = costs
        ws.gate_lut = None  # until the kernel has returned with every gate idle again
        out = propagate(costs, tables, nx, ny, ws.pot, ws.gate, ws.buf_a, ws.buf_b, ws.buf_c,
                        seed_cells, seed_pots, push_cells, target, threshold, increment,
                        max_cycles, quadratic, hkind, hscale, False)
        ws.gate_lut = lut_push.copy()
        return out
    tile_map(costs, nx, ny, ws.tcosts, 254)  # padding: impassable, its gate +inf anyway
    _reset_tiled(ws.tpot, ws.gate, ws.tcosts, tables[0], nx, ny)
    out = propagate(ws.tcosts, tables, nx, ny, ws.tpot, ws.gate, ws.buf_a, ws.buf_b, ws.buf_c,
                    seed_cells, seed_pots, push_cells, target, threshold, increment, max_cycles,
                    quadratic, hkind, hscale, True)
    if row_major:
        untile_pot(ws.tpot, nx, ny, ws.pot)
    else:
        ws.pot_tiled = True
    return out
