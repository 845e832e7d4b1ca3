"""What the rest of navbt may assume about a robot body.

The simulator, the pyserial drivers and log playback all implement these; nothing above ``hw``
knows which one it talks to. Readers return the newest message or None if none has arrived yet;
they never block. Every message carries its ``stamp`` on the executive's ``Clock``.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

# BaseEvents and BatteryState are messages and live in navcore.types (behaviors/ reads them and
# must not import hw); they are re-exported here, where robot I/O code has always found them.
from navcore.types import BaseEvents, BatteryState, Imu, LaserScan, Odometry, Pose2D, Twist


@runtime_checkable
class Base(Protocol):
    """A mobile base: takes body velocity commands, reports odometry, battery and events."""

    def send(self, cmd: Twist) -> None:
        """Command a body velocity. The base stops by itself if no command arrives in time."""
        ...

    def odometry(self) -> Odometry | None:
        ...

    def battery(self) -> BatteryState | None:
        ...

    def events(self) -> BaseEvents:
        ...


@runtime_checkable
class Laser(Protocol):
    """A planar laser scanner mounted at ``mount`` (pose of the laser frame in base_link)."""

    mount: Pose2D

    def scan(self) -> LaserScan | None:
        ...


@runtime_checkable
class ImuSensor(Protocol):
    """An IMU mounted at ``mount`` in base_link."""

    mount: Pose2D

    def imu(self) -> Imu | None:
        ...


class RobotIO(Protocol):
    """A whole robot as the executive drives it: the simulator, a set of drivers, or your own.

    Implement this to run navbt on your robot (``docs/api.md``): a ``base`` and, if there is one,
    a ``laser``; ``step_to`` is called at the start of every control cycle with the clock's time.
    An optional ``close()`` is called when a mission built by ``executive.api`` is closed.
    """

    base: Base
    laser: Laser | None

    def step_to(self, t: float) -> None:
        """Bring the world up to time ``t`` (the simulator steps physics; hardware does nothing)."""
        ...

    def true_pose(self) -> Pose2D | None:
        """Ground truth in ``map`` (simulator only; None on hardware)."""
        ...

    def in_collision(self) -> bool:
        """Whether the body overlaps an obstacle right now (simulator) or a bumper is pressed."""
        ...
