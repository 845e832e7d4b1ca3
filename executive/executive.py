"""The Executive: one object owning the components, the tree, the clock, the safety gate and the
recorder, running the control cycle of docs/architecture.md.

One cycle (``Executive.step``) calls, in order: the robot I/O (``hw.interfaces.RobotIO``; the
adapters are in executive/robot_io.py) to **sense**; ``Perception`` (executive/perception.py) to
**estimate** the pose (AMCL) and **perceive** (feed scans to the costmaps and update those due);
the tree (py_trees, loaded by executive/tree_loader.py; the components it calls are the ``Stack``
of executive/stack.py) to **decide**; the ``SafetyGate`` (executive/safety.py) and the base to
**act**; the ``Recorder`` (executive/recorder.py) to **record**; the clock to **wait**.
``executive/mission.py`` wires these from a config; ``executive/api.py`` is the public face.

An exception raised in a tick, in localisation or in a costmap update is a bug, not a navigation
failure: the mission ends with INTERNAL_ERROR (where, the traceback in the tick record and the
summary) and the robot stops; a fault of the robot I/O while sensing stops the robot for that
tick and the loop carries on. Each Executive keeps its blackboard keys under its own namespace,
so two missions in one process never see each other's goal or path.
"""

from __future__ import annotations

import itertools
import math
import operator
import traceback
from types import TracebackType
from dataclasses import dataclass, field
from typing import Any, Callable

import py_trees
from py_trees.common import Status

from behaviors.base import FAILURE, Recovery
from hw.interfaces import BaseEvents, BatteryState, RobotIO
from navcore.clock import Clock, WallClock
from navcore.types import LaserScan, Odometry, Path, Pose2D, Twist

from executive.perception import Perception
from executive.recorder import BlackboardWatcher, Recorder, subsample_path, walk
from executive.safety import SafetyGate, Watchdog
from executive.task import MissionResult, Task
from executive.tree_loader import LoadedTree

_mission_ids = itertools.count(1)
_STARTS = operator.attrgetter("recovery_starts")


def new_namespace() -> str:
    """A blackboard namespace no other mission of this process has (``/mission_N``)."""
    return f"/mission_{next(_mission_ids)}"


class LiveRobotState:
    """RobotState for behaviours: the executive refreshes it once per cycle (sense/estimate)."""

    def __init__(self) -> None:
        self._pose = Pose2D()
        self._velocity = Twist()
        self._battery: BatteryState | None = None
        self._events = BaseEvents()

    def pose(self) -> Pose2D:
        return self._pose

    def velocity(self) -> Twist:
        return self._velocity

    def battery(self) -> BatteryState | None:
        return self._battery

    def events(self) -> BaseEvents:
        return self._events

    def update(self, pose: Pose2D, velocity: Twist, battery: BatteryState | None,
               events: BaseEvents) -> None:
        """This cycle's robot state (the executive's estimate phase)."""
        self._pose, self._velocity, self._battery, self._events = pose, velocity, battery, events


@dataclass
class Trace:
    """What happened during a mission, kept in memory for pictures and summaries."""

    times: list[float] = field(default_factory=list)
    poses: list[tuple[float, float, float]] = field(default_factory=list)
    paths: list[tuple[float, list[list[float]]]] = field(default_factory=list)
    recoveries: list[dict[str, Any]] = field(default_factory=list)
    contacts: list[dict[str, Any]] = field(default_factory=list)
    faults: dict[str, int] = field(default_factory=dict)
    errors: list[dict[str, Any]] = field(default_factory=list)
    overruns: int = 0
    goals: list[tuple[float, float, float]] = field(default_factory=list)

    def distance(self, first: int = 0) -> float:
        """Metres driven from pose ``first`` on (a task's share of the mission)."""
        d = 0.0
        for (x0, y0, _), (x1, y1, _) in zip(self.poses[first:], self.poses[first + 1:]):
            d += math.hypot(x1 - x0, y1 - y0)
        return d


_LIFECYCLE = ("initialise", "update", "terminate", "stop")


def failing_node(e: BaseException) -> tuple[py_trees.behaviour.Behaviour | None, str]:
    """The tree node whose method raised ``e`` (the innermost node on the traceback) and the
    method the tick called on it (``update``, ``initialise``...); (None, "tick") when no node
    method is on the traceback."""
    node, where = None, "tick"
    tb: TracebackType | None = e.__traceback__
    while tb is not None:
        owner = tb.tb_frame.f_locals.get("self")
        if isinstance(owner, py_trees.behaviour.Behaviour):
            name = tb.tb_frame.f_code.co_name
            if owner is not node:
                node, where = owner, name
            elif where not in _LIFECYCLE and name in _LIFECYCLE:  # py_trees' tick -> update
                where = name
        tb = tb.tb_next
    return node, where


class Executive:
    """Runs one behaviour tree against one robot, one control period per tick.

    ``components`` are the keyword arguments of ``tree.setup`` (see behaviors.components); the
    executive adds ``clock``, ``robot``, ``control_period`` and ``blackboard_namespace``.
    ``perception`` estimates the ``map`` pose and updates the costmaps (None: the pose is the
    robot I/O's ground truth, else its odometry, and nothing updates costmaps).
    """

    def __init__(self, tree: LoadedTree | py_trees.trees.BehaviourTree, io: RobotIO, clock: Clock,
                 control_period: float, components: dict[str, Any] | None = None, *,
                 safety: SafetyGate | None = None, recorder: Recorder | None = None,
                 perception: Perception | None = None,
                 namespace: str | None = None, meta: dict[str, Any] | None = None,
                 wall_clock: Clock | None = None) -> None:
        if control_period <= 0:
            raise ValueError(f"Executive: control_period must be > 0, got {control_period}")
        if isinstance(tree, LoadedTree):
            if namespace is not None and namespace.rstrip("/") != tree.namespace:
                raise ValueError(f"Executive: namespace {namespace!r} is not the tree's "
                                 f"{tree.namespace!r}")
            namespace = tree.namespace
        self.namespace = namespace or new_namespace()
        # the tree handle (blackboard keys of the mission) and the py_trees manager it holds
        self.handle = tree if isinstance(tree, LoadedTree) else LoadedTree.of(tree, self.namespace)
        self.tree = self.handle.tree
        self.io = io
        self.clock = clock
        self.period = float(control_period)
        self.components = dict(components or {})
        self.safety = safety if safety is not None else SafetyGate(require_laser=io.laser is not None)
        self.recorder = recorder if recorder is not None else Recorder(None)
        self.perception = perception
        self.robot = LiveRobotState()
        self.trace = Trace()
        self.tick_count = 0
        self.last_cmd = Twist.zero()
        self._meta = dict(meta or {})
        # only to measure overruns, never to decide anything
        self._wall = wall_clock if wall_clock is not None else WallClock()
        self._events: list[dict[str, Any]] = []
        self.handle.set("cmd_vel", None)
        self._watcher = BlackboardWatcher(self.namespace)
        # recovery nodes and the starts seen so far (each start is a "recovery fired" event)
        self._recoveries = [n for n in self.tree.root.iterate() if isinstance(n, Recovery)]
        self._recovery_starts = [n.recovery_starts for n in self._recoveries]
        kwargs = dict(self.components)
        kwargs.update(clock=clock, robot=self.robot, control_period=self.period,
                      blackboard_namespace=self.namespace)
        self.tree.setup(**kwargs)
        self._last_scan: LaserScan | None = None
        self._last_odom: Odometry | None = None
        # On a wall clock a stalled cycle is a fault: the gate sees the last cycle's length and a
        # watchdog thread stops the base while a cycle hangs. A simulated clock waits for us.
        self._on_wall = isinstance(clock, WallClock)
        self._last_act_wall: float | None = None
        self._watchdog: Watchdog | None = None
        self._started = False
        self.internal_error: dict[str, Any] | None = None  # the error event of a bug
        self.recorder.attach(self)

    @property
    def last_scan(self) -> LaserScan | None:
        """The newest laser scan sensed (recorders and viewers read it; behaviours do not)."""
        return self._last_scan

    @property
    def last_odom(self) -> Odometry | None:
        """The newest odometry sensed (recorders and viewers read it; behaviours do not)."""
        return self._last_odom

    # --- what the nodes did ------------------------------------------------------------------
    def _note_recoveries(self) -> None:
        """An event for each recovery node that started a run in this tick."""
        starts = list(map(_STARTS, self._recoveries))  # the usual tick: none, one C loop
        seen = self._recovery_starts
        if starts == seen:
            return
        self._recovery_starts = starts
        for i, node in enumerate(self._recoveries):
            if starts[i] != seen[i]:
                p = self.robot.pose()
                event = {"recovery": node.name, "type": type(node).__name__,
                         "t": round(self.clock.now(), 3), "pose": [round(p.x, 3), round(p.y, 3)]}
                self._events.append(event)
                self.trace.recoveries.append(event)

    def _error(self, node: Any, where: str, e: BaseException) -> None:
        name = getattr(node, "name", str(node))
        # keys named in messages are made relative to the mission, as in the tick records
        ns = self.namespace + "/"
        event = {"error": f"{type(e).__name__}: {e}".replace(ns, ""), "node": name, "in": where,
                 "t": round(self.clock.now(), 3),
                 "traceback": "".join(traceback.format_exception(e)).rstrip().replace(ns, "")}
        self._events.append(event)
        self.trace.errors.append(event)

    def _internal_error(self, node: Any, where: str, e: BaseException) -> None:
        """A bug: the error event becomes ``internal_error``; the mission ends, the robot stops
        and the tree is not ticked again."""
        self._error(node, where, e)
        self.internal_error = self.trace.errors[-1]

    # --- goals --------------------------------------------------------------------------------
    def set_goal(self, goal: Pose2D, goals: list[Pose2D] | None = None) -> None:
        """Start a new goal: the tree restarts from scratch with ``goal`` on the blackboard."""
        self.handle.set("goal", goal)
        self.handle.set("goals", list(goals) if goals is not None else [goal])
        self.handle.set("path", None)
        if self.tree.root.status != Status.INVALID:
            self.tree.interrupt()
        self.trace.goals.append((goal.x, goal.y, goal.theta))
        self._events.append({"goal": [goal.x, goal.y, goal.theta]})

    def blackboard_get(self, key: str, default: Any = None) -> Any:
        """A mission-level blackboard key, ``default`` if unset."""
        return self.handle.get(key, default)

    # --- the cycle (docs/architecture.md) ------------------------------------------------------
    def step(self) -> Status:
        """Run one control cycle and return the root's status after the tick."""
        if not self._started:
            self._start_recording()
        wall0 = self._wall.now()
        now = self.clock.now()
        pose = self.robot.pose()
        errors: list[str] = []  # a phase that raises stops the robot for this cycle
        try:
            self._sense(now)
        except Exception as e:  # noqa: BLE001 - a device fault stops the robot, not the loop
            self._error("executive", "sense", e)
            errors.append("sense")
        phase = "estimate"
        try:
            pose = self._estimate()
            phase = "perceive"
            self._perceive(pose, now)
        except Exception as e:  # noqa: BLE001 - a bug in localisation or the costmaps
            self._internal_error("executive", phase, e)
            errors.append(phase)
        requested = self._decide() if self.internal_error is None else Twist.zero()
        cmd = self._act(requested, now, errors)
        status = self.tree.root.status if self.internal_error is None else FAILURE
        self._record(now, pose, cmd, status, wall0)
        self._wait(now)
        return status

    def _start_recording(self) -> None:
        # not the namespace: it is /mission_N, N counting this process's earlier missions, and
        # the records depend on the scenario, tree, config and seed only (their keys are relative)
        self.recorder.start(self.tree.root, dict(self._meta, period=self.period))
        self._started = True

    def _sense(self, now: float) -> None:
        """The robot I/O up to ``now``; keep the newest odometry and scan."""
        self.io.step_to(now)
        odom = self.io.base.odometry()
        if odom is not None:
            self._last_odom = odom
        if self.io.laser is not None:
            scan = self.io.laser.scan()
            if scan is not None:
                self._last_scan = scan

    def _estimate(self) -> Pose2D:
        """The pose in ``map``: the localiser's, else ground truth, else odometry, else the last
        one; the behaviours' RobotState follows."""
        pose = None
        if self.perception is not None:
            pose = self.perception.estimate(self._last_odom, self._last_scan)
        if pose is None:
            pose = self.io.true_pose()
        if pose is None and self._last_odom is not None:
            pose = self._last_odom.pose
        pose = pose if pose is not None else self.robot.pose()
        base = self.io.base
        self.robot.update(pose, self._last_odom.twist if self._last_odom is not None else Twist(),
                          base.battery(), base.events())
        return pose

    def _perceive(self, pose: Pose2D, now: float) -> None:
        if self.perception is not None:
            self.perception.perceive(pose, self._last_scan, now)

    def _decide(self) -> Twist | None:
        """Tick the tree once; the ``cmd_vel`` written during this tick, None if none was or
        the tick raised (a bug: ``internal_error`` is set, the tree interrupted)."""
        try:
            return self.handle.tick_command()
        except Exception as e:  # noqa: BLE001 - a bug: INTERNAL_ERROR, the robot stops
            node, where = failing_node(e)
            self._internal_error(node if node is not None else "tree", where, e)
            try:
                self.tree.interrupt()
            except Exception:  # noqa: BLE001
                pass
            return None
        finally:
            if self._recoveries:
                self._note_recoveries()

    def _act(self, requested: Twist | None, now: float, errors: list[str] | None = None
             ) -> Twist:
        """Pass the request through the safety gate and send what it lets through."""
        scan, odom, trace = self._last_scan, self._last_odom, self.trace
        cycle = None
        if self._on_wall:
            wall = self._wall.now()
            if self._last_act_wall is not None:
                cycle = (wall - self._last_act_wall) / self.period
            self._last_act_wall = wall
        gate = self.safety.filter(
            requested, now,
            scan_stamp=scan.stamp if scan is not None else None,
            odom_stamp=odom.stamp if odom is not None else None,
            measured=odom.twist if odom is not None else None,
            bumper=self.robot.events().bumper, scan=scan, odom=odom, errors=errors or (),
            cycle_periods=cycle)
        for f in gate.faults:
            trace.faults[f] = trace.faults.get(f, 0) + 1
            self._events.append({"fault": f})
        cmd = gate.cmd
        try:
            self.io.base.send(cmd)
        except Exception as e:  # noqa: BLE001
            self._error("base", "send", e)
        self.last_cmd = cmd
        if self._on_wall:
            self._kick_watchdog()
        return cmd

    def _kick_watchdog(self) -> None:
        timeout = self.safety.params.watchdog_periods * self.period
        if self._watchdog is None:
            self._watchdog = Watchdog(timeout, self._watchdog_stop)
        self._watchdog.timeout = timeout
        self._watchdog.kick()

    def _watchdog_stop(self) -> None:
        """From the watchdog thread while a cycle hangs: zero velocity, noted for the record."""
        self.io.base.send(Twist.zero())
        self.last_cmd = Twist.zero()

    def _record(self, now: float, pose: Pose2D, cmd: Twist, status: Status,
                wall0: float) -> None:
        """The trace (pose, contacts, paths) and one tick record."""
        trace, io = self.trace, self.io
        truth = io.true_pose()
        drawn = truth if truth is not None else pose
        trace.times.append(now)
        trace.poses.append((drawn.x, drawn.y, drawn.theta))
        if io.in_collision():
            if not trace.contacts or now - trace.contacts[-1]["t"] > 1.0:
                self._events.append({"contact": [round(drawn.x, 3), round(drawn.y, 3)]})
            trace.contacts.append({"t": now, "pose": [drawn.x, drawn.y, drawn.theta]})
        bb = self._watcher.changes()
        if bb:
            path = bb.get("path")
            if isinstance(path, Path) and len(path):
                trace.paths.append((now, subsample_path(path.poses)))
        elapsed = self._wall.now() - wall0
        overrun = None
        if elapsed > self.period:
            overrun = 1000.0 * elapsed
            trace.overruns += 1
        self.recorder.record(self.tick_count, now, pose, cmd, bb, self._events, overrun, status)
        self._events = []
        self.tick_count += 1

    def _wait(self, now: float) -> None:
        """One period on the clock: a simulated clock jumps, a wall clock sleeps."""
        self.clock.sleep_until(now + self.period)

    def stop_robot(self) -> None:
        try:
            self.io.base.send(Twist.zero())
        except Exception as e:  # noqa: BLE001
            self._error("base", "send", e)

    def run(self, goals: list[Pose2D], time_limit: float = 600.0,
            on_tick: Callable[[Executive], bool | None] | None = None) -> MissionResult:
        """Drive to each goal in turn until the tree fails, time runs out or all succeed.

        ``on_tick`` is called after every cycle (progress display, scripted events); returning
        True stops the mission (outcome ``stopped``).
        """
        if not goals:
            raise ValueError("Executive.run: no goals given")
        return Task(self, goals, time_limit).run(on_tick)

    def collisions(self, first: int = 0) -> int:
        """Distinct contact episodes from contact ``first`` on (contacts more than 1 s apart
        count separately)."""
        n, last = 0, -math.inf
        for c in self.trace.contacts[first:]:
            if c["t"] - last > 1.0:
                n += 1
            last = c["t"]
        return n

    def failure_reason(self) -> str:
        """Why the tree failed: a bug's INTERNAL_ERROR, the last error, else an error key on
        the blackboard."""
        if self.internal_error is not None:
            e = self.internal_error
            return f"INTERNAL_ERROR in '{e['node']}' ({e['in']}): {e['error']}"
        if self.trace.errors:
            e = self.trace.errors[-1]
            return f"{e['node']}: {e['error']}"
        for key in ("error_msg", "error_code_id", "follow_path_error_code",
                    "compute_path_error_code"):
            v = self.blackboard_get(key)
            if v:
                return f"{key}={v}"
        return "tree returned FAILURE"

    def shutdown(self) -> None:
        """Stop the robot and release the tree (its behaviours' shutdown hooks)."""
        if self._watchdog is not None:
            self._watchdog.close()
        self.stop_robot()
        try:
            self.tree.shutdown()
        except Exception as e:  # noqa: BLE001
            self._error("tree", "shutdown", e)
        storage = py_trees.blackboard.Blackboard.storage
        for key in [k for k in storage if k.startswith(self.namespace + "/")]:
            del storage[key]


def node_statuses(root: py_trees.behaviour.Behaviour) -> dict[str, str]:
    """name -> status of every node (handy in tests)."""
    return {n.name: n.status.name for n, _ in walk(root)}
