"""CARMEN log playback: recorded laser scans and wheel odometry through the hw ``Laser`` and
``Base`` interfaces, so that localisation runs on a log exactly as on a robot.

The corrected logs in ``shared/data/logs`` (see its SOURCES.md) re-anchor the odometry at every
scan: the ODOM lines after a FLASER are integrated from that scan's *corrected* pose. The reader
therefore rebuilds a continuous raw odometry chain: the increment between scans k and k+1 is the
last ODOM before scan k+1 expressed relative to the corrected pose of scan k, and those increments
are composed from the first scan on. The FLASER poses are kept as the reference trajectory.
"""

from __future__ import annotations

import gzip
import math
import os
from dataclasses import dataclass
from typing import Any

import numpy as np
from numba import njit

from hw.interfaces import BaseEvents, BatteryState
from navcore.clock import Clock
from navcore.maps import OCCUPIED, UNKNOWN, OccupancyGrid
from navcore.types import LaserScan, Odometry, Pose2D, Twist, normalize_angle
from hw.errors import HwError


class LogError(HwError, ValueError):
    """A CARMEN log is missing or malformed; the message names the file and line."""


@dataclass(slots=True)
class CarmenLog:
    """A parsed CARMEN log.

    ``scan_times`` (K,), ``scan_ranges`` (K, n) float32, ``reference`` (K, 3) corrected poses in the
    log frame, ``scan_odom`` (K, 3) the rebuilt odometry pose at each scan; ``odom_times`` (M,) and
    ``odom_poses`` (M, 3) the full odometry stream; ``fov`` the laser field of view (rad, starting
    at -fov/2); ``laser_offset`` the forward laser offset (m) from PARAM robot_frontlaser_offset.
    """

    scan_times: np.ndarray
    scan_ranges: np.ndarray
    reference: np.ndarray
    scan_odom: np.ndarray
    odom_times: np.ndarray
    odom_poses: np.ndarray
    fov: float = math.pi
    laser_offset: float = 0.0
    source: str = ""

    def __len__(self) -> int:
        return len(self.scan_times)

    def reference_in_map(self, angle: float) -> np.ndarray:
        """Reference poses in a map frame that is the log frame rotated by ``angle`` (rad) about
        the log origin (how SOURCES.md registers the Intel and ACES maps)."""
        return rotate_poses(self.reference, angle)

    def scan(self, k: int, range_max: float) -> LaserScan:
        """Scan k as a LaserScan: n beams counter-clockwise from -fov/2, fov/n apart, readings
        >= ``range_max`` meaning no return."""
        n = self.scan_ranges.shape[1]
        inc = self.fov / n  # 180 beams over 180 degrees are 1 degree apart: -90 .. +89
        return LaserScan(stamp=float(self.scan_times[k]), angle_min=-self.fov / 2,
                         angle_max=-self.fov / 2 + (n - 1) * inc, angle_increment=inc,
                         time_increment=0.0,
                         scan_time=0.0, range_min=0.0, range_max=range_max,
                         ranges=self.scan_ranges[k], frame_id="laser")


@njit(cache=True)
def _mark_free(data: np.ndarray, poses: np.ndarray, angles: np.ndarray, ranges: np.ndarray,
               ox: float, oy: float, res: float) -> None:
    """Mark cells along each beam free, walking in half-cell steps up to one cell short."""
    h, w = data.shape
    for k in range(poses.shape[0]):
        for j in range(angles.shape[1]):
            c = math.cos(angles[k, j])
            s = math.sin(angles[k, j])
            d = 0.0
            while d < ranges[k, j] - res:
                mx = int((poses[k, 0] + d * c - ox) / res)
                my = int((poses[k, 1] + d * s - oy) / res)
                if 0 <= mx < w and 0 <= my < h:
                    data[my, mx] = 0
                d += 0.5 * res


def map_from_log(log: CarmenLog, resolution: float = 0.05, range_max: float = 50.0,
                 max_ray: float = 20.0) -> OccupancyGrid:
    """A map consistent with the log by construction: every scan drawn at its reference pose
    (cells along a beam free, the end cell occupied), in the log frame. For logs shipped without
    a map (FR079), and to measure a localiser without map-registration error."""
    if not resolution > 0.0:
        raise ValueError(f"map_from_log: resolution must be > 0, got {resolution}")
    n = log.scan_ranges.shape[1]
    bearings = -log.fov / 2 + (log.fov / n) * np.arange(n)
    r = log.scan_ranges.astype(np.float64)
    hit = r < min(range_max, max_ray)
    a = log.reference[:, 2:3] + bearings[None, :]
    ex = log.reference[:, 0:1] + r * np.cos(a)
    ey = log.reference[:, 1:2] + r * np.sin(a)
    lo = np.array([ex[hit].min(), ey[hit].min()]) - 1.0
    hi = np.array([ex[hit].max(), ey[hit].max()]) + 1.0
    w, h = (np.ceil((hi - lo) / resolution)).astype(int)
    data = np.full((h, w), UNKNOWN, np.int16)
    free_r = np.minimum(np.where(np.isfinite(r), r, max_ray), max_ray)
    _mark_free(data, log.reference, a, free_r, float(lo[0]), float(lo[1]), float(resolution))
    hx = ((ex[hit] - lo[0]) / resolution).astype(np.int64)
    hy = ((ey[hit] - lo[1]) / resolution).astype(np.int64)
    data[hy, hx] = OCCUPIED
    return OccupancyGrid(data, resolution, Pose2D(float(lo[0]), float(lo[1]), 0.0))


def rotate_poses(poses: np.ndarray, angle: float) -> np.ndarray:
    """(N, 3) poses rotated by ``angle`` about the origin (x, y rotated, theta + angle)."""
    c, s = math.cos(angle), math.sin(angle)
    out = np.empty_like(poses, dtype=np.float64)
    out[:, 0] = c * poses[:, 0] - s * poses[:, 1]
    out[:, 1] = s * poses[:, 0] + c * poses[:, 1]
    out[:, 2] = (poses[:, 2] + angle + math.pi) % (2 * math.pi) - math.pi
    return out


def _pose(a: list[float]) -> Pose2D:
    return Pose2D(a[0], a[1], normalize_angle(a[2]))


def read_carmen(path: str | os.PathLike) -> CarmenLog:
    """Parse a (gzip or plain) CARMEN log with FLASER and ODOM lines into a ``CarmenLog``."""
    path = os.fspath(path)
    opener = gzip.open if path.endswith(".gz") else open
    try:
        with opener(path, "rt", encoding="ascii", errors="replace") as f:
            lines = f.readlines()
    except OSError as e:
        raise LogError(f"{path}: cannot read log: {e}") from e
    laser_offset = 0.0
    scans: list[tuple[float, np.ndarray, Pose2D]] = []
    # odometry lines after each scan: (t, pose integrated from that scan's corrected pose)
    odoms_after: list[list[tuple[float, Pose2D]]] = []
    n_beams = None
    for no, line in enumerate(lines, 1):
        parts = line.split()
        if not parts or parts[0].startswith("#"):
            continue
        tag = parts[0]
        try:
            if tag == "PARAM" and len(parts) >= 3 and parts[1] == "robot_frontlaser_offset":
                laser_offset = float(parts[2])
            elif tag == "FLASER":
                n = int(parts[1])
                if len(parts) < 2 + n + 7:
                    raise LogError(f"{path}:{no}: FLASER with {n} ranges has only "
                                   f"{len(parts)} fields")
                if n_beams is None:
                    n_beams = n
                elif n != n_beams:
                    raise LogError(f"{path}:{no}: FLASER has {n} ranges, earlier ones {n_beams}")
                ranges = np.array(parts[2:2 + n], dtype=np.float32)
                vals = [float(v) for v in parts[2 + n:2 + n + 6]]
                t = float(parts[2 + n + 6])
                scans.append((t, ranges, _pose(vals[3:6])))
                odoms_after.append([])
            elif tag == "ODOM":
                if len(parts) < 8:
                    raise LogError(f"{path}:{no}: ODOM needs 7 numbers, got {len(parts) - 1}")
                t = float(parts[7])
                if scans and t > scans[-1][0] and math.isfinite(t):
                    odoms_after[-1].append((t, _pose([float(v) for v in parts[1:4]])))
        except ValueError as e:
            if isinstance(e, LogError):
                raise
            raise LogError(f"{path}:{no}: malformed {tag} line: {e}") from e
    if len(scans) < 2:
        raise LogError(f"{path}: fewer than two FLASER lines ({len(scans)})")
    # rebuild a continuous odometry chain from the re-anchored increments
    k_count = len(scans)
    scan_odom = np.empty((k_count, 3))
    odom_t: list[float] = []
    odom_p: list[tuple[float, float, float]] = []
    o = scans[0][2]
    for k in range(k_count):
        t_k, _, ref_k = scans[k]
        scan_odom[k] = (o.x, o.y, o.theta)
        odom_t.append(t_k)
        odom_p.append((o.x, o.y, o.theta))
        t_next = scans[k + 1][0] if k + 1 < k_count else math.inf
        last = None
        for t, q in odoms_after[k]:
            if t > t_next:  # a garbage timestamp; the last reading shares the next scan's time
                continue
            last = q
            oq = o.compose(q.relative_to(ref_k))
            odom_t.append(t)
            odom_p.append((oq.x, oq.y, oq.theta))
        if k + 1 < k_count:
            # no odometry between the scans means no measured motion
            o = o.compose(last.relative_to(ref_k)) if last is not None else o
    order = np.argsort(np.array(odom_t), kind="stable")
    return CarmenLog(
        scan_times=np.array([s[0] for s in scans]),
        scan_ranges=np.stack([s[1] for s in scans]),
        reference=np.array([(s[2].x, s[2].y, s[2].theta) for s in scans]),
        scan_odom=scan_odom,
        odom_times=np.array(odom_t)[order],
        odom_poses=np.array(odom_p)[order],
        laser_offset=laser_offset,
        source=path,
    )


class RecordedBase:
    """The ``Base`` side of a recorded log played on the executive's clock: ``odometry()`` is
    the newest odometry stamped at or before ``clock.now() - time_offset`` (None before the
    first), and ``send`` only records the last command, since a recording cannot be steered.
    A subclass sets ``log`` (with ``odom_times`` and ``odom_poses``), ``_clock``,
    ``time_offset`` and ``last_cmd``."""

    log: Any
    _clock: Clock
    time_offset: float
    last_cmd: Twist | None

    def odometry(self) -> Odometry | None:
        t = self._clock.now() - self.time_offset
        j = int(np.searchsorted(self.log.odom_times, t, side="right")) - 1
        if j < 0:
            return None
        x, y, th = self.log.odom_poses[j]
        return Odometry(stamp=float(self.log.odom_times[j]) + self.time_offset,
                        pose=Pose2D(float(x), float(y), float(th)))

    def send(self, cmd: Twist) -> None:
        self.last_cmd = cmd

    def battery(self) -> BatteryState | None:
        return None

    def events(self) -> BaseEvents:
        return BaseEvents()


class LogPlayback(RecordedBase):
    """Plays a ``CarmenLog`` on the executive's clock through the ``Base`` and ``Laser``
    interfaces: ``scan()`` and ``odometry()`` return the newest message stamped at or before
    ``clock.now()`` (log time plus ``time_offset``), or None before the first.

    A log cannot be steered: ``send`` only records the last command (``last_cmd``).
    """

    def __init__(self, log: CarmenLog, clock: Clock, range_max: float = 50.0,
                 time_offset: float = 0.0) -> None:
        if not range_max > 0.0:
            raise ValueError(f"LogPlayback: range_max must be > 0, got {range_max}")
        self.log = log
        self._clock = clock
        self.range_max = float(range_max)
        self.time_offset = float(time_offset)
        self.mount = Pose2D(log.laser_offset, 0.0, 0.0)
        self.last_cmd: Twist | None = None

    # -- Laser
    def scan(self) -> LaserScan | None:
        k = self.scan_index()
        if k < 0:
            return None
        s = self.log.scan(k, self.range_max)
        s.stamp += self.time_offset
        return s

    def scan_index(self) -> int:
        """Index of the newest scan at the clock's time, -1 before the first."""
        t = self._clock.now() - self.time_offset
        return int(np.searchsorted(self.log.scan_times, t, side="right")) - 1

    @property
    def finished(self) -> bool:
        return self._clock.now() - self.time_offset >= float(self.log.scan_times[-1])

    @property
    def start_time(self) -> float:
        return float(self.log.scan_times[0]) + self.time_offset
