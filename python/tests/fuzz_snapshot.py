"""Reading a fuzzed world and a call's result, and comparing them bit for bit (NaN-safe), for the checks of
``fuzz_execution.py`` and ``fuzz_saved.py``. Part of ``test_fuzz.py``."""

from __future__ import annotations

import dataclasses
import hashlib
import struct
from typing import Any

import numpy as np

import tumble


class Failure(Exception):
    def __init__(self, kind: str, message: str) -> None:
        super().__init__(message)
        self.kind = kind
        self.message = message


def canon(v: Any) -> bytes:
    """Bit-exact bytes of a value (NaN-safe: NaN payloads compare by bits)."""
    if isinstance(v, np.ndarray):
        return repr((v.dtype.str, v.shape)).encode() + np.ascontiguousarray(v).tobytes()
    if isinstance(v, (float, np.floating)):
        return b"f" + struct.pack("<d", float(v))
    if isinstance(v, (list, tuple)):
        return b"(" + b",".join(canon(x) for x in v) + b")"
    if isinstance(v, dict):
        return b"{" + b",".join(repr(k).encode() + b":" + canon(x) for k, x in v.items()) + b"}"
    return repr(v).encode()


def numbers(v: Any, path: str = ""):
    """Every float in a value, with where it is."""
    if isinstance(v, np.ndarray):
        if v.dtype.kind in "fc":
            yield path, v
    elif isinstance(v, (float, np.floating)):
        yield path, np.float64(v)
    elif isinstance(v, (list, tuple)):
        for k, x in enumerate(v):
            yield from numbers(x, f"{path}[{k}]")
    elif isinstance(v, dict):
        for k, x in v.items():
            yield from numbers(x, f"{path}[{k!r}]")


def non_finite(v: Any) -> list[str]:
    return [p or "value" for p, a in numbers(v) if not np.all(np.isfinite(a))]


def snapshot(w) -> list[tuple[str, Any]]:
    """The world's state as (name, value) pairs; raises Failure if reading it fails."""
    try:
        return [
            ("time", w.time),
            ("gravity", w.gravity),
            ("mode", w.mode),
            ("threads", w.threads),
            ("plan", repr(w.plan())),
            ("particle handles", [(h.index, h.generation) for h in w.particles.handles]),
            ("body handles", [(h.index, h.generation) for h in w.bodies.handles]),
            ("particles.positions", w.particles.positions),
            ("particles.velocities", w.particles.velocities),
            ("bodies.positions", w.bodies.positions),
            ("bodies.orientations", w.bodies.orientations),
            ("bodies.velocities", w.bodies.velocities),
            ("bodies.angular_velocities", w.bodies.angular_velocities),
            ("kinetic_energy()", w.kinetic_energy()),
            ("potential_energy()", w.potential_energy()),
            ("momentum()", w.momentum()),
            ("angular_momentum()", w.angular_momentum()),
        ]
    except BaseException as e:  # noqa: BLE001 - a panic is a BaseException
        raise Failure("ReadingStateFailed", f"reading the state raised {type(e).__name__}: {e}") from None


def diff(a: list, b: list) -> list[str]:
    out = []
    for (name, x), (_, y) in zip(a, b):
        if canon(x) != canon(y):
            out.append(f"{name}: {short(x)} -> {short(y)}")
    return out


def short(v: Any) -> str:
    s = repr(v).replace("\n", " ")
    return s if len(s) < 300 else s[:300] + "..."


def digest(v: Any) -> str:
    """A digest of a call's result (what is deterministic of it)."""
    if isinstance(v, tumble.Run):
        v = [(f.name, getattr(v, f.name)) for f in dataclasses.fields(v) if f.name not in ("report", "shapes")]
    elif isinstance(v, tumble.Report):
        return "report"
    elif isinstance(v, tuple) and v and isinstance(v[0], str):
        return repr(v)
    return hashlib.sha1(canon(v)).hexdigest()[:16]
