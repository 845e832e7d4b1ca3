"""ROS 1 and ROS 2 bags through the ``rosbags`` library (no ROS install): a run written as a
bag that rviz, rqt_bag, Foxglove or ``ros2 bag`` open, and a recorded bag's ``/scan`` and
``/odom`` played back through the ``Laser`` and ``Base`` interfaces, as CARMEN logs are
(hw/logplayback.py), so that localisation runs on it as on a robot.

Formats: ``ros1`` (one ``.bag`` file), ``ros2`` (a rosbag2 folder, sqlite3 storage) and
``ros2-mcap`` (a rosbag2 folder, MCAP storage). Topics written by ``BagSink``:

``/scan`` sensor_msgs/LaserScan (frame ``laser``), ``/odom`` nav_msgs/Odometry (``odom`` ->
``base_link``), ``/tf`` tf2_msgs/TFMessage (``map`` -> ``odom``, ``odom`` -> ``base_link``),
``/tf_static`` (``base_link`` -> ``laser``), ``/cmd_vel`` geometry_msgs/Twist, ``/plan``
nav_msgs/Path, ``/map`` nav_msgs/OccupancyGrid and, in the simulator,
``/base_pose_ground_truth`` nav_msgs/Odometry (Stage's name for it). Stamps are sim time.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path as FsPath
from typing import Any

import numpy as np

from hw.logplayback import RecordedBase
from navcore.clock import Clock
from navcore.types import LaserScan, Pose2D, Twist
from executive.errors import ExecutiveError

FORMATS = ("ros1", "ros2", "ros2-mcap")
_TF_MSG = "geometry_msgs/TransformStamped[] transforms\n"


class BagError(ExecutiveError, ValueError):
    """A bag cannot be written or read; the message names the file and what is wrong."""


def _rosbags() -> Any:
    try:
        import rosbags  # noqa: F401 - only whether it is there
    except ImportError:
        raise BagError("rosbags is not installed: pip install 'navbt[bags]'") from None
    from rosbags import typesys
    return typesys


def typestore(fmt: str) -> Any:
    """The message types of ROS 1 Noetic (``ros1``) or ROS 2 Humble (``ros2*``)."""
    ts_mod = _rosbags()
    if fmt == "ros1":
        ts = ts_mod.get_typestore(ts_mod.Stores.ROS1_NOETIC)
        if "tf2_msgs/msg/TFMessage" not in ts.types:
            ts.register(ts_mod.get_types_from_msg(_TF_MSG, "tf2_msgs/msg/TFMessage"))
        return ts
    return ts_mod.get_typestore(ts_mod.Stores.ROS2_HUMBLE)


def bag_path(run_dir: str | os.PathLike, fmt: str) -> FsPath:
    """Where a run folder keeps its bag: ``run.bag`` or the rosbag2 folder ``run_bag``."""
    return FsPath(run_dir) / ("run.bag" if fmt == "ros1" else "run_bag")


class _Msgs:
    """Builders of the message objects of one typestore (ROS 1 headers carry a seq)."""

    def __init__(self, ts: Any, ros1: bool) -> None:
        self.T = ts.types
        self.ros1 = ros1
        self._seq = 0

    def time(self, t: float) -> Any:
        ns = int(round(t * 1e9))
        return self.T["builtin_interfaces/msg/Time"](sec=ns // 1_000_000_000,
                                                     nanosec=ns % 1_000_000_000)

    def header(self, t: float, frame: str) -> Any:
        if self.ros1:
            self._seq += 1
            return self.T["std_msgs/msg/Header"](seq=self._seq, stamp=self.time(t),
                                                 frame_id=frame)
        return self.T["std_msgs/msg/Header"](stamp=self.time(t), frame_id=frame)

    def vec(self, x: float = 0.0, y: float = 0.0, z: float = 0.0) -> Any:
        return self.T["geometry_msgs/msg/Vector3"](x=float(x), y=float(y), z=float(z))

    def quat(self, yaw: float) -> Any:
        return self.T["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=math.sin(yaw / 2),
                                                      w=math.cos(yaw / 2))

    def pose(self, p: Pose2D) -> Any:
        return self.T["geometry_msgs/msg/Pose"](
            position=self.T["geometry_msgs/msg/Point"](x=float(p.x), y=float(p.y), z=0.0),
            orientation=self.quat(float(p.theta)))

    def twist(self, vx: float, vy: float, wz: float) -> Any:
        return self.T["geometry_msgs/msg/Twist"](linear=self.vec(vx, vy), angular=self.vec(z=wz))

    def odometry(self, t: float, p: Pose2D, v: Twist | None, frame: str, child: str) -> Any:
        v = v if v is not None else Twist()
        cov = np.zeros(36, np.float64)
        return self.T["nav_msgs/msg/Odometry"](
            header=self.header(t, frame), child_frame_id=child,
            pose=self.T["geometry_msgs/msg/PoseWithCovariance"](pose=self.pose(p),
                                                                 covariance=cov),
            twist=self.T["geometry_msgs/msg/TwistWithCovariance"](
                twist=self.twist(v.vx, v.vy, v.wz), covariance=cov.copy()))

    def transform(self, t: float, parent: str, child: str, p: Pose2D) -> Any:
        return self.T["geometry_msgs/msg/TransformStamped"](
            header=self.header(t, parent), child_frame_id=child,
            transform=self.T["geometry_msgs/msg/Transform"](
                translation=self.vec(p.x, p.y), rotation=self.quat(float(p.theta))))


class BagSink:
    """Recorder sink writing the run as a ROS bag (see the module docstring for the topics)."""

    def __init__(self, path: str | os.PathLike, fmt: str = "ros2", grid: Any = None) -> None:
        if fmt not in FORMATS:
            raise BagError(f"bag format {fmt!r}: choose one of {', '.join(FORMATS)}")
        self.path = FsPath(path)
        self.fmt = fmt
        self.grid = grid
        self.ts = typestore(fmt)
        self.m = _Msgs(self.ts, fmt == "ros1")
        self.counts: dict[str, int] = {}
        if self.path.exists():
            raise BagError(f"{self.path}: already exists; a bag is never overwritten")
        if fmt == "ros1":
            from rosbags.rosbag1 import Writer
            self.writer = Writer(self.path)
        else:
            from rosbags.rosbag2 import StoragePlugin, Writer
            plugin = StoragePlugin.MCAP if fmt == "ros2-mcap" else StoragePlugin.SQLITE3
            self.writer = Writer(self.path, version=9, storage_plugin=plugin)
        self.writer.open()
        self._conn: dict[str, Any] = {}
        self._last_scan = None

    def _write(self, topic: str, msgtype: str, msg: Any, t: float) -> None:
        conn = self._conn.get(topic)
        if conn is None:
            conn = self._conn[topic] = self.writer.add_connection(topic, msgtype,
                                                                  typestore=self.ts)
        data = (self.ts.serialize_ros1(msg, msgtype) if self.fmt == "ros1"
                else self.ts.serialize_cdr(msg, msgtype))
        self.writer.write(conn, int(round(t * 1e9)), data)
        self.counts[topic] = self.counts.get(topic, 0) + 1

    # ------------------------------------------------------------------ sink interface
    def start(self, header: dict[str, Any], executive: Any) -> None:
        io = getattr(executive, "io", None)
        mount = getattr(getattr(io, "laser", None), "mount", None)
        self.mount = mount if isinstance(mount, Pose2D) else Pose2D()
        self._static_done = False

    def tick(self, line: dict[str, Any], executive: Any) -> None:
        m, t = self.m, float(line["t"])
        if not self._static_done:
            self._static_done = True
            self._write("/tf_static", "tf2_msgs/msg/TFMessage", m.T["tf2_msgs/msg/TFMessage"](
                transforms=[m.transform(t, "base_link", "laser", self.mount)]), t)
            if self.grid is not None:
                self._write("/map", "nav_msgs/msg/OccupancyGrid", self._map(t), t)
        est = executive.robot.pose()
        odom = executive.last_odom
        op = odom.pose if odom is not None else est
        self._write("/odom", "nav_msgs/msg/Odometry",
                    m.odometry(t, op, odom.twist if odom is not None else None, "odom",
                               "base_link"), t)
        map_odom = est.compose(_inverse(op))
        self._write("/tf", "tf2_msgs/msg/TFMessage", m.T["tf2_msgs/msg/TFMessage"](
            transforms=[m.transform(t, "map", "odom", map_odom),
                        m.transform(t, "odom", "base_link", op)]), t)
        truth = executive.io.true_pose() if hasattr(executive.io, "true_pose") else None
        if truth is not None:
            self._write("/base_pose_ground_truth", "nav_msgs/msg/Odometry",
                        m.odometry(t, truth, None, "map", "base_link"), t)
        scan = executive.last_scan
        if scan is not None and scan is not self._last_scan:
            self._last_scan = scan
            self._write("/scan", "sensor_msgs/msg/LaserScan", self._scan(scan), float(scan.stamp))
        cmd = line.get("cmd") or [0.0, 0.0, 0.0]
        self._write("/cmd_vel", "geometry_msgs/msg/Twist", m.twist(*cmd), t)
        path = line.get("bb", {}).get("path")
        if isinstance(path, dict) and "path" in path:
            poses = [m.T["geometry_msgs/msg/PoseStamped"](header=m.header(t, "map"),
                                                          pose=m.pose(Pose2D(x, y, 0.0)))
                     for x, y in path["path"]]
            self._write("/plan", "nav_msgs/msg/Path",
                        m.T["nav_msgs/msg/Path"](header=m.header(t, "map"), poses=poses), t)

    def finish(self, footer: dict[str, Any]) -> None:
        pass

    def close(self) -> None:
        if self.writer is not None:
            self.writer.close()
            self.writer = None

    # ------------------------------------------------------------------ messages
    def _scan(self, s: LaserScan) -> Any:
        r = np.asarray(s.ranges, dtype=np.float32)
        return self.m.T["sensor_msgs/msg/LaserScan"](
            header=self.m.header(float(s.stamp), "laser"), angle_min=float(s.angle_min),
            angle_max=float(s.angle_max), angle_increment=float(s.angle_increment),
            time_increment=float(s.time_increment), scan_time=float(s.scan_time),
            range_min=float(s.range_min), range_max=float(s.range_max), ranges=r,
            intensities=np.zeros(0, np.float32))

    def _map(self, t: float) -> Any:
        g, T = self.grid, self.m.T
        d = np.asarray(g.data)
        data = np.where(d < 0, -1, np.clip(d, 0, 100)).astype(np.int8).ravel()
        info = T["nav_msgs/msg/MapMetaData"](
            map_load_time=self.m.time(t), resolution=float(g.resolution), width=int(g.width),
            height=int(g.height), origin=self.m.pose(g.origin))
        return T["nav_msgs/msg/OccupancyGrid"](header=self.m.header(t, "map"), info=info,
                                              data=data)


def _inverse(p: Pose2D) -> Pose2D:
    c, s = math.cos(p.theta), math.sin(p.theta)
    return Pose2D(-(c * p.x + s * p.y), -(-s * p.x + c * p.y), -p.theta)


def _yaw(q: Any) -> float:
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


@dataclass
class BagLog:
    """The scans, odometry and (when recorded) ground truth of a bag, in stamp order."""

    scans: list[LaserScan] = field(default_factory=list)
    odom_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    odom_poses: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    truth_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    truth_poses: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    laser_mount: Pose2D = field(default_factory=Pose2D)
    topics: dict[str, int] = field(default_factory=dict)
    source: str = ""

    @property
    def scan_times(self) -> np.ndarray:
        return np.array([s.stamp for s in self.scans], dtype=np.float64)


def read_bag(path: str | os.PathLike, scan_topic: str = "/scan", odom_topic: str = "/odom",
             truth_topic: str = "/base_pose_ground_truth") -> BagLog:
    """Read a ROS 1 bag, a rosbag2 folder (sqlite3 or MCAP) or a rosbag2 ``.mcap`` file."""
    typesys = _rosbags()
    from rosbags.highlevel import AnyReader
    p = FsPath(path)
    if not p.exists():
        raise BagError(f"{p}: no such bag")
    fallback = typesys.get_typestore(typesys.Stores.ROS2_HUMBLE)
    log = BagLog(source=str(p))
    odom_t: list[float] = []
    odom_p: list[tuple[float, float, float]] = []
    truth_t: list[float] = []
    truth_p: list[tuple[float, float, float]] = []
    try:
        with AnyReader([p], default_typestore=fallback) as reader:
            log.topics = {c.topic: c.msgcount for c in reader.connections}
            if scan_topic not in log.topics:
                raise BagError(f"{p}: no {scan_topic} topic (topics: "
                               f"{', '.join(sorted(log.topics)) or 'none'})")
            wanted = [c for c in reader.connections
                      if c.topic in (scan_topic, odom_topic, truth_topic, "/tf_static")]
            for conn, _stamp, raw in reader.messages(connections=wanted):
                msg = reader.deserialize(raw, conn.msgtype)
                if conn.topic == scan_topic:
                    h = msg.header.stamp
                    log.scans.append(LaserScan(
                        stamp=h.sec + h.nanosec * 1e-9, angle_min=float(msg.angle_min),
                        angle_max=float(msg.angle_max),
                        angle_increment=float(msg.angle_increment),
                        time_increment=float(msg.time_increment),
                        scan_time=float(msg.scan_time), range_min=float(msg.range_min),
                        range_max=float(msg.range_max),
                        ranges=np.asarray(msg.ranges, dtype=np.float32),
                        frame_id=msg.header.frame_id))
                elif conn.topic in (odom_topic, truth_topic):
                    h, q = msg.header.stamp, msg.pose.pose.orientation
                    pos = msg.pose.pose.position
                    (odom_t if conn.topic == odom_topic else truth_t).append(
                        h.sec + h.nanosec * 1e-9)
                    (odom_p if conn.topic == odom_topic else truth_p).append(
                        (float(pos.x), float(pos.y), _yaw(q)))
                else:
                    for tf in msg.transforms:
                        if tf.child_frame_id == (log.scans[0].frame_id if log.scans
                                                 else "laser"):
                            tr = tf.transform
                            log.laser_mount = Pose2D(float(tr.translation.x),
                                                     float(tr.translation.y),
                                                     _yaw(tr.rotation))
    except BagError:
        raise
    except Exception as e:  # noqa: BLE001 - rosbags' own errors: say which file
        raise BagError(f"{p}: cannot read bag ({type(e).__name__}: {e})") from None
    log.scans.sort(key=lambda s: s.stamp)
    if odom_t:
        order = np.argsort(odom_t, kind="stable")
        log.odom_times = np.asarray(odom_t)[order]
        log.odom_poses = np.asarray(odom_p)[order]
    if truth_t:
        order = np.argsort(truth_t, kind="stable")
        log.truth_times = np.asarray(truth_t)[order]
        log.truth_poses = np.asarray(truth_p)[order]
    return log


class BagPlayback(RecordedBase):
    """Plays a ``BagLog`` on the executive's clock through the ``Base`` and ``Laser``
    interfaces: ``scan()`` and ``odometry()`` return the newest message stamped at or before
    ``clock.now()``, or None before the first (as ``hw.logplayback.LogPlayback``)."""

    def __init__(self, log: BagLog, clock: Clock) -> None:
        if not log.scans:
            raise BagError(f"{log.source}: no scans to play")
        self.log = log
        self._clock = clock
        self._scan_times = log.scan_times
        self.mount = log.laser_mount
        self.time_offset = 0.0
        self.last_cmd: Twist | None = None

    def scan(self) -> LaserScan | None:
        k = int(np.searchsorted(self._scan_times, self._clock.now(), side="right")) - 1
        return self.log.scans[k] if k >= 0 else None

    @property
    def finished(self) -> bool:
        return self._clock.now() >= float(self._scan_times[-1])
