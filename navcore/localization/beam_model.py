"""amcl's beam range-finder model (``BeamModel``), with ranges predicted by navcore.raycast.

As in amcl's ``map_calc_range``, a beam stops at the first cell that is occupied *or unknown*
(one difference: a beam leaving the map reads range_max here, where amcl stops at the edge).
Per beam: pz = z_hit N(obs - map_range) + z_short (if short) + z_max (if max reading) +
z_rand/range_max (if not), and the scan weight is amcl's ad-hoc p = 1 + sum(pz^3).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from navcore.raycast import cast_ray_clear


@njit(cache=True)
def beam_model(particles: np.ndarray, weights: np.ndarray, ranges: np.ndarray,
               bearings: np.ndarray, mount: np.ndarray, clear: np.ndarray, grid: np.ndarray,
               z_hit: float, z_short: float, z_max: float, z_rand: float, sigma_hit: float,
               lambda_short: float, range_max: float) -> float:
    """Multiply ``weights`` by the beam-model likelihood; return the new total.

    ``clear`` is ``navcore.raycast.clearance_field`` of the grid whose occupied *and unknown*
    cells block (it lets rays leap through free space); ``grid`` is (origin x, origin y,
    cos yaw, sin yaw, resolution) of the map.
    """
    n = particles.shape[0]
    nb = ranges.shape[0]
    res = grid[4]
    total = 0.0
    for i in range(n):
        pt = particles[i, 2]
        c = math.cos(pt)
        s = math.sin(pt)
        wx = particles[i, 0] + c * mount[0] - s * mount[1] - grid[0]
        wy = particles[i, 1] + s * mount[0] + c * mount[1] - grid[1]
        # into the grid's own frame (map origin yaw)
        lx = grid[2] * wx + grid[3] * wy
        ly = -grid[3] * wx + grid[2] * wy
        lt = pt + mount[2] - math.atan2(grid[3], grid[2])
        p = 1.0
        for j in range(nb):
            obs = ranges[j]
            if obs != obs:
                continue
            if obs > range_max:
                obs = range_max
            mr = cast_ray_clear(clear, 0.0, 0.0, res, lx, ly, lt + bearings[j], range_max)
            z = obs - mr
            pz = z_hit * math.exp(-(z * z) / (2.0 * sigma_hit * sigma_hit))
            if z < 0.0:
                pz += z_short * lambda_short * math.exp(-lambda_short * obs)
            if obs == range_max:
                pz += z_max
            else:
                pz += z_rand / range_max
            p += pz * pz * pz
        weights[i] *= p
        total += weights[i]
    return total
