"""IsLocalized."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from behaviors.base import SUCCESS, Port, PortInformation, Status
from behaviors.conditions.condition import Condition, yes


class IsLocalized(Condition):
    """SUCCESS when the localiser's standard deviations are within bounds.

    Without a localiser (ground truth), SUCCESS.
    """

    INPUT_PORTS = {
        "max_xy_std": Port(float, False, "largest x or y std deviation, m", 0.25, low=0.0),
        "max_yaw_std": Port(float, False, "largest yaw std deviation, rad", 0.25, low=0.0),
    }
    OUTPUT_PORTS: dict[str, PortInformation] = {}

    def setup(self, **kwargs: Any) -> None:
        super().setup(**kwargs)
        self.localizer = kwargs.get("localizer")

    def update(self) -> Status:
        if self.localizer is None:
            self.say("no localiser: ground truth")
            return SUCCESS
        cov = np.asarray(self.localizer.covariance(), dtype=float)
        sx, sy, st = (math.sqrt(max(0.0, float(cov[i, i]))) for i in range(3))
        self.say("std x {:.2f} y {:.2f} yaw {:.2f}", sx, sy, st)
        return yes(max(sx, sy) <= self.get_input("max_xy_std")
                    and st <= self.get_input("max_yaw_std"))
