"""WouldARouteRecoveryHelp (Nav2 condition)."""

from __future__ import annotations

from behaviors.base import PortInformation
from behaviors.conditions.error_codes import WouldRecoveryHelp
from navcore.error_codes import ROUTE_RECOVERABLE


class WouldARouteRecoveryHelp(WouldRecoveryHelp):
    """SUCCESS when the last route error code is one a recovery can fix (Nav2 defaults:
    UNKNOWN, NO_VALID_ROUTE, TIMEOUT of ComputeRoute and ComputeAndTrackRoute)."""

    INPUT_PORTS = {
        "error_code": PortInformation(int, True, "ComputeRoute error code"),
        "error_codes_to_check": PortInformation(list, False, "codes a recovery may fix",
                                                ROUTE_RECOVERABLE),
    }
    DEFAULT_KEYS = {"error_code": "compute_route_error_code"}
