"""The progress checker (Nav2's SimpleProgressChecker): has the robot moved at least
``required_movement_radius`` metres within the last ``movement_time_allowance`` seconds?

One checker for every user: FollowPath (FAILED_TO_MAKE_PROGRESS), the recoveries that drive
somewhere (a stuck robot gives up early), IsStuck and IsOscillating.
"""

from __future__ import annotations

from navcore.types import Pose2D


class ProgressChecker:
    """The baseline is the pose where the robot last was after moving the radius (or where it
    was at ``reset``); the robot is stalled once it has stayed within the radius of it for
    longer than the allowance. The radius and the allowance are passed on each check (they are
    live parameters of the callers). Callers whose allowance 0 means "no check" (FollowPath,
    the recoveries) skip the call then."""

    def __init__(self) -> None:
        self.baseline: Pose2D | None = None
        self.since = 0.0  # when the baseline was set, s

    def reset(self, pose: Pose2D | None = None, now: float = 0.0) -> None:
        """Start again from ``pose`` at ``now`` (None: from wherever the next check finds it)."""
        self.baseline, self.since = pose, now

    def stalled(self, pose: Pose2D, now: float, radius: float, allowance: float) -> bool:
        """Check ``pose`` at ``now``: False (and a new baseline) once it has moved ``radius``
        from the baseline; True when it has not, for more than ``allowance`` seconds."""
        if self.baseline is None or pose.distance_to(self.baseline) >= radius:
            self.reset(pose, now)
            return False
        return now - self.since > allowance
