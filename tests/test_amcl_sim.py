"""AMCL in the simulator (hw.sim): the kidnapped robot and recovery_alpha_slow/fast, and the
tuning guide's observation (section 5.2) that low odom_alpha values keep the cloud tighter."""

from __future__ import annotations

import math

import numpy as np

from hw.sim import Simulator, World
from navcore.clock import SimClock
from navcore.localization import Amcl
from navcore.synthetic_maps import ascii_map
from navcore.types import Pose2D, Twist

# three rooms of different sizes and shapes, joined by doorways (0.2 m cells: 10.4 m x 5.6 m)
FLOOR = ascii_map("""
####################################################
#.............#...................#................#
#.............#...................#................#
#.............#...................#................#
#...###.......#...................#................#
#...###.......#...................#................#
#.............#...................#................#
#.................................#................#
#.................................#................#
#.............#...................#................#
#.............#......######.......###########......#
#.............#......######.......#................#
#.............#......######.......#................#
#.............#......######.......#................#
#.............#......######.......#................#
#.............#......######.......#................#
#.............#....................................#
#.............#....................................#
#.............#...................#................#
#.............#...................#................#
#.................................#................#
#.................................#................#
#.............#...................#................#
#.............#...................#................#
#.............#...................#................#
#.............#...................#................#
#.............#...................#................#
####################################################
""".strip("\n"), resolution=0.2)

ROBOT = {"odom_alpha1": 0.02, "odom_alpha2": 0.02, "odom_alpha3": 0.02, "odom_alpha4": 0.02,
         "laser": {"preset": "lms200", "range_max": 20.0, "range_noise_stddev": 0.01,
                   "angle_min": -math.pi, "angle_max": math.pi, "beams": 360}}


def spin_run(params: dict, kidnap_to: Pose2D | None, seconds: float, seed: int = 0,
             wz: float = 0.8) -> tuple[list[float], Amcl]:
    """Turn on the spot in room 1, optionally teleported to ``kidnap_to`` after 15 s; AMCL
    updated at every scan. Returns the position error (map -> odom (+) odometry vs truth) per
    scan."""
    clock = SimClock()
    start = Pose2D(1.5, 1.5, 0.0)
    sim = Simulator(World(FLOOR), ROBOT, clock, np.random.default_rng(seed), start=start)
    amcl = Amcl(FLOOR, params, np.random.default_rng(seed + 100))
    amcl.set_initial_pose(start, np.diag([0.02, 0.02, 0.01]))
    errs = []
    t, dt = 0.0, 0.1
    kidnapped = False
    while t < seconds:
        sim.base.send(Twist(0.0, 0.0, wz))
        t += dt
        sim.step_to(t)
        if kidnap_to is not None and not kidnapped and t >= 15.0:
            sim.set_pose(kidnap_to)
            kidnapped = True
        odom, scan = sim.base.odometry(), sim.laser.scan()
        amcl.update(odom.pose, scan, sim.laser.mount)
        est = amcl.map_to_odom().compose(odom.pose)
        errs.append(est.distance_to(sim.true_pose()))
    return errs, amcl


def test_kidnapped_robot_recovers_with_recovery_alphas_and_not_without() -> None:
    """The particle count is fixed here: amcl's average weight is sum(w p) / N, so while KLD
    shrinks N after convergence the average rises and w_slow (alpha 0.001) lags far below w_fast
    for thousands of updates, which hides a kidnapping from the recovery test (measured)."""
    away = Pose2D(8.0, 4.4, 2.0)  # the upper part of the third room
    fixed = {"max_particles": 2000, "min_particles": 2000}
    with_rec, _ = spin_run(fixed, away, 75.0)  # node defaults: 0.001 / 0.1
    without, _ = spin_run(dict(fixed, recovery_alpha_slow=0.0, recovery_alpha_fast=0.0), away,
                          75.0)
    k = 149  # the scan at which the robot is carried away (t = 15 s)
    assert max(with_rec[20:k]) < 0.15 and max(without[20:k]) < 0.15  # both tracked first
    assert with_rec[k + 5] > 3.0 and without[k + 5] > 3.0  # both were fooled
    # measured: relocalised about 28 s after the kidnapping, then within 0.1 m
    assert max(with_rec[-150:]) < 0.2
    assert min(without[-150:]) > 3.0  # never found it again


def test_low_odom_alphas_keep_the_particle_cloud_tighter() -> None:
    """The tuning guide's two odometry settings (section 5.2), on a robot driving a loop."""
    low = {"kld_err": 0.01, "kld_z": 0.99, "odom_alpha1": 0.005, "odom_alpha2": 0.005,
           "odom_alpha3": 0.005, "odom_alpha4": 0.005}
    noisy = {"kld_err": 0.10, "kld_z": 0.5, "odom_alpha1": 0.008, "odom_alpha2": 0.040,
             "odom_alpha3": 0.004, "odom_alpha4": 0.025}
    spreads, counts = {}, {}
    for name, p in (("low", low), ("noisy", noisy)):
        p = dict(p, odom_model_type="diff-corrected", recovery_alpha_slow=0.0,
                 recovery_alpha_fast=0.0)
        clock = SimClock()
        start = Pose2D(8.6, 3.1, 0.0)
        sim = Simulator(World(FLOOR), ROBOT, clock, np.random.default_rng(1), start=start)
        amcl = Amcl(FLOOR, p, np.random.default_rng(2))
        amcl.set_initial_pose(start, np.diag([0.02, 0.02, 0.01]))
        s, n, t = [], [], 0.0
        while t < 40.0:
            sim.base.send(Twist(0.25, 0.0, 0.25))  # a 1 m radius circle in room 3
            t += 0.1
            sim.step_to(t)
            odom = sim.base.odometry()
            if amcl.update(odom.pose, sim.laser.scan(), sim.laser.mount) and t > 5.0:
                c = amcl.covariance()
                s.append(math.sqrt(c[0, 0] + c[1, 1]))
                n.append(amcl.particle_count)
        assert amcl.pose().distance_to(sim.true_pose()) < 0.2  # both still localised
        spreads[name], counts[name] = float(np.median(s)), float(np.median(n))
    assert spreads["low"] < 0.7 * spreads["noisy"], spreads
