"""pyserial URL handler for ``sim://<device>?id=..&<faults>``: a port wired to an emulator.

pyserial imports this module when ``hw.emulators`` is in ``serial.protocol_handler_packages``
(importing ``hw.emulators`` puts it there). Reads follow pyserial's timeout semantics; an unplugged
device makes ``open``, ``read`` and ``write`` raise ``SerialException`` like a vanished tty does.
"""

from __future__ import annotations

import threading

from serial.serialutil import PortNotOpenError, SerialBase, SerialException, Timeout

from hw.emulators import link_for_url
from hw.emulators.link import Link, Unplugged

_POLL_S = 0.001   # wall-time poll while waiting for a timed emulator to produce bytes


class Serial(SerialBase):
    """A serial port whose other end is an emulated device."""

    def __init__(self, *args, **kwargs) -> None:
        self._link: Link | None = None
        self._gen = -1
        self._rx = bytearray()
        self._wake = threading.Event()      # never set: used only as an interruptible wait
        super().__init__(*args, **kwargs)

    def open(self) -> None:
        if self.is_open:
            raise SerialException("Port is already open.")
        if self._port is None:
            raise SerialException("Port must be configured before it can be used.")
        try:
            link = link_for_url(self._port)
        except ValueError as e:
            raise SerialException(str(e)) from None
        if not link.plugged:
            raise SerialException(f"could not open port {self._port}: device not present")
        self._link, self._gen = link, link.generation
        self._rx.clear()
        self.is_open = True
        self._reconfigure_port()

    def close(self) -> None:
        self.is_open = False
        self._link = None

    def _reconfigure_port(self) -> None:
        if self._link is not None:
            self._link.set_baudrate(self._baudrate)

    def _live(self) -> Link:
        if not self.is_open or self._link is None:
            raise PortNotOpenError()
        link = self._link
        if link.generation != self._gen or not link.plugged:
            raise SerialException(f"{self._port}: device disconnected")
        return link

    def _pull(self) -> None:
        link = self._live()
        try:
            self._rx += link.read()
        except Unplugged:
            raise SerialException(f"{self._port}: device disconnected") from None

    @property
    def in_waiting(self) -> int:
        self._pull()
        return len(self._rx)

    def read(self, size: int = 1) -> bytes:
        timeout = Timeout(self._timeout)
        self._pull()
        while len(self._rx) < size and not timeout.expired():
            self._wake.wait(_POLL_S if self._timeout is None else
                            min(_POLL_S, max(timeout.time_left(), 0.0)))
            self._pull()
        out = bytes(self._rx[:size])
        del self._rx[:size]
        return out

    def write(self, data: bytes) -> int:
        link = self._live()
        data = bytes(data)
        try:
            link.write(data)
        except Unplugged:
            raise SerialException(f"{self._port}: device disconnected") from None
        return len(data)

    def reset_input_buffer(self) -> None:
        self._pull()
        self._rx.clear()

    def reset_output_buffer(self) -> None:
        self._live()

    def flush(self) -> None:
        self._live()

    @property
    def out_waiting(self) -> int:
        return 0

    def _update_break_state(self) -> None:
        pass

    def _update_rts_state(self) -> None:
        pass

    def _update_dtr_state(self) -> None:
        pass

    @property
    def cts(self) -> bool:
        return True

    @property
    def dsr(self) -> bool:
        return True

    @property
    def ri(self) -> bool:
        return False

    @property
    def cd(self) -> bool:
        return True
