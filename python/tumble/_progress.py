"""A progress display for long runs: a tqdm bar with the time left when standard error is a terminal, and
occasional plain lines with the time left (each quarter of the run, and at most one every ten seconds in between)
when it is a log file or a pipe, so that logs hold no carriage returns. By default the bar appears only once a run
has taken two seconds, and a log gets nothing."""

from __future__ import annotations

import sys
import time
from typing import Any, Callable, TextIO

# In a log, a line at each quarter of the run, or sooner when this many seconds have passed since the last one.
LOG_EVERY = 10.0
# The default display waits this long (s) before showing a bar: a short run shows nothing.
AUTO_DELAY = 2.0


def left(elapsed: float, fraction: float) -> str:
    """The time left, projected from the time taken for the fraction done, as a person reads it."""
    if fraction <= 0.0:
        return "time left unknown"
    rest = elapsed * (1.0 - fraction) / fraction
    if rest >= 3600.0:
        return f"about {rest / 3600.0:.1f} h left"
    if rest >= 60.0:
        return f"about {rest / 60.0:.0f} min left"
    return f"about {rest:.0f} s left"


class Progress:
    """Shows the fraction of a run done, with the time left; call it with the fraction (0 to 1), then ``close()``.
    ``write(line)`` puts a line above the bar (or into the log). ``quiet_log``: show nothing where standard error is
    not a terminal; ``delay``: seconds before a bar appears."""

    def __init__(self, label: str = "run", stream: TextIO | None = None, terminal: bool | None = None,
                 quiet_log: bool = False, delay: float = 0.0) -> None:
        self._stream = stream if stream is not None else sys.stderr
        self._start = time.perf_counter()
        self._label = label
        self._logged_quarter = 0  # the first line comes at a quarter of the run
        self._logged_at = self._start
        self._bar: Any = None
        terminal = terminal if terminal is not None else bool(getattr(self._stream, "isatty", lambda: False)())
        self._quiet = quiet_log and not terminal
        if terminal:
            try:
                from tqdm import tqdm  # noqa: PLC0415 - a dependency, imported only when shown

                self._bar = tqdm(total=100, desc=label, file=self._stream, leave=False, delay=delay,
                                 bar_format="{desc} {percentage:3.0f}%|{bar}| {elapsed}<{remaining} left")
            except ImportError:  # pragma: no cover - tqdm is a dependency; plain lines without it
                self._bar = None

    def __call__(self, fraction: float) -> None:
        if self._bar is not None:
            self._bar.update(round(100.0 * fraction) - self._bar.n)
            return
        if self._quiet:
            return
        now = time.perf_counter()
        quarter = int(4.0 * fraction + 1e-12)
        if (quarter > self._logged_quarter and fraction > 0.0) or now - self._logged_at >= LOG_EVERY:
            elapsed = now - self._start
            self._stream.write(f"{self._label} {100.0 * fraction:.0f}% done after {elapsed:.1f} s, "
                               f"{left(elapsed, fraction)}\n")
            self._stream.flush()
            self._logged_at = now
        self._logged_quarter = max(self._logged_quarter, quarter)

    def write(self, line: str) -> None:
        """Shows one line (a hint) above the bar, or in the log."""
        text = f"tumble: {line}"
        if self._bar is not None:
            self._bar.write(text, file=self._stream)
        else:
            self._stream.write(text + "\n")
            self._stream.flush()

    def close(self) -> None:
        """Ends the display (removes the bar on a terminal)."""
        if self._bar is not None:
            self._bar.close()


def progress(enabled: bool | Callable[[float], None] | None) -> Progress | Callable[[float], None] | None:
    """A callable for ``World.run``'s progress: for None (the default) a :class:`Progress` that shows a bar on a
    terminal after two seconds and nothing in a log; for ``True`` one shown from the start; the callable itself;
    None for ``False``."""
    if enabled is None:
        return Progress(quiet_log=True, delay=AUTO_DELAY)
    if enabled is True:
        return Progress()
    if callable(enabled):
        return enabled
    if enabled is False:
        return None
    raise ValueError(f"invalid argument `progress`: expected True, False, None or a callable, got {enabled!r}")
