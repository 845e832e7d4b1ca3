"""Oscillation suppression (base_local_planner's OscillationCostFunction flags).

When the chosen command flips direction (forward/backward; and, while barely translating,
left/right strafe or rotation) the new direction is latched as the only one allowed. The latch
holds until the robot has moved ``oscillation_reset_dist`` or turned ``oscillation_reset_angle``
from where it was set, or the plan changes.
"""

from __future__ import annotations

import math

import numpy as np


class OscillationFlags:
    """The latched direction flags and the memory of the last commanded directions."""

    NAMES = ("forward_pos_only", "forward_neg_only", "strafe_pos_only", "strafe_neg_only",
             "rot_pos_only", "rot_neg_only")

    def __init__(self) -> None:
        self.only = np.zeros(6, dtype=np.bool_)  # order as NAMES; read by the critic kernel
        self._moved = np.zeros(6, dtype=np.bool_)  # forward_pos, forward_neg, strafe_pos, ...
        self._set_at: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def reset(self) -> None:
        """Forget every latch and every remembered direction (resetOscillationFlags)."""
        self.only[:] = False
        self._moved[:] = False

    def any(self) -> bool:
        return bool(self.only.any())

    def active(self) -> list[str]:
        """Names of the latched flags, for feedback messages."""
        return [n for n, f in zip(self.NAMES, self.only) if f]

    def _axis(self, i: int, v: float) -> bool:
        """Remember the sign of ``v`` on axis pair (2i, 2i+1); latch on a flip. True if latched."""
        pos, neg = 2 * i, 2 * i + 1
        latched = False
        if v < 0.0:
            if self._moved[pos]:
                self.only[neg] = True
                latched = True
            self._moved[pos], self._moved[neg] = False, True
        if v > 0.0:
            if self._moved[neg]:
                self.only[pos] = True
                latched = True
            self._moved[neg], self._moved[pos] = False, True
        return latched

    def update(self, x: float, y: float, theta: float, vx: float, vy: float, vth: float,
               min_vel_trans: float, reset_dist: float, reset_angle: float) -> None:
        """After a valid command (vx, vy, vth) chosen at pose (x, y, theta): latch and release."""
        latched = self._axis(0, vx)
        if abs(vx) <= min_vel_trans:  # strafe and rotation count only when barely driving
            latched = self._axis(1, vy) or latched
            latched = self._axis(2, vth) or latched
        if latched:
            self._set_at = (x, y, theta)
        if self.only.any():
            px, py, pth = self._set_at
            if (math.hypot(x - px, y - py) > reset_dist
                    or abs(theta - pth) > reset_angle):
                self.reset()
