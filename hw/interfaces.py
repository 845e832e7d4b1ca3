"""What the rest of navbt may assume about a robot body.

The simulator, the pyserial drivers and log playback all implement these; nothing above ``hw``
knows which one it talks to. Readers return the newest message or None if none has arrived yet;
they never block. Every message carries its ``stamp`` on the executive's ``Clock``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

from navcore.types import Imu, LaserScan, Odometry, Pose2D, Twist


@dataclass(frozen=True, slots=True)
class BatteryState:
    """Battery voltage (V), charge fraction 0..1 and whether it is charging."""

    voltage: float
    percentage: float
    charging: bool = False


@dataclass(frozen=True, slots=True)
class BaseEvents:
    """Contact-type events of a mobile base: bumpers, cliffs, wheel drops (True = triggered)."""

    bumper: bool = False
    cliff: bool = False
    wheel_drop: bool = False


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
