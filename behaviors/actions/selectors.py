"""PlannerSelector and ControllerSelector: choose a component id (Nav2)."""

from __future__ import annotations

from behaviors.base import SUCCESS, Leaf, PortInformation, Status


class Selector(Leaf):
    """Write the requested component id (or the default) to the selected-id output. SUCCESS."""

    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation]
    DEFAULT_PORT = ""
    OUTPUT_PORT = ""

    def update(self) -> Status:
        chosen = self.read("requested") or self.get_input(self.DEFAULT_PORT)
        self.write(self.OUTPUT_PORT, chosen)
        self.say(f"selected '{chosen}'")
        return SUCCESS


class PlannerSelector(Selector):
    """Choose the planner id for ComputePathToPose: ``requested`` if someone wrote it, else
    ``default_planner`` (Nav2 ``PlannerSelector``; the topic becomes the blackboard key
    ``planner_selection``)."""

    INPUT_PORTS = {
        "default_planner": PortInformation(str, False, "planner id when none is requested",
                                           "GridBased"),
        "requested": PortInformation(str, False, "planner id asked for at run time"),
        "topic_name": PortInformation(str, False, "Nav2's topic; unused here", "planner_selector"),
    }
    OUTPUT_PORTS = {"selected_planner": PortInformation(str, True, "the planner id to use")}
    DEFAULT_KEYS = {"requested": "planner_selection", "selected_planner": "selected_planner"}
    DEFAULT_PORT, OUTPUT_PORT = "default_planner", "selected_planner"


class ControllerSelector(Selector):
    """Choose the controller id for FollowPath: ``requested`` if someone wrote it, else
    ``default_controller`` (Nav2 ``ControllerSelector``; the topic becomes the blackboard key
    ``controller_selection``)."""

    INPUT_PORTS = {
        "default_controller": PortInformation(str, False, "controller id when none is requested",
                                              "FollowPath"),
        "requested": PortInformation(str, False, "controller id asked for at run time"),
        "topic_name": PortInformation(str, False, "Nav2's topic; unused here",
                                      "controller_selector"),
    }
    OUTPUT_PORTS = {"selected_controller": PortInformation(str, True, "the controller id to use")}
    DEFAULT_KEYS = {"requested": "controller_selection",
                    "selected_controller": "selected_controller"}
    DEFAULT_PORT, OUTPUT_PORT = "default_controller", "selected_controller"
