"""GlobalUpdatedGoal (Nav2 condition)."""

from __future__ import annotations

from behaviors.base import FAILURE, SUCCESS, PortInformation, Status
from behaviors.conditions.condition import Condition
from navcore.types import Pose2D


class GlobalUpdatedGoal(Condition):
    """SUCCESS when ``goal`` or ``goals`` differ from what this node saw on its previous tick.

    Unlike GoalUpdated, its memory outlives halts: only the very first tick of the node's life
    remembers the goals, and that tick returns SUCCESS (Nav2 ``GloballyUpdatedGoalCondition``,
    the same in every distribution). So a tree that asks "not updated?" replans once at start.
    """

    INPUT_PORTS = {
        "goal": PortInformation(Pose2D, False, "goal pose in map"),
        "goals": PortInformation(list, False, "list of Pose2D"),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"goal": "goal", "goals": "goals"}

    def __init__(self, *args, **kwargs) -> None:  # noqa: D107
        super().__init__(*args, **kwargs)
        self._first = True
        self._seen: tuple = (None, None)

    def update(self) -> Status:
        current = (self.read("goal"), _frozen(self.read("goals")))
        if self._first:
            self._first = False
            self._seen = current
            self.say("first tick: goals remembered")
            return SUCCESS
        if current != self._seen:
            self._seen = current
            self.say("goal changed")
            return SUCCESS
        return FAILURE

    def new_run(self) -> None:
        """A new navigation (the executive interrupts the tree): start afresh, as Nav2's
        navigator builds the node anew for each tree load."""
        self._first = True


def _frozen(goals: list | None) -> tuple | None:
    return None if goals is None else tuple(goals)
