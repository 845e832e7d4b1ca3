"""Pose hypotheses as amcl computes them (``pf_cluster_stats``): particles are binned, adjacent
occupied bins (26-neighbourhood, heading wrapping around) form clusters, and each cluster gets a
weight and a weighted mean. The overall mean and covariance come from the whole set.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from navcore.localization.bins import N_TH, bin_key, bin_of, find, insert, new_table


@njit(cache=True)
def _root(parent: np.ndarray, i: int) -> int:
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


@njit(cache=True)
def cluster_stats(particles: np.ndarray, weights: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(cluster weights (K,), cluster means (K, 3), set mean (3,), set covariance (3, 3)).

    Covariance: weighted x/y covariance and, for heading, -2 ln |mean resultant|, like amcl.
    """
    n = particles.shape[0]
    table = new_table(n)
    slot = np.empty(n, np.int64)
    bins = np.empty((n, 3), np.int64)
    nb = 0
    slot_bin = np.full(table.shape[0], -1, np.int64)
    for i in range(n):
        ix, iy, it = bin_of(particles[i, 0], particles[i, 1], particles[i, 2])
        s, new = insert(table, bin_key(ix, iy, it))
        if new:
            slot_bin[s] = nb
            bins[nb, 0] = ix
            bins[nb, 1] = iy
            bins[nb, 2] = it
            nb += 1
        slot[i] = slot_bin[s]
    parent = np.arange(nb)
    for b in range(nb):
        # adjacency is symmetric: visiting the 13 "forward" neighbours of every bin is enough
        for dx in range(0, 2):
            for dy in range(-1, 2):
                for dt in range(-1, 2):
                    if dx == 0 and (dy < 0 or (dy == 0 and dt <= 0)):
                        continue
                    t = (bins[b, 2] + dt) % N_TH
                    s = find(table, bin_key(bins[b, 0] + dx, bins[b, 1] + dy, t))
                    if s >= 0:
                        o = slot_bin[s]
                        ra = _root(parent, b)
                        rb = _root(parent, o)
                        if ra != rb:
                            parent[rb] = ra
    cid = np.full(nb, -1, np.int64)
    k = 0
    for b in range(nb):
        r = _root(parent, b)
        if cid[r] < 0:
            cid[r] = k
            k += 1
    acc = np.zeros((k, 5), np.float64)  # w, wx, wy, w cos, w sin
    tot = np.zeros(5, np.float64)
    sxx = 0.0
    sxy = 0.0
    syy = 0.0
    for i in range(n):
        c = cid[_root(parent, slot[i])]
        w = weights[i]
        x = particles[i, 0]
        y = particles[i, 1]
        co = math.cos(particles[i, 2])
        si = math.sin(particles[i, 2])
        acc[c, 0] += w
        acc[c, 1] += w * x
        acc[c, 2] += w * y
        acc[c, 3] += w * co
        acc[c, 4] += w * si
        tot[0] += w
        tot[1] += w * x
        tot[2] += w * y
        tot[3] += w * co
        tot[4] += w * si
        sxx += w * x * x
        sxy += w * x * y
        syy += w * y * y
    cw = np.empty(k, np.float64)
    cm = np.empty((k, 3), np.float64)
    for c in range(k):
        w = acc[c, 0]
        cw[c] = w
        if w > 0.0:
            cm[c, 0] = acc[c, 1] / w
            cm[c, 1] = acc[c, 2] / w
        else:
            cm[c, 0] = 0.0
            cm[c, 1] = 0.0
        cm[c, 2] = math.atan2(acc[c, 4], acc[c, 3])
    mean = np.zeros(3, np.float64)
    cov = np.zeros((3, 3), np.float64)
    W = tot[0]
    if W > 0.0:
        mean[0] = tot[1] / W
        mean[1] = tot[2] / W
        mean[2] = math.atan2(tot[4], tot[3])
        cov[0, 0] = sxx / W - mean[0] * mean[0]
        cov[0, 1] = sxy / W - mean[0] * mean[1]
        cov[1, 0] = cov[0, 1]
        cov[1, 1] = syy / W - mean[1] * mean[1]
        r = math.sqrt(tot[3] * tot[3] + tot[4] * tot[4]) / W
        cov[2, 2] = -2.0 * math.log(r) if r > 1e-300 else 1e300
    return cw, cm, mean, cov
