"""ros_arduino_bridge firmware emulator: ASCII commands, 30 Hz PID frames, encoder counts, and
the firmware's 2 s auto-stop. Wheel motion in ticks comes from
``motion_source(dt, left_ticks_per_s, right_ticks_per_s) -> (left_ticks, right_ticks)``."""

from __future__ import annotations

from typing import Callable

from hw.drivers import arduino_codec as ac
from hw.emulators.link import Emulator
from navcore.clock import Clock

MotionSource = Callable[[float, float, float], tuple[float, float]]


def ideal_motors(dt: float, left: float, right: float) -> tuple[float, float]:
    return left * dt, right * dt


class ArduinoBridgeEmulator(Emulator):
    """``targets`` are the commanded ticks per PID frame; ``motions`` logs (time, left, right)
    of every ``m`` command; ``encoders`` are the signed counts."""

    device = "arduino"

    def __init__(self, clock: Clock, motion_source: MotionSource = ideal_motors) -> None:
        super().__init__(clock)
        self.motion_source = motion_source
        self.motions: list[tuple[float, int, int]] = []
        self.power_cycle()

    def power_cycle(self) -> None:
        super().power_cycle()
        self._lines = ac.LineDecoder(b"\r")
        self.targets = (0, 0)
        self._enc = [0.0, 0.0]
        self._last_motor = self.clock.now()
        self._t = self.clock.now()
        self.pid = (20, 12, 0, 50)

    @property
    def encoders(self) -> tuple[int, int]:
        return int(self._enc[0]), int(self._enc[1])

    def _say(self, text: str) -> None:
        self.emit(text.encode("ascii") + b"\r\n")      # Serial.println

    def receive(self, data: bytes) -> None:
        for line in self._lines.feed(data):
            self._command(line.strip())

    def _command(self, line: str) -> None:
        parts = line.split(" ")
        cmd, args = parts[0], parts[1:]
        now = self.clock.now()
        try:
            if cmd == "b":
                return self._say(str(ac.BAUDRATE))
            if cmd == "e":
                return self._say(f"{self.encoders[0]} {self.encoders[1]}")
            if cmd == "r":
                self._enc = [0.0, 0.0]
                return self._say("OK")
            if cmd == "m" and len(args) == 2:
                self.targets = (int(args[0]), int(args[1]))
                self._last_motor = now
                self.motions.append((now, *self.targets))
                return self._say("OK")
            if cmd == "u" and len(args) == 1:
                self.pid = tuple(int(x) for x in args[0].split(":"))
                return self._say("OK")
            if cmd == "a" and len(args) == 1:
                return self._say("512")
            if cmd in ("d", "s") and len(args) == 1:
                return self._say("0")
            if cmd in ("w", "x", "c", "t") and len(args) == 2:
                return self._say("OK")
        except ValueError:
            pass                     # the firmware's atoi would read garbage as 0; we refuse
        self._say("Invalid Command")

    def advance(self, now: float) -> None:
        frame = 1.0 / ac.PID_RATE
        if now - self._t > 600.0:          # a clock jump of minutes: do not replay it
            self._t = now - frame
        while now - self._t >= frame:
            self._t += frame
            if self._t - self._last_motor > ac.AUTO_STOP_INTERVAL:
                self.targets = (0, 0)
            dl, dr = self.motion_source(frame, self.targets[0] * ac.PID_RATE,
                                        self.targets[1] * ac.PID_RATE)
            self._enc[0] += dl
            self._enc[1] += dr
