"""amcl's odometry motion models (``amcl_odom.cpp``) as one numba kernel over all particles.

``noise`` is an (N, 3) array of standard normals drawn by the caller from its seeded Generator, so
the kernel itself is deterministic. The uncorrected ``diff``/``omni`` models keep amcl's historical
bug (a variance passed where a standard deviation belongs; omni's swapped alphas) because tuned
robots depend on it; the ``-corrected`` models take square roots.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

DIFF, OMNI, DIFF_CORRECTED, OMNI_CORRECTED = 0, 1, 2, 3
MODEL_CODES = {"diff": DIFF, "omni": OMNI, "diff-corrected": DIFF_CORRECTED,
               "omni-corrected": OMNI_CORRECTED}


@njit(cache=True, inline="always")
def _wrap(a: float) -> float:
    # result in (-pi, pi]; np.fmod keeps the sign of a like C fmod
    a = np.fmod(a + math.pi, 2.0 * math.pi)
    if a <= 0.0:
        a += 2.0 * math.pi
    return a - math.pi


@njit(cache=True)
def sample_motion(particles: np.ndarray, old_theta: float, dx: float, dy: float, dth: float,
                  alphas: np.ndarray, model: int, noise: np.ndarray) -> None:
    """Move every particle by the odometry delta (dx, dy, dth; odom frame) with sampled noise.

    ``old_theta`` is the odometry heading before the motion; ``alphas`` holds odom_alpha1..5.
    """
    a1, a2, a3, a4, a5 = alphas[0], alphas[1], alphas[2], alphas[3], alphas[4]
    n = particles.shape[0]
    trans = math.sqrt(dx * dx + dy * dy)
    if model == DIFF or model == DIFF_CORRECTED:
        rot1 = 0.0 if trans < 0.01 else _wrap(math.atan2(dy, dx) - old_theta)
        rot2 = _wrap(dth - rot1)
        # rotating forward or backward is the same motion for the noise
        r1n = min(abs(_wrap(rot1)), abs(_wrap(rot1 - math.pi)))
        r2n = min(abs(_wrap(rot2)), abs(_wrap(rot2 - math.pi)))
        s_rot1 = a1 * r1n * r1n + a2 * trans * trans
        s_trans = a3 * trans * trans + a4 * r1n * r1n + a4 * r2n * r2n
        s_rot2 = a1 * r2n * r2n + a2 * trans * trans
        if model == DIFF_CORRECTED:
            s_rot1 = math.sqrt(s_rot1)
            s_trans = math.sqrt(s_trans)
            s_rot2 = math.sqrt(s_rot2)
        for i in range(n):
            h_rot1 = _wrap(rot1 - s_rot1 * noise[i, 0])
            h_trans = trans - s_trans * noise[i, 1]
            h_rot2 = _wrap(rot2 - s_rot2 * noise[i, 2])
            th = particles[i, 2]
            particles[i, 0] += h_trans * math.cos(th + h_rot1)
            particles[i, 1] += h_trans * math.sin(th + h_rot1)
            particles[i, 2] = _wrap(th + h_rot1 + h_rot2)
    else:
        rot = dth
        if model == OMNI:
            s_t = a3 * trans * trans + a1 * rot * rot
            s_r = a4 * rot * rot + a2 * trans * trans
            s_s = a1 * rot * rot + a5 * trans * trans
        else:
            s_t = math.sqrt(a3 * trans * trans + a4 * rot * rot)
            s_r = math.sqrt(a1 * rot * rot + a2 * trans * trans)
            s_s = math.sqrt(a4 * rot * rot + a5 * trans * trans)
        rel = _wrap(math.atan2(dy, dx) - old_theta)
        for i in range(n):
            th = particles[i, 2]
            b = rel + th
            cb = math.cos(b)
            sb = math.sin(b)
            h_t = trans + s_t * noise[i, 0]
            h_r = rot + s_r * noise[i, 1]
            h_s = s_s * noise[i, 2]
            particles[i, 0] += h_t * cb + h_s * sb
            particles[i, 1] += h_t * sb - h_s * cb
            particles[i, 2] = _wrap(th + h_r)
