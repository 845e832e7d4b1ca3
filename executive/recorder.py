"""The tick log: one JSON line per control cycle, cheap enough to leave on.

The first line is a header (``{"header": {...}}``) listing the tree's nodes in pre-order as
``[name, type, depth]``; later lines refer to nodes by that index, so a run can be replayed
without reloading the tree. Each tick line holds only what changed: node statuses, blackboard
writes, plus the pose, the command sent, events (recoveries, faults, errors, contacts) and an
``overrun_ms`` when the tick took longer than its period.
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


class Recorder:
    """Writes the tick log to a text stream (or keeps nothing when ``stream`` is None)."""

    def __init__(self, stream: TextIO | None) -> None:
        self.stream = stream
        self._nodes: list[py_trees.behaviour.Behaviour] = []
        self._last_status: list[str] = []
        self.ticks = 0

    def start(self, root: py_trees.behaviour.Behaviour, meta: dict[str, Any]) -> None:
        """Write the header: node table and whatever the executive wants to keep (map, goals)."""
        self._nodes = []
        table = []
        for node, depth in walk(root):
            self._nodes.append(node)
            table.append([node.name, type(node).__name__, depth])
        self._last_status = [py_trees.common.Status.INVALID] * len(self._nodes)
        self._write({"header": dict(meta, nodes=table)})

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
        """Build (and write) one tick line; returns it (None without a stream: nothing to
        serialise, only the status bookkeeping is kept)."""
        status = self.status_changes()
        self.ticks += 1
        if self.stream is None:
            return None
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
            line["overrun_ms"] = round(overrun_ms, 3)
        self._write(line)
        return line

    def footer(self, summary: dict[str, Any]) -> None:
        self._write({"footer": summary})

    def _write(self, obj: dict[str, Any]) -> None:
        if self.stream is not None:
            self.stream.write(json.dumps(obj, separators=(",", ":")) + "\n")


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
