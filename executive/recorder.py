"""The tick log: one JSON line per control cycle, cheap enough to leave on.

The first line is a header (``{"header": {...}}``) listing the tree's nodes in pre-order as
``[name, type, depth]``; later lines refer to nodes by that index, so a run can be replayed
without reloading the tree. Each tick line holds only what changed: node statuses, blackboard
writes, plus the pose, the command sent and events (recoveries, faults, errors, contacts).
Everything in it comes from the simulated clock and seeded generators, so the same seed gives a
byte-identical file. Wall-clock figures (``overrun_ms`` when a tick took longer than its period,
and the footer's count of them) are not deterministic and go to a separate ``timing`` stream
(``timing.jsonl`` in a run folder).
"""

from __future__ import annotations

import dataclasses
import enum
import json
import math
import operator
from typing import Any, Iterator, TextIO

import numpy as np
import py_trees

from navcore.types import Path, Pose2D, Twist

# Global paths are stored subsampled: enough to draw, small enough to log at every replan.
MAX_PATH_POINTS = 200

# json.dumps(obj, separators=(",", ":")) builds a new encoder per call; one shared encoder gives
# the same bytes for a fraction of the cost of a small line
dumps = json.JSONEncoder(separators=(",", ":")).encode


def walk(root: py_trees.behaviour.Behaviour) -> Iterator[tuple[py_trees.behaviour.Behaviour, int]]:
    """The tree in pre-order with depth (py_trees' own ``iterate`` is post-order)."""
    stack = [(root, 0)]
    while stack:
        node, depth = stack.pop()
        yield node, depth
        children = list(getattr(node, "children", []) or [])
        for child in reversed(children):
            stack.append((child, depth + 1))


def to_jsonable(value: Any) -> Any:
    """A JSON-friendly rendering of a blackboard value (poses and twists as short lists)."""
    kind = type(value)
    if kind is Pose2D:  # the usual values first: one type test each
        return [round(value.x, 4), round(value.y, 4), round(value.theta, 4)]
    if kind is Twist:
        return [round(value.vx, 4), round(value.vy, 4), round(value.wz, 4)]
    if kind is float:
        return round(value, 4) if math.isfinite(value) else str(value)
    if value is None or isinstance(value, (bool, int, str)):
        return value
    if isinstance(value, float):
        return round(value, 4) if math.isfinite(value) else str(value)
    if isinstance(value, Pose2D):
        return [round(value.x, 4), round(value.y, 4), round(value.theta, 4)]
    if isinstance(value, Twist):
        return [round(value.vx, 4), round(value.vy, 4), round(value.wz, 4)]
    if isinstance(value, Path):
        return {"path": subsample_path(value.poses)}
    if isinstance(value, enum.Enum):
        return value.name
    if isinstance(value, np.ndarray):
        if value.size <= 16:
            return np.round(value.astype(float), 4).tolist()
        return {"array": list(value.shape), "dtype": str(value.dtype)}
    if isinstance(value, np.generic):
        return to_jsonable(value.item())
    if isinstance(value, (list, tuple)):
        if len(value) > 8:  # long histories (pose_history) would dominate the log: summarise
            return {"len": len(value), "last": to_jsonable(value[-1])}
        return [to_jsonable(v) for v in value]
    if isinstance(value, dict):
        return {str(k): to_jsonable(v) for k, v in list(value.items())[:50]}
    if dataclasses.is_dataclass(value):
        return {f.name: to_jsonable(getattr(value, f.name)) for f in dataclasses.fields(value)}
    return repr(value)[:200]


def subsample_path(poses: np.ndarray) -> list[list[float]]:
    poses = np.asarray(poses, dtype=float).reshape(-1, 3)
    if len(poses) > MAX_PATH_POINTS:
        idx = np.linspace(0, len(poses) - 1, MAX_PATH_POINTS).round().astype(int)
        poses = poses[idx]
    return np.round(poses[:, :2], 3).tolist()


_ABSENT = object()
_STATUS = operator.attrgetter("status")


def _same(a: Any, b: Any) -> bool:
    """Cheap change test: identity for arrays and paths, equality for small values."""
    if a is b:
        return True
    if isinstance(a, (np.ndarray, Path)) or isinstance(b, (np.ndarray, Path)):
        return False
    try:
        return bool(a == b)
    except Exception:  # noqa: BLE001 - exotic __eq__; treat as changed
        return False


class BlackboardWatcher:
    """Reports the blackboard keys under one namespace whose values changed since last call."""

    def __init__(self, namespace: str) -> None:
        self.prefix = namespace.rstrip("/") + "/"
        self._last: dict[str, Any] = {}
        self._keys: list[str] = []
        self._short: list[str] = []
        self._last_values: list[Any] = []  # self._last's values in the order of self._keys
        self._seen_size = -1

    def changes(self) -> dict[str, Any]:
        storage = py_trees.blackboard.Blackboard.storage
        if len(storage) != self._seen_size:  # keys come and go rarely: rescan only then
            n = len(self.prefix)
            self._keys = [k for k in storage if k.startswith(self.prefix)]
            self._short = [k[n:] for k in self._keys]
            self._last_values = [self._last.get(s, _ABSENT) for s in self._short]
            self._seen_size = len(storage)
        get = storage.get
        values = [get(k, _ABSENT) for k in self._keys]
        out: dict[str, Any] = {}
        last_values = self._last_values
        for i, value in enumerate(values):
            old = last_values[i]
            if old is value or value is _ABSENT:
                continue
            if old is not _ABSENT and _same(old, value):
                continue
            short = self._short[i]
            last_values[i] = self._last[short] = out[short] = value
        return out


class NodeStatsVisitor(py_trees.visitors.VisitorBase):
    """Counts, per node, the ticks, SUCCESS and FAILURE results and the ticks spent RUNNING,
    and keeps the last failure that propagated: a leaf that failed with its parent failing in
    the same tick, up to the highest ancestor that failed (where the failure was caught).
    A py_trees visitor: it sees each node as it finishes its tick."""

    def __init__(self, nodes: list[py_trees.behaviour.Behaviour], period: float) -> None:
        super().__init__(full=False)
        self.period = period
        self._index = {id(n): i for i, n in enumerate(nodes)}
        self._parent = [self._index.get(id(n.parent), -1) if n.parent is not None else -1
                        for n in nodes]
        self._leaf = [not getattr(n, "children", None) for n in nodes]
        self.counts = [[0, 0, 0, 0] for _ in nodes]  # ticks, success, failure, running
        self.last_failure: list[int] | None = None   # root-first chain of node indices
        self.last_failure_tick = -1
        self._failed: list[int] = []
        self._tick = -1

    def initialise(self) -> None:
        self._failed = []
        self._tick += 1

    def run(self, behaviour: py_trees.behaviour.Behaviour) -> None:
        i = self._index.get(id(behaviour))
        if i is None:
            return
        row = self.counts[i]
        row[0] += 1
        s = behaviour.status
        if s is _SUCCESS:
            row[1] += 1
        elif s is _FAILURE:
            row[2] += 1
            self._failed.append(i)
        elif s is _RUNNING:
            row[3] += 1

    def finalise(self) -> None:
        if not self._failed:
            return
        failed = set(self._failed)
        best: list[int] = []
        for i in self._failed:
            if not self._leaf[i]:
                continue
            chain, p = [i], self._parent[i]
            while p >= 0 and p in failed:
                chain.append(p)
                p = self._parent[p]
            if len(chain) > len(best):
                best = chain
        if len(best) >= 2:
            self.last_failure = best[::-1]
            self.last_failure_tick = self._tick

    def as_lists(self) -> list[list[float]]:
        """``[ticks, successes, failures, running_s]`` per node in pre-order."""
        return [[a, b, c, round(d * self.period, 3)] for a, b, c, d in self.counts]


_SUCCESS = py_trees.common.Status.SUCCESS
_FAILURE = py_trees.common.Status.FAILURE
_RUNNING = py_trees.common.Status.RUNNING


class Recorder:
    """Writes the tick log to a text stream (or keeps nothing when ``stream`` is None).

    ``sinks`` see every tick too (the run's MCAP file, the live Foxglove server, the replay
    page's data): each has ``start(header, executive)``, ``tick(line, executive)`` and
    ``finish(footer)``."""

    def __init__(self, stream: TextIO | None, sinks: list[Any] | None = None,
                 timing: TextIO | None = None) -> None:
        self.stream = stream
        self.timing = timing  # wall-clock figures: kept apart, they differ run to run
        self.sinks = list(sinks or [])
        self.sink_errors: list[str] = []  # sinks dropped after raising, with why
        self._nodes: list[py_trees.behaviour.Behaviour] = []
        self._last_status: list[str] = []
        self.ticks = 0
        self.overruns = 0  # ticks longer than their period (wall clock): timing stream only
        self.node_stats: NodeStatsVisitor | None = None
        self._executive: Any = None

    @property
    def active(self) -> bool:
        """Whether anything is kept (a log stream or a sink)."""
        return self.stream is not None or bool(self.sinks)

    def attach(self, executive: Any) -> None:
        """Called by the Executive that owns this recorder: per-node statistics come from a
        visitor on its tree, and sinks read its components (scans, costmaps, particles)."""
        self._executive = executive
        if not self.active:
            return  # nothing kept: no visitor either, the unrecorded tick stays lean
        nodes = [n for n, _ in walk(executive.tree.root)]
        self.node_stats = NodeStatsVisitor(nodes, float(getattr(executive, "period", 0.0)))
        executive.tree.visitors.append(self.node_stats)

    def start(self, root: py_trees.behaviour.Behaviour, meta: dict[str, Any]) -> None:
        """Write the header: node table and whatever the executive wants to keep (map, goals)."""
        self._nodes = []
        table = []
        for node, depth in walk(root):
            self._nodes.append(node)
            table.append([node.name, type(node).__name__, depth])
        self._last_status = [py_trees.common.Status.INVALID] * len(self._nodes)
        header = dict(meta, nodes=table)
        self._write({"header": header})
        self._to_sinks("start", header, self._executive)

    def node_index(self, node: py_trees.behaviour.Behaviour) -> int:
        for i, n in enumerate(self._nodes):
            if n is node:
                return i
        return -1

    def status_changes(self) -> dict[str, str]:
        statuses = list(map(_STATUS, self._nodes))
        last = self._last_status
        if statuses == last:  # the usual tick: one C-level comparison, members by identity
            return {}
        self._last_status = statuses
        return {str(i): s.name for i, (s, old) in enumerate(zip(statuses, last)) if s is not old}

    def record(self, tick: int, t: float, pose: Pose2D | None, cmd: Twist,
               bb: dict[str, Any], events: list[dict[str, Any]], overrun_ms: float | None,
               root_status: py_trees.common.Status) -> dict[str, Any] | None:
        """Build (and write) one tick line; returns it (None without a stream or a sink:
        nothing is kept, not even which statuses changed)."""
        self.ticks += 1
        if self.stream is None and not self.sinks:
            return None
        status = self.status_changes()
        line: dict[str, Any] = {"tick": tick, "t": round(t, 4), "root": root_status.name}
        if status:
            line["status"] = status
        if bb:
            line["bb"] = {k: to_jsonable(v) for k, v in bb.items()}
        if pose is not None:
            line["pose"] = to_jsonable(pose)
        line["cmd"] = to_jsonable(cmd)
        if events:
            line["events"] = events
        if overrun_ms is not None:
            self.overruns += 1
            if self.timing is not None:
                self.timing.write(dumps({"tick": tick, "overrun_ms": round(overrun_ms, 3)})
                                  + "\n")
        self._write(line)
        if self.sinks:
            self._to_sinks("tick", line, self._executive)
        return line

    def footer(self, summary: dict[str, Any]) -> None:
        if self.node_stats is not None:
            summary = dict(summary, node_stats=self.node_stats.as_lists(),
                           last_failure=self.node_stats.last_failure,
                           last_failure_tick=self.node_stats.last_failure_tick)
        self._write({"footer": summary})
        if self.timing is not None:
            self.timing.write(dumps({"footer": {"ticks": self.ticks,
                                                "overruns": self.overruns}}) + "\n")
        self._to_sinks("finish", summary)

    def _to_sinks(self, method: str, *args: Any) -> None:
        """Call ``method`` on every sink; one that raises (a full disk, a broken viewer) is
        dropped and the reason kept, and the run goes on: recording never stops the robot."""
        for sink in list(self.sinks):
            try:
                getattr(sink, method)(*args)
            except Exception as e:  # noqa: BLE001 - a recording fault must not end the run
                self.sinks.remove(sink)
                self.sink_errors.append(f"{type(sink).__name__}.{method}: "
                                        f"{type(e).__name__}: {e}")
                close = getattr(sink, "close", None)
                if close is not None:
                    try:
                        close()
                    except Exception:  # noqa: BLE001 - already failing; keep the first reason
                        pass

    def close(self) -> None:
        """Close the log stream and every sink that holds a file or a server."""
        if self.stream is not None:
            self.stream.close()
        if self.timing is not None:
            self.timing.close()
        for sink in self.sinks:
            close = getattr(sink, "close", None)
            if close is not None:
                close()

    def _write(self, obj: dict[str, Any]) -> None:
        if self.stream is not None:
            self.stream.write(dumps(obj) + "\n")


def read_log(path: str) -> tuple[dict[str, Any], list[dict[str, Any]], dict[str, Any] | None]:
    """Header, tick lines and footer (None if the run did not finish) of a ticks.jsonl file."""
    header: dict[str, Any] = {}
    ticks: list[dict[str, Any]] = []
    footer = None
    with open(path, encoding="utf-8") as f:
        for n, raw in enumerate(f, 1):
            raw = raw.strip()
            if not raw:
                continue
            try:
                obj = json.loads(raw)
            except json.JSONDecodeError as e:
                raise ValueError(f"{path}:{n}: not a JSON line ({e.msg})") from None
            if "header" in obj:
                header = obj["header"]
            elif "footer" in obj:
                footer = obj["footer"]
            else:
                ticks.append(obj)
    if not header:
        raise ValueError(f"{path}: no header line; is this a navbt ticks.jsonl?")
    return header, ticks, footer


def statuses_at(header: dict[str, Any], ticks: list[dict[str, Any]], tick: int) -> list[str]:
    """Every node's status after tick ``tick`` (replaying the recorded changes)."""
    status = ["INVALID"] * len(header["nodes"])
    for line in ticks:
        if line["tick"] > tick:
            break
        for i, s in line.get("status", {}).items():
            status[int(i)] = s
    return status
