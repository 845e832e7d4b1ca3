"""The base of the planning actions (planner by id, error codes on every exit)."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, Leaf, PortInformation, Status
from navcore.error_codes import PLAN_CODES, PlannerError
from navcore.planners.result import PlanReason
from navcore.types import Path, Pose2D


class PlanningAction(Leaf):
    """Base of the planning actions: picks the planner by id and reports errors."""

    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]

    def setup(self, **kwargs: Any) -> None:
        self.robot = self.component(kwargs, "robot")
        self.planners = self.component(kwargs, "planners")

    def fail(self, code: PlannerError, msg: str) -> Status:
        self.write("error_code_id", int(code))
        self.write("error_msg", msg)
        self.say(msg)
        return FAILURE

    def planner(self) -> Any:
        return self.planners.get(self.get_input("planner_id"))

    def no_planner(self) -> Status:
        return self.fail(PlannerError.INVALID_PLANNER, f"no planner '{self.get_input('planner_id')}'")

    @staticmethod
    def plan(planner: Any, start: Pose2D, goal: Pose2D) -> tuple[Path | None, PlanReason]:
        """The planner's non-empty path and ``PlanReason.NONE``, or None and the planner's
        reason (``NO_PATH`` when a failure or an empty path names none). A reason given as its
        text becomes the enum; text that is no ``PlanReason`` is the planner's bug: ValueError."""
        result = planner.make_plan(start, goal)
        if result.ok and result.path is not None and len(result.path) > 0:
            return result.path, PlanReason.NONE
        try:
            reason = PlanReason(result.reason)
        except ValueError:
            raise ValueError(f"{type(planner).__name__}.make_plan: reason {result.reason!r} is "
                             f"not a PlanReason (one of "
                             f"{', '.join(repr(r.value) for r in PlanReason)})") from None
        return None, PlanReason.NO_PATH if reason is PlanReason.NONE else reason

    @staticmethod
    def code(reason: PlanReason) -> PlannerError:
        """The Nav2 code of a planner's reason (navcore.error_codes.PLAN_CODES, which maps
        every PlanReason)."""
        return PLAN_CODES[reason]

    def succeed(self, path: Path) -> Status:
        self.write("path", path)
        self.write("error_code_id", int(PlannerError.NONE))
        self.write("error_msg", "")
        return SUCCESS

    def start(self) -> Pose2D:
        if self.get_input("use_start"):
            start = self.read("start")
            if start is not None:
                return start
        return self.robot.pose()


PLAN_OUT = {
    "path": PortInformation(Path, True, "the plan, in map"),
    "error_code_id": PortInformation(int, False, "a PlannerError; 0 on success"),
    "error_msg": PortInformation(str, False, "why planning failed"),
}


PLAN_IN = {
    "start": PortInformation(Pose2D, False, "start pose (used when use_start)"),
    "use_start": PortInformation(bool, False, "plan from 'start' instead of the robot pose", False),
    "planner_id": PortInformation(str, False, "which planner (setup 'planners' key)", "GridBased"),
}
