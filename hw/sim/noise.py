"""Seeded Gaussian noise for njit kernels, without numba's global state.

``standard_normals(seed, n)`` returns n standard normal draws from an MT19937 generator seeded by
its reference integer initialisation, turned into normals by the ziggurat method (Marsaglia &
Tsang 2000, "The Ziggurat Method for Generating Random Variables", 256 layers): a draw picks a
layer with 8 bits and a signed position in it with 32 more; 99% of draws end there with one
multiply and one compare, the rest take the exact wedge or tail test. Numba's own ``np.random``
reaches a thread-local state through a helper call on every draw (~130 ns); the polar method
this replaced needed a log, a square root and a division per pair (~22 ns a draw); this costs a
few ns. The layer index and the position come from different words, so they are independent.
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


def _ziggurat_tables(layers: int = 256, r: float = 3.6541528853610088,
                     v: float = 0.00492867323399) -> tuple[np.ndarray, np.ndarray]:
    """Layer edges x[0..layers] (x[0] the base strip's equal-area width v / f(r), x[1] = r,
    x[layers] = 0) and f(x) = exp(-x^2 / 2) at them, for ``layers`` strips of area ``v`` each
    (r and v of the paper's 256-layer table)."""
    x = np.empty(layers + 1)
    x[0] = v / math.exp(-0.5 * r * r)
    x[1] = r
    for i in range(1, layers - 1):
        x[i + 1] = math.sqrt(-2.0 * math.log(v / x[i] + math.exp(-0.5 * x[i] * x[i])))
    x[layers] = 0.0
    return x, np.exp(-0.5 * x * x)


_ZX, _ZF = _ziggurat_tables()
_ZR = float(_ZX[1])


@njit(cache=True)
def _uniform(words: np.ndarray, mt: np.ndarray, idx: int) -> tuple[float, int]:
    """A double in (0, 1] from the next word (and the new word index)."""
    if idx >= _N:
        _mt_twist(mt)
        _temper_all(mt, words)
        idx = 0
    return (words[idx] + 1.0) / 4294967296.0, idx + 1


@njit(cache=True)
def standard_normals(seed: int, n: int) -> np.ndarray:
    """n standard normal draws (float64) of the MT19937 stream seeded with ``seed``."""
    out = np.empty(n, np.float64)
    mt = _mt_init(seed)
    words = np.empty(_N, np.uint32)  # tempered output of the current state
    idx = _N  # twist before the first word, as the reference does
    zx = _ZX
    zf = _ZF
    i = 0
    while i < n:
        if idx + 2 > _N:
            _mt_twist(mt)
            _temper_all(mt, words)
            idx = 0
        layer = words[idx] & 0xFF
        u = np.int32(words[idx + 1]) * 4.656612873077393e-10  # [-1, 1): signed word / 2^31
        idx += 2
        x = u * zx[layer]
        if abs(x) < zx[layer + 1]:
            out[i] = x  # inside the layer's rectangle below the curve: the common case
            i += 1
            continue
        if layer == 0:
            # the tail beyond r (Marsaglia 1964): r + a with a ~ Exp(r) thinned by exp(-a^2/2)
            while True:
                u1, idx = _uniform(words, mt, idx)
                u2, idx = _uniform(words, mt, idx)
                a = -math.log(u1) / _ZR
                if -2.0 * math.log(u2) > a * a:
                    break
            out[i] = _ZR + a if u >= 0.0 else -(_ZR + a)
            i += 1
            continue
        # the wedge between the rectangle and the curve: accept under f, else draw again
        u1, idx = _uniform(words, mt, idx)
        if zf[layer] + u1 * (zf[layer + 1] - zf[layer]) < math.exp(-0.5 * x * x):
            out[i] = x
            i += 1
    return out
