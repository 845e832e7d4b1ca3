"""ROS bags through rosbags: the demo run written as ROS 1, ROS 2 (sqlite3) and ROS 2 (MCAP)
bags, read back, and its /scan and /odom driving AMCL as a CARMEN log does."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

pytest.importorskip("rosbags", reason="rosbags not installed (pip install navbt[bags])")

from navcore.clock import SimClock  # noqa: E402
from navcore.localization import Amcl  # noqa: E402
from navcore.types import Pose2D  # noqa: E402
from executive.bags import BagError, BagPlayback, BagSink, FORMATS, read_bag  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _record(tmp_path, fmt):
    from executive.tree_loader import shipped_tree
    from executive.mission import World, build_mission, run_mission
    from executive.recorder import Recorder
    from executive.scenario import load_scenario, scenario_config
    s = load_scenario(os.path.join(ROOT, "executive", "data", "demo.yaml"))
    path = tmp_path / ("demo.bag" if fmt == "ros1" else f"demo_{fmt}")
    sink = BagSink(path, fmt, grid=s.grid)
    rec = Recorder(None, sinks=[sink])
    m = build_mission(shipped_tree("smach_recovery"), scenario_config(s), s.grid, s.start,
                      world=World(s.objects, s.moving, s.phantoms, s.faults), seed=s.seed,
                      recorder=rec)
    result = run_mission(m, s.goals, s.time_limit)
    rec.close()
    return s, path, sink, result, m


@pytest.mark.parametrize("fmt", FORMATS)
def test_bag_round_trip(tmp_path, fmt):
    s, path, sink, result, mission = _record(tmp_path, fmt)
    log = read_bag(path)
    expected = {"/scan", "/odom", "/tf", "/tf_static", "/cmd_vel", "/plan", "/map",
                "/base_pose_ground_truth"}
    assert set(log.topics) == expected
    assert {t: log.topics[t] for t in expected} == {t: sink.counts[t] for t in expected}
    assert log.topics["/odom"] == log.topics["/cmd_vel"] == result.ticks
    assert len(log.scans) == sink.counts["/scan"] and len(log.scans) >= result.ticks - 1
    assert np.all(np.diff(log.scan_times) > 0)
    mount = mission.sim.config.laser.mount
    assert log.laser_mount.x == pytest.approx(mount.x) and log.laser_mount.y == pytest.approx(
        mount.y)
    first = log.scans[0]
    assert first.frame_id == "laser" and len(first.ranges) == 241
    assert first.angle_max == pytest.approx(first.angle_min + 240 * first.angle_increment,
                                            abs=1e-5)
    # ground truth ends where the simulator left the robot
    truth = mission.sim.true_pose() if hasattr(mission.sim, "true_pose") else None
    if truth is not None:
        assert log.truth_poses[-1][:2] == pytest.approx([truth.x, truth.y], abs=1e-6)


def test_bag_drives_amcl_like_a_carmen_log(tmp_path):
    s, path, sink, result, mission = _record(tmp_path, "ros2")
    log = read_bag(path)
    clock = SimClock(float(log.scan_times[0]))
    pb = BagPlayback(log, clock)
    amcl = Amcl(s.grid, {"min_particles": 300, "max_particles": 1000, "update_min_d": 0.05,
                         "update_min_a": 0.1}, np.random.default_rng(3))
    amcl.set_initial_pose(Pose2D(*log.truth_poses[0]), np.diag([0.01, 0.01, 0.003]))
    errors, updates = [], 0
    for stamp in log.scan_times:
        clock.sleep_until(float(stamp))
        odom = pb.odometry().pose
        updates += amcl.update(odom, pb.scan(), pb.mount)
        est = amcl.map_to_odom().compose(odom)
        k = int(np.searchsorted(log.truth_times, stamp, side="right")) - 1
        tx, ty, _ = log.truth_poses[k]
        errors.append(math.hypot(est.x - tx, est.y - ty))
    assert pb.finished and updates >= 10
    assert float(np.median(errors)) < 0.1 and max(errors) < 0.35


def test_bag_errors(tmp_path):
    with pytest.raises(BagError, match="no such bag"):
        read_bag(tmp_path / "none.bag")
    with pytest.raises(BagError, match="bag format 'ros3'"):
        BagSink(tmp_path / "x", "ros3")
    (tmp_path / "exists").mkdir()
    with pytest.raises(BagError, match="already exists"):
        BagSink(tmp_path / "exists", "ros2")


def test_bag_command_lists_topics_and_localises(tmp_path, capsys):
    from executive.cli import main
    s, path, sink, result, mission = _record(tmp_path, "ros2-mcap")
    m = os.path.join(ROOT, "executive", "data", "maps", "two_rooms.yaml")
    assert main(["bag", str(path), "--map", m]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith(f"{path}: {sink.counts['/scan']} scans over ")
    assert f"  /odom: {result.ticks}" in out
    line = [o for o in out if o.startswith("amcl vs ground truth: median ")][0]
    assert float(line.split("median ")[1].split(" m")[0]) < 0.1
    assert main(["bag", str(tmp_path / "missing.bag")]) == 1
    assert "no such bag" in capsys.readouterr().err
    assert main(["run", os.path.join(ROOT, "trees", "smach_recovery.yaml"), "--map", m,
                 "--goal", "6,1,0", "--bag", "ros2"]) == 1
    assert "--bag needs --record" in capsys.readouterr().err
