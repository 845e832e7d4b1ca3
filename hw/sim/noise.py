"""Seeded Gaussian noise for njit kernels, without numba's global state.

``standard_normals(seed, n)`` returns n standard normal draws of the stream ``seed`` names. The
words are splitmix64's (Steele, Lea & Flood 2014, "Fast splittable pseudorandom number
generators"): word k is a fixed 64-bit mix of the (mixed) seed plus k times the golden-ratio
constant, so a stream costs nothing to seed (each laser scan has its own) and a word is a few
multiplies. Words
become normals by the ziggurat method (Marsaglia & Tsang 2000, "The Ziggurat Method for
Generating Random Variables", 256 layers): a draw picks a layer with the low 8 bits of a word
and a signed position in it with the high 32; 99 % of draws end there with one multiply and one
compare, the rest take the exact wedge or tail test. Numba's own ``np.random`` reaches a
thread-local state through a helper call on every draw (~130 ns); MT19937 with the polar method
needed a 624-word seeding and a log, a square root and a division per pair (~28 ns a draw with
the seeding); this costs ~5 ns.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)
_S30, _S27, _S31, _S32, _S11 = (np.uint64(k) for k in (30, 27, 31, 32, 11))


@njit(cache=True, inline="always")
def _mix(z: np.uint64) -> np.uint64:
    """splitmix64's output function (a bijection of 64-bit words that avalanches)."""
    z = (z ^ (z >> _S30)) * _MIX1
    z = (z ^ (z >> _S27)) * _MIX2
    return z ^ (z >> _S31)


@njit(cache=True, inline="always")
def _word(s: np.uint64, k: np.uint64) -> np.uint64:
    """Word k of the stream that starts at state s: splitmix64's output for s + (k + 1) golden."""
    return _mix(s + (k + np.uint64(1)) * _GOLDEN)


@njit(cache=True, inline="always")
def _uniform(w: np.uint64) -> float:
    """A double in (0, 1] from the top 53 bits of a word."""
    return (np.float64(w >> _S11) + 1.0) * 1.1102230246251565e-16


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
def standard_normals(seed: int, n: int) -> np.ndarray:
    """n standard normal draws (float64) of stream ``seed`` (taken mod 2**64); a longer draw of
    the same stream starts with the shorter one."""
    out = np.empty(n, np.float64)
    # the seed is mixed first, so that neighbouring seeds do not start overlapping streams
    s = _mix(np.uint64(seed))
    k = np.uint64(0)
    one = np.uint64(1)
    zx = _ZX
    zf = _ZF
    i = 0
    while i < n:
        w = _word(s, k)
        k += one
        layer = w & np.uint64(0xFF)
        # the high 32 bits as a signed position in [-1, 1)
        u = (np.float64(w >> _S32) - 2147483648.0) * 4.656612873077393e-10
        x = u * zx[layer]
        if abs(x) < zx[layer + one]:
            out[i] = x  # inside the layer's rectangle below the curve: the common case
            i += 1
            continue
        if layer == 0:
            # the tail beyond r (Marsaglia 1964): r + a with a ~ Exp(r) thinned by exp(-a^2/2)
            while True:
                u1 = _uniform(_word(s, k))
                u2 = _uniform(_word(s, k + one))
                k += np.uint64(2)
                a = -math.log(u1) / _ZR
                if -2.0 * math.log(u2) > a * a:
                    break
            out[i] = _ZR + a if u >= 0.0 else -(_ZR + a)
            i += 1
            continue
        # the wedge between the rectangle and the curve: accept under f, else draw again
        u1 = _uniform(_word(s, k))
        k += one
        if zf[layer] + u1 * (zf[layer + one] - zf[layer]) < math.exp(-0.5 * x * x):
            out[i] = x
            i += 1
    return out
