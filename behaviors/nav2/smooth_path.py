"""SmoothPath (Nav2 action) and the SmoothPath action's error codes."""

from __future__ import annotations

from typing import Any

from behaviors.base import FAILURE, SUCCESS, Leaf, PortInformation, Status
from navcore import path_ops
from navcore.error_codes import SmootherError
from navcore.types import Path


class SmoothPath(Leaf):
    """Smooth ``unsmoothed_path`` as Nav2's SimpleSmoother does (poses pulled toward their
    neighbours, held to the original; ends fixed) and write ``smoothed_path``. With
    ``check_for_collisions`` a result crossing a lethal cell of the global costmap FAILs with
    SMOOTHED_PATH_IN_COLLISION; no path FAILs with INVALID_PATH. ``was_completed`` says whether
    it converged within its iterations. (Nav2 ``SmoothPath``; ``smoother_id`` and
    ``max_smoothing_duration`` are accepted, one smoother here.)"""

    INPUT_PORTS = {
        "unsmoothed_path": PortInformation(Path, True, "path to smooth"),
        "max_smoothing_duration": PortInformation(float, False, "Nav2's time limit, s", 3.0),
        "check_for_collisions": PortInformation(bool, False, "fail if the result collides",
                                                False),
        "smoother_id": PortInformation(str, False, "smoother plugin id", ""),
    }
    OUTPUT_PORTS = {
        "smoothed_path": PortInformation(Path, True, "the smoothed path"),
        "smoothing_duration": PortInformation(float, False, "time spent, s (simulated: 0)"),
        "was_completed": PortInformation(bool, False, "converged within the iterations"),
        "error_code_id": PortInformation(int, False, "a SmootherError; 0 on success"),
        "error_msg": PortInformation(str, False, "why smoothing failed"),
    }

    def setup(self, **kwargs: Any) -> None:
        self.costmap = self.component(kwargs, "global_costmap", optional=True)

    def update(self) -> Status:
        path = self.read("unsmoothed_path")
        if path is None or len(path) == 0:
            return self._fail(SmootherError.INVALID_PATH, "no path to smooth")
        smoothed, done = path_ops.smooth(path)
        if self.get_input("check_for_collisions") and self.costmap is not None:
            from navcore.costmap.cost_values import LETHAL_OBSTACLE
            grid = self.costmap.costmap
            for x, y, _ in smoothed.poses:
                cell = grid.world_to_map(float(x), float(y))
                if cell is not None and int(grid.costs[cell[1], cell[0]]) >= LETHAL_OBSTACLE:
                    return self._fail(SmootherError.SMOOTHED_PATH_IN_COLLISION,
                                      f"smoothed path collides at ({x:.2f}, {y:.2f})")
        self.write("smoothed_path", smoothed)
        self.write("smoothing_duration", 0.0)
        self.write("was_completed", done)
        self.write("error_code_id", int(SmootherError.NONE))
        self.write("error_msg", "")
        return SUCCESS

    def _fail(self, code: int, msg: str) -> Status:
        self.write("error_code_id", int(code))
        self.write("error_msg", msg)
        self.say(msg)
        return FAILURE
