"""What a local planner hands back every control cycle."""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

import numpy as np

from navcore.types import Twist


class ControlStatus(StrEnum):
    """What one control cycle achieved; compares equal to its text. The failures map to Nav2
    FollowPath codes in ``navcore.error_codes.CONTROL_CODES``."""

    FOLLOWING = "following"
    ROTATING_TO_GOAL = "rotating_to_goal"
    GOAL_REACHED = "goal_reached"
    NO_VALID_TRAJECTORY = "no_valid_trajectory"  # every sample rejected, or a bad input
    NO_PLAN = "no_plan"



@dataclass
class ControlResult:
    """One cycle's outcome.

    ``cmd`` is the body velocity to send (zero unless ``status`` is following or
    rotating_to_goal). ``best`` is the chosen trajectory's poses (M, 3); ``trajectories`` every
    simulated trajectory (K, N, 3), NaN past each one's end; ``scores`` their costs (K,), negative
    for a rejected one (the ROS codes: -2 unreachable, -3 on an obstacle in a grid, -4 off the map,
    -5 oscillation, -6 footprint on a lethal or unknown cell, -7 footprint off the map; -1 the
    trajectory rollout planner's own "illegal"). ``samples`` holds the (K, 3) commanded velocities
    and ``reason`` says why, in words.
    """

    cmd: Twist
    status: ControlStatus
    best: np.ndarray | None = None
    trajectories: np.ndarray | None = None
    scores: np.ndarray | None = None
    samples: np.ndarray | None = None
    reason: str = ""

    @property
    def ok(self) -> bool:
        """True when the command moves the robot on purpose or the goal is reached."""
        return self.status in _OK


_OK = (ControlStatus.FOLLOWING, ControlStatus.GOAL_REACHED, ControlStatus.ROTATING_TO_GOAL)


def describe_rejections(scores: np.ndarray) -> str:
    """"12 off the map, 30 on lethal cells, ..." for a no-valid-trajectory message."""
    names = {-1: "illegal footprint", -2: "cut off from the path", -3: "over an obstacle",
             -4: "off the map", -5: "blocked by oscillation flags",
             -6: "footprint on a lethal or unknown cell", -7: "footprint off the map"}
    parts = []
    for code in sorted(names, reverse=True):
        n = int(np.sum(scores == code))
        if n:
            parts.append(f"{n} {names[code]}")
    return ", ".join(parts) if parts else "no samples"
