"""Exact Euclidean distance transform (Felzenszwalb & Huttenlocher), one implementation for all.

Two separable passes of the lower envelope of parabolas, O(cells). Used by the likelihood field
(AMCL), the ray caster's clearance field and tests of the inflation layer. The inflation layer
keeps its own capped, windowed variant inside its kernel because it works on uint8 distances.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def _edt_1d(f: np.ndarray, n: int, d: np.ndarray, v: np.ndarray, z: np.ndarray) -> None:
    """Squared distance transform of the sampled function ``f[:n]`` into ``d[:n]``."""
    k = 0
    v[0] = 0
    z[0] = -1e300
    z[1] = 1e300
    for q in range(1, n):
        while True:
            p = v[k]
            s = ((f[q] + q * q) - (f[p] + p * p)) / (2.0 * (q - p))
            if s <= z[k] and k > 0:
                k -= 1
            else:
                break
        if s <= z[k]:  # k == 0: the new parabola is lowest everywhere seen so far
            v[0] = q
            continue
        k += 1
        v[k] = q
        z[k] = s
        z[k + 1] = 1e300
    k = 0
    for q in range(n):
        while z[k + 1] < q:
            k += 1
        d[q] = (q - v[k]) * (q - v[k]) + f[v[k]]


@njit(cache=True, nogil=True)
def squared_edt(mask: np.ndarray) -> np.ndarray:
    """float64 squared distance, in cells, from each cell centre to the nearest True cell centre.

    ``mask`` is a 2-D boolean (or 0/1) array indexed [row, col]. A grid without any True cell
    gives ``NO_SITE`` (h*h + w*w + 1, larger than any real distance) everywhere.
    """
    h, w = mask.shape
    inf = float(h * h + w * w) + 1.0
    out = np.empty((h, w), dtype=np.float64)
    n = max(h, w)
    f = np.empty(n, dtype=np.float64)
    d = np.empty(n, dtype=np.float64)
    v = np.empty(n, dtype=np.int64)
    z = np.empty(n + 1, dtype=np.float64)
    for x in range(w):
        for y in range(h):
            f[y] = 0.0 if mask[y, x] else inf
        _edt_1d(f, h, d, v, z)
        for y in range(h):
            out[y, x] = d[y]
    for y in range(h):
        for x in range(w):
            f[x] = out[y, x]
        _edt_1d(f, w, d, v, z)
        for x in range(w):
            out[y, x] = d[x]
    return out


def squared_distance_transform(mask: np.ndarray) -> np.ndarray:
    """Checked entry point of ``squared_edt`` for any array-like mask."""
    mask = np.ascontiguousarray(mask, dtype=np.bool_)
    if mask.ndim != 2:
        raise ValueError(f"squared_distance_transform: mask must be 2-D, got shape {mask.shape}")
    return squared_edt(mask)
