"""The simulator: a deterministic robot world behind the ``hw`` interfaces.

>>> from hw.sim import SimWorld, Simulator
>>> sim = Simulator(SimWorld(grid), {"kinematics": "diff", "laser": {"preset": "lms291"}},
...                 clock, np.random.default_rng(0), start=Pose2D(1, 1, 0))  # doctest: +SKIP
"""

from hw.sim.config import LASER_PRESETS, RobotConfig, robot_config
from hw.sim.faults import FAULT_KINDS, Fault, FaultError, fault_from_mapping
from hw.sim.simulator import Contact, SimBase, SimImu, SimLaser, Simulator
from hw.sim.world import Box, Circle, MovingObstacle, Pole, Polygon, SimWorld, WorldError

__all__ = ["LASER_PRESETS", "RobotConfig", "robot_config", "FAULT_KINDS", "Fault", "FaultError",
           "fault_from_mapping", "Contact", "SimBase", "SimImu", "SimLaser", "Simulator", "Box",
           "Circle", "MovingObstacle", "Pole", "Polygon", "SimWorld", "WorldError"]
