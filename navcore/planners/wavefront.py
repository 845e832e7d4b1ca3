"""The navigation-function wavefront shared by navfn and global_planner (numba kernels).

navfn's "priority block" propagation: cells wait in three buffers (current, next, overflow); a
cell whose new potential is below the threshold pushes its improvable 4-neighbours to ``next``,
otherwise to ``overflow``; when current and next are empty the threshold rises by ``increment``
and the overflow becomes current. The update is navfn's quadratic (planar-wave) one or the plain
``min(4 neighbours) + cost``.

Where this differs from the C++ (no dropped pushes, no cell left waiting in the overflow, a
converged target, wider bands) is listed in docs/ros-users.md, "The planners' wavefront".

Costs reach the kernel as the raw uint8 costmap plus a 256-entry float32 lookup table (the
planner's cost transform). Each cell has an 8-byte record: its potential and its "gate" (queue
state and push cost in one float32, see the push rule), set from the costs. Cells on the outer
border have a gate of +inf and are never queued: that is navfn's border of COST_OBS and
global_planner's ``outline_map`` without writing into the shared costmap. The planners read the
potential through a strided view of the records (``Workspace.pot``).

A* (``hkind``) is navfn's ``calcNavFnAstar``: the band of a cell is chosen by potential plus
heuristic.

Why it is shaped this way: one update per passable cell is about all a band order can do, so the
time is the cost of one update, mostly memory. Hence the 8-byte record (one cache line holds
what a push test and an update need), one compiled variant per (update, search) kind (no flag
tests in the loop), branch-free pushes (at the wave front their outcome is a coin flip), and
buffers and gates reused from plan to plan. The planners run a fast variant of the same kernel
(``KERNEL_VARIANT``: cache prefetch hints, and on AVX-512 the four pushes as one vector step
that packs the pushed cells in a register, both LLVM IR) that visits the cells in the same
order with the same results; the plain kernel beside it is what NUMBA_DISABLE_JIT=1 and
NAVBT_PLAIN_KERNELS=1 run. The measurements behind each choice, and what was tried without
gain, are in docs/performance.md.

``plan_field`` roots the field at the goal and repairs it on a replan, with a monotone form of the
quadratic update that makes the field independent of the visiting order (see there).
"""

from __future__ import annotations

import math

import numpy as np
import os

from numba import njit

from navcore.planners import push4
from navcore.planners.push4 import push4_next, push4_over
from navcore.prefetch import prefetch_write

POT_HIGH = np.float32(1.0e10)
INVSQRT2 = 0.707106781

_QA = np.float32(-0.2301)
_QB = np.float32(0.5307)
_QC = np.float32(0.7040)
# the same coefficients for the monotone update (float64 arithmetic)
_QA64 = -0.2301
_QB64 = 0.5307
_QC64 = 0.7040

# Update kinds (``propagate``'s ``quadratic``): min(4 neighbours) + cost, navfn's quadratic, and
# the quadratic made monotone for the goal-rooted field a replan repairs (``plan_field``)
UPDATE_PLAIN = 0
UPDATE_QUADRATIC = 1
UPDATE_MONOTONE = 2
# The idle gate of every passable cell under UPDATE_MONOTONE: a neighbour is queued whenever it
# is above the new potential (see ``plan_field``)
EXACT_GATE = np.float32(np.finfo(np.float32).tiny)
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
assert push4.GATE == GATE


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
    for i in range(buf.shape[0]):  # not a slice copy: see ``pending`` in propagate
        big[i] = buf[i]
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
# coin flip, and mispredictions dominated the run time): each neighbour, in the order left,
# right, up, down, is stored at the queue's end and the count advances only when it was pushed.


@njit(cache=True, inline="always")
def _push_next(rec: np.ndarray, queue: np.ndarray, count: np.uintp, p: np.float32,
               pm: np.float32, m: np.uintp) -> np.uintp:
    """The push rule below the threshold for neighbour ``m`` (old potential ``pm``): to next,
    also from overflow. Branch-free: the cell is always written at ``count``, which advances
    only when it was pushed."""
    g = rec[np.uintp(2) * m + np.uintp(GATE)]
    ok = pm > p + abs(g)
    rec[np.uintp(2) * m + np.uintp(GATE)] = np.float32(np.inf) if ok else g
    queue[count] = m
    return count + np.uintp(ok)


@njit(cache=True, inline="always")
def _push_over(rec: np.ndarray, queue: np.ndarray, count: np.uintp, p: np.float32,
               pm: np.float32, m: np.uintp) -> np.uintp:
    """The push rule above the threshold: to overflow when idle (the gate turns negative)."""
    g = rec[np.uintp(2) * m + np.uintp(GATE)]
    ok = (pm > p + g) & (g > np.float32(0.0))
    rec[np.uintp(2) * m + np.uintp(GATE)] = -g if ok else g
    queue[count] = m
    return count + np.uintp(ok)


# The same two rules with the gate's new value chosen by integer masks on its bits (``bits``, an
# int32 view of the records), for the fast variant on CPUs without AVX-512: compiled for those,
# LLVM turns the float selects above into branches, which at the wave front mispredict half the
# time (with AVX-512 they are masked moves, and the masks cost more than they save).
_INF_BITS = np.int32(0x7F800000)
_SIGN_BIT = np.int32(-0x80000000)


@njit(cache=True, inline="always")
def _push_next_bits(rec: np.ndarray, bits: np.ndarray, queue: np.ndarray, count: np.uintp,
                    p: np.float32, pm: np.float32, m: np.uintp) -> np.uintp:
    """``_push_next`` with an integer select."""
    k = np.uintp(2) * m + np.uintp(GATE)
    ok = pm > p + abs(rec[k])
    b = bits[k]
    bits[k] = b ^ ((b ^ _INF_BITS) & (np.int32(0) - np.int32(ok)))  # +inf if pushed
    queue[count] = m
    return count + np.uintp(ok)


@njit(cache=True, inline="always")
def _push_over_bits(rec: np.ndarray, bits: np.ndarray, queue: np.ndarray, count: np.uintp,
                    p: np.float32, pm: np.float32, m: np.uintp) -> np.uintp:
    """``_push_over`` with an integer select."""
    k = np.uintp(2) * m + np.uintp(GATE)
    g = rec[k]
    ok = (pm > p + g) & (g > np.float32(0.0))
    bits[k] = bits[k] ^ (_SIGN_BIT & (np.int32(0) - np.int32(ok)))  # negated if pushed
    queue[count] = m
    return count + np.uintp(ok)


# How many queue places ahead the fast kernel prefetches a cell's lines
PREFETCH_AHEAD = 8


def _target_has_avx512vl() -> bool:
    """Whether numba compiles for a CPU with AVX-512VL (the vector compress): the CPU named
    by NUMBA_CPU_NAME / NUMBA_CPU_FEATURES, else the host's (llvmlite's public query)."""
    from numba.core import config
    if config.CPU_NAME or config.CPU_FEATURES:
        return "+avx512vl" in (config.CPU_FEATURES or "")
    from llvmlite import binding
    return bool(binding.get_host_cpu_features().get("avx512vl", False))


# The kernel variant the planners run, (prefetch, compress): the plain kernel (False, False)
# under NUMBA_DISABLE_JIT or with NAVBT_PLAIN_KERNELS=1, else the prefetch hints and, on
# AVX-512 targets, the vector push, elsewhere the integer-select pushes (docs/performance.md).
PLAIN_VARIANT = (False, False)
KERNEL_VARIANT = PLAIN_VARIANT if (os.environ.get("NUMBA_DISABLE_JIT", "0") not in ("", "0")
                                   or os.environ.get("NAVBT_PLAIN_KERNELS") == "1") \
    else (True, _target_has_avx512vl())




@njit(cache=True, inline="always")
def _make_idle(rec: np.ndarray, costs: np.ndarray, lut_push: np.ndarray, queue: np.ndarray,
               count: int) -> None:
    for i in range(count):
        m = queue[i]
        rec[2 * m + GATE] = lut_push[costs[m]]


def _make_propagate(update: int, astar: bool, prefetch: bool, compress: bool):
    """``propagate`` compiled for one update kind (UPDATE_*) and search kind, with or without the
    prefetch hints and the compressing push (``KERNEL_VARIANT``): the flags are constants of the
    closure, so each variant carries only its own code (a single generic kernel spent a third of
    its instructions on flag tests and on spilled registers)."""
    quadratic = update != UPDATE_PLAIN
    monotone = update == UPDATE_MONOTONE
    # the fast variant without the vector push (a CPU without AVX-512): integer-select pushes
    int_select = prefetch and not compress

    @njit(cache=True)
    def propagate(costs: np.ndarray, lut_push: np.ndarray, lut_hf: np.ndarray,
                  lut_inv: np.ndarray, nx: int, ny: int, rec: np.ndarray,
                  buf_a: np.ndarray, buf_b: np.ndarray, buf_c: np.ndarray,
                  seed_cells: np.ndarray, seed_pots: np.ndarray, push_cells: np.ndarray,
                  target: int, threshold: float, increment: float, max_cycles: int, hkind: int,
                  hscale: float, stop_margin: float) -> tuple:
        ns = nx * ny
        if int_select:
            bits = rec.view(np.int32)  # the records' bits, for the integer selects
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
            ahead = np.uintp(PREFETCH_AHEAD)
            for i in range(ncur):
                # unsigned indices: numba then skips its negative-index wraparound test
                n = np.uintp(cur[i])
                if prefetch and i + ahead < ncur:
                    # the front's lines come from L3 or memory: ask for those of a cell a few
                    # places ahead in the queue while this one is updated (same results)
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
                if monotone:
                    # navfn's planar-wave update with its factor capped at 1 (it reaches 1.0046
                    # at dc == hf and then drops to 1), in float64: monotone in both sides
                    # (``plan_field`` says why)
                    q = min(abs(np.float64(tc) - np.float64(ta0))
                            * np.float64(cost_rec[cn + np.uintp(2)]), 1.0)
                    g = min(_QC64 + q * (_QB64 + _QA64 * q), 1.0)
                    p = np.float32(np.float64(ta) + np.float64(hf) * g)
                elif quadratic:
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
                if compress:  # the same pushes as one vector step (navcore/planners/push4.py)
                    if below:
                        nnext = push4_next(rec, nxt, nnext, p, l, r, u, d, n - one, n + one,
                                           n - unx, n + unx)
                    else:
                        nover = push4_over(rec, over, nover, p, l, r, u, d, n - one, n + one,
                                           n - unx, n + unx)
                elif int_select:  # (the same pushes, see _push_next_bits)
                    if below:
                        nnext = _push_next_bits(rec, bits, nxt, nnext, p, l, n - one)
                        nnext = _push_next_bits(rec, bits, nxt, nnext, p, r, n + one)
                        nnext = _push_next_bits(rec, bits, nxt, nnext, p, u, n - unx)
                        nnext = _push_next_bits(rec, bits, nxt, nnext, p, d, n + unx)
                    else:
                        nover = _push_over_bits(rec, bits, over, nover, p, l, n - one)
                        nover = _push_over_bits(rec, bits, over, nover, p, r, n + one)
                        nover = _push_over_bits(rec, bits, over, nover, p, u, n - unx)
                        nover = _push_over_bits(rec, bits, over, nover, p, d, n + unx)
                elif below:
                    nnext = _push_next(rec, nxt, nnext, p, l, n - one)
                    nnext = _push_next(rec, nxt, nnext, p, r, n + one)
                    nnext = _push_next(rec, nxt, nnext, p, u, n - unx)
                    nnext = _push_next(rec, nxt, nnext, p, d, n + unx)
                else:
                    nover = _push_over(rec, over, nover, p, l, n - one)
                    nover = _push_over(rec, over, nover, p, r, n + one)
                    nover = _push_over(rec, over, nover, p, u, n - unx)
                    nover = _push_over(rec, over, nover, p, d, n + unx)
            tmp = cur
            cur = nxt
            nxt = tmp
            ncur = nnext
            nnext = zero
            from_over = False
            if ncur == zero:
                # band below t is exhausted: every cell under t is final
                if rec[2 * target + POT] + stop_margin < t:
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
        # what was still queued: a repair (``repair_field``) continues the wave from there
        # (element loops: a slice copy brings numba's shape-error formatting, seconds of compile)
        pending = np.empty(ncur + nnext + nover, np.int32)
        for i in range(ncur):
            pending[i] = cur[i]
        for i in range(nnext):
            pending[ncur + i] = nxt[i]
        for i in range(nover):
            pending[ncur + nnext + i] = over[i]
        return reached, updates, cycle, pending

    return propagate


_PROPAGATE = {(q, a, *v): _make_propagate(q, a, *v)
              for q in (UPDATE_PLAIN, UPDATE_QUADRATIC, UPDATE_MONOTONE)
              for a in (False, True) for v in {PLAIN_VARIANT, KERNEL_VARIANT}}


def propagate(costs: np.ndarray, tables: tuple, nx: int, ny: int, rec: np.ndarray,
              buf_a: np.ndarray, buf_b: np.ndarray, buf_c: np.ndarray,
              seed_cells: np.ndarray, seed_pots: np.ndarray, push_cells: np.ndarray,
              target: int, threshold: float, increment: float, max_cycles: int,
              quadratic: int, hkind: int = HEURISTIC_NONE, hscale: float = 0.0,
              stop_margin: float = 0.0) -> tuple:
    """Spread potential from the seeds until ``target`` is final or nothing is left to update.

    ``quadratic`` is the update kind: UPDATE_PLAIN (False), UPDATE_QUADRATIC (True, navfn's) or
    UPDATE_MONOTONE (with EXACT_GATE push costs; see ``plan_field``).

    ``costs`` is the flat uint8 costmap and ``tables`` its ``kernel_tables``. ``rec`` (float32,
    two per cell: potential at 2n, gate at 2n + 1) must hold POT_HIGH potentials and the idle
    gates with +inf on the border (``reset_records``). Seeds get ``seed_pots``; ``push_cells``
    start the wave. The search stops once every cell below the target's potential plus
    ``stop_margin`` is final. Returns ``(reached, cell_updates, cycles, pending)``, ``pending``
    the cells still queued then.

    With ``hkind`` HEURISTIC_MANHATTAN or HEURISTIC_EUCLIDEAN this is A* in navfn's
    ``calcNavFnAstar`` manner: a cell's band is decided by potential plus ``hscale`` x its
    distance to ``target`` instead of the potential alone (the stored potential has no heuristic).
    With a consistent heuristic every cell whose key is below a finished band is final, as above.
    """
    kernel = _PROPAGATE[(int(quadratic), hkind != HEURISTIC_NONE, *KERNEL_VARIANT)]
    return kernel(costs, *tables, nx, ny, rec, buf_a, buf_b, buf_c, seed_cells, seed_pots,
                  push_cells, target, threshold, increment, max_cycles, hkind, hscale,
                  stop_margin)


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
        # the goal-rooted field a replan may repair (``plan_field``): its key and queued cells
        self.field: tuple | None = None
        self.pending = np.empty(0, np.int32)
        self.old_pot = np.empty(ns, np.float32)


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
    ws.field = None  # a robot-rooted field: nothing a repair could reuse
    return out[:3]



# ---------------------------------------------------------------- replanning: repair, not redo
#
# A replan toward the same goal can reuse the last field when the field is rooted at the goal:
# the robot is then only where the wave stops, and a cell's potential depends only on the costs
# along its way down to the goal. A cost change invalidates the changed cells and, transitively,
# each cell whose update read an invalidated cell: the update reads min(left, right) and
# min(up, down), so m depends on a neighbour n only if n's potential is below m's and n was the
# lower of m's pair along that axis. Those cells lose their potential; the wave restarts from
# them, from the changed cells and from whatever the last run left queued (the LPA* idea on
# navfn's bands).
#
# A repair visits cells in another order than a fresh plan, so it gives the fresh plan's field
# only where the field does not depend on the order. The plain update's does not. navfn's
# quadratic one does, for two reasons: its factor jumps down from 1.0046 to 1 at dc == hf (not
# monotone: a neighbour that drops can raise the candidate, and a cell keeps the lowest candidate
# it ever saw), and its push rule (queue m when pm > p + cost/sqrt(2)) misses neighbours for which
# p is the larger side (the candidate is then as little as 0.005 x cost above p), which then keep
# a value computed from stale neighbours. The goal-rooted field therefore uses UPDATE_MONOTONE:
# the factor capped at 1 (an update's value moves by at most 0.46 % of the cell's cost, where
# 0.945 < dc/hf < 1), computed in float64 (exact differences of float32 inputs dwarf its rounding,
# so the float32 result is monotone in both sides), and neighbours queued whenever they are above
# the new potential (EXACT_GATE). Every run then ends with every cell below its last finished band
# equal to the greatest fixed point of the update, whatever the order or band width, from any
# starting state that is nowhere below that fixed point and has every cell it could lower queued;
# the invalidation above leaves such a state. So a repair equals the fresh plan bit for bit on the
# cells the descent reads, and both equal the plain FIFO propagation of the tests. The cost: 8 %
# more updates than navfn's rule on the office maps.


@njit(cache=True)
def sync_view(view: np.ndarray, costs: np.ndarray, free_cell: int, changed: np.ndarray,
              cap: int) -> int:
    """Bring ``view`` (the planner's copy of the flat costs) up to ``costs``, with ``free_cell``
    reading free (navfn clears the robot's cell; here on the copy only). The cells that changed
    go to ``changed``; returns their count, or -1 once more than ``cap`` changed (``view`` is
    then partly updated: plan afresh)."""
    ns = costs.shape[0]
    end = ns - ns % 64
    cw = costs[:end].view(np.uint64)
    vw = view[:end].view(np.uint64)
    n = 0
    for start in range(0, ns, 64):  # blocks of 64 cells (8 words); the last may be shorter
        if start < end and start != free_cell - free_cell % 64:
            diff = np.uint64(0)
            for w in range(start // 8, start // 8 + 8):
                diff |= cw[w] ^ vw[w]
            if diff == 0:
                continue
        for i in range(start, min(start + 64, ns)):
            want = 0 if i == free_cell else costs[i]
            if view[i] != want:
                if n >= cap:
                    return -1
                changed[n] = i
                n += 1
                view[i] = want
    return n


@njit(cache=True)
def invalidate(rec: np.ndarray, view: np.ndarray, lut_push: np.ndarray, nx: int, ny: int,
               changed: np.ndarray, n_changed: int, lost: np.ndarray, old_pot: np.ndarray,
               cap: int) -> int:
    """Give the changed cells their new gate and take the potential (POT_HIGH) of every cell
    that may depend on one of them (see above); ``lost`` lists those cells (``old_pot`` their
    former potentials). Returns how many, or -1 once more than ``cap``."""
    k = 0
    for j in range(n_changed):
        c = changed[j]
        x = c % nx
        y = c // nx
        if x == 0 or y == 0 or x == nx - 1 or y == ny - 1:
            rec[2 * c + GATE] = np.inf
        else:
            rec[2 * c + GATE] = lut_push[view[c]]
        p = rec[2 * c + POT]
        if p < POT_HIGH:
            if k >= cap:
                return -1
            lost[k] = c
            old_pot[k] = p
            k += 1
            rec[2 * c + POT] = POT_HIGH
    i = 0
    while i < k:
        n = lost[i]
        po = old_pot[i]
        i += 1
        for side in range(4):
            # neighbour m and the other cell of m's pair along the same axis
            if side == 0:
                m, other = n - 1, n - 2
            elif side == 1:
                m, other = n + 1, n + 2
            elif side == 2:
                m, other = n - nx, n - 2 * nx
            else:
                m, other = n + nx, n + 2 * nx
            pm = rec[2 * m + POT]
            if pm >= POT_HIGH or not pm > po:  # the border is never reached: other is inside
                continue
            if po <= rec[2 * other + POT]:
                if k >= cap:
                    return -1
                lost[k] = m
                old_pot[k] = pm
                k += 1
                rec[2 * m + POT] = POT_HIGH
    return k


def plan_field(ws: Workspace, costs: np.ndarray, tables: tuple, nx: int, ny: int,
               seed_cells: np.ndarray, seed_pots: np.ndarray, push_cells: np.ndarray,
               target: int, threshold: float, increment: float, max_cycles: int,
               quadratic: bool, stop_margin: float, reuse: bool = True,
               max_changed: float = 0.02) -> tuple:
    """A field rooted at the seeds (the goal), final below the potential of ``target`` (the
    robot) plus ``stop_margin``, computed on the workspace's copy of ``costs`` in which the
    target's cell reads free (``ws.gate_costs``; the potential ends in ``ws.pot``).

    With ``reuse``, a field from the same seeds, tables and bands is repaired instead of
    recomputed, unless more than ``max_changed`` of the cells changed. Returns ``(reached,
    cell_updates, cycles, repaired)``. The quadratic update runs as UPDATE_MONOTONE (``tables``
    then get EXACT_GATE push costs): repaired and fresh fields agree exactly (see above).
    """
    update = UPDATE_PLAIN
    if quadratic:
        update = UPDATE_MONOTONE
        tables = (np.where(tables[0] < np.inf, EXACT_GATE, np.float32(np.inf)).astype(np.float32),
                  tables[1], tables[2])
    lut_push = tables[0]
    ns = nx * ny
    key = (seed_cells.tobytes(), seed_pots.tobytes(), bool(quadratic), float(threshold),
           float(increment), float(stop_margin))
    same = ws.gate_lut is not None and np.array_equal(ws.gate_lut, lut_push)
    if reuse and same and ws.field is not None and ws.field[:5] == key[:5]:
        cap = max(64, int(max_changed * ns))
        n = sync_view(ws.gate_costs, costs, target, ws.buf_a, cap)
        changed = ws.buf_a[:max(n, 0)]
        if n >= 0 and not np.isin(seed_cells, changed).any():
            ws.gate_lut = None
            k = invalidate(ws.rec, ws.gate_costs, lut_push, nx, ny, ws.buf_a, n, ws.buf_b,
                           ws.old_pot, max(64, ns // 4))
            if k >= 0:
                push = np.concatenate((changed, ws.buf_b[:k], ws.pending)).astype(np.int64)
                out = propagate(ws.gate_costs, tables, nx, ny, ws.rec, ws.buf_a, ws.buf_b,
                                ws.buf_c, seed_cells[:0], seed_pots[:0], push, target,
                                _repair_threshold(ws.pot, push, nx, ns, threshold) + increment,
                                increment, max_cycles, update, stop_margin=stop_margin)
                ws.pending, ws.field, ws.gate_lut = out[3], key, lut_push.copy()
                return out[0], out[1], out[2], True
        ws.gate_lut = None  # the copy is partly synced, or gates were rewritten: start afresh
    # afresh: the copy and the gates from the costs, then a full wave from the seeds
    if same and ws.gate_lut is not None:
        refresh_records(ws.rec, ws.gate_costs, costs, lut_push, nx, ny)
    else:
        reset_records(ws.rec, costs, lut_push, nx, ny)
        ws.gate_costs[:] = costs
    ws.gate_lut = None
    if 0 <= target < ns and ws.gate_costs[target] != 0:
        ws.gate_costs[target] = 0
        tx, ty = target % nx, target // nx
        if 0 < tx < nx - 1 and 0 < ty < ny - 1:
            ws.rec[2 * target + GATE] = lut_push[0]
    out = propagate(ws.gate_costs, tables, nx, ny, ws.rec, ws.buf_a, ws.buf_b, ws.buf_c,
                    seed_cells, seed_pots, push_cells, target, threshold, increment, max_cycles,
                    update, stop_margin=stop_margin)
    ws.pending, ws.field, ws.gate_lut = out[3], key, lut_push.copy()
    return out[0], out[1], out[2], False


def _repair_threshold(pot: np.ndarray, cells: np.ndarray, nx: int, ns: int,
                      fallback: float) -> float:
    """The lowest potential next to the cells a repair starts from: its first band's base."""
    if len(cells) == 0:
        return fallback
    nb = np.concatenate((cells - 1, cells + 1, cells - nx, cells + nx))
    v = pot[nb[(nb >= 0) & (nb < ns)]]
    v = v[v < POT_HIGH]
    return float(v.min()) if len(v) else fallback


def descent_margin(lut: np.ndarray, costs2d: np.ndarray, cell: tuple[int, int],
                   block: float) -> float:
    """How far above the robot's potential a goal-rooted field must be final for the descent
    from the robot: it reads cells up to three steps away, each step costing at most the
    dearest passable cost in the 7x7 cells around it."""
    x, y = cell
    win = lut[costs2d[max(0, y - 3):y + 4, max(0, x - 3):x + 4]]
    win = win[win < block]
    return 3.0 * float(win.max()) if len(win) else 0.0
