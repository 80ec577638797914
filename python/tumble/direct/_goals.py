"""Goals of a directed search: each a cost of a run that is zero when the goal is met and grows with how far the run
missed it, in metres (angles count as the arc they sweep at ``ARM`` metres, speeds over ``SETTLE`` seconds), so that
goals of different kinds add up. Goals name bodies by handle; a search reads them by their rows in the world."""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np

from .._geometry import quaternion_to_matrix

# How angles and speeds count in a cost: an angle as the arc it sweeps 0.1 m from the axis, a speed as the distance
# it covers in 0.1 s.
ARM = 0.1
SETTLE = 0.1
# The speed below which a body counts as at rest (m/s).
REST_SPEED = 0.01


def _vector(name: str, value: Any, size: int = 3) -> np.ndarray:
    v = np.asarray(value, dtype=float)
    if v.shape != (size,) or not np.all(np.isfinite(v)):
        raise ValueError(f"invalid argument `{name}`: expected {size} finite numbers, got {value!r}")
    return v


def _positive(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
        raise ValueError(f"invalid argument `{name}`: expected a finite number > 0, got {value!r}")
    return float(value)


def _optional(name: str, value: Any) -> float | None:
    """``value`` checked as ``_positive``'s, or None."""
    return None if value is None else _positive(name, value)


def _angle(q: np.ndarray, target: np.ndarray) -> float:
    """The angle (rad) between two unit quaternions (w, x, y, z)."""
    return 2.0 * math.acos(min(1.0, abs(float(np.dot(q / np.linalg.norm(q), target)))))


class Goal(ABC):
    """A goal: ``cost(run, rows)`` (rows: each body handle's row in the run) is 0 when met. ``a & b`` is both."""

    @abstractmethod
    def cost(self, run: Any, rows: dict[Any, int]) -> float:
        """How far ``run`` missed the goal (m; 0: met)."""

    def bodies(self) -> list[Any]:
        """The body handles the goal names."""
        return []

    def __and__(self, other: Goal) -> Goal:
        return All([self, as_goal(other)])


@dataclass
class All(Goal):
    """Every goal of ``goals``: their costs summed (zero only when each is met)."""

    goals: list[Goal]

    def cost(self, run: Any, rows: dict[Any, int]) -> float:
        return float(sum(g.cost(run, rows) for g in self.goals))

    def bodies(self) -> list[Any]:
        return [b for g in self.goals for b in g.bodies()]

    def __and__(self, other: Goal) -> Goal:
        return All([*self.goals, as_goal(other)])


@dataclass
class Callable_(Goal):
    """A cost the user wrote: ``function(run) -> float`` (zero when met; negative counts as zero)."""

    function: Callable[[Any], float]

    def cost(self, run: Any, rows: dict[Any, int]) -> float:
        value = float(self.function(run))
        if not math.isfinite(value):
            raise ValueError(f"invalid argument `goal`: the cost function returned {value!r}")
        return max(0.0, value)


def as_goal(goal: Any) -> Goal:
    """A goal, or a callable made one; anything else is refused naming ``goal``."""
    if isinstance(goal, Goal):
        return goal
    if callable(goal):
        return Callable_(goal)
    raise ValueError(f"invalid argument `goal`: expected a tumble.direct goal or a function of the run, got {goal!r}")


@dataclass
class _RestAt(Goal):
    body: Any
    position: np.ndarray
    within: float
    angle: float | None
    orientation: np.ndarray | None

    def cost(self, run: Any, rows: dict[Any, int]) -> float:
        row = rows[self.body]
        x, v = run.body_positions[-1, row], run.body_velocities[-1, row]
        miss = max(0.0, float(np.linalg.norm(x - self.position)) - self.within)
        if self.orientation is not None:
            allowed = self.angle if self.angle is not None else math.radians(5.0)
            miss += ARM * max(0.0, _angle(run.body_orientations[-1, row], self.orientation) - allowed)
        return miss + SETTLE * max(0.0, float(np.linalg.norm(v)) - REST_SPEED)

    def bodies(self) -> list[Any]:
        return [self.body]


def rest_at(body: Any, position: Sequence[float] | np.ndarray, within: float = 0.01, angle: float | None = None,
            orientation: Sequence[float] | None = None) -> Goal:
    """``body`` at rest at the run's end (its speed below 1 cm/s) within ``within`` metres of ``position``, and,
    given an ``orientation`` (w, x, y, z), turned within ``angle`` degrees of it (5 by default)."""
    return _RestAt(body, _vector("position", position), (_positive("within", within)),
                   None if angle is None else math.radians((_positive("angle", angle))),
                   None if orientation is None else _unit(_vector("orientation", orientation, 4)))


def _unit(q: np.ndarray) -> np.ndarray:
    n = float(np.linalg.norm(q))
    if n == 0.0:
        raise ValueError("invalid argument `orientation`: a quaternion of length zero")
    return q / n


@dataclass
class _FaceUp(Goal):
    body: Any
    axis: np.ndarray
    within: float

    def cost(self, run: Any, rows: dict[Any, int]) -> float:
        row = rows[self.body]
        up = quaternion_to_matrix(run.body_orientations[-1, row]) @ self.axis
        tilt = math.acos(max(-1.0, min(1.0, float(up[2]))))
        v = float(np.linalg.norm(run.body_velocities[-1, row]))
        return ARM * max(0.0, tilt - self.within) + SETTLE * max(0.0, v - REST_SPEED)

    def bodies(self) -> list[Any]:
        return [self.body]


def face_up(body: Any, axis: Sequence[float], within: float = 10.0) -> Goal:
    """``body`` at rest at the run's end with its body-frame ``axis`` pointing up (+z), within ``within``
    degrees: a die's face (the axis through that face's centre) up."""
    a = _vector("axis", axis)
    if np.linalg.norm(a) == 0.0:
        raise ValueError("invalid argument `axis`: a vector of length zero")
    return _FaceUp(body, a / np.linalg.norm(a), math.radians((_positive("within", within))))


def _frames_before(run: Any, before: float | None) -> slice:
    if before is None:
        return slice(None)
    return slice(0, max(1, int(np.searchsorted(run.times, before, side="right"))))


@dataclass
class _PassesThrough(Goal):
    body: Any
    centre: np.ndarray
    radius: float
    before: float | None

    def cost(self, run: Any, rows: dict[Any, int]) -> float:
        path = run.body_positions[_frames_before(run, self.before), rows[self.body]]
        return max(0.0, float(np.linalg.norm(path - self.centre, axis=1).min()) - self.radius)

    def bodies(self) -> list[Any]:
        return [self.body]


def passes_through(body: Any, centre: Sequence[float], radius: float, before: float | None = None) -> Goal:
    """``body``'s centre of mass within ``radius`` metres of ``centre`` at some frame (up to ``before`` seconds)."""
    return _PassesThrough(body, _vector("centre", centre), (_positive("radius", radius)),
                          _optional("before", before))


@dataclass
class _Touches(Goal):
    a: Any
    b: Any
    before: float | None
    touching: bool
    reach: float

    def cost(self, run: Any, rows: dict[Any, int]) -> float:
        frames = range(run.frames)[_frames_before(run, self.before)]
        nearest = min(_distance(run, rows[self.a], rows[self.b], f) for f in frames)
        if self.touching:
            return max(0.0, nearest - self.reach)
        return max(0.0, self.reach - nearest)

    def bodies(self) -> list[Any]:
        return [self.a, self.b]


def _distance(run: Any, a: int, b: int, f: int) -> float:
    """The distance between bodies in rows ``a`` and ``b`` at frame ``f`` (their colliders' nearest pair)."""
    def posed(row: int) -> list[tuple[Any, np.ndarray, np.ndarray]]:
        x, q = run.body_positions[f, row], run.body_orientations[f, row]
        r = quaternion_to_matrix(q)
        return [(shape, x + r @ np.asarray(offset, dtype=float), _compose(q, np.asarray(turn, dtype=float)))
                for shape, offset, turn in run.shapes[row]]
    pairs = [(sa, xa, qa, sb, xb, qb) for sa, xa, qa in posed(a) for sb, xb, qb in posed(b)]
    if not pairs:
        raise ValueError("invalid argument `goal`: touches() needs two bodies with shapes")
    return float(min(sa.distance(xa, qa, sb, xb, qb) for sa, xa, qa, sb, xb, qb in pairs))


def _compose(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The quaternion product p q (w, x, y, z)."""
    w1, v1, w2, v2 = p[0], p[1:], q[0], q[1:]
    return np.concatenate([[w1 * w2 - v1 @ v2], w1 * v2 + w2 * v1 + np.cross(v1, v2)])


def touches(a: Any, b: Any, before: float | None = None, touching: bool = True, reach: float = 1e-3) -> Goal:
    """Bodies ``a`` and ``b`` within ``reach`` metres of each other at some frame (up to ``before`` seconds), by
    their shapes; ``touching=False``: never that near."""
    return _Touches(a, b, _optional("before", before), bool(touching),
                    (_positive("reach", reach)))


@dataclass
class _PoseAt(Goal):
    body: Any
    time: float
    position: np.ndarray
    orientation: np.ndarray | None
    within: float

    def cost(self, run: Any, rows: dict[Any, int]) -> float:
        f = int(np.argmin(np.abs(run.times - self.time)))
        row = rows[self.body]
        miss = max(0.0, float(np.linalg.norm(run.body_positions[f, row] - self.position)) - self.within)
        if self.orientation is not None:
            miss += ARM * max(0.0, _angle(run.body_orientations[f, row], self.orientation) - math.radians(5.0))
        return miss

    def bodies(self) -> list[Any]:
        return [self.body]


def pose_at(body: Any, time: float, position: Sequence[float], orientation: Sequence[float] | None = None,
            within: float = 0.01) -> Goal:
    """``body`` at the frame nearest ``time`` within ``within`` metres of ``position`` (a keyframe), and turned
    within 5 degrees of ``orientation`` (w, x, y, z) if given."""
    if isinstance(time, bool) or not isinstance(time, (int, float)) or not math.isfinite(time) or time < 0:
        raise ValueError(f"invalid argument `time`: expected a finite number >= 0, got {time!r}")
    return _PoseAt(body, float(time), _vector("position", position),
                   None if orientation is None else _unit(_vector("orientation", orientation, 4)),
                   (_positive("within", within)))
