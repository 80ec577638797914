"""A progress display for long runs: tqdm when it is installed, a one-line counter on stderr otherwise."""

from __future__ import annotations

import sys
import time
from typing import Callable


class Progress:
    """Shows the fraction of a run done; call it with the fraction, then ``close()``."""

    def __init__(self, label: str = "run") -> None:
        self._start = time.perf_counter()
        self._label = label
        self._last = -1.0
        try:
            from tqdm import tqdm  # noqa: PLC0415 - optional dependency

            self._bar = tqdm(total=100, desc=label, bar_format="{desc} {percentage:3.0f}%|{bar}| {elapsed}<{remaining}", leave=False)
        except ImportError:
            self._bar = None

    def __call__(self, fraction: float) -> None:
        percent = 100.0 * fraction
        if self._bar is not None:
            self._bar.update(round(percent) - self._bar.n)
        elif percent - self._last >= 5.0 or fraction >= 1.0:
            elapsed = time.perf_counter() - self._start
            sys.stderr.write(f"\r{self._label} {percent:5.1f}% ({elapsed:.1f} s)")
            sys.stderr.flush()
            self._last = percent

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
        elif self._last >= 0.0:
            sys.stderr.write("\n")


def progress(enabled: bool | Callable[[float], None]) -> Progress | Callable[[float], None] | None:
    """A callable for ``World.run``'s progress: a :class:`Progress` for ``True``, the callable itself, or None."""
    if enabled is True:
        return Progress()
    if callable(enabled):
        return enabled
    if enabled is False or enabled is None:
        return None
    raise ValueError(f"invalid argument `progress`: expected True, False, None or a callable, got {enabled!r}")
