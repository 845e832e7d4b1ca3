"""The run on Foxglove channels: ``run.mcap`` in a run folder and ``mission run --live``.

``FoxgloveSink`` is a Recorder sink. After each tick it logs, on a private ``foxglove.Context``,
Foxglove's well-known schemas (sim time stamps):

=================  ==========================  =============================================
topic              schema                      what
=================  ==========================  =============================================
/map               foxglove.Grid               the static map (0 free .. 100 occupied, 255 unknown)
/global_costmap    foxglove.Grid               costmap_2d values, when they change (<= 0.1 Hz)
/local_costmap     foxglove.Grid               costmap_2d values, 1 Hz
/scan              foxglove.LaserScan          every new scan, in the ``laser`` frame
/pose              foxglove.PoseInFrame        the estimated robot pose in ``map``
/plan              foxglove.PosesInFrame       the global path, when it changes
/particlecloud     foxglove.PosesInFrame       AMCL's particles (when AMCL runs), 2 Hz
/tf                foxglove.FrameTransforms    map->odom, odom->base_link; base_link->laser first
/behavior_tree     JSON                        every node's status when one changes
/cmd_vel           JSON                        the command sent to the base
/events            foxglove.Log                goals, recoveries (warning), faults and errors
=================  ==========================  =============================================

An MCAP writer (``run.mcap``) and a WebSocket server (``--live``, 127.0.0.1 by default) are sinks
of that context. Live, the sink paces the run to ``rate`` x real time, publishes the sim time,
re-sends the slow channels (map, costmaps) every few seconds for clients that join late, and
serves the run's parameters (``namespace.name``) as Foxglove parameters.
"""

from __future__ import annotations

import json
import math
import os
from typing import Any

import numpy as np

from navcore.clock import Clock, WallClock
from navcore.types import Pose2D, normalize_angle

from executive.errors import ExecutiveError
from executive.recorder import dumps

TOPICS = ("/map", "/global_costmap", "/local_costmap", "/scan", "/pose", "/plan",
          "/particlecloud", "/tf", "/behavior_tree", "/cmd_vel", "/events")
LIVE_RESEND_S = 2.0        # simulated seconds between re-sends of map and costmaps, live
# simulated seconds between checks of the global costmap in a recording: a big map is a few MB a
# message, and compressing those dominated the cost of run.mcap at shorter periods
GLOBAL_EVERY_S = 10.0
LOCAL_EVERY_S = 1.0        # simulated seconds between local costmaps
MAX_PARTICLES = 500


class FoxgloveUnavailable(ExecutiveError, ImportError):
    """foxglove-sdk is not installed."""


def _fox() -> Any:
    try:
        import foxglove
    except ImportError:
        raise FoxgloveUnavailable("foxglove-sdk is not installed: pip install 'navbt[foxglove]'"
                                  ) from None
    return foxglove


def _ns(t: float) -> int:
    return int(round(t * 1e9))


class FoxgloveSink:
    """Recorder sink logging the run to Foxglove channels; see the module docstring.

    ``mcap_path``: write an MCAP file. ``live``: serve a WebSocket on ``host:port`` (port 0
    picks a free one; ``port`` tells which after ``start``), paced to ``rate`` x real time
    (None: as fast as it runs)."""

    def __init__(self, *, mcap_path: str | os.PathLike | None = None, live: bool = False,
                 host: str = "127.0.0.1", port: int = 8765, rate: float | None = 1.0,
                 wall_clock: Clock | None = None, grid: Any = None) -> None:
        fox = _fox()
        from foxglove import channels as ch
        self._m = _messages()
        self.ctx = fox.Context()
        self.grid = grid
        self.rate = rate
        self.live = live
        self._wall = wall_clock
        self.counts = {t: 0 for t in TOPICS}
        c = self.ctx
        self.ch = {
            "/map": ch.GridChannel("/map", context=c),
            "/global_costmap": ch.GridChannel("/global_costmap", context=c),
            "/local_costmap": ch.GridChannel("/local_costmap", context=c),
            "/scan": ch.LaserScanChannel("/scan", context=c),
            "/pose": ch.PoseInFrameChannel("/pose", context=c),
            "/plan": ch.PosesInFrameChannel("/plan", context=c),
            "/particlecloud": ch.PosesInFrameChannel("/particlecloud", context=c),
            "/tf": ch.FrameTransformsChannel("/tf", context=c),
            "/behavior_tree": fox.Channel("/behavior_tree", context=c, schema=_TREE_SCHEMA),
            "/cmd_vel": fox.Channel("/cmd_vel", context=c, schema=_CMD_SCHEMA),
            "/events": ch.LogChannel("/events", context=c),
        }
        self.writer = None
        if mcap_path is not None:
            self.writer = fox.open_mcap(str(mcap_path), allow_overwrite=True, context=c)
        self.server = None
        self._params: dict[str, Any] = {}
        if live:
            from foxglove.websocket import Capability
            self.server = fox.start_server(
                name="navbt", host=host, port=port, context=c,
                capabilities=[Capability.Time, Capability.Parameters],
                server_listener=_parameter_listener(self))
        self._next = {"global": -math.inf, "local": -math.inf, "particles": -math.inf,
                      "resend": -math.inf}
        self._origin = _pose(self._m, Pose2D())
        self._last_scan = None
        self._last_global: np.ndarray | None = None
        self._status: list[str] = []
        self._t0_wall: float | None = None
        self._t0_sim = 0.0

    @property
    def port(self) -> int | None:
        return self.server.port if self.server is not None else None

    # ------------------------------------------------------------------ sink interface
    def start(self, header: dict[str, Any], executive: Any) -> None:
        self._nodes = header.get("nodes", [])
        self._status = ["INVALID"] * len(self._nodes)
        # /behavior_tree is every node each time one changes: its fixed part encoded once
        self._node_json = [f'{{"name":{dumps(n[0])},"type":{dumps(n[1])},'
                           f'"depth":{dumps(n[2])},"status":' for n in self._nodes]
        self._period = float(header.get("period") or 0.05)
        io = getattr(executive, "io", None)
        mount = getattr(getattr(io, "laser", None), "mount", None)
        self._mount = mount if isinstance(mount, Pose2D) else Pose2D()
        params = executive.components.get("parameters") or {}
        for ns, p in params.items():
            values = p.as_dict() if hasattr(p, "as_dict") else dict(p)
            for name, value in values.items():
                if isinstance(value, (bool, int, float, str)):
                    self._params[f"{ns}.{name}"] = value
        if self.server is not None:
            self.server.publish_parameter_values(self.parameters())

    def tick(self, line: dict[str, Any], executive: Any) -> None:
        t = float(line["t"])
        ns = _ns(t)
        m = self._m
        stamp = _stamp(m, ns)   # one per tick, shared by its messages
        if self.live:
            self._pace(t)
        comps = executive.components
        # fixed things (the map, the laser's mount) go out first, and again now and then live
        resend = t >= self._next["resend"]
        if resend:
            self._next["resend"] = t + LIVE_RESEND_S if self.live else math.inf
        if self.grid is not None and resend:
            self._log("/map", _occupancy_grid(self._m, self.grid, ns), ns)
        self._costmaps(comps, t, ns)
        est = executive.robot.pose()
        odom = executive.last_odom
        self._transforms(est, odom.pose if odom is not None else est, ns, stamp,
                         with_laser=resend)
        self._log("/pose", m.PoseInFrame(timestamp=stamp, frame_id="map", pose=_pose(m, est)),
                  ns)
        scan = executive.last_scan
        if scan is not None and scan is not self._last_scan:
            self._last_scan = scan
            self._scan(scan, ns)
        path = line.get("bb", {}).get("path")
        if isinstance(path, dict) and "path" in path:
            xy = path["path"]
            self._log("/plan", m.PosesInFrame(
                timestamp=stamp, frame_id="map",
                poses=_poses(m, [p[0] for p in xy], [p[1] for p in xy], [0.0] * len(xy))), ns)
        loc = comps.get("localizer")
        if loc is not None and t >= self._next["particles"]:
            parts = np.asarray(getattr(loc, "particles", np.zeros((0, 3))), dtype=np.float64)
            parts = parts[:: max(1, int(math.ceil(len(parts) / MAX_PARTICLES)))]
            self._log("/particlecloud", m.PosesInFrame(
                timestamp=stamp, frame_id="map",
                poses=_poses(m, parts[:, 0].tolist(), parts[:, 1].tolist(),
                             parts[:, 2].tolist())), ns)
            self._next["particles"] = t + 0.5
        changes = line.get("status")
        if changes or not self.counts["/behavior_tree"]:
            for i, s in (changes or {}).items():
                self._status[int(i)] = s
            # the bytes json.dumps of {"tick", "root", "nodes": [{name, type, depth, status}]}
            # gives, from the parts encoded at start
            nodes = ",".join([head + dumps(s) + "}"
                              for head, s in zip(self._node_json, self._status)])
            self._log_raw("/behavior_tree", f'{{"tick":{dumps(line["tick"])},'
                          f'"root":{dumps(line.get("root", ""))},"nodes":[{nodes}]}}', ns)
        cmd = line.get("cmd") or [0.0, 0.0, 0.0]
        self._log_raw("/cmd_vel", f'{{"linear_x":{_num(cmd[0])},"linear_y":{_num(cmd[1])},'
                                  f'"angular_z":{_num(cmd[2])}}}', ns)
        for e in line.get("events", ()):
            self._event(e, ns)
        if self.server is not None:
            self.server.broadcast_time(ns)

    def finish(self, footer: dict[str, Any]) -> None:
        if self.counts["/behavior_tree"] and footer:
            level = self._m.LogLevel.Info if footer.get("outcome") == "succeeded" \
                else self._m.LogLevel.Error
            ns = _ns(footer.get("time_s", 0.0) + self._t0_sim)
            self._log("/events", self._m.Log(
                timestamp=_stamp(self._m, ns), level=level, name="navbt",
                message=f"mission {footer.get('outcome')}: {footer.get('reason', '')}".strip()),
                ns)

    def close(self) -> None:
        if self.writer is not None:
            self.writer.close()
            self.writer = None
        if self.server is not None:
            self.server.stop()
            self.server = None

    # ------------------------------------------------------------------ parameters
    def parameters(self, names: list[str] | None = None) -> list[Any]:
        fox = _fox()
        keys = sorted(self._params) if not names else [n for n in names if n in self._params]
        return [fox.Parameter(k, value=self._params[k]) for k in keys]

    # ------------------------------------------------------------------ helpers
    def _pace(self, t: float) -> None:
        if not self.live or not self.rate:
            return
        wall = self._wall if self._wall is not None else WallClock()
        self._wall = wall
        if self._t0_wall is None:
            self._t0_wall, self._t0_sim = wall.now(), t
            return
        wall.sleep_until(self._t0_wall + (t - self._t0_sim) / self.rate)

    def _log(self, topic: str, msg: Any, ns: int) -> None:
        self.ch[topic].log(msg, log_time=ns)
        self.counts[topic] += 1

    def _log_json(self, topic: str, obj: dict[str, Any], ns: int) -> None:
        # encoded here, compactly: the SDK's own dict path cost several times more per message
        self._log_raw(topic, dumps(obj), ns)

    def _log_raw(self, topic: str, text: str, ns: int) -> None:
        self.ch[topic].log(text.encode("utf-8"), log_time=ns)
        self.counts[topic] += 1

    def _scan(self, scan: Any, ns: int) -> None:
        r = np.asarray(scan.ranges, dtype=np.float64)
        r = np.where(r < scan.range_max, r, 0.0)   # NaN, inf and max range: no return
        self._log("/scan", self._m.LaserScan(
            timestamp=_stamp(self._m, _ns(float(scan.stamp))), frame_id="laser",
            pose=self._origin, start_angle=float(scan.angle_min),
            end_angle=float(scan.angle_min + scan.angle_increment * (len(r) - 1)),
            ranges=r.tolist()), ns)

    def _costmaps(self, comps: dict[str, Any], t: float, ns: int) -> None:
        cm = comps.get("local_costmap")
        if cm is not None and t >= self._next["local"]:
            self._log("/local_costmap", _cost_grid(self._m, cm.costmap, ns), ns)
            self._next["local"] = t + LOCAL_EVERY_S
        cm = comps.get("global_costmap")
        if cm is not None and t >= self._next["global"]:
            costs = cm.costmap.costs
            if self.live or self._last_global is None or \
                    not np.array_equal(self._last_global, costs):
                self._log("/global_costmap", _cost_grid(self._m, cm.costmap, ns), ns)
                self._last_global = costs.copy()
            self._next["global"] = t + (LIVE_RESEND_S if self.live else GLOBAL_EVERY_S)

    def _transforms(self, est: Pose2D, odom: Pose2D, ns: int, stamp: Any,
                    with_laser: bool) -> None:
        m = self._m
        # map->odom corrects odometry drift: est = map_odom * odom
        tfs = [_tf_xyt(m, stamp, "map", "odom", *_map_odom(est, odom)),
               _tf(m, stamp, "odom", "base_link", odom)]
        if with_laser:
            tfs.append(_tf(m, stamp, "base_link", "laser", self._mount))
        self._log("/tf", m.FrameTransforms(transforms=tfs), ns)

    def _event(self, e: dict[str, Any], ns: int) -> None:
        m = self._m
        if "recovery" in e:
            level, text = m.LogLevel.Warning, (f"recovery {e['recovery']} ({e.get('type', '')}) "
                                               f"at {e.get('pose')}")
        elif "error" in e:
            level, text = m.LogLevel.Error, f"{e.get('node', '')}: {e['error']}"
        elif "fault" in e:
            level, text = m.LogLevel.Error, f"safety fault: {e['fault']}"
        elif "goal" in e:
            level, text = m.LogLevel.Info, f"goal {e['goal']}"
        elif "contact" in e:
            level, text = m.LogLevel.Error, f"contact at {e['contact']}"
        else:
            level, text = m.LogLevel.Info, json.dumps(e)
        self._log("/events", m.Log(timestamp=_stamp(m, ns), level=level, name="navbt",
                                   message=text), ns)


def _map_odom(est: Pose2D, odom: Pose2D) -> tuple[float, float, float]:
    """map->odom as (x, y, theta): est (+) odom^-1, written out (no Pose2D made per tick)."""
    c, s = math.cos(odom.theta), math.sin(odom.theta)
    ix, iy = -(c * odom.x + s * odom.y), -(-s * odom.x + c * odom.y)
    c, s = math.cos(est.theta), math.sin(est.theta)
    return (est.x + c * ix - s * iy, est.y + s * ix + c * iy,
            normalize_angle(est.theta + -odom.theta))


def _num(v: Any) -> str:
    """``v`` as json.dumps writes it (a finite float is its repr): a per-tick message built as
    text costs a fraction of a dict through the encoder."""
    if type(v) is float and v - v == 0.0:
        return float.__repr__(v)
    return dumps(v)


def _messages() -> Any:
    try:
        from foxglove import messages
    except ImportError:  # older SDKs name the module schemas
        from foxglove import schemas as messages  # type: ignore[no-redef]
    return messages


def _stamp(m: Any, ns: int) -> Any:
    return m.Timestamp(ns // 1_000_000_000, ns % 1_000_000_000)


def _quat(m: Any, yaw: float) -> Any:
    return m.Quaternion(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2))


def _pose(m: Any, p: Pose2D) -> Any:
    return m.Pose(position=m.Vector3(x=float(p.x), y=float(p.y), z=0.0),
                  orientation=_quat(m, float(p.theta)))


def _poses(m: Any, xs: list[float], ys: list[float], thetas: list[float]) -> list[Any]:
    """Poses as ``_pose`` builds them, for many at once (particles, paths)."""
    vec, quat, pose, sin, cos = m.Vector3, m.Quaternion, m.Pose, math.sin, math.cos
    return [pose(position=vec(x=float(x), y=float(y), z=0.0),
                 orientation=quat(x=0.0, y=0.0, z=sin(th / 2), w=cos(th / 2)))
            for x, y, th in zip(xs, ys, thetas)]


def _tf(m: Any, stamp: Any, parent: str, child: str, p: Pose2D) -> Any:
    return _tf_xyt(m, stamp, parent, child, p.x, p.y, p.theta)


def _tf_xyt(m: Any, stamp: Any, parent: str, child: str, x: float, y: float, theta: float
            ) -> Any:
    return m.FrameTransform(timestamp=stamp, parent_frame_id=parent, child_frame_id=child,
                            translation=m.Vector3(x=float(x), y=float(y), z=0.0),
                            rotation=_quat(m, float(theta)))


def _grid(m: Any, values: np.ndarray, res: float, ox: float, oy: float, ns: int,
          field: str) -> Any:
    rows, cols = values.shape
    return m.Grid(timestamp=_stamp(m, ns), frame_id="map",
                  pose=_pose(m, Pose2D(ox, oy, 0.0)), column_count=int(cols),
                  cell_size=m.Vector2(x=float(res), y=float(res)), row_stride=int(cols),
                  cell_stride=1,
                  fields=[m.PackedElementField(name=field, offset=0,
                                               type=m.PackedElementFieldNumericType.Uint8)],
                  data=np.ascontiguousarray(values, dtype=np.uint8).tobytes())


def _occupancy_grid(m: Any, grid: Any, ns: int) -> Any:
    d = np.asarray(grid.data)
    v = np.where(d < 0, 255, np.clip(d, 0, 100)).astype(np.uint8)
    return _grid(m, v, grid.resolution, grid.origin.x, grid.origin.y, ns, "occupancy")


def _cost_grid(m: Any, costmap: Any, ns: int) -> Any:
    return _grid(m, costmap.costs, costmap.resolution, costmap.origin_x, costmap.origin_y, ns,
                 "cost")


def _parameter_listener(sink: FoxgloveSink) -> Any:
    """A ServerListener answering parameter requests with the run's parameters (read-only:
    a set request gets the unchanged values back)."""
    from foxglove.websocket import ServerListener

    class Parameters(ServerListener):
        def on_get_parameters(self, client: Any, param_names: list[str],
                              request_id: str | None = None) -> list[Any]:
            return sink.parameters(param_names)

        def on_set_parameters(self, client: Any, parameters: list[Any],
                              request_id: str | None = None) -> list[Any]:
            return sink.parameters([p.name for p in parameters])

    return Parameters()


_TREE_SCHEMA = {
    "type": "object", "title": "navbt.BehaviorTreeStatus",
    "properties": {
        "tick": {"type": "integer"}, "root": {"type": "string"},
        "nodes": {"type": "array", "items": {"type": "object", "properties": {
            "name": {"type": "string"}, "type": {"type": "string"},
            "depth": {"type": "integer"}, "status": {"type": "string"}}}}}}
_CMD_SCHEMA = {
    "type": "object", "title": "navbt.Twist2D",
    "properties": {"linear_x": {"type": "number"}, "linear_y": {"type": "number"},
                   "angular_z": {"type": "number"}}}
