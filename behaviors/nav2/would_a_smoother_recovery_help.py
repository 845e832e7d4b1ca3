"""WouldASmootherRecoveryHelp (Nav2 condition)."""

from __future__ import annotations

from behaviors.base import PortInformation
from behaviors.conditions.error_codes import WouldRecoveryHelp
from navcore.error_codes import SMOOTHER_RECOVERABLE


class WouldASmootherRecoveryHelp(WouldRecoveryHelp):
    """SUCCESS when the last SmoothPath error code is one a recovery can fix (Nav2 defaults:
    UNKNOWN, TIMEOUT, FAILED_TO_SMOOTH_PATH, SMOOTHED_PATH_IN_COLLISION)."""

    INPUT_PORTS = {
        "error_code": PortInformation(int, True, "SmoothPath error code"),
        "error_codes_to_check": PortInformation(list, False, "codes a recovery may fix",
                                                SMOOTHER_RECOVERABLE),
    }
    DEFAULT_KEYS = {"error_code": "smoother_error_code"}
