"""Seeded Gaussian noise for njit kernels: the legacy numpy stream, without numba's global state.

``standard_normals(seed, n)`` returns what ``numpy.random.RandomState(seed).standard_normal(n)``
returns (and what numba's ``np.random.seed(seed)`` followed by n ``np.random.standard_normal()``
calls gives): MT19937 seeded by its reference integer initialisation, doubles of 53 bits from two
words, normals by the polar method, each pair handed out second value first. Numba's own
``np.random`` reaches a thread-local state through a helper call on every draw, which made the
laser noise cost ~130 ns a beam, as much as casting the beam; this keeps the state in a local
array and is ten times cheaper, bit for bit the same.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

_N = 624
_M = 397


@njit(cache=True)
def _mt_init(seed: int) -> np.ndarray:
    """MT19937 state words after the reference ``init_genrand(seed)`` (seed taken mod 2**32)."""
    mt = np.empty(_N, np.uint32)
    s = seed & 0xFFFFFFFF
    for i in range(_N):
        mt[i] = s
        s = (1812433253 * (s ^ (s >> 30)) + i + 1) & 0xFFFFFFFF
    return mt


@njit(cache=True)
def _mt_twist(mt: np.ndarray) -> None:
    """Regenerate all 624 state words (the reference ``next_state``; split loops, no modulo)."""
    for i in range(_N - _M):
        y = (mt[i] & 0x80000000) | (mt[i + 1] & 0x7FFFFFFF)
        mt[i] = mt[i + _M] ^ (y >> 1) ^ ((y & 1) * 0x9908B0DF)
    for i in range(_N - _M, _N - 1):
        y = (mt[i] & 0x80000000) | (mt[i + 1] & 0x7FFFFFFF)
        mt[i] = mt[i + _M - _N] ^ (y >> 1) ^ ((y & 1) * 0x9908B0DF)
    y = (mt[_N - 1] & 0x80000000) | (mt[0] & 0x7FFFFFFF)
    mt[_N - 1] = mt[_M - 1] ^ (y >> 1) ^ ((y & 1) * 0x9908B0DF)


@njit(cache=True)
def _temper_all(mt: np.ndarray, out: np.ndarray) -> None:
    """The reference output tempering of every state word (one pass the compiler vectorises)."""
    for i in range(_N):
        y = mt[i]
        y ^= y >> 11
        y ^= (y << 7) & 0x9D2C5680
        y ^= (y << 15) & 0xEFC60000
        y ^= y >> 18
        out[i] = y


@njit(cache=True)
def standard_normals(seed: int, n: int) -> np.ndarray:
    """n standard normal draws (float64) of the legacy numpy stream seeded with ``seed``."""
    out = np.empty(n, np.float64)
    mt = _mt_init(seed)
    words = np.empty(_N, np.uint32)  # tempered output of the current state
    idx = _N  # twist before the first word, as the reference does
    i = 0
    while i < n:
        while True:
            # four words make the two 53-bit doubles x1, x2 of one polar-method attempt
            if idx + 4 <= _N:
                a, b, c, d = words[idx], words[idx + 1], words[idx + 2], words[idx + 3]
                idx += 4
            else:
                q = np.empty(4, np.uint32)
                for k in range(4):
                    if idx >= _N:
                        _mt_twist(mt)
                        _temper_all(mt, words)
                        idx = 0
                    q[k] = words[idx]
                    idx += 1
                a, b, c, d = q[0], q[1], q[2], q[3]
            u1 = ((a >> 5) * 67108864.0 + (b >> 6)) / 9007199254740992.0
            u2 = ((c >> 5) * 67108864.0 + (d >> 6)) / 9007199254740992.0
            x1 = 2.0 * u1 - 1.0
            x2 = 2.0 * u2 - 1.0
            r2 = x1 * x1 + x2 * x2
            if r2 < 1.0 and r2 != 0.0:
                break
        f = math.sqrt(-2.0 * math.log(r2) / r2)
        out[i] = f * x2
        if i + 1 < n:
            out[i + 1] = f * x1
        i += 2
    return out
