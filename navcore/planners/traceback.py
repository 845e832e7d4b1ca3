"""Path extraction from a potential field (numba kernels).

``gradient_path`` is navfn's ``calcPath`` / global_planner's ``GradientPath``: descend the
bilinearly interpolated, normalised gradient in half-cell steps, falling back to a step to the
lowest 8-neighbour next to unreached cells or when the path oscillates. ``grid_path`` is
global_planner's ``GridPath``: steepest descent over the 8 neighbours.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from navcore.planners.wavefront import POT_HIGH

PATH_STEP = 0.5  # cells per gradient step (navfn pathStep)
STOP_NEAR_NEUTRAL = 0  # navfn: stop where the potential drops below COST_NEUTRAL
STOP_NEAR_POINT = 1  # global_planner: stop within half a cell of the seed point

_INT_MIN = -2147483648.0


@njit(cache=True, inline="always")
def _round_half_away(v: float) -> int:
    return int(math.floor(v + 0.5)) if v >= 0.0 else -int(math.floor(-v + 0.5))


@njit(cache=True, inline="always")
def _int_trunc(v: float) -> float:
    """C++ float -> int conversion on x86: truncation, INT_MIN when out of range."""
    if v >= 2147483648.0 or v < -2147483648.0:
        return _INT_MIN
    return float(int(v))


@njit(cache=True, inline="always")
def _grad_cell(pot: np.ndarray, n: int, nx: int, ns: int, obs_grad: float) -> tuple:
    """Unit descent direction at cell n, rounded to float32 as navfn stores it; (0, 0) on the
    first and last rows and where the gradient vanishes.

    navfn caches these per cell, but its cache test (``gradx + grady > 0``) misses for every
    gradient pointing down or left, and the potential does not change while a path is extracted,
    so computing each one afresh gives the same values without two map-sized caches to reset.
    navfn's row test lets the first cell of the last row through and reads one cell past the
    end of the map there; here the whole last row gives (0, 0).
    """
    if n < nx or n >= ns - nx:
        return 0.0, 0.0
    cv = pot[n]
    pl = pot[n - 1]
    pr = pot[n + 1]
    pu = pot[n - nx]
    pd = pot[n + nx]
    dx = 0.0
    dy = 0.0
    if cv >= POT_HIGH:  # inside an obstacle: head for a reached neighbour
        if pl < POT_HIGH:
            dx = -obs_grad
        elif pr < POT_HIGH:
            dx = obs_grad
        if pu < POT_HIGH:
            dy = -obs_grad
        elif pd < POT_HIGH:
            dy = obs_grad
    else:
        # float32 differences summed in double (float(): plain Python would keep float32)
        if pl < POT_HIGH:
            dx += float(pl - cv)
        if pr < POT_HIGH:
            dx += float(cv - pr)
        if pu < POT_HIGH:
            dy += float(pu - cv)
        if pd < POT_HIGH:
            dy += float(cv - pd)
    norm = np.hypot(dx, dy)  # libm's in both modes (Python's math.hypot rounds differently)
    if norm > 0.0:
        return float(np.float32(dx / norm)), float(np.float32(dy / norm))
    return 0.0, 0.0


@njit(cache=True, inline="always")
def _unreached_near(pot: np.ndarray, stc: int, nx: int) -> bool:
    """Whether cell ``stc`` or one of its 8 neighbours has no potential (one max over the nine:
    a loop over them or a chain of ``or`` tests took a third of a path's time)."""
    up = stc + nx
    dn = stc - nx
    a = max(pot[dn - 1], pot[dn])
    b = max(pot[dn + 1], pot[stc - 1])
    c = max(pot[stc], pot[stc + 1])
    d = max(pot[up - 1], pot[up])
    e = pot[up + 1]
    return max(max(max(a, b), max(c, d)), e) >= POT_HIGH


@njit(cache=True)
def gradient_path(pot: np.ndarray, nx: int, ny: int, from_x: float, from_y: float,
                  stop_mode: int, to_x: float, to_y: float, max_steps: int, obs_grad: float
                  ) -> tuple:
    """Descend from (from_x, from_y) (cells, fractional allowed) to the seed at (to_x, to_y).

    Returns ``(ok, xy)`` with ``xy`` an (N, 2) float64 array of cell coordinates from the start of
    the descent to the seed. ``pot`` may be a strided view (the wavefront's ``Workspace.pot``).
    """
    ns = nx * ny
    stc = int(from_y) * nx + int(from_x)
    dx = from_x - int(from_x)
    dy = from_y - int(from_y)
    cap = 1024
    xs = np.empty(cap, np.float64)
    ys = np.empty(cap, np.float64)
    npath = 0
    ok = False
    # the four corner gradients of the last cell interpolated in: the fractional position moves
    # half a cell a step within (-1, 1), so the next steps mostly stay in the same cell
    gcell = -1
    gx00 = gy00 = gx10 = gy10 = gx01 = gy01 = gx11 = gy11 = 0.0
    for _ in range(max_steps):
        if npath + 1 >= cap:
            cap *= 2
            xs2 = np.empty(cap, np.float64)
            ys2 = np.empty(cap, np.float64)
            for i in range(npath):  # element loops: a slice copy costs seconds of compile
                xs2[i] = xs[i]
                ys2[i] = ys[i]
            xs = xs2
            ys = ys2
        px = stc % nx + dx
        py = stc // nx + dy
        if stop_mode == STOP_NEAR_NEUTRAL:
            near = stc + _round_half_away(dx) + nx * _round_half_away(dy)
            near = max(0, min(ns - 1, near))
            if pot[near] < 50.0:
                xs[npath] = to_x
                ys[npath] = to_y
                npath += 1
                ok = True
                break
        elif abs(px - to_x) < 0.5 and abs(py - to_y) < 0.5:
            xs[npath] = to_x
            ys[npath] = to_y
            npath += 1
            ok = True
            break
        if stc < nx or stc >= ns - nx:  # would read outside the grid
            break
        xs[npath] = px
        ys[npath] = py
        npath += 1
        oscillating = (npath > 2 and xs[npath - 1] == xs[npath - 3]
                       and ys[npath - 1] == ys[npath - 3])
        up = stc + nx
        dn = stc - nx
        if oscillating or _unreached_near(pot, stc, nx):
            # grid step to the lowest 8-neighbour; the C++ compares against an int copy
            minc = stc
            minp = _int_trunc(pot[stc])
            for st in (dn - 1, dn, dn + 1, stc - 1, stc + 1, up - 1, up, up + 1):
                v = pot[st]
                if v < minp:
                    minp = _int_trunc(v)
                    minc = st
            stc = minc
            dx = 0.0
            dy = 0.0
            if pot[stc] >= POT_HIGH:
                break
        else:
            if stc != gcell:
                # a step to a side neighbour keeps the two corners they share (a corner's
                # gradient depends on the potential only, which a descent does not change)
                step = stc - gcell if gcell >= 0 and nx > 2 else 0
                if step == 1:
                    gx00, gy00, gx01, gy01 = gx10, gy10, gx11, gy11
                elif step == -1:
                    gx10, gy10, gx11, gy11 = gx00, gy00, gx01, gy01
                elif step == nx:
                    gx00, gy00, gx10, gy10 = gx01, gy01, gx11, gy11
                elif step == -nx:
                    gx01, gy01, gx11, gy11 = gx00, gy00, gx10, gy10
                if step != 1 and step != nx:
                    gx00, gy00 = _grad_cell(pot, stc, nx, ns, obs_grad)
                if step != -1 and step != nx:
                    gx10, gy10 = _grad_cell(pot, stc + 1, nx, ns, obs_grad)
                if step != 1 and step != -nx:
                    gx01, gy01 = _grad_cell(pot, up, nx, ns, obs_grad)
                if step != -1 and step != -nx:
                    gx11, gy11 = _grad_cell(pot, up + 1, nx, ns, obs_grad)
                gcell = stc
            x1 = (1.0 - dx) * gx00 + dx * gx10
            x2 = (1.0 - dx) * gx01 + dx * gx11
            gx = (1.0 - dy) * x1 + dy * x2
            y1 = (1.0 - dx) * gy00 + dx * gy10
            y2 = (1.0 - dx) * gy01 + dx * gy11
            gy = (1.0 - dy) * y1 + dy * y2
            if gx == 0.0 and gy == 0.0:
                break
            ss = PATH_STEP / np.hypot(gx, gy)
            dx += gx * ss
            dy += gy * ss
            if dx > 1.0:
                stc += 1
                dx -= 1.0
            if dx < -1.0:
                stc -= 1
                dx += 1.0
            if dy > 1.0:
                stc += nx
                dy -= 1.0
            if dy < -1.0:
                stc -= nx
                dy += 1.0
            if stc < 0 or stc >= ns:
                break
    out = np.empty((npath, 2), np.float64)
    for i in range(npath):
        out[i, 0] = xs[i]
        out[i, 1] = ys[i]
    return ok, out


@njit(cache=True)
def grid_path(pot: np.ndarray, nx: int, ny: int, from_x: float, from_y: float, to_x: float,
              to_y: float, max_steps: int) -> tuple:
    """Steepest 8-neighbour descent from (from_x, from_y) to the cell of (to_x, to_y).

    Returns ``(ok, xy)``: the first point is (from_x, from_y), the rest are cell indices.
    """
    target = int(to_y) * nx + int(to_x)
    cap = 1024
    xs = np.empty(cap, np.float64)
    ys = np.empty(cap, np.float64)
    cx = from_x
    cy = from_y
    xs[0] = cx
    ys[0] = cy
    npath = 1
    ok = True
    steps = 0
    while int(cy) * nx + int(cx) != target:
        best = 1.0e10
        bx = 0
        by = 0
        for xd in range(-1, 2):
            for yd in range(-1, 2):
                if xd == 0 and yd == 0:
                    continue
                x = int(cx + xd)
                y = int(cy + yd)
                if x < 0 or y < 0 or x >= nx or y >= ny:
                    continue
                v = pot[y * nx + x]
                if v < best:
                    best = v
                    bx = x
                    by = y
        if bx == 0 and by == 0:
            ok = False
            break
        cx = float(bx)
        cy = float(by)
        if npath >= cap:
            cap *= 2
            xs2 = np.empty(cap, np.float64)
            ys2 = np.empty(cap, np.float64)
            for i in range(npath):  # element loops: a slice copy costs seconds of compile
                xs2[i] = xs[i]
                ys2[i] = ys[i]
            xs = xs2
            ys = ys2
        xs[npath] = cx
        ys[npath] = cy
        npath += 1
        steps += 1
        if steps > max_steps:
            ok = False
            break
    out = np.empty((npath, 2), np.float64)
    for i in range(npath):
        out[i, 0] = xs[i]
        out[i, 1] = ys[i]
    return ok, out
