"""A navigation task: goals visited in turn by one Executive, and what it came to.

``Executive.run`` and the public API (executive/api.py) both drive missions through a ``Task``:
it sets each goal, reads the root's status after every cycle, moves to the next goal on
SUCCESS, and ends on FAILURE, the time limit, a cancel or a caller's stop. Ending stops the
robot (zero velocity) and writes the result as the run record's footer.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

from py_trees.common import Status

from navcore.motion.path_progress import remaining_length
from navcore.types import Path, Pose2D

OUTCOMES = ("succeeded", "failed", "timeout", "stopped", "canceled")


@dataclass
class MissionResult:
    """Outcome of a task: ``succeeded``, ``failed``, ``timeout``, ``stopped`` (by an
    ``on_tick``) or ``canceled``. Times, ticks, distance, recoveries and collisions are the
    task's own (a mission may run several tasks in turn)."""

    outcome: str
    goals_reached: int
    goals_total: int
    sim_time: float
    ticks: int
    distance: float
    recoveries: list[str]
    collisions: int
    reason: str = ""
    traceback: str = ""  # of the INTERNAL_ERROR that ended the mission, if one did

    @property
    def succeeded(self) -> bool:
        return self.outcome == "succeeded"

    def as_dict(self) -> dict[str, Any]:
        return {"outcome": self.outcome, "goals_reached": self.goals_reached,
                "goals_total": self.goals_total, "time_s": round(self.sim_time, 3),
                "ticks": self.ticks, "distance_m": round(self.distance, 3),
                "recoveries": list(self.recoveries), "collisions": self.collisions,
                "reason": self.reason, **({"traceback": self.traceback} if self.traceback else {})}


@dataclass(frozen=True)
class Feedback:
    """How a running task goes (nav2's NavigateToPose / FollowWaypoints feedback, as far as
    the executive knows it). ``distance_remaining``: along the current path from its pose
    nearest the robot, or straight to the goal when there is no path yet (m)."""

    current_pose: Pose2D
    goal: Pose2D
    current_waypoint: int
    distance_remaining: float
    navigation_time: float
    number_of_recoveries: int
    tree_status: str


class Task:
    """Drive ``executive`` to each of ``goals`` in turn, ending after ``time_limit`` s."""

    def __init__(self, executive: Any, goals: list[Pose2D], time_limit: float = math.inf
                 ) -> None:
        if not goals:
            raise ValueError("Task: no goals given")
        self.executive = executive
        self.goals = list(goals)
        self.time_limit = float(time_limit)
        self.index = 0
        self.reached = 0
        self.t0 = executive.clock.now()
        self.result: MissionResult | None = None
        # where the mission's trace stood: a task's result counts only what came after
        trace = executive.trace
        self._ticks0, self._poses0 = executive.tick_count, len(trace.poses)
        self._recoveries0, self._contacts0 = len(trace.recoveries), len(trace.contacts)
        executive.set_goal(self.goals[0])

    @property
    def done(self) -> bool:
        return self.result is not None

    def step(self, on_tick: Callable[[Any], bool | None] | None = None) -> bool:
        """One control cycle of the executive, then the task's own bookkeeping; True once the
        task has ended. ``on_tick(executive)`` returning True stops it (outcome ``stopped``)."""
        if self.result is not None:
            return True
        ex = self.executive
        status = ex.step()
        if on_tick is not None and on_tick(ex):
            self.finish("stopped", "stopped by caller")
        elif status is Status.SUCCESS:
            self.reached += 1
            self.index += 1
            if self.index < len(self.goals):
                ex.set_goal(self.goals[self.index])
            else:
                self.finish("succeeded")
        elif status is Status.FAILURE:
            self.finish("failed", ex.failure_reason())
        elif ex.clock.now() - self.t0 >= self.time_limit:
            self.finish("timeout", f"time limit {self.time_limit:g} s reached")
        return self.result is not None

    def update_goal(self, goal: Pose2D) -> None:
        """Replace the goal being driven to without restarting the tree, as Nav2's navigator
        takes a pre-empting goal: the new goal goes on the blackboard (``goal``, ``goals``)
        and the tree decides what to do about it (``GoalUpdated``)."""
        self.goals[self.index] = goal
        self.executive.handle.set("goal", goal)
        self.executive.handle.set("goals", [goal])

    def add_goal(self, goal: Pose2D) -> None:
        """Append a goal, visited after the others."""
        self.goals.append(goal)

    def run(self, on_tick: Callable[[Any], bool | None] | None = None) -> MissionResult:
        """Step until the task ends; its result."""
        while not self.step(on_tick):
            pass
        assert self.result is not None
        return self.result

    def finish(self, outcome: str, reason: str = "") -> MissionResult:
        """End the task: halt the tree, stop the robot, record the result."""
        ex = self.executive
        if ex.tree.root.status == Status.RUNNING:
            ex.tree.interrupt()
        ex.stop_robot()
        self.result = MissionResult(outcome, self.reached, len(self.goals),
                                    ex.clock.now() - self.t0, ex.tick_count - self._ticks0,
                                    ex.trace.distance(self._poses0),
                                    [r["recovery"] for r in
                                     ex.trace.recoveries[self._recoveries0:]],
                                    ex.collisions(self._contacts0), reason,
                                    ex.internal_error["traceback"] if ex.internal_error else "")
        ex.recorder.footer(self.result.as_dict())
        return self.result

    def feedback(self) -> Feedback:
        ex = self.executive
        pose = ex.robot.pose()
        goal = self.goals[min(self.index, len(self.goals) - 1)]
        return Feedback(pose, goal, self.index, _remaining(ex.blackboard_get("path"), pose, goal),
                        ex.clock.now() - self.t0,
                        len(ex.trace.recoveries) - self._recoveries0,
                        ex.tree.root.status.name)


def _remaining(path: Any, pose: Pose2D, goal: Pose2D) -> float:
    """Metres left: to the path's pose nearest the robot, then along the path to its end; the
    straight line to the goal before there is a path."""
    if not isinstance(path, Path) or len(path) == 0:
        return math.hypot(goal.x - pose.x, goal.y - pose.y)
    return remaining_length(path, pose)
