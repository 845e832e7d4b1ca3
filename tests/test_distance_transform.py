"""The exact EDT shared by AMCL's likelihood field, the ray caster and the inflation tests."""

from __future__ import annotations

import numpy as np

from navcore.distance_transform import squared_distance_transform


def _brute(mask):
    ys, xs = np.nonzero(mask)
    h, w = mask.shape
    yy, xx = np.mgrid[0:h, 0:w]
    return ((yy[..., None] - ys) ** 2 + (xx[..., None] - xs) ** 2).min(-1).astype(np.float64)


def test_random_masks_of_every_shape_and_density_match_brute_force():
    rng = np.random.default_rng(17)
    for trial in range(200):
        h, w = (int(v) for v in rng.integers(1, 40, 2))
        mask = rng.random((h, w)) < rng.choice([0.002, 0.02, 0.2, 0.7, 1.0])
        if not mask.any():
            mask[int(rng.integers(h)), int(rng.integers(w))] = True
        got = squared_distance_transform(mask)
        assert got.dtype == np.float64
        assert np.array_equal(got, _brute(mask)), (trial, h, w)


def test_columns_and_rows_without_sites():
    mask = np.zeros((30, 7), bool)
    mask[29, 6] = True                 # one site in a corner: most columns and rows have none
    d2 = squared_distance_transform(mask)
    assert d2[0, 0] == 29 ** 2 + 6 ** 2 and d2[29, 6] == 0 and d2[0, 6] == 29 ** 2
    assert np.array_equal(d2, _brute(mask))


def test_a_grid_without_sites_is_beyond_every_real_distance():
    d2 = squared_distance_transform(np.zeros((5, 9), bool))
    assert (d2 == 5 * 5 + 9 * 9 + 1).all()
