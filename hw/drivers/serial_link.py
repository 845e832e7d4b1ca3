"""What every serial driver shares: open a port from a URL, a reader thread, reconnect.

A driver subclasses ``SerialDriver`` and supplies ``_handshake(port)`` (start-up dialogue,
raising ``HandshakeError`` when the device does not answer right), ``_on_bytes(data)`` (feed the
codec, keep the newest message) and optionally ``_on_tick(port)`` (periodic writes such as the
base's command re-send and watchdog). The thread reopens the port after an unplug or after
``silence_timeout`` without a valid message, and never lets an exception escape.
"""

from __future__ import annotations

import threading
from typing import Any

import serial
from serial.serialutil import Timeout

from navcore.clock import Clock
from hw.errors import HwError


# A device may answer this late and still count as connected (s): reply deadlines in handshakes
# and polls, and the silence that means "reconnect", all allow it (issue 18: a URG at 0.3 s, a
# Razor at 0.3 s and an Arduino at 0.1 s reply latency did not work). The executive's safety gate
# stops the robot on stale data within a control period whatever this allows.
DEVICE_LATENCY = 1.0
REPLY_WAIT = DEVICE_LATENCY + 0.5


class HandshakeError(HwError, RuntimeError):
    """A device did not complete its start-up dialogue; the message says which step failed."""


def open_port(url: str, baudrate: int, timeout: float) -> serial.SerialBase:
    """``serial.serial_for_url`` with the ``sim://`` emulator scheme available."""
    if url.startswith("sim://"):
        import hw.emulators  # noqa: F401  (registers the scheme with pyserial)
    return serial.serial_for_url(url, baudrate=baudrate, timeout=timeout)


def wire_deadline(seconds: float) -> Timeout:
    """A deadline for a reply on the wire. Wire timeouts are wall time, not robot time: a device
    answers a command within its own latency whether or not a simulated clock moves, so this uses
    pyserial's Timeout (monotonic) rather than the injected Clock."""
    return Timeout(seconds)


class SerialDriver:
    """Reader thread, reconnect and statistics around one serial device."""

    #: seconds a read may block; also the granularity of ``_on_tick``
    read_timeout = 0.01

    def __init__(self, url: str, clock: Clock, baudrate: int, *, silence_timeout: float = 1.0,
                 retry_period: float = 0.2, name: str = "device") -> None:
        self.url = url
        self.clock = clock
        self.baudrate = baudrate
        self.silence_timeout = max(silence_timeout, REPLY_WAIT)
        self.retry_period = retry_period
        self.name = name
        self.connected = False
        self.connects = 0          # successful handshakes (1 + reconnects)
        self.rejected = 0          # frames the codec refused (implausible ones included)
        self.implausible = 0       # frames that decoded but failed a plausibility check
        self.delivered = 0         # messages made available to readers
        self.ticks = 0             # reader-loop turns while connected (tests wait on this)
        self.last_error = ""
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._idle = threading.Event()     # never set: an interruptible wall-time wait
        self._thread: threading.Thread | None = None
        self._port: serial.SerialBase | None = None
        self._last_valid = 0.0
        self._retry_at = -float("inf")
        self.polling = False       # True once poll() drives this driver instead of a thread

    # -- lifecycle ---------------------------------------------------------------------------
    def start(self) -> SerialDriver:
        if self._thread is None:
            self._stop.clear()
            self._thread = threading.Thread(target=self._run, name=f"{self.name}-reader",
                                            daemon=True)
            self._thread.start()
        return self

    def close(self) -> None:
        """Stop the thread (joined) and close the port; the last words go to ``_on_close``."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=5.0)
            self._thread = None
        self._drop_port()

    def __enter__(self) -> Any:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close()

    def wait_connected(self, timeout: float = 2.0) -> bool:
        """Block (wall time) until the handshake has succeeded; for start-up and tests."""
        deadline = wire_deadline(timeout)
        while not self.connected and not deadline.expired():
            self._idle.wait(0.005)
        return self.connected

    # -- to override -------------------------------------------------------------------------
    def _handshake(self, port: serial.SerialBase) -> None:
        raise NotImplementedError

    def _on_bytes(self, data: bytes) -> None:
        raise NotImplementedError

    def _on_tick(self, port: serial.SerialBase) -> None:
        """Called after every read (at least every ``read_timeout``) while connected."""

    def _on_close(self, port: serial.SerialBase) -> None:
        """Last words before the port closes, on close and before a reconnect (stop the base,
        stop the stream). The port may already be dead: errors are ignored."""

    # -- helpers for subclasses -------------------------------------------------------------
    def mark_valid(self) -> None:
        """A valid message arrived: resets the silence timer."""
        self._last_valid = self.clock.now()

    def _waiting(self, deadline: Timeout) -> bool:
        """For reply loops in handshakes: True while ``deadline`` runs; a ``close()`` meanwhile
        aborts the handshake at once instead of letting it finish its retries."""
        if self._stop.is_set():
            raise HandshakeError("driver closing")
        return not deadline.expired()

    def _reject(self, why: str) -> None:
        self.rejected += 1
        self.last_error = why

    def _implausible(self, why: str) -> None:
        """A frame passed the protocol's own checks but not physics: dropped and counted."""
        self.implausible += 1
        self._reject(f"implausible: {why}")

    def diagnostics(self) -> dict[str, Any]:
        """The driver's health, for logs and ``mission`` output."""
        return {"name": self.name, "url": self.url, "connected": self.connected,
                "connects": self.connects, "delivered": self.delivered,
                "rejected": self.rejected, "implausible": self.implausible,
                "last_error": self.last_error}

    def _reject_decoder_errors(self, before: int, now: int, why: str) -> None:
        """Count the frames a decoder dropped (its error count went from ``before`` to ``now``)
        as rejected, with ``why`` as the last error."""
        if now != before:
            self.rejected += now - before - 1
            self._reject(why)

    # -- the thread --------------------------------------------------------------------------
    def _drop_port(self) -> None:
        port, self._port = self._port, None
        self.connected = False
        if port is not None:
            try:
                # best effort on every drop, not only on close: a base that can still hear us
                # is stopped before we reconnect (on any fault the robot gets zero velocity)
                self._on_close(port)
            except (serial.SerialException, OSError):
                pass
            try:
                port.close()
            except (serial.SerialException, OSError):
                pass

    def _run(self) -> None:
        while not self._stop.is_set():
            if self._port is None:
                if not self._connect():
                    self._stop.wait(self.retry_period)
                continue
            self._step(self._port, block=True)

    def poll(self) -> None:
        """Lock-step use without a thread: connect if needed, take in everything the device has
        sent up to now, and do the periodic writes. On a SimClock with ``sim://`` devices, a
        loop that advances the clock and polls every driver once per cycle is deterministic."""
        if self._thread is not None:
            raise RuntimeError(f"{self.name}: poll() is for drivers not started as a thread")
        self.polling = True
        if self._port is None:
            if self.clock.now() < self._retry_at:
                return
            if not self._connect():
                self._retry_at = self.clock.now() + self.retry_period
                return
        self._step(self._port, block=False)

    def _step(self, port: serial.SerialBase, block: bool) -> None:
        """One turn of the reader: read, decode, periodic writes, silence check."""
        try:
            if block:
                data = port.read(max(1, port.in_waiting))
            else:
                waiting = port.in_waiting
                data = port.read(waiting) if waiting else b""
            if data:
                self._on_bytes(data)
            self._on_tick(port)
            self.ticks += 1
        except (serial.SerialException, OSError) as e:
            self.last_error = f"{self.url}: {e}"
            self._drop_port()
            return
        except Exception as e:    # a codec bug must not kill the reader; count and go on
            self._reject(f"{self.url}: {type(e).__name__}: {e}")
        if self.clock.now() - self._last_valid > self.silence_timeout:
            self.last_error = f"{self.url}: no valid message for {self.silence_timeout} s"
            self._drop_port()       # reconnect: the device may have reset or hung

    def _connect(self) -> bool:
        try:
            port = open_port(self.url, self.baudrate, self.read_timeout)
        except Exception as e:     # a bad URL or vanished device: report, retry, never die
            self.last_error = f"{self.url}: open failed: {e}"
            return False
        self._port = port
        try:
            self._handshake(port)
        except Exception as e:     # any handshake failure means: not connected, retry later
            self.last_error = f"{self.url}: handshake failed: {type(e).__name__}: {e}"
            self._drop_port()
            return False
        self._last_valid = self.clock.now()
        self.connects += 1
        self.connected = True
        return True
