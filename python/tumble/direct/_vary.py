"""What a directed search may change, per body, within bounds the user gives, and the map from a point of the unit
cube [-1, 1]^D to a changed world: each bound the largest change from the user's start."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ._goals import _compose


def _bound(name: str, value: Any) -> float:
    if value is None:
        return 0.0
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0:
        raise ValueError(f"invalid argument `{name}`: expected a finite number >= 0, got {value!r}")
    return float(value)


def _range(name: str, value: Any) -> tuple[float, float] | None:
    if value is None:
        return None
    try:
        lo, hi = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(f"invalid argument `{name}`: expected a range (low, high), got {value!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 <= lo <= hi):
        raise ValueError(f"invalid argument `{name}`: expected 0 <= low <= high, finite, got {value!r}")
    return lo, hi


@dataclass(frozen=True)
class Vary:
    """How far a body's start may change: ``position`` (m), ``orientation`` (degrees, a turn about any axis),
    ``velocity`` (m/s) and ``spin`` (rad/s), each the largest change from the start along each axis; and, given as
    ranges (low, high), ``friction`` and ``restitution``. What is left at 0 or None is kept."""

    position: float = 0.0
    orientation: float = 0.0
    velocity: float = 0.0
    spin: float = 0.0
    friction: tuple[float, float] | None = None
    restitution: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        for name in ("position", "orientation", "velocity", "spin"):
            object.__setattr__(self, name, _bound(name, getattr(self, name)))
        object.__setattr__(self, "friction", _range("friction", self.friction))
        restitution = _range("restitution", self.restitution)
        if restitution is not None and restitution[1] > 1.0:
            raise ValueError(f"invalid argument `restitution`: must be within [0, 1], got {self.restitution!r}")
        object.__setattr__(self, "restitution", restitution)


@dataclass
class Space:
    """The search's unknowns: for each varied body (by its row in the world, so that a copy of the world sent to
    another process, whose handles are its own, is changed the same), three numbers for each vector it may change
    and one for each coefficient, each in [-1, 1]."""

    bodies: list[tuple[int, Vary]]
    slots: list[tuple[int, str, int]] = field(default_factory=list)  # (body index, what, width)

    def __post_init__(self) -> None:
        for k, (_, vary) in enumerate(self.bodies):
            for what in ("position", "orientation", "velocity", "spin"):
                if getattr(vary, what) > 0.0:
                    self.slots.append((k, what, 3))
            for what in ("friction", "restitution"):
                if getattr(vary, what) is not None:
                    self.slots.append((k, what, 1))
        if not self.slots:
            raise ValueError("invalid argument `vary`: nothing may change (give a bound > 0 for some body)")

    @property
    def dims(self) -> int:
        return sum(width for _, _, width in self.slots)

    def changes(self, u: np.ndarray, world: Any) -> list[tuple[Any, dict[str, Any]]]:
        """The set_body_state and set_material keywords of point ``u`` for each varied body of ``world``."""
        out: dict[int, dict[str, Any]] = {}
        at = 0
        for k, what, width in self.slots:
            row, vary = self.bodies[k]
            x = np.clip(u[at:at + width], -1.0, 1.0)
            at += width
            kw = out.setdefault(k, {})
            if what == "position":
                kw["position"] = world.bodies.positions[row] + vary.position * x
            elif what == "velocity":
                kw["velocity"] = world.bodies.velocities[row] + vary.velocity * x
            elif what == "spin":
                kw["angular_velocity"] = world.bodies.angular_velocities[row] + vary.spin * x
            elif what == "orientation":
                r = math.radians(vary.orientation) * x
                size = float(np.linalg.norm(r))
                limit = math.radians(vary.orientation)
                r = r * (limit / size) if size > limit else r
                angle = float(np.linalg.norm(r))
                turn = np.concatenate([[math.cos(angle / 2)], (r / angle if angle > 0 else r) * math.sin(angle / 2)])
                kw["orientation"] = _compose(turn, world.bodies.orientations[row])
            else:
                lo, hi = getattr(vary, what)
                kw[what] = lo + (hi - lo) * (float(x[0]) + 1.0) / 2.0
        handles = world.bodies.handles
        return [(handles[self.bodies[k][0]], kw) for k, kw in out.items()]

    def apply(self, u: np.ndarray, world: Any) -> None:
        """Changes ``world`` (a copy of the user's) to point ``u``."""
        for body, kw in self.changes(u, world):
            material = {k: kw.pop(k) for k in ("friction", "restitution") if k in kw}
            if kw:
                world.set_body_state(body, **kw)
            if material:
                world.set_material(body, **material)

    @staticmethod
    def size(u: np.ndarray) -> float:
        """How far point ``u`` is from the user's start: the root mean square of its numbers (0: the start, 1:
        every bound at its limit)."""
        return float(np.sqrt(np.mean(np.square(u))))
