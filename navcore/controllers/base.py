"""What DWA and trajectory rollout share: the plan, the footprint, input checks, and the promise
that nothing raises out of the control loop."""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Any

import numpy as np

from navcore.costmap.costmap2d import Costmap2D
from navcore.costmap.footprint import parse_footprint
from navcore.params import Parameters
from navcore.types import Path, Pose2D, Twist

from navcore.controllers.map_grid import local_plan, prune_plan
from navcore.controllers.result import ControlResult, ControlStatus


class LocalPlannerBase:
    """Plan bookkeeping and the exception-safe ``compute_velocity`` wrapper.

    Subclasses set ``self.params`` and implement ``_compute(pose, velocity)``.
    """

    NAME = "LocalPlanner"
    params: Parameters

    def __init__(self, costmap: Costmap2D, footprint: np.ndarray) -> None:
        if not isinstance(costmap, Costmap2D):
            raise TypeError(f"{self.NAME}: costmap must be a Costmap2D, got {type(costmap).__name__}")
        self.costmap = costmap
        self.footprint = parse_footprint(footprint)
        self._plan = np.zeros((0, 3))      # the global plan (pruned in place when prune_plan)
        self._given: np.ndarray | None = None  # the poses as handed in, to spot a new plan
        self._last_pose: Pose2D | None = None
        self._last_vel = Twist()
        self._cycle_params: SimpleNamespace | None = None  # set while a cycle runs

    def _p(self) -> Any:
        """The parameter values: frozen for the running cycle (a parameter set from elsewhere
        mid-cycle cannot mix old and new values in one decision), else the live ones."""
        if self._cycle_params is not None:
            return self._cycle_params
        return self.params

    # --- plan ---------------------------------------------------------------------------------
    def set_plan(self, path: Path) -> None:
        """Take a new global plan (same frame as the pose); forget latches and oscillation flags."""
        poses = np.asarray(path.poses, dtype=np.float64).reshape(-1, 3)
        if not np.all(np.isfinite(poses)):
            raise ValueError(f"{self.NAME}.set_plan: the path has non-finite poses")
        self._given = poses
        self._plan = poses.copy()
        self._on_new_plan()

    def _on_new_plan(self) -> None:
        self.reset()

    def reset(self) -> None:  # overridden
        """Forget latched goal tolerance and oscillation flags."""

    def has_plan(self) -> bool:
        return len(self._plan) > 0

    def goal(self) -> Pose2D | None:
        """The last pose of the global plan, or None without a plan."""
        if len(self._plan) == 0:
            return None
        x, y, t = self._plan[-1]
        return Pose2D(float(x), float(y), float(t))

    def _local_plan(self, pose: Pose2D, prune: bool) -> np.ndarray:
        """The plan part inside the local costmap, after pruning what lies behind the robot."""
        if prune and len(self._plan):
            pruned = prune_plan(self._plan, pose.x, pose.y)
            if len(pruned):  # ROS keeps an all-far plan untouched until the robot gets near
                self._plan = pruned
        cm = self.costmap
        size_m = max(cm.size_x, cm.size_y) * cm.resolution
        return local_plan(self._plan, pose.x, pose.y, size_m)

    # --- the control loop entry -----------------------------------------------------------------
    def compute_velocity(self, pose: Pose2D, velocity: Twist, path: Path | None = None
                         ) -> ControlResult:
        """One control cycle: a command and a status (never a reason to raise for bad input:
        a non-finite pose, velocity or path gives a zero command and the reason). An exception
        is a bug and leaves the call (the executive ends the mission with INTERNAL_ERROR)."""
        if not all(math.isfinite(v) for v in (pose.x, pose.y, pose.theta)):
            return ControlResult(Twist.zero(), ControlStatus.NO_VALID_TRAJECTORY,
                                 reason=f"{self.NAME}: pose is not finite: {pose}")
        if not all(math.isfinite(v) for v in (velocity.vx, velocity.vy, velocity.wz)):
            return ControlResult(Twist.zero(), ControlStatus.NO_VALID_TRAJECTORY,
                                 reason=f"{self.NAME}: velocity is not finite: {velocity}")
        if path is not None:
            poses = np.asarray(path.poses, dtype=np.float64).reshape(-1, 3)
            # a path equal to the one given last passed this check then (NaN is never equal)
            if self._given is None or poses.shape != self._given.shape \
                    or not np.array_equal(poses, self._given):
                if not np.isfinite(poses).all():
                    return ControlResult(Twist.zero(), ControlStatus.NO_VALID_TRAJECTORY,
                                         reason=f"{self.NAME}: the path has non-finite poses")
                self.set_plan(path)
        self._last_pose, self._last_vel = pose, velocity
        if len(self._plan) == 0:
            return ControlResult(Twist.zero(), ControlStatus.NO_PLAN,
                                 reason=f"{self.NAME}: no plan")
        self._cycle_params = SimpleNamespace(**self.params.as_dict())
        try:
            return self._compute(pose, velocity)
        finally:
            self._cycle_params = None

    def _compute(self, pose: Pose2D, velocity: Twist) -> ControlResult:
        raise NotImplementedError

    def _costs(self) -> np.ndarray:
        return np.ascontiguousarray(self.costmap.costs, dtype=np.uint8)
