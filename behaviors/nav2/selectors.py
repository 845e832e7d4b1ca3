"""ProgressCheckerSelector, GoalCheckerSelector, PathHandlerSelector, SmootherSelector (Nav2
actions).

As PlannerSelector and ControllerSelector: the id asked for at run time (Nav2's topic becomes a
blackboard key) else the default, written to the selected-id output; SUCCESS.
"""

from __future__ import annotations

from behaviors.actions.selectors import Selector
from behaviors.base import PortInformation


def _ports(kind: str, default: str, topic: str) -> dict[str, PortInformation]:
    return {
        f"default_{kind}": PortInformation(str, False, f"{kind} id when none is requested",
                                           default),
        "requested": PortInformation(str, False, f"{kind} id asked for at run time"),
        "topic_name": PortInformation(str, False, "Nav2's topic; unused here", topic),
    }


class ProgressCheckerSelector(Selector):
    """Choose the progress checker id FollowPath uses (Nav2 ``ProgressCheckerSelector``)."""

    INPUT_PORTS = _ports("progress_checker", "progress_checker", "progress_checker_selector")
    OUTPUT_PORTS = {"selected_progress_checker": PortInformation(str, True,
                                                                 "the progress checker id")}
    DEFAULT_KEYS = {"requested": "progress_checker_selection",
                    "selected_progress_checker": "selected_progress_checker"}
    DEFAULT_PORT, OUTPUT_PORT = "default_progress_checker", "selected_progress_checker"


class GoalCheckerSelector(Selector):
    """Choose the goal checker id FollowPath uses (Nav2 ``GoalCheckerSelector``)."""

    INPUT_PORTS = _ports("goal_checker", "goal_checker", "goal_checker_selector")
    OUTPUT_PORTS = {"selected_goal_checker": PortInformation(str, True, "the goal checker id")}
    DEFAULT_KEYS = {"requested": "goal_checker_selection",
                    "selected_goal_checker": "selected_goal_checker"}
    DEFAULT_PORT, OUTPUT_PORT = "default_goal_checker", "selected_goal_checker"


class PathHandlerSelector(Selector):
    """Choose the path handler id FollowPath uses (Nav2 main ``PathHandlerSelector``)."""

    INPUT_PORTS = _ports("path_handler", "PathHandler", "path_handler_selector")
    OUTPUT_PORTS = {"selected_path_handler": PortInformation(str, True, "the path handler id")}
    DEFAULT_KEYS = {"requested": "path_handler_selection",
                    "selected_path_handler": "selected_path_handler"}
    DEFAULT_PORT, OUTPUT_PORT = "default_path_handler", "selected_path_handler"


class SmootherSelector(Selector):
    """Choose the smoother id SmoothPath uses (Nav2 ``SmootherSelector``)."""

    INPUT_PORTS = _ports("smoother", "simple_smoother", "smoother_selector")
    OUTPUT_PORTS = {"selected_smoother": PortInformation(str, True, "the smoother id")}
    DEFAULT_KEYS = {"requested": "smoother_selection", "selected_smoother": "selected_smoother"}
    DEFAULT_PORT, OUTPUT_PORT = "default_smoother", "selected_smoother"
