"""AreErrorCodesPresent and WouldA{Planner,Controller}RecoveryHelp (Nav2)."""

from __future__ import annotations

from behaviors.base import FAILURE, PortInformation, Status
from behaviors.conditions.condition import Condition, yes
from navcore.error_codes import CONTROLLER_RECOVERABLE, PLANNER_RECOVERABLE


class WouldRecoveryHelp(Condition):
    INPUT_PORTS: dict[str, PortInformation]
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        code = self.read("error_code")
        if code is None:
            self.say("no error code yet")
            return FAILURE
        helps = int(code) in self.get_input("error_codes_to_check")
        self.say(f"error code {code}: a recovery {'may' if helps else 'would not'} help")
        return yes(helps)


class AreErrorCodesPresent(Condition):
    """SUCCESS when ``error_code`` is one of ``error_codes_to_check`` (Nav2)."""

    INPUT_PORTS = {
        "error_code": PortInformation(int, True, "an error code key"),
        "error_codes_to_check": PortInformation(list, True, "codes to look for"),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def update(self) -> Status:
        code = self.read("error_code")
        return yes(code is not None and int(code) in self.get_input("error_codes_to_check"))


class WouldAPlannerRecoveryHelp(WouldRecoveryHelp):
    """SUCCESS when the last planning error code is one a recovery can fix (Nav2 defaults:
    UNKNOWN, NO_VALID_PATH, TIMEOUT)."""

    INPUT_PORTS = {
        "error_code": PortInformation(int, True, "ComputePathToPose error code"),
        "error_codes_to_check": PortInformation(list, False, "codes a recovery may fix",
                                                PLANNER_RECOVERABLE),
    }
    DEFAULT_KEYS = {"error_code": "compute_path_error_code"}


class WouldAControllerRecoveryHelp(WouldRecoveryHelp):
    """SUCCESS when the last FollowPath error code is one a recovery can fix (Nav2 defaults:
    UNKNOWN, PATIENCE_EXCEEDED, FAILED_TO_MAKE_PROGRESS, NO_VALID_CONTROL)."""

    INPUT_PORTS = {
        "error_code": PortInformation(int, True, "FollowPath error code"),
        "error_codes_to_check": PortInformation(list, False, "codes a recovery may fix",
                                                CONTROLLER_RECOVERABLE),
    }
    DEFAULT_KEYS = {"error_code": "follow_path_error_code"}
