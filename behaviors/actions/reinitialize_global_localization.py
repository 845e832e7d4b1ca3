"""ReinitializeGlobalLocalization (amcl's global_localization) and its navbt alias."""

from __future__ import annotations

from typing import Any

from behaviors.actions.recovery_action import RecoveryAction
from behaviors.base import FAILURE, SUCCESS, PortInformation, Status


class ReinitializeGlobalLocalization(RecoveryAction):
    """Ask the localiser to spread its particles over all free space (amcl's
    global_localization service). SUCCESS in one tick; FAILURE without a localiser."""

    INPUT_PORTS: dict[str, PortInformation] = {}
    OUTPUT_PORTS: dict[str, PortInformation] = {}
    NEEDS_ROBOT = False

    def setup(self, **kwargs: Any) -> None:
        super().setup(**kwargs)
        self.localizer = kwargs.get("localizer")

    def update(self) -> Status:
        if self.localizer is None:
            self.say("no localiser to reinitialise")
            return FAILURE
        self.localizer.global_localization()
        self.say("particles spread over the free space")
        return SUCCESS


class GlobalLocalization(ReinitializeGlobalLocalization):
    """navbt's plain name for ReinitializeGlobalLocalization (same node, same semantics)."""
