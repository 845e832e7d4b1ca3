"""Rigid-body physics of the simulated base, as numba kernels.

One call of ``physics_steps`` advances the robot by n fixed steps: the wheel velocity tracks the
command within the acceleration limits, faults and slip turn wheel motion into (less) body motion,
and the body moves along exact arcs in sub-steps small enough that no footprint point moves more
than half a map cell between collision checks, so the robot cannot tunnel through a one-cell wall
or a thin object. A sub-step that would overlap something is not taken: the robot stops there
(bisected to under a millimetre from the obstacle) and the contact is reported. Odometry and IMU
samples fall due inside a chunk, so they are published here too, into the state vector; the
Python side builds a message only when someone reads it.

The state lives in one float64 array (indices below) so that the Python side stays thin; it
travels to the kernel with the robot's constants, the fault and contact vectors and the laser's
constants in one "kernel vector" (``KV_*`` offsets): each array argument of a numba call costs
~0.2 us to pass, and the simulator makes one call per chunk.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from hw.sim.sensors import odometry_noise_step, scan_ranges, wrap_angle
from navcore.raycast import segment_blocked

# state vector indices
X, Y, TH = 0, 1, 2            # true pose in map
VX, VY, WZ = 3, 4, 5          # wheel (motor) body velocity, tracks the command
OX, OY, OTH = 6, 7, 8         # noise-free wheel-odometry pose (integrates what the wheels did)
AVX, AVY, AWZ = 9, 10, 11     # actual body velocity (after slip, faults and contacts)
DIST, ROT = 12, 13            # wheel distance and rotation so far (battery drain)
# the published odometry message, one block NOX..O_STAMP (read with one conversion)
NOX, NOY, NOTH = 14, 15, 16   # published (noisy) odometry pose
OTX, OTY, OTW = 17, 18, 19    # published odometry twist
OVX, OVY, OVW = 20, 21, 22    # its variances (diagonal of the twist covariance)
O_STAMP = 23                  # step of the last publication
PWX, PWY, PWTH = 24, 25, 26   # wheel-odometry pose at the last odometry publication
O_K, O_NEXT, O_CUR = 27, 28, 29  # publications so far, step of the next, normals cursor
I_YAW, I_PTH, I_PVX, I_PVY = 30, 31, 32, 33   # imu yaw; true yaw and velocity at last sample
I_RATE, I_AX, I_AY = 34, 35, 36               # published imu readings
I_STAMP, I_K, I_NEXT, I_CUR = 37, 38, 39, 40  # as for odometry (I_NEXT < 0: no imu)
STATE_SIZE = 41

# limits vector indices (constants of the robot)
(L_ACC_X, L_ACC_Y, L_ACC_TH, L_MAX_X, L_MAX_Y, L_MAX_TH, L_OMNI, L_SEP, L_STEP, L_RMAX,
 L_ODOM_P, L_A1, L_A2, L_A3, L_A4, L_A5, L_IMU_P, L_GBIAS, L_GSIG, L_ASIG,
 L_DT, L_OX, L_OY, L_RES) = range(24)
LIMITS_SIZE = 24  # L_ODOM_P / L_IMU_P: publication periods in physics steps (may be fractional);
# L_DT the physics period, L_OX, L_OY, L_RES the map's origin and resolution

# fault vector indices: F_SLIP fraction of wheel motion lost; F_NOROT 1 = body cannot yaw;
# F_STUCK 0 none, 1 left wheel stuck, 2 right wheel stuck
F_SLIP, F_NOROT, F_STUCK = 0, 1, 2
FAULTS_SIZE = 3

# contact info indices
C_FIRST, C_X, C_Y, C_TH, C_LAST, C_SPEED = range(6)
CONTACT_SIZE = 6

# laser vector indices (constants of the laser): mount pose on base_link, first beam angle and
# increment (laser frame), range limit, range noise and the value of a beam that hits nothing
LS_MX, LS_MY, LS_MTH, LS_A0, LS_INC, LS_RMAX, LS_SIGMA, LS_NONE = range(8)
LASER_SIZE = 8

# the kernel vector: where each of the vectors above starts in it
KV_ST = 0
KV_LIM = KV_ST + STATE_SIZE
KV_F = KV_LIM + LIMITS_SIZE
KV_C = KV_F + FAULTS_SIZE
KV_LS = KV_C + CONTACT_SIZE
KV_SIZE = KV_LS + LASER_SIZE


@njit(cache=True)
def arc(x: float, y: float, th: float, vx: float, vy: float, wz: float, dt: float
        ) -> tuple[float, float, float]:
    """Pose after moving with constant body twist (vx, vy, wz) for dt: the exact circular arc."""
    a = wz * dt
    if abs(a) < 1e-9:
        lx = vx * dt - 0.5 * vy * a * dt
        ly = vy * dt + 0.5 * vx * a * dt
    else:
        s = math.sin(a)
        c1 = 1.0 - math.cos(a)
        lx = (vx * s - vy * c1) / wz
        ly = (vx * c1 + vy * s) / wz
    c = math.cos(th)
    sn = math.sin(th)
    return x + c * lx - sn * ly, y + sn * lx + c * ly, th + a


@njit(cache=True)
def _seg_point_dist2(ax: float, ay: float, bx: float, by: float, px: float, py: float) -> float:
    ex = bx - ax
    ey = by - ay
    L = ex * ex + ey * ey
    u = 0.0 if L == 0.0 else ((px - ax) * ex + (py - ay) * ey) / L
    u = min(max(u, 0.0), 1.0)
    dx = ax + u * ex - px
    dy = ay + u * ey - py
    return dx * dx + dy * dy


@njit(cache=True)
def _orient(ax: float, ay: float, bx: float, by: float, cx: float, cy: float) -> float:
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)


@njit(cache=True)
def _segments_touch(ax: float, ay: float, bx: float, by: float,
                    cx: float, cy: float, dx: float, dy: float) -> bool:
    d1 = _orient(cx, cy, dx, dy, ax, ay)
    d2 = _orient(cx, cy, dx, dy, bx, by)
    d3 = _orient(ax, ay, bx, by, cx, cy)
    d4 = _orient(ax, ay, bx, by, dx, dy)
    if ((d1 > 0 and d2 < 0) or (d1 < 0 and d2 > 0)) and ((d3 > 0 and d4 < 0)
                                                         or (d3 < 0 and d4 > 0)):
        return True
    # touching or collinear cases: an end point lying on the other segment
    if d1 == 0 and _seg_point_dist2(cx, cy, dx, dy, ax, ay) == 0.0:
        return True
    if d2 == 0 and _seg_point_dist2(cx, cy, dx, dy, bx, by) == 0.0:
        return True
    if d3 == 0 and _seg_point_dist2(ax, ay, bx, by, cx, cy) == 0.0:
        return True
    if d4 == 0 and _seg_point_dist2(ax, ay, bx, by, dx, dy) == 0.0:
        return True
    return False


@njit(cache=True)
def _inside(fp: np.ndarray, px: float, py: float) -> bool:
    """Even-odd point-in-polygon for a point in the footprint's own frame."""
    n = fp.shape[0]
    inside = False
    j = n - 1
    for i in range(n):
        yi = fp[i, 1]
        yj = fp[j, 1]
        if (yi > py) != (yj > py):
            xc = fp[i, 0] + (py - yi) * (fp[j, 0] - fp[i, 0]) / (yj - yi)
            if px < xc:
                inside = not inside
        j = i
    return inside


@njit(cache=True)
def footprint_hits(fp: np.ndarray, rmax: float, x: float, y: float, th: float,
                   blocked: np.ndarray, clear: np.ndarray, ox: float, oy: float, res: float,
                   circles: np.ndarray, segments: np.ndarray) -> bool:
    """True when the footprint polygon (no vertex farther than ``rmax`` from base_link) at pose
    (x, y, th) overlaps a blocked map cell, a circle or a segment. Map cells are checked along
    the outline only: the robot moves in sub-steps of at most half a cell from a free pose, so a
    cell can only get inside across the outline. The clearance field (cells from this cell's
    centre to the nearest blocked centre) skips that check when every wall is out of reach."""
    n = fp.shape[0]
    c = math.cos(th)
    s = math.sin(th)
    check_map = True
    mx = int(math.floor((x - ox) / res))
    my = int(math.floor((y - oy) / res))
    if 0 <= mx < clear.shape[1] and 0 <= my < clear.shape[0]:
        # the nearest blocked square is at least (clearance - sqrt 2) cells from (x, y)
        check_map = (clear[my, mx] - 1.4143) * res <= rmax
    for i in range(n):
        j = (i + 1) % n
        ax = x + c * fp[i, 0] - s * fp[i, 1]
        ay = y + s * fp[i, 0] + c * fp[i, 1]
        bx = x + c * fp[j, 0] - s * fp[j, 1]
        by = y + s * fp[j, 0] + c * fp[j, 1]
        if check_map and segment_blocked(blocked, ox, oy, res, ax, ay, bx, by):
            return True
        for k in range(circles.shape[0]):
            r = circles[k, 2]
            if _seg_point_dist2(ax, ay, bx, by, circles[k, 0], circles[k, 1]) <= r * r:
                return True
        for k in range(segments.shape[0]):
            if _segments_touch(ax, ay, bx, by, segments[k, 0], segments[k, 1],
                               segments[k, 2], segments[k, 3]):
                return True
    # objects wholly inside the outline
    for k in range(circles.shape[0]):
        dx = circles[k, 0] - x
        dy = circles[k, 1] - y
        if _inside(fp, c * dx + s * dy, -s * dx + c * dy):
            return True
    for k in range(segments.shape[0]):
        dx = segments[k, 0] - x
        dy = segments[k, 1] - y
        if _inside(fp, c * dx + s * dy, -s * dx + c * dy):
            return True
    return False


@njit(cache=True)
def _approach(v: float, target: float, step: float) -> float:
    if target > v + step:
        return v + step
    if target < v - step:
        return v - step
    return target


@njit(cache=True)
def physics_steps(kv: np.ndarray, cvx: float, cvy: float, cwz: float, n_cmd: int, n_steps: int,
                  step0: int, check_idle: bool, fp: np.ndarray, blocked: np.ndarray,
                  clear: np.ndarray, circles: np.ndarray, segments: np.ndarray,
                  odom_normals: np.ndarray, imu_normals: np.ndarray, seed: int,
                  out: np.ndarray) -> None:
    """Advance the state (``kv``, see ``KV_*``) by ``n_steps`` physics steps from global step
    ``step0``; the command (cvx, cvy, cwz) holds for the first ``n_cmd`` of them (then the
    command has timed out: target zero). Odometry and IMU publish into the state when due,
    drawing their noise from the normals buffers at the cursors ``O_CUR`` / ``I_CUR``. The
    contact vector receives the first and last step with a blocked motion (-1: none), the pose
    and speed of the first. Unless ``out`` is empty, the laser (LS_* constants) then scans from
    the final pose into it with noise stream ``seed`` (``scan_ranges``): a chunk that ends where
    a scan falls due is one call."""
    st = kv[KV_ST:KV_LIM]
    lim = kv[KV_LIM:KV_F]
    laser = kv[KV_LS:KV_SIZE]
    ox = lim[L_OX]
    oy = lim[L_OY]
    res = lim[L_RES]
    _move(st, cvx, cvy, cwz, n_cmd, n_steps, lim[L_DT], lim, kv[KV_F:KV_C], check_idle, fp,
          blocked, clear, ox, oy, res, circles, segments, kv[KV_C:KV_LS], step0, odom_normals,
          imu_normals)
    if out.shape[0] > 0:
        lx, ly, lth = laser_xyt(st, laser)
        scan_ranges(clear, ox, oy, res, lx, ly, lth + laser[LS_A0], laser[LS_INC],
                    laser[LS_RMAX], circles, segments, laser[LS_SIGMA], seed, laser[LS_NONE],
                    out)


@njit(cache=True)
def laser_xyt(st: np.ndarray, laser: np.ndarray) -> tuple[float, float, float]:
    """The laser's true pose in ``map``: base_link's (``st``) composed with the mount."""
    th = st[TH]
    c = math.cos(th)
    s = math.sin(th)
    mx = laser[LS_MX]
    my = laser[LS_MY]
    return (st[X] + c * mx - s * my, st[Y] + s * mx + c * my, wrap_angle(th + laser[LS_MTH]))


@njit(cache=True, inline="always")
def _move(st: np.ndarray, cvx: float, cvy: float, cwz: float, n_cmd: int, n_steps: int,
          dt: float, lim: np.ndarray, faults: np.ndarray, check_idle: bool, fp: np.ndarray,
          blocked: np.ndarray, clear: np.ndarray, ox: float, oy: float, res: float,
          circles: np.ndarray, segments: np.ndarray, contact: np.ndarray, step0: int,
          odom_normals: np.ndarray, imu_normals: np.ndarray) -> None:
    """The motion part of ``physics_steps``."""
    contact[C_FIRST] = -1.0
    contact[C_LAST] = -1.0
    omni = lim[L_OMNI] > 0.5
    half = 0.5 * lim[L_SEP]
    keep = 1.0 - faults[F_SLIP]
    stuck = int(faults[F_STUCK])
    rmax = lim[L_RMAX]
    for k in range(n_steps):
        if k < n_cmd:
            tvx = min(max(cvx, -lim[L_MAX_X]), lim[L_MAX_X])
            tvy = min(max(cvy, -lim[L_MAX_Y]), lim[L_MAX_Y]) if omni else 0.0
            twz = min(max(cwz, -lim[L_MAX_TH]), lim[L_MAX_TH])
        else:
            tvx = 0.0
            tvy = 0.0
            twz = 0.0
        st[VX] = _approach(st[VX], tvx, lim[L_ACC_X] * dt)
        st[VY] = _approach(st[VY], tvy, lim[L_ACC_Y] * dt)
        st[WZ] = _approach(st[WZ], twz, lim[L_ACC_TH] * dt)
        wvx = st[VX]
        wvy = st[VY]
        wwz = st[WZ]
        if stuck != 0:
            vl = wvx - wwz * half
            vr = wvx + wwz * half
            if stuck == 1:
                vl = 0.0
            else:
                vr = 0.0
            wvx = 0.5 * (vl + vr)
            wwz = (vr - vl) / lim[L_SEP]
        avx = wvx * keep
        avy = wvy * keep
        awz = 0.0 if faults[F_NOROT] > 0.5 else wwz * keep
        x = st[X]
        y = st[Y]
        th = st[TH]
        frac = 1.0
        hit = False
        moving = avx != 0.0 or avy != 0.0 or awz != 0.0
        if moving or check_idle:
            disp = (math.hypot(avx, avy) + abs(awz) * lim[L_RMAX]) * dt
            nsub = max(1, int(math.ceil(disp / lim[L_STEP])))
            h = dt / nsub
            for j in range(nsub):
                nx, ny, nth = arc(x, y, th, avx, avy, awz, h)
                if footprint_hits(fp, rmax, nx, ny, nth, blocked, clear, ox, oy, res, circles,
                                  segments):
                    hit = True
                    # bisect the blocked sub-step so that the body stops touching, not short
                    # (to 1/64 of a sub-step: under half a millimetre)
                    lo = 0.0
                    hi = h
                    for _ in range(6):
                        mid = 0.5 * (lo + hi)
                        mx, my, mth = arc(x, y, th, avx, avy, awz, mid)
                        if footprint_hits(fp, rmax, mx, my, mth, blocked, clear, ox, oy, res,
                                          circles, segments):
                            hi = mid
                        else:
                            lo = mid
                    if lo > 0.0:
                        x, y, th = arc(x, y, th, avx, avy, awz, lo)
                    frac = (j * h + lo) / dt
                    break
                x = nx
                y = ny
                th = nth
        st[X] = x
        st[Y] = y
        st[TH] = wrap_angle(th)
        # the wheels turned (and the encoders counted) until the body was stopped
        wx, wy, wth = arc(st[OX], st[OY], st[OTH], wvx, wvy, wwz, dt * frac)
        st[OX] = wx
        st[OY] = wy
        st[OTH] = wrap_angle(wth)
        st[DIST] += math.hypot(wvx, wvy) * dt * frac
        st[ROT] += abs(wwz) * dt * frac
        if hit:
            if contact[C_FIRST] < 0.0:
                contact[C_FIRST] = k
                contact[C_X] = x
                contact[C_Y] = y
                contact[C_TH] = st[TH]
                contact[C_SPEED] = math.hypot(avx, avy)
            contact[C_LAST] = k
            st[VX] = 0.0
            st[VY] = 0.0
            st[WZ] = 0.0
            st[AVX] = 0.0
            st[AVY] = 0.0
            st[AWZ] = 0.0
        else:
            st[AVX] = avx
            st[AVY] = avy
            st[AWZ] = awz
        g = step0 + k + 1
        if g >= st[O_NEXT]:
            publish_odometry(st, lim, g, dt, odom_normals)
        if st[I_NEXT] >= 0.0 and g >= st[I_NEXT]:
            publish_imu(st, lim, g, dt, imu_normals)


@njit(cache=True)
def publish_odometry(st: np.ndarray, lim: np.ndarray, g: int, dt: float,
                     normals: np.ndarray) -> None:
    """Odometry of global step g: the wheel motion since the last one, with amcl's noise."""
    if st[O_K] > 0.0:
        c = int(st[O_CUR])
        ox, oy, oth = st[NOX], st[NOY], st[NOTH]
        nx, ny, nth = odometry_noise_step(ox, oy, oth, st[PWX], st[PWY], st[PWTH], st[OX],
                                          st[OY], st[OTH], lim[L_A1], lim[L_A2], lim[L_A3],
                                          lim[L_A4], lim[L_A5], lim[L_OMNI] > 0.5,
                                          normals[c], normals[c + 1], normals[c + 2])
        st[O_CUR] = c + 3
        period = (g - st[O_STAMP]) * dt
        # the constant body twist that moves the old odometry pose to the new one in a period:
        # an arc of angle a has its chord turned by a/2 and shortened by sinc(a/2)
        a = wrap_angle(nth - oth)
        h = 0.5 * a
        k = 1.0 if abs(h) < 1e-9 else math.sin(h) / h
        cs = math.cos(oth + h)
        sn = math.sin(oth + h)
        st[OTX] = (cs * (nx - ox) + sn * (ny - oy)) / (k * period)
        st[OTY] = (-sn * (nx - ox) + cs * (ny - oy)) / (k * period)
        st[OTW] = a / period
        st[NOX] = nx
        st[NOY] = ny
        st[NOTH] = nth
    # the twist covariance of amcl's model over one nominal period (diff drive: no strafe)
    period = lim[L_ODOM_P] * dt
    scale = 1.0 / (period * period)
    vx, vy, wz = st[OTX], st[OTY], st[OTW]
    t2 = (vx * vx + vy * vy) * period * period
    r2 = (wz * period) ** 2
    st[OVX] = (lim[L_A3] * t2 + lim[L_A4] * r2) * scale + 1e-9
    st[OVY] = ((lim[L_A4] * r2 + lim[L_A5] * t2) * scale if lim[L_OMNI] > 0.5 else 0.0) + 1e-9
    st[OVW] = (lim[L_A1] * r2 + lim[L_A2] * t2) * scale + 1e-9
    st[PWX] = st[OX]
    st[PWY] = st[OY]
    st[PWTH] = st[OTH]
    st[O_STAMP] = g
    st[O_K] += 1.0
    st[O_NEXT] = math.ceil(st[O_K] * lim[L_ODOM_P] - 1e-9)


@njit(cache=True)
def publish_imu(st: np.ndarray, lim: np.ndarray, g: int, dt: float,
                normals: np.ndarray) -> None:
    """IMU sample of global step g: yaw rate with bias and noise, its integral as yaw, and the
    body acceleration (finite difference plus the centripetal term) with noise."""
    c = int(st[I_CUR])
    n0, n1, n2 = normals[c], normals[c + 1], normals[c + 2]
    st[I_CUR] = c + 3
    err = lim[L_GBIAS] + lim[L_GSIG] * n0
    st[I_RATE] = st[AWZ] + err
    ax = 0.0
    ay = 0.0
    if st[I_K] > 0.0:
        period = (g - st[I_STAMP]) * dt
        # the gyro's yaw is the integral of what it measured: the true turn plus its error
        st[I_YAW] = wrap_angle(st[I_YAW] + wrap_angle(st[TH] - st[I_PTH]) + err * period)
        ax = (st[AVX] - st[I_PVX]) / period - st[AVY] * st[AWZ]
        ay = (st[AVY] - st[I_PVY]) / period + st[AVX] * st[AWZ]
    st[I_AX] = ax + lim[L_ASIG] * n1
    st[I_AY] = ay + lim[L_ASIG] * n2
    st[I_PTH] = st[TH]
    st[I_PVX] = st[AVX]
    st[I_PVY] = st[AVY]
    st[I_STAMP] = g
    st[I_K] += 1.0
    st[I_NEXT] = math.ceil(st[I_K] * lim[L_IMU_P] - 1e-9)
