"""ros_arduino_bridge base driver: implements ``hw.interfaces.Base`` for home-built bases.

A polled protocol: at ``base_controller_rate`` the driver asks for the encoders (``e``) and writes
the wheel targets (``m``). One request is in flight at a time, so each reply is checked against
the shape its request expects (there is no echo or checksum); a mismatch clears the line.
Encoder steps larger than the wheels can make are refused (three in a row: the counts really
jumped, e.g. a firmware reset, and become the new reference). The watchdog writes ``m 0 0`` once no
``send`` came for ``base_controller_timeout``.
"""

from __future__ import annotations

import math
import threading
from collections import deque
from typing import Any, Callable, Mapping

import numpy as np
import serial

from hw.drivers import arduino_codec as ac
from hw.drivers.serial_link import HandshakeError, REPLY_WAIT, SerialDriver, wire_deadline
from hw.interfaces import BaseEvents, BatteryState
from navcore.clock import Clock
from navcore.params import Param, Parameters
from navcore.types import Odometry, Pose2D, Twist, normalize_angle

# ros_arduino_python's parameter names and defaults (arduino_params.yaml).
ARDUINO_PARAMS = (
    Param("baud", 57600, int, "bit rate of the Arduino's serial port", 9600, 1000000),
    Param("base_controller_rate", 10.0, float, "encoder polls and motor writes per second (Hz)",
          1.0, 100.0),
    Param("base_controller_timeout", 1.0, float, "stop the motors when no command came for this "
          "long (s)", 0.05, 10.0),
    Param("wheel_diameter", 0.146, float, "m", 0.01, 2.0),
    Param("wheel_track", 0.2969, float, "distance between the wheels (m)", 0.01, 5.0),
    Param("encoder_resolution", 8384, int, "ticks per wheel revolution", 1, 10**7),
    Param("gear_reduction", 1.0, float, "motor turns per wheel turn", 0.01, 1000.0),
    Param("motors_reversed", False, bool, "swap the sign of both motors and encoders"),
    Param("Kp", 20, int, "PID proportional gain"),
    Param("Kd", 12, int, "PID derivative gain"),
    Param("Ki", 0, int, "PID integral gain"),
    Param("Ko", 50, int, "PID output scale"),
    Param("max_wheel_speed", 3.0, float, "fastest plausible wheel speed (m/s); larger encoder "
          "steps are refused as corrupt", 0.1, 50.0),
)


def _two_ints(line: str) -> bool:
    parts = line.split()
    return len(parts) == 2 and all(p.lstrip("-").isdigit() for p in parts)


class ArduinoBaseDriver(SerialDriver):
    """A ros_arduino_bridge base on ``url``. ``send`` never blocks."""

    def __init__(self, url: str, clock: Clock, params: Mapping[str, Any] | None = None) -> None:
        self.params = Parameters(ARDUINO_PARAMS, params or {}, "arduino")
        p = self.params
        super().__init__(url, clock, p.baud, silence_timeout=max(1.0, 5.0 / p.base_controller_rate),
                         name="arduino")
        self.geometry = ac.Geometry(p.wheel_diameter, p.wheel_track, p.encoder_resolution,
                                    p.gear_reduction)
        self._lines = ac.LineDecoder(b"\r")
        self._pending: deque[tuple[str, float]] = deque()
        self._wlock = threading.Lock()
        self._cmd, self._cmd_stamp = Twist(), -np.inf
        self._sent: tuple[int, int] | None = None
        self._next_poll = -np.inf
        self._enc: tuple[int, int] | None = None
        self._enc_stamp = 0.0
        self._refused_in_row = 0
        self._latency = 0.0        # the slowest reply seen (s), for the reply deadline
        self._pose = Pose2D()
        self._odom: Odometry | None = None

    # -- Base interface ------------------------------------------------------------------------
    def send(self, cmd: Twist) -> None:
        with self._wlock:
            self._cmd, self._cmd_stamp = cmd, self.clock.now()

    def odometry(self) -> Odometry | None:
        with self._lock:
            return self._odom

    def battery(self) -> BatteryState | None:
        return None          # the bridge has no battery monitor

    def events(self) -> BaseEvents:
        return BaseEvents()  # nor contact sensors

    def commanded(self) -> tuple[int, int] | None:
        """The (left, right) ticks per PID frame last written."""
        return self._sent

    # -- start-up ------------------------------------------------------------------------------
    def _ask(self, port: serial.SerialBase, line: bytes, accept: Callable[[str], bool],
             tries: int = 3) -> str:
        """Send ``line`` until a reply ``accept`` takes arrives; other lines (late replies to
        an earlier session's requests, on a slow bridge) are skipped."""
        for _ in range(tries):
            port.write(line)
            dec = ac.LineDecoder(b"\r")
            deadline = wire_deadline(REPLY_WAIT)
            while self._waiting(deadline):
                for got in dec.feed(port.read(max(1, port.in_waiting))):
                    if accept(got.strip()):
                        # wire time, like the deadline: how slow this bridge answers
                        self._latency = max(self._latency,
                                            REPLY_WAIT - deadline.time_left())
                        return got
        raise HandshakeError(f"no reply to {line!r}")

    def _handshake(self, port: serial.SerialBase) -> None:
        self._latency = 0.0
        port.write(b"\r")                      # end whatever half command is in the buffer
        port.reset_input_buffer()
        self._ask(port, ac.command("b"), str.isdigit)
        p = self.params
        is_ok = "OK".__eq__
        try:
            self._ask(port, ac.pid_command(p.Kp, p.Kd, p.Ki, p.Ko), is_ok)
            self._ask(port, ac.motor_command(0, 0), is_ok)
            self._enc = self._sign(ac.parse_encoders(self._ask(port, ac.command("e"),
                                                               _two_ints)))
        except ac.ArduinoError as e:
            raise HandshakeError(str(e)) from None
        self._enc_stamp = self.clock.now()
        self._sent = (0, 0)
        self._pending.clear()
        self._lines.reset()

    def _sign(self, pair: tuple[int, int]) -> tuple[int, int]:
        return (-pair[0], -pair[1]) if self.params.motors_reversed else pair

    def _on_close(self, port: serial.SerialBase) -> None:
        port.write(ac.motor_command(0, 0))
        self._sent = (0, 0)

    # -- polling -------------------------------------------------------------------------------
    def _on_tick(self, port: serial.SerialBase) -> None:
        now = self.clock.now()
        p = self.params
        # a reply is given up on after twice the device's own latency (measured), at least two
        # poll periods, at most REPLY_WAIT: a slow bridge still works, a lost reply costs little
        wait = min(REPLY_WAIT, max(2.0 / p.base_controller_rate, 2.0 * self._latency + 0.05))
        if self._pending and now - self._pending[0][1] > wait:
            self._reject(f"no reply to a '{self._pending[0][0]}' request")
            self._pending.clear()              # a reply went missing: start afresh
            self._lines.reset()
            port.reset_input_buffer()
        with self._wlock:
            cmd, stamp = self._cmd, self._cmd_stamp
        if now - stamp > p.base_controller_timeout:
            cmd = Twist()
        targets = self._sign(self.geometry.wheel_targets(cmd.vx, cmd.wz))
        urgent = targets != self._sent and targets == (0, 0)    # stops do not wait for a poll
        if urgent:              # nor for the replies still due: a stop goes out at once
            port.write(ac.motor_command(*targets))
            self._pending.append(("ok", now))
            self._sent = targets
            return
        if now < self._next_poll or self._pending:
            return
        self._next_poll = now + 1.0 / p.base_controller_rate
        port.write(ac.motor_command(*targets))
        self._pending.append(("ok", now))
        self._sent = targets
        port.write(ac.command("e"))
        self._pending.append(("enc", now))

    def _on_bytes(self, data: bytes) -> None:
        before = self._lines.errors
        lines = self._lines.feed(data)
        self._reject_decoder_errors(before, self._lines.errors, "garbled reply line")
        for line in lines:
            if not self._pending:
                self._reject(f"unsolicited reply {line!r}")
                continue
            kind, asked = self._pending.popleft()
            self._latency = max(self.clock.now() - asked, 0.9 * self._latency)
            try:
                if kind == "ok":
                    ac.expect_ok(line)
                    self.mark_valid()          # an answer is a sign of life too
                else:
                    self._take_encoders(self._sign(ac.parse_encoders(line)))
            except ac.ArduinoError as e:
                self._reject(str(e))
                self._pending.clear()          # replies may now be out of step: resync
                self._lines.reset()

    def _take_encoders(self, enc: tuple[int, int]) -> None:
        now = self.clock.now()
        last, dt = self._enc, now - self._enc_stamp
        g = self.geometry
        if last is not None and self._refused_in_row >= 3:
            last = None           # the counts really moved (a firmware reset): new reference
        if last is not None:
            dl = (enc[0] - last[0]) / g.ticks_per_meter
            dr = (enc[1] - last[1]) / g.ticks_per_meter
            limit = self.params.max_wheel_speed * max(dt, 1.0 / self.params.base_controller_rate) \
                * 2.0 + 0.01
            if abs(dl) > limit or abs(dr) > limit:
                self._refused_in_row += 1     # no checksum: physics is the only check
                self._implausible(f"encoder step {dl:.3f}/{dr:.3f} m exceeds {limit:.3f} m")
                return
            ds, dth = (dl + dr) / 2.0, (dr - dl) / g.wheel_track
            mid = self._pose.theta + dth / 2.0
            self._pose = Pose2D(self._pose.x + ds * math.cos(mid),
                                self._pose.y + ds * math.sin(mid),
                                normalize_angle(self._pose.theta + dth))
            twist = Twist(ds / dt, 0.0, dth / dt) if dt > 0 else Twist()
            with self._lock:
                self._odom = Odometry(now, self._pose, twist)
        self._enc, self._enc_stamp, self._refused_in_row = enc, now, 0
        self.delivered += 1
        self.mark_valid()
