"""A progress display for long runs: a tqdm bar when standard error is a terminal, and occasional plain lines
(each quarter of the run, and at most one every ten seconds in between) when it is a log file or a pipe, so that
logs hold no carriage returns."""

from __future__ import annotations

import sys
import time
from typing import Any, Callable, TextIO

# In a log, a line at each quarter of the run, or sooner when this many seconds have passed since the last one.
LOG_EVERY = 10.0


class Progress:
    """Shows the fraction of a run done; call it with the fraction (0 to 1), then ``close()``."""

    def __init__(self, label: str = "run", stream: TextIO | None = None, terminal: bool | None = None) -> None:
        self._stream = stream if stream is not None else sys.stderr
        self._start = time.perf_counter()
        self._label = label
        self._logged_quarter = 0  # the first line comes at a quarter of the run
        self._logged_at = self._start
        self._bar: Any = None
        terminal = terminal if terminal is not None else bool(getattr(self._stream, "isatty", lambda: False)())
        if terminal:
            try:
                from tqdm import tqdm  # noqa: PLC0415 - a dependency, imported only when shown

                self._bar = tqdm(total=100, desc=label, file=self._stream, leave=False,
                                 bar_format="{desc} {percentage:3.0f}%|{bar}| {elapsed}<{remaining}")
            except ImportError:  # pragma: no cover - tqdm is a dependency; plain lines without it
                self._bar = None

    def __call__(self, fraction: float) -> None:
        if self._bar is not None:
            self._bar.update(round(100.0 * fraction) - self._bar.n)
            return
        now = time.perf_counter()
        quarter = int(4.0 * fraction + 1e-12)
        if (quarter > self._logged_quarter and fraction > 0.0) or now - self._logged_at >= LOG_EVERY:
            self._stream.write(f"{self._label} {100.0 * fraction:.0f}% done after {now - self._start:.1f} s\n")
            self._stream.flush()
            self._logged_at = now
        self._logged_quarter = max(self._logged_quarter, quarter)

    def close(self) -> None:
        """Ends the display (removes the bar on a terminal)."""
        if self._bar is not None:
            self._bar.close()


def progress(enabled: bool | Callable[[float], None] | None) -> Progress | Callable[[float], None] | None:
    """A callable for ``World.run``'s progress: a :class:`Progress` for ``True``, the callable itself, or None."""
    if enabled is True:
        return Progress()
    if callable(enabled):
        return enabled
    if enabled is False or enabled is None:
        return None
    raise ValueError(f"invalid argument `progress`: expected True, False, None or a callable, got {enabled!r}")
