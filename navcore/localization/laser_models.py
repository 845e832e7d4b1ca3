"""amcl's likelihood-field laser models as numba kernels over all particles at once.

Each kernel multiplies ``weights`` in place by the scan's likelihood at every particle and returns
the new total weight, like ``pf_update_sensor``'s model callback. Beams arrive already subsampled
and in the *laser* frame (range, bearing); the laser mount (x, y, theta in base_link) is composed
into each particle pose. ``grid`` holds the map geometry: origin x, y, cos and sin of the origin
yaw, and resolution.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, inline="always")
def _cell(wx: float, wy: float, grid: np.ndarray, h: int, w: int) -> tuple[int, int]:
    """Cell (mx, my) of a world point, or (-1, -1) when it is off the map."""
    dx = wx - grid[0]
    dy = wy - grid[1]
    lx = grid[2] * dx + grid[3] * dy
    ly = -grid[3] * dx + grid[2] * dy
    if lx < 0.0 or ly < 0.0:
        return -1, -1
    mx = int(lx / grid[4])
    my = int(ly / grid[4])
    if mx >= w or my >= h:
        return -1, -1
    return mx, my


@njit(cache=True)
def hit_table(dist: np.ndarray, z_hit: float, z_rand: float, sigma_hit: float,
              range_max: float) -> np.ndarray:
    """Per-cell pz = z_hit exp(-d^2 / 2 sigma^2) + z_rand / range_max (float32), so that the
    per-beam work is one lookup instead of an exp."""
    h, w = dist.shape
    out = np.empty((h, w), np.float32)
    denom = 2.0 * sigma_hit * sigma_hit
    rnd = z_rand / range_max
    for y in range(h):
        for x in range(w):
            d = dist[y, x]
            out[y, x] = z_hit * math.exp(-(d * d) / denom) + rnd
    return out


@njit(cache=True)
def cube_table(pz: np.ndarray) -> tuple[np.ndarray, float]:
    """pz^3 per cell as uint16 and the scale back to a probability: half the bytes of float32
    keep more of the table in cache (the per-beam lookups are random accesses), at a
    quantisation of 1/65535 of the largest value."""
    h, w = pz.shape
    top = 0.0
    for y in range(h):
        for x in range(w):
            c = float(pz[y, x]) ** 3
            if c > top:
                top = c
    scale = top / 65535.0 if top > 0.0 else 1.0
    out = np.empty((h, w), np.uint16)
    for y in range(h):
        for x in range(w):
            out[y, x] = np.uint16(round(float(pz[y, x]) ** 3 / scale))
    return out, scale


@njit(cache=True, inline="always")
def _beam_ends(ranges: np.ndarray, bearings: np.ndarray, mount: np.ndarray,
               range_max: float) -> tuple[np.ndarray, np.ndarray]:
    """End points (x, y) in the laser frame of the informative beams only: those shorter than
    ``range_max`` (a max-range or NaN reading carries no information)."""
    nb = 0
    for j in range(ranges.shape[0]):
        if ranges[j] < range_max:
            nb += 1
    rx = np.empty(nb)
    ry = np.empty(nb)
    k = 0
    for j in range(ranges.shape[0]):
        r = ranges[j]
        if r < range_max:
            a = mount[2] + bearings[j]
            rx[k] = r * math.cos(a)
            ry[k] = r * math.sin(a)
            k += 1
    return rx, ry


@njit(cache=True, inline="always")
def _laser_in_grid(px: float, py: float, pt: float, mount: np.ndarray,
                   grid: np.ndarray) -> tuple[float, float, float, float]:
    """The laser of a particle at (px, py, pt), in grid cells: a laser-frame point (x, y) lands
    at (lx0 + cc x - ss y, ly0 + ss x + cc y). The rotation into the map's grid frame and the
    division by the resolution are folded into one 2x2: cc, ss = cos, sin(pt - origin yaw) / res."""
    gc, gs = grid[2], grid[3]
    inv_res = 1.0 / grid[4]
    c = math.cos(pt)
    s = math.sin(pt)
    dx = px + c * mount[0] - s * mount[1] - grid[0]
    dy = py + s * mount[0] + c * mount[1] - grid[1]
    lx0 = (gc * dx + gs * dy) * inv_res
    ly0 = (-gs * dx + gc * dy) * inv_res
    cc = (gc * c + gs * s) * inv_res
    ss = (gc * s - gs * c) * inv_res
    return lx0, ly0, cc, ss


@njit(cache=True)
def likelihood_field(particles: np.ndarray, weights: np.ndarray, ranges: np.ndarray,
                     bearings: np.ndarray, mount: np.ndarray, cubes: np.ndarray, scale: float,
                     grid: np.ndarray, off_map_pz: float, range_max: float) -> float:
    """amcl ``LikelihoodFieldModel``: p = 1 + sum(pz^3) per particle, weights *= p.

    ``cubes, scale`` come from ``cube_table(hit_table(dist, ...))``; an end point off the map
    scores ``off_map_pz`` (pz at max_occ_dist). Beams at or beyond range_max (and NaN) carry no
    information and are skipped.
    """
    h, w = cubes.shape
    n = particles.shape[0]
    off_cube = off_map_pz * off_map_pz * off_map_pz
    rx, ry = _beam_ends(ranges, bearings, mount, range_max)
    nb = rx.shape[0]
    total = 0.0
    for i in range(n):
        lx0, ly0, cc, ss = _laser_in_grid(particles[i, 0], particles[i, 1], particles[i, 2],
                                          mount, grid)
        q = 0
        off = 0
        for j in range(nb):
            gx = lx0 + cc * rx[j] - ss * ry[j]
            gy = ly0 + ss * rx[j] + cc * ry[j]
            if gx >= 0.0 and gy >= 0.0 and gx < w and gy < h:
                q += int(cubes[int(gy), int(gx)])  # int(): plain Python would sum in uint16
            else:
                off += 1
        weights[i] *= 1.0 + q * scale + off * off_cube
        total += weights[i]
    return total


@njit(cache=True)
def likelihood_field_prob(particles: np.ndarray, weights: np.ndarray, ranges: np.ndarray,
                          bearings: np.ndarray, mount: np.ndarray, table: np.ndarray,
                          dist: np.ndarray, grid: np.ndarray, off_map_pz: float,
                          range_max: float, do_beamskip: bool, beam_skip_distance: float,
                          beam_skip_threshold: float, beam_skip_error_threshold: float) -> float:
    """amcl ``LikelihoodFieldModelProb``: w *= exp(sum log pz), with optional beam skipping.

    ``table`` is ``hit_table`` (pz per cell), ``dist`` the distance field it came from.
    Beam skipping (only when asked, i.e. once the filter has converged): a beam is used only when
    more than ``beam_skip_threshold`` of the particles see its end point within
    ``beam_skip_distance`` of an obstacle; if too many beams would be skipped, all are used.
    """
    h, w = table.shape
    n = particles.shape[0]
    rx, ry = _beam_ends(ranges, bearings, mount, range_max)
    nb = rx.shape[0]
    cells = np.empty((n, nb), np.int64)  # flat cell index per particle and beam, -1 off the map
    for i in range(n):
        lx0, ly0, cc, ss = _laser_in_grid(particles[i, 0], particles[i, 1], particles[i, 2],
                                          mount, grid)
        for j in range(nb):
            gx = lx0 + cc * rx[j] - ss * ry[j]
            gy = ly0 + ss * rx[j] + cc * ry[j]
            if gx >= 0.0 and gy >= 0.0 and gx < w and gy < h:
                cells[i, j] = int(gy) * w + int(gx)
            else:
                cells[i, j] = -1
    use = np.ones(nb, np.bool_)
    if do_beamskip and nb > 0:
        flat_dist = dist.ravel()
        skipped = 0
        for j in range(nb):
            agree = 0
            for i in range(n):
                cell = cells[i, j]
                if cell >= 0 and flat_dist[cell] < beam_skip_distance:
                    agree += 1
            if agree / n <= beam_skip_threshold:
                use[j] = False
                skipped += 1
        if skipped >= nb * beam_skip_error_threshold:
            use[:] = True  # most beams disagree: the filter may be wrong, trust the scan
    flat = table.ravel()
    log_off = math.log(off_map_pz)
    total = 0.0
    for i in range(n):
        log_p = 0.0
        for j in range(nb):
            if not use[j]:
                continue
            cell = cells[i, j]
            log_p += log_off if cell < 0 else math.log(flat[cell])
        weights[i] *= math.exp(log_p)
        total += weights[i]
    return total
