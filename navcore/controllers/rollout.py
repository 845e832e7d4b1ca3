"""Velocity sampling and forward simulation (base_local_planner's SimpleTrajectoryGenerator).

Samples are rows (vx, vy, vth). A trajectory is a run of poses from explicit Euler integration in
the world frame, starting at the robot pose; the final integrated pose is not kept. With
``ramped`` the velocity moves toward the sample under the acceleration limits every step (the
trajectory rollout model); otherwise the sample is held for the whole horizon (DWA).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

EPS = 1e-4  # the generator's tolerance on the min/max translational checks


@njit(cache=True, nogil=True)
def velocity_iterator(vmin: float, vmax: float, n: int) -> np.ndarray:
    """VelocityIterator: one sample when the range is empty, else max(2, n) evenly spaced samples
    with both ends, plus an exact 0 where the range crosses zero between two samples."""
    if vmin == vmax:
        out = np.empty(1)
        out[0] = vmin
        return out
    n = max(2, n)
    step = (vmax - vmin) / max(1, n - 1)
    out = np.empty(n + 1)
    k = 0
    nxt = vmin
    for _ in range(n - 1):
        cur = nxt
        nxt += step
        out[k] = cur
        k += 1
        if cur < 0.0 < nxt:
            out[k] = 0.0
            k += 1
    out[k] = vmax
    return out[:k + 1]


@njit(cache=True, nogil=True)
def sample_grid(lo: np.ndarray, hi: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """The Cartesian product vx x vy x vth of the three iterators, vth varying fastest, (K, 3).

    A window with ``lo > hi`` (a velocity already outside the limits) still yields its iterator's
    samples, as in ROS.
    """
    ax = velocity_iterator(lo[0], hi[0], counts[0])
    ay = velocity_iterator(lo[1], hi[1], counts[1])
    at = velocity_iterator(lo[2], hi[2], counts[2])
    out = np.empty((ax.size * ay.size * at.size, 3))
    k = 0
    for i in range(ax.size):
        for j in range(ay.size):
            for m in range(at.size):
                out[k, 0] = ax[i]
                out[k, 1] = ay[j]
                out[k, 2] = at[m]
                k += 1
    return out


@njit(cache=True, nogil=True)
def filter_and_steps(samples: np.ndarray, sim_time: float, sim_granularity: float,
                     angular_sim_granularity: float, min_vel_trans: float, min_vel_theta: float,
                     max_vel_trans: float) -> tuple[np.ndarray, np.ndarray]:
    """Drop the samples generateTrajectory refuses and give each kept one its step count.

    Refused: too slow both in translation and rotation (each check only when its minimum is >= 0),
    faster than ``max_vel_trans`` (when >= 0), or zero steps (standing still).
    """
    kept = np.empty_like(samples)
    steps = np.empty(samples.shape[0], dtype=np.int64)
    k = 0
    for i in range(samples.shape[0]):
        vmag = math.hypot(samples[i, 0], samples[i, 1])
        w = abs(samples[i, 2])
        if (min_vel_trans >= 0 and vmag + EPS < min_vel_trans
                and min_vel_theta >= 0 and w + EPS < min_vel_theta):
            continue
        if max_vel_trans >= 0 and vmag - EPS > max_vel_trans:
            continue
        n = int(math.ceil(max(vmag * sim_time / sim_granularity,
                              w * sim_time / angular_sim_granularity)))
        if n <= 0:
            continue
        kept[k, 0] = samples[i, 0]
        kept[k, 1] = samples[i, 1]
        kept[k, 2] = samples[i, 2]
        steps[k] = n
        k += 1
    return kept[:k].copy(), steps[:k].copy()


@njit(cache=True, nogil=True)
def _ramp(target: float, v: float, acc: float, dt: float) -> float:
    """computeNewVelocities for one axis: move toward ``target`` by at most acc*dt."""
    if target < v:
        return max(target, v - acc * dt)
    return min(target, v + acc * dt)


CONSTANT, RAMPED, RAMPED_FROM_CURRENT = 0, 1, 2
"""Velocity models of ``simulate``: DWA holds the sample; SimpleTrajectoryGenerator without DWA
ramps toward it and takes the first ramped step as the command; TrajectoryPlanner ramps from the
current velocity and commands the sample itself."""


@njit(cache=True, nogil=True)
def simulate(samples: np.ndarray, steps: np.ndarray, x: float, y: float, theta: float,
             vel: np.ndarray, acc: np.ndarray, sim_time: float, mode: int, nose: float = 0.0
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Roll every sample out; return (points (K, max_steps, 3) NaN-padded, commands (K, 3),
    nose points (K, max_steps, 2)).

    Row k holds ``steps[k]`` poses. ``mode`` is CONSTANT, RAMPED or RAMPED_FROM_CURRENT. The nose
    points lie ``nose`` metres ahead of each pose (DWA scores some critics there); computing them
    here reuses the heading's sine and cosine.
    """
    k_n = samples.shape[0]
    n_max = 1
    for k in range(k_n):
        if steps[k] > n_max:
            n_max = steps[k]
    pts = np.empty((k_n, n_max, 3))
    fwd = np.empty((k_n, n_max, 2))
    cmd = np.empty((k_n, 3))
    for k in range(k_n):
        n = steps[k]
        dt = sim_time / n
        tx, ty, tw = samples[k, 0], samples[k, 1], samples[k, 2]
        if mode == 1:  # the generator ramps once before the loop and again in every step
            vx = _ramp(tx, vel[0], acc[0], dt)
            vy = _ramp(ty, vel[1], acc[1], dt)
            vw = _ramp(tw, vel[2], acc[2], dt)
            cmd[k, 0], cmd[k, 1], cmd[k, 2] = vx, vy, vw
        elif mode == 2:
            vx, vy, vw = vel[0], vel[1], vel[2]
            cmd[k, 0], cmd[k, 1], cmd[k, 2] = tx, ty, tw
        else:
            vx, vy, vw = tx, ty, tw
            cmd[k, 0], cmd[k, 1], cmd[k, 2] = tx, ty, tw
        px, py, pth = x, y, theta
        c = math.cos(pth)
        s = math.sin(pth)
        # constant yaw rate: rotate (c, s) by a fixed step instead of calling cos/sin per point
        cw = math.cos(vw * dt)
        sw = math.sin(vw * dt)
        for i in range(n):
            pts[k, i, 0] = px
            pts[k, i, 1] = py
            pts[k, i, 2] = pth
            if mode != 0:
                vx = _ramp(tx, vx, acc[0], dt)
                vy = _ramp(ty, vy, acc[1], dt)
                vw = _ramp(tw, vw, acc[2], dt)
                if i > 0:
                    c = math.cos(pth)
                    s = math.sin(pth)
            elif i > 0:
                c, s = c * cw - s * sw, s * cw + c * sw
            fwd[k, i, 0] = px + nose * c
            fwd[k, i, 1] = py + nose * s
            px += (vx * c - vy * s) * dt
            py += (vx * s + vy * c) * dt
            pth += vw * dt
        for i in range(n, n_max):  # NaN past the end, so a drawing stops there
            pts[k, i, 0] = np.nan
            pts[k, i, 1] = np.nan
            pts[k, i, 2] = np.nan
            fwd[k, i, 0] = np.nan
            fwd[k, i, 1] = np.nan
    return pts, cmd, fwd
