"""A one-line progress display that stays quiet when the output is not a terminal (CI logs)."""

from __future__ import annotations

import sys
from typing import TextIO


class Progress:
    """Rewrites one status line with ``\\r``; silent unless ``stream`` is a TTY (or forced)."""

    def __init__(self, stream: TextIO | None = None, enabled: bool | None = None,
                 every: int = 10) -> None:
        self.stream = stream if stream is not None else sys.stdout
        isatty = getattr(self.stream, "isatty", lambda: False)
        self.enabled = isatty() if enabled is None else enabled
        self.every = max(1, every)
        self._n = 0
        self._width = 0

    def update(self, text: str) -> None:
        self._n += 1
        if not self.enabled or self._n % self.every:
            return
        pad = max(0, self._width - len(text))
        self.stream.write("\r" + text + " " * pad)
        self.stream.flush()
        self._width = len(text) + pad  # what is on the line now, padding included

    def done(self) -> None:
        if self.enabled and self._width:
            self.stream.write("\r" + " " * self._width + "\r")
            self.stream.flush()
            self._width = 0


def bar(fraction: float, width: int = 20) -> str:
    fraction = min(1.0, max(0.0, fraction))
    full = int(round(fraction * width))
    return "[" + "#" * full + "." * (width - full) + "]"
