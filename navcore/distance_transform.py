"""Exact Euclidean distance transform (Felzenszwalb & Huttenlocher), one implementation for all.

Two separable passes, O(cells): the vertical distance by two sweeps, then the lower envelope of
parabolas along each row. Used by the likelihood field (AMCL), the ray caster's clearance field
and tests of the inflation layer. The inflation layer keeps its own capped, windowed variant
inside its kernel because it works on uint8 distances.
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
    # Pass 1, down the columns: of a 0/inf column, the 1-D squared transform is the squared
    # distance to the nearest site in the column, so two sweeps (down, then up) of the plain
    # distance give it. Row after row they read memory in order and vectorise; ``none`` (h, more
    # than any distance in a column) marks columns without a site.
    none = float(h)
    for x in range(w):
        out[0, x] = 0.0 if mask[0, x] else none
    for y in range(1, h):
        for x in range(w):
            out[y, x] = 0.0 if mask[y, x] else min(out[y - 1, x] + 1.0, none)
    for y in range(h - 2, -1, -1):
        for x in range(w):
            out[y, x] = min(out[y, x], out[y + 1, x] + 1.0)
    # Pass 2, along the rows: the lower envelope of parabolas over pass 1's squares
    f = np.empty(w, dtype=np.float64)
    d = np.empty(w, dtype=np.float64)
    v = np.empty(w, dtype=np.int64)
    z = np.empty(w + 1, dtype=np.float64)
    for y in range(h):
        for x in range(w):
            g = out[y, x]
            f[x] = inf if g >= none else g * g
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
