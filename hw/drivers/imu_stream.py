"""Shared reader for IMUs that stream one text line per sample (Razor, VectorNav)."""

from __future__ import annotations

from typing import Callable

from hw.drivers.lines import LineDecoder
from hw.drivers.serial_link import SerialDriver
from navcore.clock import Clock
from navcore.types import Imu, Pose2D


class LineImuDriver(SerialDriver):
    """Keeps the newest ``Imu`` parsed from the line stream; lines ``parse`` refuses are counted.
    Subclasses give the handshake and ``_parse(line, stamp) -> Imu | None`` (None: not a sample,
    e.g. a command reply, which is ignored)."""

    def __init__(self, url: str, clock: Clock, baudrate: int, name: str,
                 mount: Pose2D = Pose2D()) -> None:
        super().__init__(url, clock, baudrate, silence_timeout=0.5, name=name)
        self.mount = mount
        self._lines = LineDecoder(b"\n")
        self._imu: Imu | None = None
        self._parse: Callable[[str, float], Imu | None]

    def imu(self) -> Imu | None:
        with self._lock:
            return self._imu

    def _on_bytes(self, data: bytes) -> None:
        before = self._lines.errors
        now = self.clock.now()
        for line in self._lines.feed(data):
            try:
                msg = self._parse(line, now)
            except ValueError as e:
                self._reject(str(e))
                continue
            if msg is None:
                continue
            with self._lock:
                self._imu = msg
            self.delivered += 1
            self.mark_valid()
        self._reject_decoder_errors(before, self._lines.errors, "garbled line")
