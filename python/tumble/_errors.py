"""Argument errors that name the argument. The compiled module's conversions raise ``TypeError`` (a wrong type) or
``OverflowError`` (an integer out of range) with the argument's name only in a note ("while processing 'x'"); these
helpers put the name in the message, as every other bad argument has it, and turn an out-of-range integer into a
``ValueError``."""

from __future__ import annotations

import functools
import os
import re
from pathlib import Path
from typing import Any, Callable, TypeVar

F = TypeVar("F", bound=Callable[..., Any])

_PROCESSING = re.compile(r"while processing '([^']+)'")


def renamed(error: BaseException) -> BaseException | None:
    """The error with its argument named in the message, or None when it names no argument."""
    if not isinstance(error, (TypeError, OverflowError)):
        return None
    for note in getattr(error, "__notes__", ()):
        match = _PROCESSING.search(note)
        if match:
            kind = ValueError if isinstance(error, OverflowError) else TypeError
            name = match.group(1).removeprefix("r#")  # a Rust raw identifier (`static`)
            return kind(f"invalid argument `{name}`: {error}")
    return None


def named_arguments(function: F) -> F:
    """Wraps a compiled method so that its argument errors name the argument."""

    @functools.wraps(function)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return function(*args, **kwargs)
        except (TypeError, OverflowError) as error:
            better = renamed(error)
            if better is None:
                raise
            raise better from error

    return wrapper  # type: ignore[return-value]


def as_path(value: Any, name: str = "path") -> Path:
    """``value`` (a str or os.PathLike) as a Path, or a TypeError naming the argument."""
    if not isinstance(value, (str, os.PathLike)):
        raise TypeError(f"invalid argument `{name}`: expected a str or os.PathLike path, got {type(value).__name__}")
    return Path(value)
