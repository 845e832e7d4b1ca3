"""Decorators: Nav2's throttles and goal handling, BT.CPP's retry/repeat/timeout family.

Every time-based decorator reads the injected ``clock`` (setup kwarg); none reads the system
clock, so Timeout, Delay and RateController run in simulated time.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import py_trees

from behaviors.base import (FAILURE, INVALID, RUNNING, SUCCESS, DecoratorNode, PortInformation,
                            Status, tick_child)
from navcore.types import Pose2D

Behaviour = py_trees.behaviour.Behaviour


class _Passthrough(DecoratorNode):
    """Tick the child every tick and map its status through ``convert``."""

    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def convert(self, status: Status) -> Status:
        raise NotImplementedError

    def tick_now(self) -> None:
        tick_child(self.decorated)
        self._finish(self.convert(self.decorated.status))


class Inverter(_Passthrough):
    """SUCCESS <-> FAILURE of the child; RUNNING passes through."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def convert(self, status: Status) -> Status:
        if status is SUCCESS:  # comparisons, not a dict: Enum hashes in Python
            return FAILURE
        return SUCCESS if status is FAILURE else status


class ForceSuccess(_Passthrough):
    """SUCCESS whenever the child finishes (either way); RUNNING passes through."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def convert(self, status: Status) -> Status:
        return RUNNING if status is RUNNING else SUCCESS


class ForceFailure(_Passthrough):
    """FAILURE whenever the child finishes (either way); RUNNING passes through."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def convert(self, status: Status) -> Status:
        return RUNNING if status is RUNNING else FAILURE


class _Rerun(DecoratorNode):
    """Run the child again each time it ends with ``RERUN_ON``, until it has done so
    ``LIMIT_PORT`` times in all (-1: forever); RUNNING in between, so the rerun starts on the next
    tick. Any other final status passes through. (Shared by RetryUntilSuccessful and Repeat.)
    """

    RERUN_ON: ClassVar[Status]
    LIMIT_PORT: ClassVar[str]
    FEEDBACK: ClassVar[str]  # said at each counted run: {n} runs so far, {limit}

    def tick_now(self) -> None:
        if self.status is not RUNNING:
            self._count = 0
        tick_child(self.decorated)
        status = self.decorated.status
        if status is self.RERUN_ON:
            self._count += 1
            limit = self.get_input(self.LIMIT_PORT)
            self.say(self.FEEDBACK.format(n=self._count, limit=limit))
            if limit < 0 or self._count < limit:
                self.decorated.stop(INVALID)
                status = RUNNING
        self._finish(status)


class RetryUntilSuccessful(_Rerun):
    """Run the child again after a failure, up to ``num_attempts`` attempts in all (-1: forever).

    SUCCESS as soon as the child succeeds; FAILURE after the last failed attempt. Unlike BT.CPP,
    a failed attempt is retried on the *next* tick (RUNNING in between), so a synchronous child
    that keeps failing cannot stall the control loop.
    """

    INPUT_PORTS = {"num_attempts": PortInformation(int, False, "attempts in all; -1 = forever", 1)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    RERUN_ON, LIMIT_PORT = FAILURE, "num_attempts"
    FEEDBACK = "attempt {n} of {limit} failed"


class Repeat(_Rerun):
    """Run the child ``num_cycles`` times in a row (-1: forever), one run per tick at most.

    RUNNING between runs; FAILURE as soon as a run fails; SUCCESS after the last success.
    """

    INPUT_PORTS = {"num_cycles": PortInformation(int, False, "successful runs; -1 = forever", 1)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    RERUN_ON, LIMIT_PORT = SUCCESS, "num_cycles"
    FEEDBACK = "cycle {n} of {limit} done"


class KeepRunningUntilFailure(DecoratorNode):
    """RUNNING while the child succeeds (it runs again next tick); FAILURE when it fails."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def tick_now(self) -> None:
        tick_child(self.decorated)
        status = self.decorated.status
        if status is SUCCESS:
            self.decorated.stop(INVALID)
            status = RUNNING
        self._finish(status)


class _Timed(DecoratorNode):
    """A decorator that needs the clock."""

    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def setup(self, **kwargs: Any) -> None:
        self.clock = self.component(kwargs, "clock")


class Timeout(_Timed):
    """FAILURE (child halted) if the child is still RUNNING ``msec`` milliseconds after it started.

    Otherwise the child's status. The clock starts on the first tick of a run.
    """

    INPUT_PORTS = {"msec": PortInformation(int, True, "time allowed, ms")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def tick_now(self) -> None:
        now = self.clock.now()
        if self.status is not RUNNING:
            self._deadline = now + self.get_input("msec") / 1000.0
        if now >= self._deadline:
            self.say("timed out")
            self._finish(FAILURE)
            return
        tick_child(self.decorated)
        self._finish(self.decorated.status)


class Delay(_Timed):
    """RUNNING for ``delay_msec`` milliseconds, then tick the child and return its status."""

    INPUT_PORTS = {"delay_msec": PortInformation(int, True, "delay before the child runs, ms")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def tick_now(self) -> None:
        now = self.clock.now()
        if self.status is not RUNNING:
            self._start_at = now + self.get_input("delay_msec") / 1000.0
        if now < self._start_at:
            self.say("waiting {:.2f} s", self._start_at - now)
            self._finish(RUNNING)
            return
        tick_child(self.decorated)
        self._finish(self.decorated.status)


class RateController(_Timed):
    """Tick the child at most ``hz`` times per second (Nav2 ``RateController``).

    The child is ticked on the first tick of a run, whenever it is RUNNING, and when ``1/hz``
    seconds passed since its last success; otherwise the child's last result is returned.
    ``hz: 0`` ticks it once per run (move_base's ``planner_frequency: 0``).
    """

    INPUT_PORTS = {"hz": PortInformation(float, False, "rate, Hz; 0 = once per run", 10.0)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def tick_now(self) -> None:
        now = self.clock.now()
        hz = self.get_input("hz")
        if self.status is INVALID:
            self._last_ok = -math.inf
            self._last_status = INVALID
        due = hz > 0.0 and now - self._last_ok >= 1.0 / hz - 1e-9  # float sums of periods
        if (self._last_status is INVALID or self.decorated.status is RUNNING or due):
            tick_child(self.decorated)
            self._last_status = self.decorated.status
            if self._last_status is SUCCESS:
                self._last_ok = now
        self._finish(self._last_status)


class _UsesRobot(DecoratorNode):
    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def setup(self, **kwargs: Any) -> None:
        self.clock = self.component(kwargs, "clock")
        self.robot = self.component(kwargs, "robot")


class DistanceController(_UsesRobot):
    """Tick the child each time the robot has travelled ``distance`` metres (Nav2).

    Also on the first tick of a run and while the child is RUNNING; otherwise the child's last
    result. Distance is straight-line from where the child last succeeded.
    """

    INPUT_PORTS = {"distance": PortInformation(float, False, "travel between ticks, m", 1.0)}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def tick_now(self) -> None:
        pose = self.robot.pose()
        if self.status is INVALID:
            self._last_status = INVALID
            self._anchor = pose
        far = pose.distance_to(self._anchor) >= self.get_input("distance")
        if self._last_status is INVALID or self.decorated.status is RUNNING or far:
            tick_child(self.decorated)
            self._last_status = self.decorated.status
            if self._last_status is SUCCESS:
                self._anchor = pose
        self._finish(self._last_status)


class SpeedController(_UsesRobot):
    """Tick the child at a rate that grows with the robot's speed (Nav2 ``SpeedController``).

    Rate = min_rate + (max_rate - min_rate) * (v - min_speed) / (max_speed - min_speed), clamped;
    first tick of a run, RUNNING child, or period elapsed tick the child.
    """

    INPUT_PORTS = {
        "min_rate": PortInformation(float, False, "rate at min_speed, Hz", 0.1),
        "max_rate": PortInformation(float, False, "rate at max_speed, Hz", 1.0),
        "min_speed": PortInformation(float, False, "speed giving min_rate, m/s", 0.0),
        "max_speed": PortInformation(float, False, "speed giving max_rate, m/s", 0.5),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def rate(self, speed: float) -> float:
        lo, hi = self.get_input("min_speed"), self.get_input("max_speed")
        r0, r1 = self.get_input("min_rate"), self.get_input("max_rate")
        f = 0.0 if hi <= lo else min(1.0, max(0.0, (speed - lo) / (hi - lo)))
        return r0 + (r1 - r0) * f

    def tick_now(self) -> None:
        now = self.clock.now()
        v = self.robot.velocity()
        rate = self.rate(math.hypot(v.vx, v.vy))
        if self.status is INVALID:
            self._last_status, self._last_ok = INVALID, -math.inf
        due = rate > 0.0 and now - self._last_ok >= 1.0 / rate - 1e-9
        if self._last_status is INVALID or self.decorated.status is RUNNING or due:
            tick_child(self.decorated)
            self._last_status = self.decorated.status
            if self._last_status is SUCCESS:
                self._last_ok = now
        self._finish(self._last_status)


class SingleTrigger(DecoratorNode):
    """Run the child once per activation; afterwards FAILURE until the parent resets this node.

    (Nav2 ``SingleTrigger``: e.g. one Spin per navigation attempt.)
    """

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def tick_now(self) -> None:
        if self.status is INVALID:
            self._fired = False
        if self._fired and self.decorated.status is not RUNNING:
            self._finish(FAILURE)
            return
        tick_child(self.decorated)
        if self.decorated.status is not RUNNING:
            self._fired = True
        self._finish(self.decorated.status)


class GoalUpdater(DecoratorNode):
    """Pass a newer goal on to the subtree: ``output_goal`` = ``goal_update`` if one arrived, else
    ``input_goal``; then tick the child and return its status (Nav2 ``GoalUpdater``).

    ``goal_update`` is the key an operator (or the executive) writes a replacement goal to.
    """

    INPUT_PORTS = {
        "input_goal": PortInformation(Pose2D, True, "the current goal"),
        "goal_update": PortInformation(Pose2D, False, "a replacement goal, if one arrived"),
    }
    OUTPUT_PORTS = {"output_goal": PortInformation(Pose2D, True, "goal the subtree should use")}
    DEFAULT_KEYS = {"input_goal": "goal", "goal_update": "goal_update", "output_goal": "goal"}

    def tick_now(self) -> None:
        update = self.read("goal_update")
        goal = update if update is not None else self.read("input_goal")
        if goal is not None:
            self.write("output_goal", goal)
        tick_child(self.decorated)
        self._finish(self.decorated.status)


class GoalUpdatedController(DecoratorNode):
    """Tick the child on the first tick of a run, while it is RUNNING, and whenever ``goal``
    changed; otherwise return the child's last result (Nav2 ``GoalUpdatedController``).

    Around ComputePathToPose this is move_base's ``planner_frequency: 0``: plan once, and again
    for a new goal.
    """

    INPUT_PORTS = {"goal": PortInformation(Pose2D, True, "the goal watched for changes")}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"goal": "goal"}

    def tick_now(self) -> None:
        goal = self.read("goal")
        if self.status is INVALID:
            self._last_status, self._goal = INVALID, goal
        changed = goal != self._goal
        self._goal = goal
        if self._last_status is INVALID or self.decorated.status is RUNNING or changed:
            if changed and self.decorated.status is RUNNING:
                self.halt_child()  # restart the child for the new goal
            tick_child(self.decorated)
            self._last_status = self.decorated.status
        self._finish(self._last_status)
