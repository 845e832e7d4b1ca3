"""Serve an emulated device on a pty pair, so a driver talks to it through a real tty.

The driver opens ``PtyDevice.port_name`` (``/dev/pts/N``) as an ordinary serial port. A thread
shuttles bytes between the pty master and the emulator's ``Link``. Unplugging here makes the
device fall silent and discard input (the tty node itself stays, as with a USB adapter whose
device has lost power); the driver must notice the silence and reconnect.
"""

from __future__ import annotations

import os
import select
import threading
import tty

from hw.emulators.link import Link, Unplugged


class PtyDevice:
    """A pty pair whose master end is the emulated device. Use as a context manager."""

    def __init__(self, link: Link, poll: float = 0.002) -> None:
        self.link = link
        self._poll = poll
        self._master, self._slave = os.openpty()
        tty.setraw(self._slave)      # no echo, no line discipline: bytes pass unchanged
        os.set_blocking(self._master, False)   # a full tty buffer must not wedge the thread
        self.port_name = os.ttyname(self._slave)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="pty-device", daemon=True)

    def start(self) -> PtyDevice:
        self._thread.start()
        return self

    def close(self) -> None:
        self._stop.set()
        self._thread.join(timeout=5.0)
        for fd in (self._master, self._slave):
            try:
                os.close(fd)
            except OSError:
                pass

    def __enter__(self) -> PtyDevice:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _run(self) -> None:
        while not self._stop.is_set():
            r, _, _ = select.select([self._master], [], [], self._poll)
            if r:
                try:
                    data = os.read(self._master, 4096)
                except OSError:
                    data = b""
                if data:
                    try:
                        self.link.write(data)
                    except Unplugged:
                        pass             # a powered-off device ignores what it is sent
            try:
                out = self.link.read()
            except Unplugged:
                continue
            view = memoryview(out)
            while view and not self._stop.is_set():
                try:
                    n = os.write(self._master, view)
                except BlockingIOError:
                    self._stop.wait(self._poll)
                    continue
                except OSError:
                    break
                view = view[n:]
