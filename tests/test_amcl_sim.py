"""AMCL in the simulator (hw.sim): the kidnapped robot and recovery_alpha_slow/fast, and the
tuning guide's observation (section 5.2) that low odom_alpha values keep the cloud tighter."""

from __future__ import annotations

import math

import numpy as np

from hw.sim import Simulator, SimWorld
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
    sim = Simulator(SimWorld(FLOOR), ROBOT, clock, np.random.default_rng(seed), start=start)
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
    for thousands of updates, which hides a kidnapping from the recovery test (measured).

    Recovery is a matter of chance: the injected particles must land near the true pose before
    the cloud settles on a place whose scans fit about as well. Measured: of 48 seeds run for
    75 s, 14 relocalised (18 with the earlier laser noise stream); of seeds 0-23 run for three
    minutes, 6 relocalised 7-36 s after the kidnapping, one after 79 s and 17 never. So the test
    asks it of some of eight seeds, and of none without the alphas."""
    away = Pose2D(8.0, 4.4, 2.0)  # the upper part of the third room
    fixed = {"max_particles": 2000, "min_particles": 2000}
    k = 149  # the scan at which the robot is carried away (t = 15 s)
    recovered: dict[bool, list[int]] = {True: [], False: []}
    for alphas in (True, False):
        params = fixed if alphas else dict(fixed, recovery_alpha_slow=0.0,
                                           recovery_alpha_fast=0.0)  # else the node defaults
        for seed in range(8):
            errs, _ = spin_run(params, away, 75.0, seed=seed)
            assert max(errs[20:k]) < 0.15  # tracked first
            assert errs[k + 5] > 3.0  # fooled by the kidnapping
            if max(errs[-150:]) < 0.2:  # relocalised and within 0.2 m for the last 15 s
                recovered[alphas].append(seed)
    assert len(recovered[True]) >= 1  # measured: seeds 2 and 3, 9.6 s and 25.1 s after it
    assert recovered[False] == []


def cloud_spread(params: dict, seed: int, laser: bool) -> float:
    """Median spread sqrt(var x + var y) of the particles over a 30 s circle drive at amcl's own
    update points, with or without the laser."""
    clock = SimClock()
    start = Pose2D(8.6, 0.8, 0.0)
    sim = Simulator(SimWorld(FLOOR), ROBOT, clock, np.random.default_rng(seed), start=start)
    amcl = Amcl(FLOOR, dict(params, recovery_alpha_slow=0.0, recovery_alpha_fast=0.0),
                np.random.default_rng(seed + 1))
    amcl.set_initial_pose(start, np.diag([0.02, 0.02, 0.01]))
    s, t, last = [], 0.0, Pose2D()
    while t < 30.0:
        sim.base.send(Twist(0.25, 0.0, 0.25))  # a 1 m circle in room 3, lower part
        t += 0.1
        sim.step_to(t)
        odom = sim.base.odometry().pose
        if laser:
            if amcl.update(odom, sim.laser.scan(), sim.laser.mount):
                s.append(math.sqrt(amcl.particles[:, 0].var() + amcl.particles[:, 1].var()))
        elif odom.distance_to(last) > 0.2:  # dead reckoning: the motion model alone
            amcl.predict(odom)
            last = odom
            s.append(math.sqrt(amcl.particles[:, 0].var() + amcl.particles[:, 1].var()))
    return float(np.median(s))


def test_low_odom_alphas_keep_the_particle_cloud_tighter() -> None:
    """The tuning guide's two odometry settings (section 5.2), on a robot driving a loop."""
    low = {"kld_err": 0.01, "kld_z": 0.99, "odom_alpha1": 0.005, "odom_alpha2": 0.005,
           "odom_alpha3": 0.005, "odom_alpha4": 0.005}
    noisy = {"kld_err": 0.10, "kld_z": 0.5, "odom_alpha1": 0.008, "odom_alpha2": 0.040,
             "odom_alpha3": 0.004, "odom_alpha4": 0.025}
    # with the laser the likelihood field dominates the spread in this small world (measured
    # 0.110 vs 0.116 / 0.119 m; one seed of three reversed), so the clear effect is the
    # odometry-driven cloud between scans
    for seed in (1, 2):
        low_s = cloud_spread(dict(low, odom_model_type="diff-corrected"), seed, laser=False)
        noisy_s = cloud_spread(dict(noisy, odom_model_type="diff-corrected"), seed, laser=False)
        assert low_s < 0.75 * noisy_s, (seed, low_s, noisy_s)  # measured 0.29 vs 0.47 m
    with_laser = [cloud_spread(p, 1, laser=True) for p in (low, noisy)]
    assert max(with_laser) < 0.3  # both stay localised
