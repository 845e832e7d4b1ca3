"""The likelihood-field set-up: distance (m) from every cell to the nearest occupied cell.

amcl's ``map_update_cspace`` runs a priority-queue brushfire; we compute the same capped field with
an exact Euclidean distance transform (Felzenszwalb & Huttenlocher's lower envelope of parabolas,
two separable 1-D passes, O(cells)), which is both exact and much faster.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def _edt_1d(f: np.ndarray, d: np.ndarray, v: np.ndarray, z: np.ndarray, n: int) -> None:
    """Squared distance transform of the 1-D sampled function f (length n) into d."""
    inf = 1e20
    k = 0
    v[0] = 0
    z[0] = -inf
    z[1] = inf
    for q in range(1, n):
        s = ((f[q] + q * q) - (f[v[k]] + v[k] * v[k])) / (2.0 * q - 2.0 * v[k])
        while s <= z[k]:
            k -= 1
            s = ((f[q] + q * q) - (f[v[k]] + v[k] * v[k])) / (2.0 * q - 2.0 * v[k])
        k += 1
        v[k] = q
        z[k] = s
        z[k + 1] = inf
    k = 0
    for q in range(n):
        while z[k + 1] < q:
            k += 1
        dq = q - v[k]
        d[q] = dq * dq + f[v[k]]


@njit(cache=True)
def squared_edt(occupied: np.ndarray) -> np.ndarray:
    """Exact squared Euclidean distance (in cells) from each cell to the nearest True cell.

    With no True cell at all every value is about 1e20.
    """
    h, w = occupied.shape
    n = max(h, w)
    out = np.empty((h, w), np.float64)
    f = np.empty(n, np.float64)
    d = np.empty(n, np.float64)
    v = np.empty(n, np.int64)
    z = np.empty(n + 1, np.float64)
    inf = 1e20
    for x in range(w):  # columns first
        for y in range(h):
            f[y] = 0.0 if occupied[y, x] else inf
        _edt_1d(f, d, v, z, h)
        for y in range(h):
            out[y, x] = d[y]
    for y in range(h):
        for x in range(w):
            f[x] = out[y, x]
        _edt_1d(f, d, v, z, w)
        for x in range(w):
            out[y, x] = d[x]
    return out


@njit(cache=True)
def _capped_metres(d2: np.ndarray, resolution: float, max_dist: float) -> np.ndarray:
    h, w = d2.shape
    out = np.empty((h, w), np.float32)
    for y in range(h):
        for x in range(w):
            m = np.sqrt(d2[y, x]) * resolution
            out[y, x] = m if m < max_dist else max_dist
    return out


def distance_field(data: np.ndarray, resolution: float, max_dist: float) -> np.ndarray:
    """float32 (height, width) distance in metres to the nearest occupied (== 100) cell, capped at
    ``max_dist`` like amcl's ``max_occ_dist``. ``data`` is OccupancyGrid.data."""
    if data.ndim != 2:
        raise ValueError(f"distance_field: data must be 2-D, got shape {data.shape}")
    occ = np.ascontiguousarray(data == 100)
    return _capped_metres(squared_edt(occ), float(resolution), float(max_dist))
