"""Serve an emulated device over TCP, for a driver in another process (``socket://host:port``).

One client at a time, as a serial line has one host. Unplugging closes the client's connection
and refuses new ones until replugged, which a pyserial ``socket://`` port reports as a
disconnection.
"""

from __future__ import annotations

import select
import socket
import threading

from hw.emulators.link import Link, Unplugged


class TcpDevice:
    """A TCP server whose single client talks to the emulated device. Context manager."""

    def __init__(self, link: Link, host: str = "127.0.0.1", port: int = 0,
                 poll: float = 0.002) -> None:
        self.link = link
        self._poll = poll
        self._srv = socket.create_server((host, port))
        self._srv.setblocking(False)
        self.address = self._srv.getsockname()[:2]
        self.url = f"socket://{self.address[0]}:{self.address[1]}"
        self._client: socket.socket | None = None
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="tcp-device", daemon=True)

    def start(self) -> TcpDevice:
        self._thread.start()
        return self

    def close(self) -> None:
        self._stop.set()
        self._thread.join(timeout=5.0)
        self._drop()
        self._srv.close()

    def __enter__(self) -> TcpDevice:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _drop(self) -> None:
        if self._client is not None:
            try:
                self._client.close()
            except OSError:
                pass
            self._client = None

    def _run(self) -> None:
        while not self._stop.is_set():
            socks = [self._srv] + ([self._client] if self._client else [])
            r, _, _ = select.select(socks, [], [], self._poll)
            if self._srv in r:
                try:
                    conn, _ = self._srv.accept()
                except OSError:
                    conn = None
                if conn is not None:
                    if self._client is not None or not self.link.plugged:
                        conn.close()          # busy or powered off: the connection is refused
                    else:
                        conn.setblocking(True)
                        self._client = conn
            if self._client is None:
                continue
            if not self.link.plugged:
                self._drop()
                continue
            try:
                if self._client in r:
                    data = self._client.recv(4096)
                    if not data:
                        self._drop()
                        continue
                    self.link.write(data)
                out = self.link.read()
                if out:
                    self._client.sendall(out)
            except Unplugged:
                self._drop()
            except OSError:
                self._drop()
