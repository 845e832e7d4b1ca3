"""NavigateThroughPoses: Nav2's plan-through-poses-and-follow pipeline as one node."""

from __future__ import annotations

from typing import Any

from behaviors.actions.compute_path_through_poses import ComputePathThroughPoses
from behaviors.actions.follow_path import FollowPath
from behaviors.base import Control, Port, PortInformation, Ticking, namespaced
from behaviors.controls.pipeline_sequence import PipelineSequence
from behaviors.decorators.rate_controller import RateController


class NavigateThroughPoses(Control):
    """Plan through ``goals`` in order and follow the path, replanning at ``replan_hz`` (a
    subtree, as navbt's NavigateToPose; Nav2's node asks another navigator to do this).

    Inside: PipelineSequence[RateController(hz)[ComputePathThroughPoses], FollowPath].
    SUCCESS when FollowPath reaches the last pose; FAILURE with the failing child's error code
    on the blackboard (``compute_path_error_code`` / ``follow_path_error_code``).
    """

    INPUT_PORTS = {
        "goals": PortInformation(list, True, "poses to pass, Pose2D in map, in order"),
        "replan_hz": Port(float, False, "replanning rate, Hz; 0 = plan once", 1.0, low=0.0),
        "planner_id": PortInformation(str, False, "planner id", "GridBased"),
        "controller_id": PortInformation(str, False, "controller id", "FollowPath"),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"goals": "goals"}
    MIN_CHILDREN = 0
    MAX_CHILDREN = 0

    def __init__(self, name: str = "", children: Any = None, **kwargs: Any) -> None:
        base = name or "NavigateThroughPoses"
        self._plan = ComputePathThroughPoses(name=f"{base}.ComputePathThroughPoses")
        self._rate = RateController(name=f"{base}.RateController", child=self._plan)
        self._follow = FollowPath(name=f"{base}.FollowPath")
        self._pipe = PipelineSequence(name=f"{base}.Pipeline", children=[self._rate, self._follow])
        super().__init__(name=name, children=[self._pipe], **kwargs)

    def wire(self, namespace: str, refs: dict[str, str] | None = None,
             literals: dict[str, Any] | None = None) -> None:
        super().wire(namespace, refs, literals)
        lit = self._literals
        goals_ref = {} if "goals" in lit else {"goals": self.port_key("goals")}
        goals_lit = {"goals": lit["goals"]} if "goals" in lit else {}
        self._plan.wire(namespace, goals_ref, {**goals_lit,
                                               "planner_id": self.get_input("planner_id")})
        self._rate.wire(namespace, {}, {"hz": self.get_input("replan_hz")})
        self._follow.wire(namespace, {"path": namespaced(namespace, "path")},
                          {"controller_id": self.get_input("controller_id")})
        self._pipe.wire(namespace)

    def tick_children(self) -> Ticking:
        yield from self._pipe.tick()
        return self._pipe.status
