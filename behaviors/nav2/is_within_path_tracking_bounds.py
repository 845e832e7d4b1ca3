"""IsWithinPathTrackingBounds (Nav2 main condition)."""

from __future__ import annotations

from behaviors.base import FAILURE, SUCCESS, PortInformation, Status
from behaviors.conditions.condition import Condition
from navcore.path_ops import TrackingFeedback


class IsWithinPathTrackingBounds(Condition):
    """SUCCESS while FollowPath's ``tracking_feedback`` is within bounds: cross-track error
    at most ``max_error_left`` m (robot left of the path) or ``max_error_right`` m (right), and
    heading error at most ``max_error_heading`` rad (negative bounds count as their size).
    SUCCESS also while there is no feedback yet. (Nav2 main ``IsWithinPathTrackingBounds``.)"""

    INPUT_PORTS = {
        "max_error_left": PortInformation(float, False, "allowed error left of the path, m",
                                          0.5),
        "max_error_right": PortInformation(float, False, "allowed error right of the path, m",
                                           0.5),
        "max_error_heading": PortInformation(float, False, "allowed heading error, rad", 3.14),
        "tracking_feedback": PortInformation(TrackingFeedback, False,
                                             "FollowPath's tracking feedback"),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    DEFAULT_KEYS = {"tracking_feedback": "tracking_feedback"}

    def update(self) -> Status:
        fb = self.read("tracking_feedback")
        if fb is None:
            return SUCCESS
        err = fb.position_tracking_error
        bound = abs(self.get_input("max_error_left" if err >= 0.0 else "max_error_right"))
        ok = abs(err) <= bound and \
            abs(fb.heading_tracking_error) <= abs(self.get_input("max_error_heading"))
        if not ok:
            self.say("out of tracking bounds: {:.2f} m, {:.2f} rad", err,
                     fb.heading_tracking_error)
        return SUCCESS if ok else FAILURE
