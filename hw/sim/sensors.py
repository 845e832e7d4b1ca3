"""Sensor models of the simulated robot: laser ranges, odometry noise, IMU and battery.

The laser casts every beam against the static map (``navcore.raycast``, exact to the cell faces)
and against the objects the map does not know, then adds Gaussian range noise to the beams that
hit something. Odometry noise follows amcl's motion models (``odom_alpha1..5``; the *corrected*
diff and omni forms, standard deviation = sqrt of the variance expression), applied to the wheel
motion of each odometry period.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from navcore.raycast import cast_ray_clear, ray_circle, ray_segment
from navcore.types import Pose2D, angle_diff, normalize_angle


@njit(cache=True)
def scan_ranges(clear: np.ndarray, ox: float, oy: float, res: float, x: float, y: float,
                th: float, angles: np.ndarray, range_max: float, circles: np.ndarray,
                segments: np.ndarray, noise: np.ndarray, no_return: float,
                out: np.ndarray) -> None:
    """Ranges (float32 ``out``) of beams at ``angles`` (laser frame) from the laser at (x, y, th):
    nearest of map and objects, plus ``noise`` on hits, ``no_return`` where nothing is hit."""
    for i in range(angles.shape[0]):
        a = th + angles[i]
        r = cast_ray_clear(clear, ox, oy, res, x, y, a, range_max)
        if circles.shape[0] > 0 or segments.shape[0] > 0:
            dx = math.cos(a)
            dy = math.sin(a)
            for k in range(circles.shape[0]):
                d = ray_circle(x, y, dx, dy, circles[k, 0], circles[k, 1], circles[k, 2])
                if d < r:
                    r = d
            for k in range(segments.shape[0]):
                d = ray_segment(x, y, dx, dy, segments[k, 0], segments[k, 1], segments[k, 2],
                                segments[k, 3])
                if d < r:
                    r = d
        if r >= range_max:
            out[i] = no_return
        else:
            out[i] = min(max(r + noise[i], 0.0), range_max)


def noisy_odometry_step(odom: Pose2D, prev_wheel: tuple[float, float, float],
                        wheel: tuple[float, float, float], alphas: tuple[float, ...],
                        omni: bool, normals: np.ndarray) -> Pose2D:
    """The odometry pose after one period: the wheel motion from ``prev_wheel`` to ``wheel``
    (both in the noise-free wheel-odometry frame) perturbed by amcl's motion model and composed
    onto ``odom``. ``normals`` are three standard normal draws."""
    a1, a2, a3, a4, a5 = alphas
    n0, n1, n2 = float(normals[0]), float(normals[1]), float(normals[2])
    px, py, pth = prev_wheel
    dxw, dyw = wheel[0] - px, wheel[1] - py
    c, s = math.cos(pth), math.sin(pth)
    lx, ly = c * dxw + s * dyw, -s * dxw + c * dyw  # motion in the old body frame
    dth = angle_diff(wheel[2], pth)
    trans = math.hypot(lx, ly)
    if not omni:
        rot1 = math.atan2(ly, lx) if trans > 1e-12 else 0.0
        rot2 = angle_diff(dth, rot1)
        # driving backwards is not a half turn: noise grows with the smaller of the two readings
        r1n = min(abs(rot1), abs(angle_diff(rot1, math.pi)))
        r2n = min(abs(rot2), abs(angle_diff(rot2, math.pi)))
        rot1h = rot1 - math.sqrt(a1 * r1n * r1n + a2 * trans * trans) * n0
        transh = trans - math.sqrt(a3 * trans * trans + a4 * (r1n * r1n + r2n * r2n)) * n1
        rot2h = rot2 - math.sqrt(a1 * r2n * r2n + a2 * trans * trans) * n2
        return Pose2D(odom.x + transh * math.cos(odom.theta + rot1h),
                      odom.y + transh * math.sin(odom.theta + rot1h),
                      normalize_angle(odom.theta + rot1h + rot2h))
    bearing = (math.atan2(ly, lx) if trans > 1e-12 else 0.0) + odom.theta
    st = math.sqrt(a3 * trans * trans + a4 * dth * dth)
    sr = math.sqrt(a1 * dth * dth + a2 * trans * trans)
    ss = math.sqrt(a4 * dth * dth + a5 * trans * trans)
    transh = trans + st * n0
    roth = dth + sr * n1
    strafe = ss * n2
    return Pose2D(odom.x + transh * math.cos(bearing) + strafe * math.sin(bearing),
                  odom.y + transh * math.sin(bearing) - strafe * math.cos(bearing),
                  normalize_angle(odom.theta + roth))
