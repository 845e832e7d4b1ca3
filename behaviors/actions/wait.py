"""Wait: RUNNING for a while of the injected clock (Nav2)."""

from __future__ import annotations

from behaviors.actions.recovery_action import ERROR_CODE_OUT, RecoveryAction
from behaviors.base import RUNNING, SUCCESS, Port, PortInformation, Status
from navcore.error_codes import WaitError


class Wait(RecoveryAction):
    """RUNNING for ``wait_duration`` seconds of the injected clock, then SUCCESS
    (``error_code_id`` 0 and an empty ``error_msg``, Nav2 Kilted's outputs)."""

    INPUT_PORTS = {"wait_duration": Port(float, False, "s", 1.0, low=0.0)}
    OUTPUT_PORTS = dict(ERROR_CODE_OUT)
    NEEDS_ROBOT = False

    def initialise(self) -> None:
        self._until = self.clock.now() + self.get_input("wait_duration")

    def update(self) -> Status:
        left = self._until - self.clock.now()
        if left <= 1e-9:
            self.report(WaitError.NONE, "waited")
            return SUCCESS
        self.say("{:.1f} s left", left)
        return RUNNING
