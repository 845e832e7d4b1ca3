"""The KLD histogram bins of amcl's kd-tree (0.5 m x 0.5 m x 10 degrees) as an open-addressing hash
set over packed int64 keys. A flat table is all the kd-tree was used for (counting occupied bins
and finding neighbours), and it is O(1) per particle.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

BIN_XY = 0.5
BIN_TH = 10.0 * math.pi / 180.0
N_TH = 36
_OFF = 1 << 20
_EMPTY = -1


@njit(cache=True, inline="always")
def bin_key(ix: int, iy: int, it: int) -> int:
    """Pack bin indices (it already wrapped to 0..35) into one non-negative int64."""
    return ((ix + _OFF) << 28) | ((iy + _OFF) << 7) | it


@njit(cache=True, inline="always")
def bin_of(x: float, y: float, th: float) -> tuple[int, int, int]:
    ix = int(math.floor(x / BIN_XY))
    iy = int(math.floor(y / BIN_XY))
    it = int(math.floor(th / BIN_TH)) % N_TH  # +pi and -pi share a bin
    if it < 0:
        it += N_TH
    return ix, iy, it


@njit(cache=True)
def new_table(capacity: int) -> np.ndarray:
    """A table for up to ``capacity`` keys, at most half full."""
    size = 16
    while size < 2 * capacity:
        size *= 2
    return np.full(size, _EMPTY, np.int64)


@njit(cache=True, inline="always")
def _slot0(key: int, mask: int) -> int:
    """First probe slot: splitmix64's finaliser, so that every bit of the key moves the slot."""
    h = np.uint64(key)
    h = (h ^ (h >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    h = (h ^ (h >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    h = h ^ (h >> np.uint64(31))
    return np.int64(h & np.uint64(mask))


@njit(cache=True)
def insert(table: np.ndarray, key: int) -> tuple[int, bool]:
    """Slot of ``key``, inserting it when absent; True when it was new."""
    mask = table.shape[0] - 1
    i = _slot0(key, mask)
    while True:
        k = table[i]
        if k == key:
            return i, False
        if k == _EMPTY:
            table[i] = key
            return i, True
        i = (i + 1) & mask


@njit(cache=True)
def find(table: np.ndarray, key: int) -> int:
    """Slot of ``key`` or -1."""
    mask = table.shape[0] - 1
    i = _slot0(key, mask)
    while True:
        k = table[i]
        if k == key:
            return i
        if k == _EMPTY:
            return -1
        i = (i + 1) & mask
