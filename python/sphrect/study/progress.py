"""A small stderr progress bar (no dependency): `with ProgressBar(total, "runs") as bar: bar.update()`."""
from __future__ import annotations

import sys
import time


def _format_seconds(seconds: float) -> str:
    seconds = max(0, int(round(seconds)))
    h, rest = divmod(seconds, 3600)
    m, s = divmod(rest, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m:02d}:{s:02d}"


class ProgressBar:
    """Redraws one line on stderr (with \\r on a terminal; a new line every 10% otherwise, so logs stay short)."""

    def __init__(self, total: float, label: str = "", width: int = 30, stream=None, enabled: bool = True):
        self.total = max(float(total), 1e-12)
        self.label = label
        self.width = width
        self.stream = stream if stream is not None else sys.stderr
        self.enabled = enabled
        self.done = 0.0
        self.note = ""
        self.start = time.monotonic()
        self._tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self._last_decile = -1
        self._last_draw = 0.0

    def update(self, amount: float = 1.0, note: str | None = None) -> None:
        self.set(self.done + amount, note)

    def set(self, done: float, note: str | None = None) -> None:
        self.done = min(float(done), self.total)
        if note is not None:
            self.note = note
        self._draw()

    def _line(self) -> str:
        fraction = self.done / self.total
        filled = int(round(self.width * fraction))
        elapsed = time.monotonic() - self.start
        eta = elapsed * (1 - fraction) / fraction if fraction > 0 else float("nan")
        eta_text = _format_seconds(eta) if fraction > 0 else "--:--"
        count = f"{self.done:g}/{self.total:g}"
        return (f"{self.label} [{'#' * filled}{'.' * (self.width - filled)}] {100 * fraction:5.1f}% {count} "
                f"{_format_seconds(elapsed)}<{eta_text} {self.note}")

    def _draw(self, final: bool = False) -> None:
        if not self.enabled:
            return
        if self._tty:
            now = time.monotonic()
            if final or now - self._last_draw > 0.1 or self.done >= self.total:
                self._last_draw = now
                self.stream.write("\r\033[K" + self._line())
                self.stream.flush()
        else:
            decile = int(10 * self.done / self.total)
            if decile != self._last_decile or final:
                self._last_decile = decile
                self.stream.write(self._line() + "\n")
                self.stream.flush()

    def close(self) -> None:
        if self.enabled and self._tty:
            self._draw(final=True)
            self.stream.write("\n")
            self.stream.flush()

    def __enter__(self) -> "ProgressBar":
        self._draw()
        return self

    def __exit__(self, *exc) -> None:
        self.close()
