"""GoalUpdater (Nav2)."""

from __future__ import annotations

from behaviors.base import DecoratorNode, PortInformation, Ticking
from navcore.types import Pose2D


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

    def tick(self) -> Ticking:
        self.begin_tick()
        update = self.read("goal_update")
        goal = update if update is not None else self.read("input_goal")
        if goal is not None:
            self.write("output_goal", goal)
        yield from self.decorated.tick()
        yield self.finish(self.decorated.status)
