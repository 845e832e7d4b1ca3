"""Line framing shared by the ASCII protocols (ros_arduino_bridge, Razor, VectorNav). No I/O."""

from __future__ import annotations


class LineDecoder:
    """Splits a byte stream into lines at ``terminator``; CR/LF around a line are stripped.
    A line with control or non-ASCII bytes, or a run longer than ``max_line`` without a
    terminator, is dropped and counted in ``errors``."""

    def __init__(self, terminator: bytes = b"\n", max_line: int = 256) -> None:
        self._buf = bytearray()
        self._term = terminator
        self._max = max_line
        self.errors = 0

    def reset(self) -> None:
        self._buf.clear()

    def feed(self, chunk: bytes) -> list[str]:
        self._buf += chunk
        out = []
        while True:
            k = self._buf.find(self._term)
            if k < 0:
                if len(self._buf) > self._max:
                    self.errors += 1
                    self._buf.clear()
                return out
            raw = bytes(self._buf[:k]).strip(b"\r\n")
            del self._buf[:k + 1]
            if any(c < 0x20 or c > 0x7E for c in raw):
                self.errors += 1
                continue
            out.append(raw.decode("ascii"))
