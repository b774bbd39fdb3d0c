"""A quiet-able progress bar on stderr for long computations."""

from __future__ import annotations

import sys
import time

__all__ = ["Progress"]


class Progress:
    """``Progress(total, label)``; call ``advance()``; ``close()`` at the end.

    Writes nothing when ``quiet`` is set or ``total`` is small; redraws at most
    ten times a second.
    """

    def __init__(self, total: int, label: str, *, quiet: bool = False, stream=None):
        self.total, self.label, self.done = max(int(total), 1), label, 0
        self.quiet = quiet
        self.stream = stream if stream is not None else sys.stderr
        self._last = 0.0
        self._start = time.perf_counter()

    def advance(self, count: int = 1) -> None:
        self.done += count
        now = time.perf_counter()
        if not self.quiet and (now - self._last > 0.1 or self.done >= self.total):
            self._last = now
            filled = int(30 * self.done / self.total)
            self.stream.write(
                f"\r{self.label} [{'#' * filled}{'.' * (30 - filled)}] "
                f"{self.done}/{self.total} {now - self._start:.1f} s"
            )
            self.stream.flush()

    def close(self) -> None:
        if not self.quiet:
            self.stream.write("\n")
            self.stream.flush()
