"""Resampling with KLD-adaptive sample size (Fox 2003, as amcl's ``pf_update_resample``).

amcl draws each new sample by a linear scan of the CDF (O(N^2) per resample). We draw the
``max_particles`` candidates at once by systematic (low-variance) resampling in O(N), visit them in
a random order (so that stopping early is still an unbiased draw), and stop like amcl does: as soon
as the sample count exceeds the KLD limit for the number of occupied bins.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from navcore.localization.bins import bin_key, bin_of, insert, new_table


@njit(cache=True)
def kld_limit(k: int, min_n: int, max_n: int, err: float, z: float) -> int:
    """amcl ``pf_resample_limit``: samples needed for ``k`` occupied bins.

    Quirks kept for parity: k <= 1 gives max_n, and ``z`` is used as given (kld_z = 0.99).
    """
    if k <= 1 or k > max_n:
        return max_n
    b = 2.0 / (9.0 * (k - 1))
    c = math.sqrt(2.0 / (9.0 * (k - 1))) * z
    x = 1.0 - b + c
    n = int(math.ceil((k - 1) / (2.0 * err) * x * x * x))
    if n < min_n:
        return min_n
    if n > max_n:
        return max_n
    return n


@njit(cache=True)
def systematic_indices(weights: np.ndarray, m: int, u0: float) -> np.ndarray:
    """Indices of ``m`` systematic draws (positions (u0 + j)/m, u0 in [0, 1)) from ``weights``."""
    n = weights.shape[0]
    total = 0.0
    for i in range(n):
        total += weights[i]
    out = np.empty(m, np.int64)
    i = 0
    c = weights[0] / total
    for j in range(m):
        u = (u0 + j) / m
        while c <= u and i < n - 1:
            i += 1
            c += weights[i] / total
        out[j] = i
    return out


@njit(cache=True)
def kld_resample(particles: np.ndarray, weights: np.ndarray, min_n: int, max_n: int,
                 err: float, z: float, u0: float, order: np.ndarray, is_random: np.ndarray,
                 random_poses: np.ndarray) -> np.ndarray:
    """New particle set (count, 3).

    ``order`` is a permutation of range(max_n); ``is_random[j]`` (empty array: never) makes draw j
    a fresh pose, taken in turn from ``random_poses`` (augmented MCL's random injection).
    """
    idx = systematic_indices(weights, max_n, u0)
    table = new_table(max_n)
    out = np.empty((max_n, 3), np.float64)
    use_random = is_random.shape[0] == max_n
    r = 0
    count = 0
    k = 0
    for j in range(max_n):
        if use_random and is_random[j]:
            x, y, t = random_poses[r, 0], random_poses[r, 1], random_poses[r, 2]
            r += 1
        else:
            s = idx[order[j]]
            x, y, t = particles[s, 0], particles[s, 1], particles[s, 2]
        out[count, 0] = x
        out[count, 1] = y
        out[count, 2] = t
        count += 1
        ix, iy, it = bin_of(x, y, t)
        _, new = insert(table, bin_key(ix, iy, it))
        if new:
            k += 1
        if count > kld_limit(k, min_n, max_n, err, z):
            break
    return out[:count].copy()
