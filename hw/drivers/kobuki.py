"""Kobuki base driver: implements ``hw.interfaces.Base`` over the Kobuki binary protocol.

Commands are re-sent every ``cmd_resend_period`` so that one frame lost on the wire cannot leave
the base running a stale command, and the watchdog sends zero once no ``send`` arrived for
``cmd_vel_timeout`` (the firmware has no timeout of its own). Odometry, battery and contact
events come from the 50 Hz feedback stream; frames failing the codec's checks are dropped.
"""

from __future__ import annotations

import threading
from typing import Any, Mapping

import numpy as np
import serial

from hw.drivers import kobuki_codec as kc
from hw.drivers.serial_link import HandshakeError, REPLY_WAIT, SerialDriver, wire_deadline
from hw.interfaces import BaseEvents, BatteryState
from navcore.clock import Clock
from navcore.params import Param, Parameters
from navcore.types import Odometry, Twist

# kobuki_node's parameter names and defaults.
# What a Kobuki can do (0.7 m/s, 180 deg/s by its spec), with margin: a frame claiming more
# got a corrupted encoder or heading past the XOR checksum.
MAX_WHEEL_SPEED = 2.0   # m/s
MAX_TURN_RATE = 6.0     # rad/s

KOBUKI_PARAMS = (
    Param("cmd_vel_timeout", 0.6, float, "stop the base when no command came for this long (s)",
          0.01, 10.0),
    Param("battery_capacity", 16.5, float, "battery voltage when full (V)", 0.0, 30.0),
    Param("battery_low", 14.0, float, "low battery voltage (V)", 0.0, 30.0),
    Param("battery_dangerous", 13.2, float, "dangerously low battery voltage (V)", 0.0, 30.0),
    Param("use_imu_heading", True, bool, "odometry yaw from the factory-calibrated gyro"),
    Param("odom_frame", "odom", str, "frame of the odometry pose"),
    Param("base_frame", "base_footprint", str, "child frame of the odometry"),
    Param("cmd_resend_period", 0.1, float, "re-send the command in force this often (s)",
          0.01, 1.0),
)


class KobukiDriver(SerialDriver):
    """A Kobuki on ``url`` (``/dev/kobuki``, ``sim://kobuki``...). ``send`` never blocks."""

    def __init__(self, url: str, clock: Clock, params: Mapping[str, Any] | None = None) -> None:
        self.params = Parameters(KOBUKI_PARAMS, params or {}, "kobuki")
        super().__init__(url, clock, 115200, silence_timeout=0.5, name="kobuki")
        self._dec = kc.FrameDecoder()
        self._odo = kc.KobukiOdometry(self.params.use_imu_heading)
        self._refused_in_row = 0
        self._odom: Odometry | None = None
        self._battery: BatteryState | None = None
        self._events = BaseEvents()
        self._wlock = threading.Lock()
        self._cmd = Twist()
        self._cmd_stamp = -np.inf
        self._cmd_new = False
        self._sent: tuple[int, int] | None = None
        self._sent_at = -np.inf
        self.versions: dict[str, tuple[int, ...]] = {}
        # kobuki_node's fixed odometry covariances: 0.1 on x and y, yaw 0.05 with the gyro
        # heading and 0.2 from the encoders alone
        self._cov = np.diag([0.1, 0.1, 0.05 if self.params.use_imu_heading else 0.2])
        self.feedback: kc.Feedback | None = None

    # -- Base interface ------------------------------------------------------------------------
    def send(self, cmd: Twist) -> None:
        with self._wlock:
            self._cmd, self._cmd_stamp, self._cmd_new = cmd, self.clock.now(), True

    def odometry(self) -> Odometry | None:
        with self._lock:
            return self._odom

    def battery(self) -> BatteryState | None:
        with self._lock:
            return self._battery

    def events(self) -> BaseEvents:
        with self._lock:
            return self._events

    def commanded(self) -> tuple[int, int] | None:
        """The (speed mm/s, radius mm) last written to the wire."""
        return self._sent

    # -- start-up ------------------------------------------------------------------------------
    def _handshake(self, port: serial.SerialBase) -> None:
        # no input flush: the frame finder skips stale or partial bytes, and in lock-step the
        # frames already sent are all the handshake will get until the clock moves
        self._dec.reset()
        self._odo = kc.KobukiOdometry(self.params.use_imu_heading)
        self._refused_in_row = 0
        self._sent = None
        port.write(kc.base_control_frame(0, 0))          # whatever ran before: stop first
        self.versions = {}
        self.feedback = None
        for _ in range(3):
            port.write(kc.request_extra_frame(0x01 | 0x02 | 0x08))
            deadline = wire_deadline(REPLY_WAIT)
            while self._waiting(deadline):
                self._take(port.read(max(1, port.in_waiting)))
                if self.versions or (self.polling and self.feedback is not None):
                    return          # in lock-step the clock will not move while we wait
        if self.feedback is None:
            raise HandshakeError("no valid feedback frame from the base")
        # streaming but the version reply was lost three times: usable all the same

    # -- streaming -----------------------------------------------------------------------------
    def _on_bytes(self, data: bytes) -> None:
        self._take(data)

    def _take(self, data: bytes) -> int:
        before = self._dec.errors
        n = 0
        for payload in self._dec.feed(data):
            try:
                fb = kc.parse_feedback(payload)
            except kc.KobukiError as e:
                self._reject(str(e))
                continue
            why = self._odo.implausibility(fb, MAX_WHEEL_SPEED, MAX_TURN_RATE)
            if why is not None:
                self._refused_in_row += 1
                if self._refused_in_row >= 3:     # the reference itself was bad
                    self._odo.rebase(fb)
                    self._refused_in_row = 0
                self._implausible(why)
                continue
            self._refused_in_row = 0
            n += 1
            self._use(fb)
        self._reject_decoder_errors(before, self._dec.errors, self._dec.last_error)
        return n

    def _use(self, fb: kc.Feedback) -> None:
        now = self.clock.now()
        self.feedback = fb
        pose, twist = self._odo.update(fb)
        b, p = fb.basic, self.params
        v = b.battery_dv / 10.0
        pct = float(np.clip((v - p.battery_dangerous) / (p.battery_capacity - p.battery_dangerous),
                            0.0, 1.0))
        for ident, key in ((kc.HW_VERSION, "hardware"), (kc.FW_VERSION, "firmware"),
                           (kc.UDID, "udid")):
            if ident in fb.extra:
                d = fb.extra[ident]
                self.versions[key] = tuple(d) if ident != kc.UDID else \
                    tuple(int.from_bytes(d[i:i + 4], "little") for i in (0, 4, 8))
        with self._lock:
            self._odom = Odometry(now, pose, twist, self._cov, self._cov,
                                  frame_id=p.odom_frame, child_frame_id=p.base_frame)
            self._battery = BatteryState(v, pct, bool(b.charger & 0x04))
            self._events = BaseEvents(bool(b.bumper), bool(b.cliff), bool(b.wheel_drop))
        self.delivered += 1
        self.mark_valid()

    def _on_tick(self, port: serial.SerialBase) -> None:
        """Watchdog and re-send, on the injected clock: the command's age is robot time."""
        now = self.clock.now()
        with self._wlock:
            cmd, stamp, new = self._cmd, self._cmd_stamp, self._cmd_new
            self._cmd_new = False
        if now - stamp > self.params.cmd_vel_timeout:
            cmd = Twist()
        sr = kc.twist_to_speed_radius(cmd.vx, cmd.wz)
        if new or sr != self._sent or now - self._sent_at >= self.params.cmd_resend_period:
            port.write(kc.base_control_frame(*sr))
            self._sent, self._sent_at = sr, now

    def _on_close(self, port: serial.SerialBase) -> None:
        port.write(kc.base_control_frame(0, 0))
        self._sent = (0, 0)
