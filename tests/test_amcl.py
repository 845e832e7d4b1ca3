"""AMCL on synthetic maps: parameters, kernels (distance field, motion, resampling, clusters) and
the filter's behaviour (gating, tracking, global localisation, map -> odom)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from navcore.localization import Amcl
from navcore.localization.clusters import cluster_stats
from navcore.localization.distance_field import distance_field
from navcore.localization.motion_models import MODEL_CODES, sample_motion
from navcore.localization.resampling import kld_limit, kld_resample, systematic_indices
from navcore.maps import OccupancyGrid
from navcore.params import ParameterError
from navcore.raycast import cast_rays
from navcore.synthetic_maps import ascii_map, office_map
from navcore.types import LaserScan, Pose2D

GRID = office_map(240, seed=3)  # 12 m x 12 m, 6 m rooms


def sim_scan(grid: OccupancyGrid, pose: Pose2D, n: int = 181, rmax: float = 12.0) -> LaserScan:
    """A noiseless 360-degree scan at ``pose`` from the shared ray caster."""
    angles = np.linspace(-math.pi, math.pi, n, endpoint=False)
    occ = (grid.data != 0).view(np.uint8) if grid.data.dtype == np.bool_ else \
        np.ascontiguousarray(grid.data == 100).astype(np.uint8)
    r = cast_rays(occ, grid.origin.x, grid.origin.y, grid.resolution, pose.x, pose.y,
                  angles + pose.theta, rmax)
    return LaserScan(0.0, angles[0], angles[-1], angles[1] - angles[0], 0.0, 0.0, 0.05, rmax,
                     r.astype(np.float32))


def test_parameters_carry_the_effective_ros_defaults_and_reject_bad_values() -> None:
    a = Amcl(GRID, None, np.random.default_rng(0))
    p = a.params
    assert (p.min_particles, p.max_particles, p.resample_interval) == (100, 5000, 2)
    assert (p.recovery_alpha_slow, p.recovery_alpha_fast) == (0.001, 0.1)  # node code, not .cfg
    assert p.update_min_a == pytest.approx(math.pi / 6) and p.laser_max_beams == 30
    assert p.laser_model_type == "likelihood_field" and p.odom_model_type == "diff"
    assert len(a.particles) == 5000 and a.weights.sum() == pytest.approx(1.0)
    with pytest.raises(ParameterError, match="laser_z_hitt.*did you mean 'laser_z_hit'"):
        Amcl(GRID, {"laser_z_hitt": 0.5}, np.random.default_rng(0))
    with pytest.raises(ParameterError, match="odom_model_type"):
        Amcl(GRID, {"odom_model_type": "ackermann"}, np.random.default_rng(0))
    with pytest.raises(ValueError, match="min_particles"):
        Amcl(GRID, {"min_particles": 600, "max_particles": 500}, np.random.default_rng(0))
    with pytest.raises(ValueError, match="positive semi-definite"):
        a.set_initial_pose(Pose2D(), -np.eye(3))


def test_distance_field_is_the_exact_capped_euclidean_distance() -> None:
    rng = np.random.default_rng(1)
    data = np.where(rng.random((37, 53)) < 0.03, 100, 0).astype(np.int16)
    d = distance_field(data, 0.1, 1.5)
    oy, ox = np.nonzero(data == 100)
    yy, xx = np.mgrid[0:37, 0:53]
    brute = np.sqrt((yy[..., None] - oy) ** 2 + (xx[..., None] - ox) ** 2).min(-1) * 0.1
    np.testing.assert_allclose(d, np.minimum(brute, 1.5), atol=1e-5)


def test_kld_limit_follows_pf_resample_limit_including_its_quirks() -> None:
    assert kld_limit(1, 100, 5000, 0.01, 0.99) == 5000  # k == 1 gives max (amcl quirk)
    k, err, z = 10, 0.01, 0.99
    b = 2 / (9 * (k - 1))
    expect = math.ceil((k - 1) / (2 * err) * (1 - b + math.sqrt(b) * z) ** 3)
    assert kld_limit(k, 100, 5000, err, z) == expect == 651
    assert kld_limit(2, 100, 5000, 0.01, 0.99) == 100  # clamped to min
    assert kld_limit(400, 100, 5000, 0.01, 0.99) == 5000  # clamped to max


def test_systematic_resampling_is_proportional_within_one_draw() -> None:
    w = np.array([0.5, 0.25, 0.125, 0.125, 0.0])
    idx = systematic_indices(w, 1000, 0.37)
    counts = np.bincount(idx, minlength=5)
    assert np.all(np.abs(counts - 1000 * w) <= 1) and counts[4] == 0


def test_kld_resample_shrinks_a_tight_cloud_and_keeps_a_spread_one() -> None:
    rng = np.random.default_rng(2)
    tight = np.c_[rng.normal(0, 0.05, (5000, 2)), rng.normal(0, 0.02, 5000)]
    w = np.full(5000, 1 / 5000)
    none_b, none_p = np.zeros(0, np.bool_), np.zeros((0, 3))
    out = kld_resample(tight, w, 100, 5000, 0.01, 0.99, 0.5, rng.permutation(5000), none_b, none_p)
    assert 100 <= len(out) < 600
    spread = np.c_[rng.uniform(-20, 20, (5000, 2)), rng.uniform(-math.pi, math.pi, 5000)]
    out = kld_resample(spread, w, 100, 5000, 0.01, 0.99, 0.5, rng.permutation(5000), none_b,
                       none_p)
    assert len(out) == 5000
    # every new particle is one of the old ones
    assert np.isin(out[:, 0], spread[:, 0]).all()


@pytest.mark.parametrize("model", ["diff", "diff-corrected", "omni", "omni-corrected"])
def test_motion_model_without_noise_moves_by_the_odometry_in_each_particle_frame(model: str
                                                                                 ) -> None:
    parts = np.array([[0.0, 0.0, 0.0], [1.0, 2.0, math.pi / 2]])
    # odometry heading 0.3, moving 1 m straight ahead and turning 0.2
    dx, dy, dth = math.cos(0.3), math.sin(0.3), 0.2
    sample_motion(parts, 0.3, dx, dy, dth, np.zeros(5), MODEL_CODES[model], np.ones((2, 3)))
    np.testing.assert_allclose(parts[0], [1.0, 0.0, 0.2], atol=1e-12)
    np.testing.assert_allclose(parts[1], [1.0, 3.0, math.pi / 2 + 0.2], atol=1e-12)


def test_motion_noise_uncorrected_diff_uses_the_variance_as_sigma() -> None:
    rng = np.random.default_rng(3)
    alphas = np.array([0.0, 0.0, 0.2, 0.0, 0.0])
    spreads = {}
    for model in ("diff", "diff-corrected"):
        parts = np.zeros((20000, 3))
        sample_motion(parts, 0.0, 0.5, 0.0, 0.0, alphas, MODEL_CODES[model],
                      rng.standard_normal((20000, 3)))
        spreads[model] = parts[:, 0].std()
    assert spreads["diff"] == pytest.approx(0.2 * 0.5 ** 2, rel=0.03)  # 0.05 m
    assert spreads["diff-corrected"] == pytest.approx(math.sqrt(0.2 * 0.5 ** 2), rel=0.03)


def test_clusters_pick_the_heavier_hypothesis_and_set_covariance_spans_both() -> None:
    rng = np.random.default_rng(4)
    a = np.c_[rng.normal(2.0, 0.05, (300, 2)), np.full(300, 0.5)]
    b = np.c_[rng.normal(-4.0, 0.05, (100, 2)), np.full(100, -1.0)]
    parts = np.vstack([a, b])
    w = np.r_[np.full(300, 1.0), np.full(100, 2.0)]
    w /= w.sum()
    cw, cm, mean, cov = cluster_stats(parts, w)
    assert len(cw) == 2
    heavy = cm[np.argmax(cw)]
    assert heavy == pytest.approx([2.0, 2.0, 0.5], abs=0.02)
    assert cw.max() == pytest.approx(0.6)
    assert cov[0, 0] == pytest.approx(0.6 * 0.4 * 6.0 ** 2, rel=0.02)


def test_update_is_gated_by_update_min_d_and_a_and_forced_by_nomotion_request() -> None:
    a = Amcl(GRID, {"max_particles": 500}, np.random.default_rng(5))
    pose = Pose2D(3.0, 3.0, 0.0)
    a.set_initial_pose(pose, np.diag([0.01, 0.01, 0.01]))
    scan = sim_scan(GRID, pose)
    assert a.update(Pose2D(), scan, Pose2D()) is True  # first scan after initialisation
    assert a.update(Pose2D(0.15, 0.1, 0.4), scan, Pose2D()) is False  # below 0.2 m and pi/6
    a.request_nomotion_update()
    assert a.update(Pose2D(0.15, 0.1, 0.4), scan, Pose2D()) is True
    assert a.update(Pose2D(0.15, 0.1, 0.45), scan, Pose2D()) is False
    assert a.update(Pose2D(0.15, 0.1, 0.45 + math.pi / 6 + 0.01), scan, Pose2D()) is True
    assert a.update(Pose2D(0.15, 0.31, 0.45 + math.pi / 6 + 0.01), None, Pose2D()) is False


@pytest.mark.parametrize("model", ["likelihood_field", "likelihood_field_prob", "beam"])
def test_tracks_a_robot_driving_through_rooms_from_an_offset_start(model: str) -> None:
    rng = np.random.default_rng(6)
    amcl = Amcl(GRID, {"laser_model_type": model, "max_particles": 1000, "min_particles": 200,
                       "laser_max_beams": 60},
                rng)
    amcl.set_initial_pose(Pose2D(3.3, 2.8, 0.15), np.diag([0.1, 0.1, 0.03]))
    true = Pose2D(3.0, 3.0, 0.0)
    odom = Pose2D(10.0, -5.0, 1.0)  # the odom frame is anywhere
    errs = []
    for step in range(40):
        amcl.update(odom, sim_scan(GRID, true), Pose2D())
        est = amcl.map_to_odom().compose(odom)
        errs.append(true.distance_to(est))
        move = Pose2D(0.15, 0.0, 0.12 if step % 20 < 10 else -0.12)
        true, odom = true.compose(move), odom.compose(move)
    assert max(errs[-10:]) < 0.1, errs
    est = amcl.map_to_odom().compose(odom)
    assert abs(math.remainder(est.theta - true.theta, 2 * math.pi)) < 0.05
    assert amcl.covariance()[0, 0] < 0.05


ROOMS = ascii_map("""
??????????????????????????????
?############################?
?#..........#...............#?
?#..........#...............#?
?#..........#.......###.....#?
?#..........#.......###.....#?
?#...##.....................#?
?#...##.....................#?
?#..........#...............#?
?#..........#####...#########?
?#..........#...............#?
?#..........................#?
?#..........#...............#?
?############################?
??????????????????????????????
""".strip("\n"), resolution=0.25)


def test_global_localization_uses_free_cells_only_and_finds_the_robot() -> None:
    rng = np.random.default_rng(7)
    # the product model (likelihood_field_prob) sharpens the posterior quickly; amcl's default
    # 1 + sum(pz^3) needs driving around (see the ACES test)
    amcl = Amcl(ROOMS, {"max_particles": 5000, "laser_max_beams": 60,
                        "laser_model_type": "likelihood_field_prob"}, rng)
    amcl.global_localization()
    cells = [ROOMS.world_to_map(x, y) for x, y in amcl.particles[:, :2]]
    assert all(c is not None and ROOMS.data[c[1], c[0]] == 0 for c in cells)
    true, odom = Pose2D(2.0, 1.5, 2.0), Pose2D()
    for step in range(20):  # turn on the spot: every update sees the room from a new side
        amcl.update(odom, sim_scan(ROOMS, true), Pose2D())
        true, odom = true.compose(Pose2D(0, 0, 0.6)), odom.compose(Pose2D(0, 0, 0.6))
    amcl.request_nomotion_update()
    amcl.update(odom, sim_scan(ROOMS, true), Pose2D())
    est = amcl.map_to_odom().compose(odom)
    assert true.distance_to(est) < 0.12
    assert amcl.particle_count < 1000  # KLD shrank the set once it converged


def test_map_to_odom_composes_with_odometry_into_the_estimate() -> None:
    amcl = Amcl(GRID, {"max_particles": 300}, np.random.default_rng(8))
    amcl.set_initial_pose(Pose2D(4.0, 3.0, 1.0), np.diag([0.01, 0.01, 0.01]))
    odom = Pose2D(-2.0, 7.0, -0.4)
    amcl.update(odom, sim_scan(GRID, Pose2D(4.0, 3.0, 1.0)), Pose2D())
    back = amcl.map_to_odom().compose(odom)
    assert back.distance_to(amcl.pose()) < 1e-9
    assert abs(back.theta - amcl.pose().theta) < 1e-9


def test_laser_mount_is_composed_into_each_particle() -> None:
    """A laser 0.3 m ahead and turned 90 degrees: the same scan must localise the base."""
    rng = np.random.default_rng(9)
    base = Pose2D(3.0, 9.0, 0.3)
    mount = Pose2D(0.3, 0.0, math.pi / 2)
    scan = sim_scan(GRID, base.compose(mount))
    amcl = Amcl(GRID, {"max_particles": 2000, "laser_max_beams": 60}, rng)
    amcl.set_initial_pose(Pose2D(3.1, 8.9, 0.35), np.diag([0.04, 0.04, 0.01]))
    for _ in range(6):
        amcl.request_nomotion_update()
        amcl.update(Pose2D(), scan, mount)
    assert amcl.pose().distance_to(base) < 0.08
    assert abs(amcl.pose().theta - base.theta) < 0.05


def test_beam_skipping_ignores_beams_that_hit_an_unmapped_obstacle() -> None:
    """likelihood_field_prob with do_beamskip: once converged, beams whose end points most
    particles find far from any mapped obstacle are left out, so a person in front of the robot
    does not drag the weights."""
    from navcore.localization.laser_models import hit_table, likelihood_field_prob
    pose = Pose2D(3.0, 3.0, 0.0)
    scan = sim_scan(GRID, pose)
    ranges = scan.ranges.astype(np.float64)
    bearings = scan.angles()
    ranges_blocked = ranges.copy()
    ranges_blocked[:40] = 0.7  # a third of the beams hit something not in the map
    dist = distance_field(GRID.data, GRID.resolution, 2.0)
    table = hit_table(dist, 0.95, 0.05, 0.2, 12.0)
    geom = np.array([0.0, 0.0, 1.0, 0.0, GRID.resolution])
    rng = np.random.default_rng(10)
    parts = np.c_[3.0 + rng.normal(0, 0.03, (200, 2)), rng.normal(0, 0.01, 200)]

    def weights(r: np.ndarray, skip: bool) -> np.ndarray:
        w = np.full(200, 1 / 200)
        likelihood_field_prob(parts, w, r, bearings, np.zeros(3), table, dist, geom,
                              0.95 * math.exp(-4 / 0.08) + 0.05 / 12, 12.0, skip, 0.5, 0.3, 0.9)
        return w / w.sum()
    clean = weights(np.r_[np.full(40, 12.0), ranges[40:]], False)  # those beams never seen
    skipped = weights(ranges_blocked, True)
    np.testing.assert_allclose(skipped, clean, rtol=1e-9)
    assert not np.allclose(weights(ranges_blocked, False), clean, rtol=1e-3)


def test_likelihood_field_matches_amcls_formula_within_the_table_quantisation() -> None:
    a = Amcl(GRID, {"max_particles": 500}, np.random.default_rng(11))
    a.set_initial_pose(Pose2D(3, 3, 0.2), np.diag([0.3, 0.3, 0.1]))
    scan = sim_scan(GRID, Pose2D(3, 3, 0.2))
    parts = a.particles.copy()
    mount = Pose2D(0.1, 0.05, 0.3)
    a._sensor_update(scan, mount)
    r, b, rmax = a._beams(scan)
    ok = r < rmax
    expect = []
    for x, y, t in parts:  # amcl's LikelihoodFieldModel written out plainly
        lx = x + math.cos(t) * mount.x - math.sin(t) * mount.y
        ly = y + math.sin(t) * mount.x + math.cos(t) * mount.y
        ex = lx + r[ok] * np.cos(t + mount.theta + b[ok])
        ey = ly + r[ok] * np.sin(t + mount.theta + b[ok])
        mx, my = np.floor(ex / 0.05).astype(int), np.floor(ey / 0.05).astype(int)
        inside = (mx >= 0) & (my >= 0) & (mx < GRID.width) & (my < GRID.height)
        d = a._dist[np.clip(my, 0, GRID.height - 1), np.clip(mx, 0, GRID.width - 1)]
        z = np.where(inside, d, 2.0)
        pz = 0.95 * np.exp(-z ** 2 / (2 * 0.2 ** 2)) + 0.05 / rmax
        expect.append(1.0 + np.sum(pz ** 3))
    expect = np.array(expect) / np.sum(expect)
    np.testing.assert_allclose(a.weights, expect, rtol=1e-4)


def test_bad_input_in_the_control_loop_is_refused_with_a_reason() -> None:
    a = Amcl(GRID, {"max_particles": 200}, np.random.default_rng(12))
    scan = sim_scan(GRID, Pose2D(3.0, 3.0, 0.0))
    assert a.update(Pose2D(math.nan, 0.0, 0.0), scan, Pose2D()) is False
    assert "not finite" in a.last_error
    broken = LaserScan(0.0, -1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, np.array([1.0, 1.0, 1.0]))
    assert a.update(Pose2D(), broken, Pose2D()) is False and "range_max" in a.last_error
    assert a.update(Pose2D(), scan, Pose2D()) is True
