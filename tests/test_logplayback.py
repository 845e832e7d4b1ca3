"""CARMEN log reader and playback through the hw Laser/Base interfaces."""

from __future__ import annotations

import gzip
import math

import numpy as np
import pytest

from hw.interfaces import Base, Laser
from hw.logplayback import LogError, LogPlayback, map_from_log, read_carmen, rotate_poses
from navcore.clock import SimClock
from navcore.types import Pose2D, Twist

# Two scans of 4 beams. After scan 1 (corrected pose (1, 0, 0)) the odometry, integrated from
# that pose, says the robot drove 1 m ahead and turned 0.5 rad; the SLAM correction then puts
# scan 2 at (2.1, 0.05, 0.45). One garbage timestamp as in the Intel log.
TINY = """\
# comment
PARAM robot_frontlaser_offset 0.25 nohost 0
ODOM 0 0 0 0 0 0 0.5 pippo 0.5
FLASER 4 1.0 2.0 3.0 81.9 1.0 0.0 0.0 1.0 0.0 0.0 10.0 pippo 10.0
ODOM 1.0 0.0 0.0 0 0 0 0 pippo 0
NEFF 30
ODOM 1.5 0.0 0.2 0 0 0 10.5 pippo 10.5
ODOM 9.0 9.0 9.0 0 0 0 1.3e-153 pippo 1.3e-153
ODOM 2.0 0.0 0.5 0 0 0 11.0 pippo 11.0
FLASER 4 4.0 3.0 2.0 1.0 2.1 0.05 0.45 2.1 0.05 0.45 11.0 pippo 11.0
ODOM 2.1 0.05 0.45 0 0 0 0 pippo 0
ODOM 2.1 0.05 0.55 0 0 0 11.5 pippo 11.5
"""


@pytest.fixture()
def tiny(tmp_path):
    p = tmp_path / "tiny.log.gz"
    with gzip.open(p, "wt") as f:
        f.write(TINY)
    return read_carmen(p)


def test_reader_rebuilds_continuous_odometry_from_re_anchored_increments(tiny) -> None:
    assert len(tiny) == 2 and tiny.laser_offset == 0.25
    np.testing.assert_allclose(tiny.scan_times, [10.0, 11.0])
    np.testing.assert_allclose(tiny.reference, [[1, 0, 0], [2.1, 0.05, 0.45]])
    # odometry starts at the first corrected pose; the increment is the last ODOM before scan 2
    # relative to scan 1's pose: (1, 0, 0.5), regardless of the SLAM correction
    np.testing.assert_allclose(tiny.scan_odom, [[1, 0, 0], [2, 0, 0.5]], atol=1e-12)
    # after scan 2 the chain continues from the *odometry* pose, not the corrected one
    np.testing.assert_allclose(tiny.odom_poses[-1], [2.0, 0.0, 0.6], atol=1e-12)
    assert 1.3e-153 not in tiny.odom_times and np.all(np.diff(tiny.odom_times) >= 0)
    assert np.isclose(tiny.scan_ranges[0, 3], 81.9)


def test_playback_serves_the_newest_messages_on_the_clock(tiny) -> None:
    clock = SimClock(9.0)
    pb = LogPlayback(tiny, clock, range_max=50.0)
    assert isinstance(pb, Laser) and isinstance(pb, Base)
    assert pb.scan() is None and pb.odometry() is None and pb.mount == Pose2D(0.25, 0.0, 0.0)
    clock.sleep_until(10.7)
    s, o = pb.scan(), pb.odometry()
    assert s.stamp == 10.0 and s.range_max == 50.0 and len(s.ranges) == 4
    assert s.angle_min == pytest.approx(-math.pi / 2)
    assert s.angle_increment == pytest.approx(math.pi / 4)  # 4 beams over 180 degrees
    assert o.stamp == 10.5 and o.pose.x == pytest.approx(1.5) and o.pose.theta == pytest.approx(0.2)
    pb.send(Twist(0.3, 0.0, 0.0))
    assert pb.last_cmd == Twist(0.3, 0.0, 0.0) and pb.battery() is None
    clock.sleep_until(12.0)
    assert pb.scan().stamp == 11.0 and pb.finished


def test_malformed_logs_name_file_and_line(tmp_path) -> None:
    bad = tmp_path / "bad.log"
    bad.write_text("FLASER 4 1.0 2.0\n")
    with pytest.raises(LogError, match=r"bad.log:1: FLASER with 4 ranges"):
        read_carmen(bad)
    bad.write_text(TINY.replace("ODOM 1.5 0.0 0.2", "ODOM 1.5 x 0.2"))
    with pytest.raises(LogError, match=r"bad.log:7: malformed ODOM"):
        read_carmen(bad)
    with pytest.raises(LogError, match="cannot read"):
        read_carmen(tmp_path / "missing.log")


def test_rotate_poses_is_the_sources_md_registration() -> None:
    out = rotate_poses(np.array([[1.0, 0.0, 3.0]]), math.pi / 2)
    np.testing.assert_allclose(out, [[0.0, 1.0, 3.0 + math.pi / 2 - 2 * math.pi]], atol=1e-12)


def test_real_logs_parse_with_the_figures_of_sources_md(shared_data) -> None:
    """Scan counts and the mean per-scan odometry error (xy m, heading deg) of SOURCES.md 2.2."""
    for name, scans, err_xy, err_deg in (("aces", 440, 0.059, 1.6), ("intel", 910, 0.059, 2.7)):
        log = read_carmen(shared_data / "logs" / f"{name}-corrected.log.gz")
        assert len(log) == scans and log.scan_ranges.shape == (scans, 180)
        exy, eth = [], []
        for k in range(scans - 1):
            o = Pose2D(*log.scan_odom[k + 1]).relative_to(Pose2D(*log.scan_odom[k]))
            r = Pose2D(*log.reference[k + 1]).relative_to(Pose2D(*log.reference[k]))
            exy.append(math.hypot(o.x - r.x, o.y - r.y))
            eth.append(abs(math.remainder(o.theta - r.theta, 2 * math.pi)))
        assert np.mean(exy) == pytest.approx(err_xy, rel=0.1)
        assert math.degrees(np.mean(eth)) == pytest.approx(err_deg, rel=0.1)


def test_map_from_log_is_consistent_with_the_scans(shared_data) -> None:
    log = read_carmen(shared_data / "logs" / "aces-corrected.log.gz")
    grid = map_from_log(log, 0.05)
    k = 100
    ref = log.reference[k]
    r = log.scan_ranges[k].astype(float)
    a = ref[2] - math.pi / 2 + math.radians(1.0) * np.arange(180)
    ok = r < 20
    cells = [grid.world_to_map(x, y) for x, y in zip(ref[0] + r[ok] * np.cos(a[ok]),
                                                     ref[1] + r[ok] * np.sin(a[ok]))]
    assert all(grid.data[my, mx] == 100 for mx, my in cells)
    mx, my = grid.world_to_map(ref[0], ref[1])
    assert grid.data[my, mx] == 0
