"""NavigateToPose: Nav2's plan-and-follow pipeline packaged as one node (a fixed subtree)."""

from __future__ import annotations

from typing import Any

from behaviors.actions.compute_path_to_pose import ComputePathToPose
from behaviors.actions.follow_path import FollowPath
from behaviors.base import Control, Port, PortInformation, namespaced, Ticking
from behaviors.controls.pipeline_sequence import PipelineSequence
from behaviors.decorators.rate_controller import RateController
from navcore.types import Pose2D


class NavigateToPose(Control):
    """Plan to ``goal`` and follow the path, replanning at ``replan_hz`` (a subtree).

    Inside: PipelineSequence[RateController(hz)[ComputePathToPose], FollowPath]. SUCCESS when
    FollowPath reaches the goal; FAILURE with the failing child's error code on the blackboard
    (``compute_path_error_code`` / ``follow_path_error_code``). It has no children of its own.
    """

    INPUT_PORTS = {
        "goal": PortInformation(Pose2D, True, "goal pose in map"),
        "replan_hz": Port(float, False, "replanning rate, Hz; 0 = plan once", 1.0, low=0.0),
        "planner_id": PortInformation(str, False, "planner id", "GridBased"),
        "controller_id": PortInformation(str, False, "controller id", "FollowPath"),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"goal": "goal"}
    MIN_CHILDREN = 0
    MAX_CHILDREN = 0
    # what NavigateThroughPoses changes: the planning node and the port its goal arrives on
    PLANNER: type = ComputePathToPose
    GOAL_PORT = "goal"

    def __init__(self, name: str = "", children: Any = None, **kwargs: Any) -> None:
        base = name or type(self).__name__
        self._plan = self.PLANNER(name=f"{base}.{self.PLANNER.__name__}")
        self._rate = RateController(name=f"{base}.RateController", child=self._plan)
        self._follow = FollowPath(name=f"{base}.FollowPath")
        self._pipe = PipelineSequence(name=f"{base}.Pipeline", children=[self._rate, self._follow])
        super().__init__(name=name, children=[self._pipe], **kwargs)

    def wire(self, namespace: str, refs: dict[str, str] | None = None,
             literals: dict[str, Any] | None = None, private_tag: str | None = None) -> None:
        super().wire(namespace, refs, literals, private_tag)
        tag = self.private_tag  # the inner nodes' names differ, so their private keys do too
        lit = self._literals
        g = self.GOAL_PORT
        goal_ref = {} if g in lit else {g: self.port_key(g)}
        goal_lit = {g: lit[g]} if g in lit else {}
        self._plan.wire(namespace, goal_ref, {**goal_lit,
                                              "planner_id": self.get_input("planner_id")}, tag)
        self._rate.wire(namespace, {}, {"hz": self.get_input("replan_hz")}, tag)
        self._follow.wire(namespace, {"path": namespaced(namespace, "path")},
                          {"controller_id": self.get_input("controller_id")}, tag)
        self._pipe.wire(namespace, private_tag=tag)

    def tick(self) -> Ticking:
        self.begin_tick()
        yield from self._pipe.tick()
        yield self.finish(self._pipe.status)
