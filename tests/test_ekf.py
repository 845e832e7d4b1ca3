"""robot_pose_ekf semantics: relative fusion of odometry and IMU, activation, timeouts, rate."""

from __future__ import annotations

import math

import numpy as np
import pytest

from navcore.localization import Ekf
from navcore.params import ParameterError
from navcore.types import Imu, Odometry, Pose2D

ODOM_COV = np.diag([1e-3, 1e-3, 1e-2])


def odom(t: float, x: float, y: float, th: float, cov: np.ndarray = ODOM_COV) -> Odometry:
    return Odometry(stamp=t, pose=Pose2D(x, y, th), pose_covariance=cov)


def drive(ekf: Ekf, seconds: float, imu_yaw=None, odom_yaw=None, imu_var: float = 1e-4,
          t0: float = 0.0, imu_until: float = math.inf, imu_offset: float = 0.0) -> None:
    """Drive a 0.5 m/s, 0.2 rad/s arc; 30 Hz odometry and IMU; one EKF cycle per message."""
    dt = 1.0 / 30.0
    for i in range(int(round(seconds / dt)) + 1):
        t = t0 + i * dt
        th_true = 0.2 * t
        x = 2.5 * math.sin(th_true)
        y = 2.5 * (1 - math.cos(th_true))
        th_odom = odom_yaw(t) if odom_yaw else th_true
        ekf.add_odometry(odom(t, x, y, th_odom))
        if t < imu_until or t >= imu_until + 3.0:
            yaw = imu_yaw(t) if imu_yaw else th_true
            ekf.add_imu(Imu(stamp=t, yaw=yaw + (imu_offset if t >= imu_until else 0.0),
                            yaw_variance=imu_var))
        ekf.update(t)


def test_parameters_are_robot_pose_ekf_defaults() -> None:
    e = Ekf()
    p = e.params
    assert (p.freq, p.sensor_timeout, p.odom_used, p.imu_used, p.vo_used, p.gps_used) == \
        (30.0, 1.0, True, True, True, False)
    assert p.output_frame == "odom_combined"
    with pytest.raises(ParameterError, match="sensor_timeout"):
        Ekf({"sensor_timeout": -1.0})


def test_initialises_from_odometry_once_it_is_active_and_then_follows_it() -> None:
    e = Ekf({"imu_used": False})
    e.add_odometry(odom(0.0, 1.0, 2.0, 0.3))
    assert e.update(0.0) is False and not e.initialized  # first message: initialising only
    e.add_odometry(odom(0.04, 1.02, 2.0, 0.3))
    assert e.update(0.04) is True and e.initialized
    assert e.pose().x == pytest.approx(1.02)
    drive(e, 5.0, t0=0.1)  # odometry-only fusion reproduces the odometry
    t = 0.1 + 5.0
    expect = Pose2D(2.5 * math.sin(0.2 * t), 2.5 * (1 - math.cos(0.2 * t)), 0.2 * t)
    assert e.pose().theta == pytest.approx(expect.theta, abs=1e-6)
    assert e.pose().distance_to(expect) < 1e-6


def test_imu_yaw_corrects_drifting_wheel_odometry_by_the_variances() -> None:
    truth = lambda t: 0.2 * t  # noqa: E731
    drifting = lambda t: 0.2 * t + 0.05 * t  # odometry gyro-less yaw creeps 0.05 rad/s
    sharp = Ekf()
    drive(sharp, 10.0, odom_yaw=drifting, imu_var=1e-6)  # IMU 100x more certain (1e-2 / 1e-4)
    assert sharp.active("odom") and sharp.active("imu")
    err_sharp = abs(math.remainder(sharp.pose().theta - truth(10.0), 2 * math.pi))
    equal = Ekf()
    drive(equal, 10.0, odom_yaw=drifting, imu_var=1e-2)  # as certain as the odometry
    err_equal = abs(math.remainder(equal.pose().theta - truth(10.0), 2 * math.pi))
    odom_only = Ekf({"imu_used": False})
    drive(odom_only, 10.0, odom_yaw=drifting)
    err_odom = abs(math.remainder(odom_only.pose().theta - truth(10.0), 2 * math.pi))
    assert err_odom == pytest.approx(0.5, abs=0.01)
    assert err_equal == pytest.approx(err_odom / 2, rel=0.1)  # equal weights: half the drift
    assert err_sharp < 0.02 * err_odom


def test_filter_time_waits_for_the_slowest_active_sensor() -> None:
    e = Ekf()
    for i in range(20):
        t = i * 0.05
        e.add_odometry(odom(t, 0.1 * t, 0.0, 0.0))
        if t >= 0.2:
            e.add_imu(Imu(stamp=t - 0.2, yaw=0.0, yaw_variance=1e-4))  # IMU 0.2 s late
        e.update(t + 0.001)
    assert e.active("imu")
    assert e.stamp == pytest.approx(0.95 - 0.2)
    assert e.pose().x == pytest.approx(0.1 * 0.75, abs=1e-6)  # odometry interpolated there


def test_a_timed_out_sensor_drops_out_and_re_anchors_without_a_jump() -> None:
    e = Ekf()
    # IMU silent for 3 s after t = 3, then back with a constant 1 rad offset (a re-started IMU)
    drive(e, 8.0, imu_until=3.0, imu_offset=1.0)
    assert e.active("imu")
    assert e.pose().theta == pytest.approx(math.remainder(0.2 * 8.0, 2 * math.pi), abs=0.01)
    e2 = Ekf()
    drive(e2, 4.5, imu_until=3.0)
    assert not e2.active("imu") and e2.active("odom")


def test_cycles_run_at_freq_and_bad_messages_are_refused_with_a_reason() -> None:
    e = Ekf({"freq": 10.0, "imu_used": False})
    e.add_odometry(odom(0.0, 0, 0, 0))
    e.update(0.0)
    e.add_odometry(odom(0.05, 0.01, 0, 0))
    assert e.update(0.05) is False  # 1/freq = 0.1 s has not passed
    assert e.update(0.1) is True
    assert e.add_odometry(odom(0.2, 0, 0, 0, cov=np.zeros((3, 3)))) is False
    assert "zero" in e.last_error
    assert e.add_odometry(odom(0.01, 0, 0, 0)) is False and "not newer" in e.last_error
    f = Ekf()
    assert f.add_imu(Imu(stamp=0.0, yaw=0.0)) is False and "orientation" in f.last_error
    assert Ekf({"imu_used": False}).add_imu(Imu(0.0, 0.0, yaw_variance=1.0)) is False
