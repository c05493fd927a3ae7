"""The progress bar of the commands: one line on a terminal or in a notebook, silent elsewhere.

``hardspheres run`` (through :class:`hardspheres.cli.run.ProgressWriter`),
``compress``, ``sweep`` and ``render`` all draw this bar: how far, the rate,
and the time left.  It is written by hand rather than with ``tqdm`` (not a
dependency): a few lines, and the same look on every command.

Example:
    >>> import io
    >>> bar = Progress(10.0, stream=io.StringIO(), enabled=True)
    >>> bar.line(10.0, label="t=10")
    '[##############################] 100.0%  t=10  done'
"""

from __future__ import annotations

import math
import sys
import time
from typing import TextIO


def isatty(stream: TextIO) -> bool:
    """Whether ``stream`` is a terminal (``False`` for anything that cannot say)."""
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False


def in_notebook(stream: TextIO) -> bool:
    """Whether ``stream`` is a Jupyter kernel's output (ipykernel's ``OutStream``).

    A notebook shows such a stream as the cell's output and honours ``\\r``
    there, so the bar redraws in place as on a terminal.
    """
    return type(stream).__module__.split(".")[0] == "ipykernel"


def duration(seconds: float) -> str:
    """``42 s``, ``3 min 5 s``, ``2 h 10 min`` (``?`` if not finite).

    Example:
        >>> duration(185.2), duration(7800), duration(float("inf"))
        ('3 min 5 s', '2 h 10 min', '?')
    """
    if not math.isfinite(seconds):
        return "?"
    whole = max(0, round(seconds))
    if whole < 60:
        return f"{whole} s"
    if whole < 3600:
        return f"{whole // 60} min {whole % 60} s"
    return f"{whole // 3600} h {whole % 3600 // 60} min"


class Progress:
    """A one-line progress bar with rate and time left, on a terminal or in a notebook; silent otherwise.

    Every update rewrites the whole line (padded over the previous one), and
    :meth:`close` clears it, so no stale characters remain.

    Args:
        total: how much there is to do (a time, a count of frames or tasks).
        stream: where to draw (default: stderr).
        enabled: draw or not (default: whether ``stream`` is a terminal or
            a Jupyter notebook's output).
        unit: what the rate counts (``events`` -> "events/s").
        every: redraw at most this often [s] (the last step always shows;
            in a notebook at most four times a second).
    """

    def __init__(
        self,
        total: float,
        stream: TextIO | None = None,
        enabled: bool | None = None,
        unit: str = "events",
        every: float = 0.0,
    ) -> None:
        self.total = total
        self.stream = sys.stderr if stream is None else stream
        notebook = in_notebook(self.stream)
        self.on = (isatty(self.stream) or notebook) if enabled is None else bool(enabled)
        self.unit = unit
        self.every = max(every, 0.25) if notebook else every
        self.t0 = time.perf_counter()
        self.width = 0
        self._text = ""
        self._shown = -math.inf

    def line(self, done: float, events: float = 0, label: str = "") -> str:
        """The text of the bar after ``done`` of ``total``, ``events`` counted so far."""
        frac = min(1.0, done / self.total) if self.total > 0 else 1.0
        wall = time.perf_counter() - self.t0
        rate = f"{events / wall:.3g} {self.unit}/s" if wall > 0 and events else ""
        left = wall * (1.0 - frac) / frac if frac > 0 else math.inf
        eta = f"{duration(left)} left" if frac < 1.0 else "done"
        bar = "#" * int(30 * frac)
        parts = [f"[{bar:<30}] {frac:6.1%}", label, rate, eta]
        return "  ".join(p for p in parts if p)

    def update(self, done: float, events: float = 0, label: str = "") -> None:
        """Redraw the bar: ``done`` of ``total``, ``events`` counted (the rate), a ``label``."""
        if not self.on:
            return
        now = time.perf_counter()
        if now - self._shown < self.every and done < self.total:
            return
        self._shown = now
        self._text = self.line(done, events, label)
        self._show()

    def _show(self) -> None:
        text = self._text
        pad = max(0, self.width - len(text))
        self.width = len(text) + pad  # what the terminal line holds now
        self.stream.write("\r" + text + " " * pad)
        self.stream.flush()

    def clear(self) -> None:
        """Blank the bar's line (for words of the caller's own); :meth:`redraw` brings it back."""
        if self.on and self.width:
            self.stream.write("\r" + " " * self.width + "\r")
            self.stream.flush()
            self.width = 0

    def redraw(self) -> None:
        """Draw the bar again after :meth:`clear`."""
        if self.on and self._text:
            self._show()

    def note(self, text: str) -> None:
        """One line on the stream, above the bar."""
        self.clear()
        self.stream.write(text + "\n")
        self.stream.flush()
        self.redraw()

    def close(self) -> None:
        """Clear the bar for good."""
        self.clear()
        self._text = ""
