"""TransformAvailable (Nav2 condition)."""

from __future__ import annotations

from behaviors.base import FAILURE, SUCCESS, PortInformation, Status
from behaviors.conditions.condition import Condition

# The frames the executive keeps; it always knows how they relate.
FRAMES = frozenset({"map", "odom", "base_link", "base_footprint", "laser"})


class TransformAvailable(Condition):
    """SUCCESS when the transform from ``parent`` to ``child`` is known: both are frames of
    the executive (map, odom, base_link, base_footprint, laser), whose transforms always
    exist; FAILURE for any other frame (Nav2 ``TransformAvailable`` asks TF, and once it
    succeeds it keeps succeeding)."""

    INPUT_PORTS = {
        "child": PortInformation(str, False, "child frame", ""),
        "parent": PortInformation(str, False, "parent frame", ""),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        child, parent = self.get_input("child"), self.get_input("parent")
        if child in FRAMES and parent in FRAMES:
            return SUCCESS
        self.say(f"no transform {parent!r} -> {child!r}: navbt's frames are "
                 f"{', '.join(sorted(FRAMES))}")
        return FAILURE
