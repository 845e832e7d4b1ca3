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
planner's cost transform). Each cell has an 8-byte record: its potential and its "gate" (queue
state and push cost in one float32, see the push rule), set from the costs. Cells on the outer
border have a gate of +inf and are never queued: that is navfn's border of COST_OBS and
global_planner's ``outline_map`` without writing into the shared costmap. The planners read the
potential through a strided view of the records (``Workspace.pot``).

A* (``hkind``) is navfn's ``calcNavFnAstar``: the band of a cell is chosen by potential plus
heuristic.

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
(update, search) with the flags and the push costs in one gate array took 30 -> 26 ms at
1000^2 (navfn, same potentials); bands of ``BAND_NEUTRALS`` cut the updates by ~15 %.

A single-pass (Fast-Marching-style) order cannot do much better here: with 10-neutral bands the
kernel makes one update per passable cell (office maps, navfn: 809k updates for 805k passable
cells at 1000^2, 3.25M for 3.26M at 2000^2), each reading its four neighbours once and checking
four pushes. What is left is the cost of one update (~25 ns at 1000^2 then).

That cost was mostly waiting for memory: replaying the same updates in the recorded order without
the queue takes ~11 ns each, and the front's lines come from L3 or memory (potential and gate
are 8 bytes a cell, 8 MB at 1000^2 against a 1 MB L2). The kernel now prefetches (for writing)
the potential, gate and cost lines of the cell ``PREFETCH_AHEAD`` places ahead in the queue: same
visiting order, same potentials; CPU time of the whole wavefront at 1000^2 22.99 -> 17.10 ms
(navfn, interleaved A/B in one process, min of 9; 4 and 16 places ahead within 2 %). Row-major
with the prefetch then beats the tiled copy at 2000^2 (118 vs 134 ms tiled without it) but not
at 2800^2 (184 vs 174 ms) or 4000^2 (608 vs 547 ms), hence a tiled copy for big maps then
(replaced since by the records below).

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
one process, interleaved): the tiled layout at 1000^2 (+15 %) and 4x4 tiles (one line a tile) at
1000^2 and 2000^2; the buffers on transparent huge pages (within 2 %); no costs prefetch
(+4..6 %); the prefetch's bound test replaced by a clamp (within 1 %).

The potential and the gate of a cell in one 8-byte record (queues and costs unchanged, the
record of cell n at 2n): one line holds both values a push test and an update need, and the
prefetch asks for three lines instead of six. Same visiting order, bit-identical potentials and
paths. Whole make_plan, interleaved A/B in one process against the previous form (row-major
separate arrays below 6M cells, an 8x8-tiled copy from there), min of 21 / 7 / 3: 2000^2 navfn
-9 %, global_planner -8 %, its A* -3 %; 4000^2 (against the tiled copy, which it replaces: one
layout for every size) navfn -6 %, global_planner -2..-16 %, its A* -17 %; 1000^2 within +-2 %
(the kernel -2..3 %, but resetting the potentials now touches 8 bytes a cell: 0.28 -> 0.45 ms).
No hardware performance counters on this host (a VM without a PMU driver), so the causes were
found by experiment: shortening the quadratic update's dependency chain by three operations (not
exact, only to measure) saved 7-9 %, so the update's latency still counts; the cell processed
before is a neighbour of the current one in under 2 % of the updates (so the chain runs within
an update, not from one to the next: forwarding the previous potential in a register was +1..4 %
slower); 6 % of updates lower nothing and 7 % switch between the next and overflow sides (the
branches that remain); building the neighbour index vector with one add instead of four inserts
changed nothing measurable. On a 250^2 map (all in L2) an update takes 16 ns, at 1000^2 18 ns and
2000^2 19 ns (whole run_wavefront), so memory is now 10-15 % of the kernel: the rest is the
core's work on ~95 micro-ops an update. Also measured without gain on top of the records (kernel,
interleaved A/B): the push step loading the neighbours' whole records and gathering the gates by
shuffles (within 1 %); the band test branch-free, one push step selecting its queue and count
(+15 %: the queue counts then depend on each update's potential, which serialises the updates;
the predicted branch lets them overlap); two queue cells a step with both new potentials computed
before either is settled (exact: the second recomputed when the first is its neighbour; navfn
-2 %, A* +3 %, not worth the code); ``PREFETCH_AHEAD`` 5 or 12 (+1..7 %); the records and queues
on transparent huge pages (+0..3 %); wider bands (1000^2 navfn, 10 / 15 / 20 / 30 neutral costs:
809k / 809k / 818k / 856k updates, kernel time within 2 %, goal potential moving 6e-6 / 2e-5 /
8e-6 / 2e-4 from navfn's 2 x bands), so ``BAND_NEUTRALS`` stays 10.
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.core.extending import intrinsic

from navcore.prefetch import prefetch_write

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

# The kernel's map array: one 8-byte record per cell, the potential at 2n and the gate (see the
# push rule) at 2n + 1, so an update finds both of a neighbour's values in one cache line.
POT = 0
GATE = 1


@njit(cache=True, inline="always")
def _heuristic(x: int, y: int, tx: int, ty: int, hkind: int, hscale: float) -> float:
    dx = abs(x - tx)
    dy = abs(y - ty)
    if hkind == HEURISTIC_MANHATTAN:
        return hscale * (dx + dy)
    return hscale * math.sqrt(dx * dx + dy * dy)


@njit(cache=True, inline="always")
def _cell_xy(n: int, nx: int, inv_nx: float) -> tuple:
    """(x, y) of cell ``n``; ``inv_nx`` is 1/nx. A* asks this on every update, so the row comes
    from a multiply, not an integer division (~30 cycles): floor((n + 0.5) * inv_nx) is exact
    while the double's error, below n/nx x 2^-52, stays under 0.5/nx, i.e. for any map below
    2^20 cells a side."""
    y = np.intp((n + 0.5) * inv_nx)
    return n - y * nx, y


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
# The queue state and the push cost share one float32, the "gate", so a push test is one load:
# idle cells hold cost/sqrt(2) (> 0), cells in overflow its negation, cells in current/next,
# impassable cells and the border +inf. Below the threshold ``pm > p + |gate|`` is the whole test,
# above it ``gate > 0`` joins it. The pushes are branch-free (at the wave front the outcome is a
# coin flip, and mispredictions dominated the run time), and the four neighbours are tested as one
# 4-lane vector (``_push4``): one compare, the four gates written back, and the pushed cells
# appended in neighbour order (left, right, up, down) with one compressing store where the CPU has
# one (AVX-512), else one store per neighbour with the count advancing only for pushed ones.


def _push4_codegen(above: bool):  # type: ignore[no-untyped-def]
    def codegen(context, builder, sig, args):  # type: ignore[no-untyped-def]
        rec = context.make_array(sig.args[0])(context, builder, args[0])
        queue = context.make_array(sig.args[1])(context, builder, args[1])
        count, p, pms, cells = args[2], args[3], args[4:8], args[8:12]
        f32, i32, i64 = ir.FloatType(), ir.IntType(32), ir.IntType(64)
        v4f, v4i = ir.VectorType(f32, 4), ir.VectorType(i32, 4)
        g = pm = ir.Constant(v4f, None)
        idx = ir.Constant(v4i, None)
        ptrs = []
        for k in range(4):
            slot = builder.add(builder.shl(cells[k], i64(1)), i64(GATE))
            ptrs.append(builder.gep(rec.data, [slot]))
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
    def typer(typingctx, rec, queue, count, p, l, r, u, d, ml, mr, mu, md):  # type: ignore
        """Apply the push rule to the four neighbours (old potentials l, r, u, d; cells ml, mr, mu,
        md) of a cell that got potential p: update their gates in the records ``rec`` and append
        the pushed ones to ``queue`` (int32) at ``count``; returns the new count (uintp)."""
        ok = (isinstance(rec, types.Array) and rec.dtype == types.float32
              and isinstance(queue, types.Array) and queue.dtype == types.int32
              and count == types.uintp and p == types.float32
              and all(v == types.float32 for v in (l, r, u, d))
              and all(m == types.uintp for m in (ml, mr, mu, md)))
        if not ok:
            return None
        return (types.uintp(rec, queue, count, p, l, r, u, d, ml, mr, mu, md),
                _push4_codegen(above))
    return typer


_push4_next = intrinsic(_push4_typing(False))
_push4_over = intrinsic(_push4_typing(True))


# How many queue places ahead the kernel prefetches a cell's lines (measured: see the notes above).
PREFETCH_AHEAD = 8


@njit(cache=True, inline="always")
def _make_idle(rec: np.ndarray, costs: np.ndarray, lut_push: np.ndarray, queue: np.ndarray,
               count: int) -> None:
    for i in range(count):
        m = queue[i]
        rec[2 * m + GATE] = lut_push[costs[m]]


def _make_propagate(quadratic: bool, astar: bool):
    """``propagate`` compiled for one update kind and search kind: the flags are constants of the
    closure, so each variant carries only its own code (a single generic kernel spent a third of
    its instructions on flag tests and on spilled registers)."""

    @njit(cache=True)
    def propagate(costs: np.ndarray, lut_push: np.ndarray, lut_hf: np.ndarray,
                  lut_inv: np.ndarray, nx: int, ny: int, rec: np.ndarray,
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
        tx = target % nx
        ty = target // nx
        for i in range(seed_cells.shape[0]):
            k = seed_cells[i]
            if 0 <= k < ns:
                rec[2 * k + POT] = seed_pots[i]
        cur, nxt, over = buf_a, buf_b, buf_c
        zero = np.uintp(0)
        ncur = zero
        nnext = zero
        nover = zero
        for i in range(push_cells.shape[0]):
            m = push_cells[i]
            if 0 <= m < ns and 0.0 < rec[2 * m + GATE] < np.inf:
                cur[ncur] = m
                ncur += np.uintp(1)
                rec[2 * m + GATE] = np.inf
        inv_nx = 1.0 / nx
        if astar and seed_cells.shape[0] > 0:
            # the first band starts at the seed's key, not at its potential
            sx, sy = _cell_xy(seed_cells[0], nx, inv_nx)
            threshold += _heuristic(sx, sy, tx, ty, hkind, hscale)
        t = np.float32(threshold)
        inc = np.float32(increment)
        unx = np.uintp(nx)
        one = np.uintp(1)
        two = np.uintp(2)
        gate = np.uintp(GATE)
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
                _make_idle(rec, costs, lut_push, cur, ncur)
            ahead = np.uintp(PREFETCH_AHEAD)  # unsigned like i: an int/uint mix compares as float
            for i in range(ncur):
                # unsigned indices: numba then skips its negative-index wraparound test
                n = np.uintp(cur[i])
                if i + ahead < ncur:
                    # the front's lines come from L3 or memory: ask for those of a cell a few
                    # places ahead in the queue while this one is updated (same results); a
                    # record holds potential and gate, so three lines plus the cost
                    f = np.uintp(cur[i + ahead])
                    prefetch_write(rec, two * (f - unx))
                    prefetch_write(rec, two * f)
                    prefetch_write(rec, two * (f + unx))
                    prefetch_write(costs, f)
                cn = np.uintp(costs[n]) << np.uintp(2)
                if not from_over:
                    # a queue filled as ``next`` holds each cell once, so it turns idle as it
                    # comes up: a cell lowered earlier in this cycle that is still to come is
                    # then not queued a second time
                    rec[two * n + gate] = cost_rec[cn]
                updates += 1
                hf = cost_rec[cn + one]  # queued cells are passable: every push checks it
                l = rec[two * (n - one)]
                r = rec[two * (n + one)]
                u = rec[two * (n - unx)]
                d = rec[two * (n + unx)]
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
                if not p < rec[two * n]:
                    continue
                rec[two * n] = p
                if astar:
                    hx, hy = _cell_xy(np.intp(n), nx, inv_nx)
                    below = p + _heuristic(hx, hy, tx, ty, hkind, hscale) < t
                else:
                    below = p < t
                # the push rule above, all four neighbours at once
                if below:
                    nnext = _push4_next(rec, nxt, nnext, p, l, r, u, d, n - one, n + one,
                                        n - unx, n + unx)
                else:
                    nover = _push4_over(rec, over, nover, p, l, r, u, d, n - one, n + one,
                                        n - unx, n + unx)
            tmp = cur
            cur = nxt
            nxt = tmp
            ncur = nnext
            nnext = zero
            from_over = False
            if ncur == zero:
                # band below t is exhausted: every cell under t is final
                if rec[2 * target + POT] < t:
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
        _make_idle(rec, costs, lut_push, cur, ncur)
        _make_idle(rec, costs, lut_push, nxt, nnext)
        _make_idle(rec, costs, lut_push, over, nover)
        if not reached and rec[2 * target + POT] < POT_HIGH:
            reached = True
        return reached, updates, cycle

    return propagate


_PROPAGATE = {(q, a): _make_propagate(q, a) for q in (False, True) for a in (False, True)}


def propagate(costs: np.ndarray, tables: tuple, nx: int, ny: int, rec: np.ndarray,
              buf_a: np.ndarray, buf_b: np.ndarray, buf_c: np.ndarray,
              seed_cells: np.ndarray, seed_pots: np.ndarray, push_cells: np.ndarray,
              target: int, threshold: float, increment: float, max_cycles: int,
              quadratic: bool, hkind: int = HEURISTIC_NONE, hscale: float = 0.0) -> tuple:
    """Spread potential from the seeds until ``target`` is final or nothing is left to update.

    ``costs`` is the flat uint8 costmap and ``tables`` its ``kernel_tables``. ``rec`` (float32,
    two per cell: potential at 2n, gate at 2n + 1) must hold POT_HIGH potentials and the idle
    gates with +inf on the border (``reset_records``). Seeds get ``seed_pots``; ``push_cells``
    start the wave. Returns ``(reached, cell_updates, cycles)``.

    With ``hkind`` HEURISTIC_MANHATTAN or HEURISTIC_EUCLIDEAN this is A* in navfn's
    ``calcNavFnAstar`` manner: a cell's band is decided by potential plus ``hscale`` x its
    distance to ``target`` instead of the potential alone (the stored potential has no heuristic).
    With a consistent heuristic every cell whose key is below a finished band is final, as above.
    """
    kernel = _PROPAGATE[(bool(quadratic), hkind != HEURISTIC_NONE)]
    return kernel(costs, *tables, nx, ny, rec, buf_a, buf_b, buf_c, seed_cells, seed_pots,
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
def _close_border(rec: np.ndarray, nx: int, ny: int) -> None:
    for x in range(nx):
        rec[2 * x + GATE] = np.inf
        rec[2 * ((ny - 1) * nx + x) + GATE] = np.inf
    for y in range(ny):
        rec[2 * (y * nx) + GATE] = np.inf
        rec[2 * (y * nx + nx - 1) + GATE] = np.inf


@njit(cache=True)
def reset_records(rec: np.ndarray, costs: np.ndarray, lut_push: np.ndarray, nx: int,
                  ny: int) -> None:
    """POT_HIGH potentials; the gate idle inside, +inf (never queued) on the outer border."""
    for i in range(costs.shape[0]):
        rec[2 * i + POT] = POT_HIGH
        rec[2 * i + GATE] = lut_push[costs[i]]
    _close_border(rec, nx, ny)


# A record as one 8-byte word: the potential half set to POT_HIGH, and the mask of the gate half
# (built through numpy, so either byte order puts them in the right place)
_POT_HIGH_WORD = np.array([POT_HIGH, 0.0], np.float32).view(np.uint64)[0]
_GATE_MASK = np.array([0, 0xFFFFFFFF], np.uint32).view(np.uint64)[0]


@njit(cache=True)
def refresh_records(rec: np.ndarray, gate_costs: np.ndarray, costs: np.ndarray,
                    lut_push: np.ndarray, nx: int, ny: int) -> None:
    """``reset_records`` for records whose gates a run on ``gate_costs`` (with the same
    ``lut_push``) left idle: only cells whose cost changed since get a new gate (and
    ``gate_costs`` their cost). On an unchanged map this is a compare of 64-cell blocks instead
    of the gather ``lut_push[costs]`` of a full reset."""
    ns = costs.shape[0]
    # the potentials set as whole words that keep the gate half: vectorised, where a strided
    # store of the potentials alone took 1.5 x as long (and one pass with the compare below 1.4 x)
    words = rec.view(np.uint64)
    for i in range(ns):
        words[i] = (words[i] & _GATE_MASK) | _POT_HIGH_WORD
    # costs compared as 8-byte words, 8 words (64 cells) a block: uint8 arithmetic would widen
    end = ns - ns % 64
    cw = costs[:end].view(np.uint64)
    last_cw = gate_costs[:end].view(np.uint64)
    changed = False
    for b in range(0, end // 8, 8):
        diff = np.uint64(0)
        for w in range(b, b + 8):
            diff |= cw[w] ^ last_cw[w]
        if diff != 0:
            changed = True
            for i in range(8 * b, 8 * b + 64):
                gate_costs[i] = costs[i]
                rec[2 * i + GATE] = lut_push[costs[i]]
    for i in range(end, ns):
        if costs[i] != gate_costs[i]:
            changed = True
            gate_costs[i] = costs[i]
            rec[2 * i + GATE] = lut_push[costs[i]]
    if changed:  # a border cell may have been rewritten
        _close_border(rec, nx, ny)


class Workspace:
    """Per-map-size buffers reused from plan to plan (ROS reallocates them on every plan).

    ``rec`` holds the kernel's records (potential and gate of each cell); ``pot`` is the
    potential in it, a row-major view with a stride of two floats, which the path and tolerance
    code read (and global_planner's ``clearEndpoint`` writes) as they would a plain array.
    """

    def __init__(self) -> None:
        self.shape: tuple[int, int] = (0, 0)

    def ensure(self, nx: int, ny: int) -> None:
        if self.shape == (nx, ny):
            return
        ns = nx * ny
        if ns >= 2**31:
            raise ValueError(f"map of {ns} cells: the queues hold int32 cell indices")
        self.shape = (nx, ny)
        # the costs and push table the idle gates were built from (None: rebuild them)
        self.gate_lut: np.ndarray | None = None
        self.gate_costs = np.empty(ns, np.uint8)
        self.rec = np.empty(2 * ns, np.float32)
        self.pot = self.rec[POT::2]
        # Whole-map queues: current and next hold a cell at most once, so they cannot overflow;
        # the overflow queue grows itself in the rare case its repeats outgrow the map.
        # np.empty does not touch the pages, so unused queue space costs no time.
        self.buf_a = np.empty(ns, np.int32)
        self.buf_b = np.empty(ns, np.int32)
        self.buf_c = np.empty(ns, np.int32)


def run_wavefront(ws: Workspace, costs: np.ndarray, tables: tuple, nx: int, ny: int,
                  seed_cells: np.ndarray, seed_pots: np.ndarray, push_cells: np.ndarray,
                  target: int, threshold: float, increment: float, max_cycles: int,
                  quadratic: bool, hkind: int = HEURISTIC_NONE, hscale: float = 0.0) -> tuple:
    """``propagate`` on the workspace (``ensure`` it first) from a fresh start; the potential
    ends in ``ws.pot``. ``costs`` is the flat row-major uint8 costmap, ``tables`` the
    ``kernel_tables``."""
    lut_push = tables[0]
    if ws.gate_lut is not None and np.array_equal(ws.gate_lut, lut_push):
        refresh_records(ws.rec, ws.gate_costs, costs, lut_push, nx, ny)
    else:
        reset_records(ws.rec, costs, lut_push, nx, ny)
        ws.gate_costs[:] = costs
    ws.gate_lut = None  # until the kernel has returned with every gate idle again
    out = propagate(costs, tables, nx, ny, ws.rec, ws.buf_a, ws.buf_b, ws.buf_c, seed_cells,
                    seed_pots, push_cells, target, threshold, increment, max_cycles, quadratic,
                    hkind, hscale)
    ws.gate_lut = lut_push.copy()
    return out
