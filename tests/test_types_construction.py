"""The hand-written constructors of the frozen messages keep the dataclass semantics."""

import copy
import dataclasses
import inspect
import pickle

import numpy as np
import pytest

from navcore.types import Odometry, Pose2D, Twist


@pytest.mark.parametrize("cls", [Pose2D, Twist, Odometry])
def test_signature_matches_fields(cls):
    params = list(inspect.signature(cls).parameters.values())
    fields = dataclasses.fields(cls)
    assert [p.name for p in params] == [f.name for f in fields]
    for p, f in zip(params, fields):
        if f.default is not dataclasses.MISSING:
            assert p.default == f.default
        elif f.default_factory is dataclasses.MISSING:
            assert p.default is inspect.Parameter.empty


def test_pose_and_twist_values_defaults_equality_frozen():
    p = Pose2D(1.5, -2.0, 0.25)
    assert (p.x, p.y, p.theta) == (1.5, -2.0, 0.25)
    assert Pose2D(y=3.0) == Pose2D(0.0, 3.0, 0.0)
    assert p == Pose2D(x=1.5, y=-2.0, theta=0.25) and hash(p) == hash(Pose2D(1.5, -2.0, 0.25))
    assert p != Pose2D(1.5, -2.0, 0.26)
    assert Twist(wz=0.5) == Twist(0.0, 0.0, 0.5) and Twist().is_zero()
    with pytest.raises(dataclasses.FrozenInstanceError):
        p.x = 0.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        Twist().vx = 1.0
    with pytest.raises(TypeError):
        Pose2D(1.0, 2.0, 3.0, 4.0)
    with pytest.raises(TypeError):
        Twist(v=1.0)
    assert dataclasses.replace(p, x=7.0) == Pose2D(7.0, -2.0, 0.25)
    assert pickle.loads(pickle.dumps(p)) == p and copy.deepcopy(p) == p
    assert repr(p) == "Pose2D(x=1.5, y=-2.0, theta=0.25)"


def test_odometry_defaults_are_fresh_zero_matrices():
    a = Odometry(1.0, Pose2D(1.0, 2.0, 0.5))
    b = Odometry(1.0, Pose2D(1.0, 2.0, 0.5))
    assert a.twist == Twist() and a.frame_id == "odom" and a.child_frame_id == "base_link"
    for m in (a.pose_covariance, a.twist_covariance, b.pose_covariance):
        assert m.shape == (3, 3) and m.flags.writeable and not m.any()
    assert a.pose_covariance is not b.pose_covariance
    assert a.pose_covariance is not a.twist_covariance
    cov = np.eye(3)
    c = Odometry(2.0, Pose2D(), Twist(0.1, 0.0, 0.2), pose_covariance=cov, twist_covariance=cov,
                 frame_id="odom_combined", child_frame_id="base_footprint")
    assert c.pose_covariance is cov and c.twist_covariance is cov
    assert (c.stamp, c.twist.wz, c.frame_id, c.child_frame_id) == (2.0, 0.2, "odom_combined",
                                                                   "base_footprint")
    with pytest.raises(dataclasses.FrozenInstanceError):
        c.stamp = 3.0
    with pytest.raises(TypeError):
        Odometry(1.0)
    d = pickle.loads(pickle.dumps(c))
    assert d.pose == c.pose and d.stamp == c.stamp and np.array_equal(d.twist_covariance, cov)
    assert dataclasses.replace(c, stamp=5.0).stamp == 5.0


def test_path_length_is_the_sum_of_np_diff_steps_bit_for_bit():
    """Path.length skips np.diff's wrapper: the same floats as the numpy statement, on any
    length (numpy's pairwise sum blocks), memory layout, NaN and infinity."""
    from navcore.types import Path
    rng = np.random.default_rng(11)
    for n in [0, 1, 2, 3, 8, 9, 129, 130, 257, 1000, 4097] + list(rng.integers(0, 3000, 40)):
        poses = rng.normal(0.0, 4.0, (int(n), 3))
        if n % 3 == 0:
            poses = np.asfortranarray(poses)
        if n > 5 and n % 4 == 1:
            poses[n // 2, int(n) % 2] = [np.nan, np.inf][int(n) % 2]
        path = Path(poses)
        want = float(np.sum(np.hypot(np.diff(path.poses[:, 0]), np.diff(path.poses[:, 1])))) \
            if n >= 2 else 0.0
        got = path.length()
        assert got == want or (np.isnan(got) and np.isnan(want)), n
