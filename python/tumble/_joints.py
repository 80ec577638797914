"""Joints as Python objects: ``tumble.Ball``, ``Hinge``, ``Slider``, ``Weld`` and ``Distance``, with ``Motor`` and
``JointSpring``, added to a world with ``World.add_joint``. Each only holds its fields; the world checks them (a
bad axis, a body joined to itself, limits out of order, non-finite anchors raise ``ValueError`` naming the
argument) and fixes the joint's reference: the bodies' relative rotation when it is added is its zero.

Anchors are in each body's frame (relative to its centre of mass); ``None`` for a body means the world, and its
anchor is then ``world_point``. A hinge's or slider's ``axis`` is in the first body's frame (world axes when it is
the world). Both modes take every kind, limits, motors, joint springs and ropes: a limit or a taut rope pushes only
when reached, a motor drives its speed with at most its force. Fast mode solves the joints with its contacts at each
substep; accurate mode holds them exactly as constraints inside the equations of motion. ``softness`` (a joint made
a soft row) is fast mode's only: accurate mode refuses it (``ValueError`` naming ``softness``). Any joint may be
given ``breaking=Breaking(force=..., torque=...)``: it breaks in either mode once it carries more; ``collide=True``
lets its two bodies collide with each other (they do not by default); ``cluster=True`` binds its bodies into one
piece with every body bound to them by other such joints (a glued object's welds): none of them collide with each
other while the joints hold.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Optional, Sequence, Tuple

from ._tumble import BodyHandle

Vec = Sequence[float]


def _number(name: str, value: Any) -> float:
    """`value` as a float, or a ValueError naming the argument."""
    if isinstance(value, bool):
        raise ValueError(f"invalid argument `{name}`: expected a number, got {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"invalid argument `{name}`: expected a number, got {value!r}") from None


def _pair(name: str, value: Any) -> Tuple[float, float]:
    """`value` as two floats, or a ValueError naming the argument."""
    try:
        first, second = value
    except (TypeError, ValueError):
        raise ValueError(f"invalid argument `{name}`: expected two numbers, got {value!r}") from None
    return (_number(name, first), _number(name, second))


@dataclass(frozen=True)
class Motor:
    """Drives a hinge's angular speed (rad/s, at most ``max_torque`` N m) or a slider's speed (m/s, at most
    ``max_force`` N)."""

    speed: float
    max_torque: Optional[float] = None
    max_force: Optional[float] = None

    def _pair(self) -> Tuple[float, float]:
        if (self.max_torque is None) == (self.max_force is None):
            raise ValueError("invalid argument `motor`: give one of max_torque (hinge) or max_force (slider)")
        bound = self.max_torque if self.max_torque is not None else self.max_force
        return (_number("motor", self.speed), _number("motor", bound))


@dataclass(frozen=True)
class JointSpring:
    """A spring on a hinge's angle (N m/rad, N m s/rad) or a slider's travel (N/m, N s/m) towards ``target``."""

    stiffness: float
    damping: float = 0.0
    target: float = 0.0


@dataclass(frozen=True)
class Breaking:
    """When a joint breaks: as soon as the force it carries exceeds ``force`` (N) or its torque about the second
    body's anchor exceeds ``torque`` (N m), in either mode (either may be left infinite, not both). With a
    ``window`` (s) the load judged is the one carried averaged over about that long (an impact's impulse counts in
    full whatever the step, so what breaks converges as the step shrinks); without (0) the load at the instant. A
    broken joint holds nothing from then on and its bodies collide again; ``World.joint_broken`` and
    ``Run.joint_breaks`` say which broke and when."""

    force: float = float("inf")
    torque: float = float("inf")
    window: float = 0.0

    def _pair(self) -> Tuple[float, float]:
        return (_number("breaking", self.force), _number("breaking", self.torque))


@dataclass(frozen=True)
class _Joint:
    a: Optional[BodyHandle]
    b: Optional[BodyHandle] = None
    anchor_a: Optional[Vec] = None
    anchor_b: Optional[Vec] = None
    world_point: Optional[Vec] = None
    softness: Optional[Tuple[float, float]] = None
    breaking: Optional[Breaking] = None
    collide: bool = False
    cluster: bool = False

    _kind = ""

    def _fields(self) -> dict[str, Any]:
        anchor_a, anchor_b = self.anchor_a, self.anchor_b
        if self.world_point is not None:
            if self.a is not None and self.b is not None:
                raise ValueError("invalid argument `world_point`: both ends are bodies")
            if self.b is None:
                anchor_b = self.world_point
            else:
                anchor_a = self.world_point
        if self.breaking is not None and not isinstance(self.breaking, Breaking):
            raise ValueError(f"invalid argument `breaking`: expected a tumble.Breaking, got {self.breaking!r}")
        return dict(kind=self._kind, a=self.a, b=self.b, anchor_a=anchor_a, anchor_b=anchor_b,
                    softness=None if self.softness is None else _pair("softness", self.softness),
                    breaking=None if self.breaking is None else self.breaking._pair(),
                    break_window=0.0 if self.breaking is None else _number("window", self.breaking.window),
                    collide=self._collide(), cluster=bool(self.cluster))

    def _collide(self) -> bool:
        if not isinstance(self.collide, bool):
            raise ValueError(f"invalid argument `collide`: expected True or False, got {self.collide!r}")
        return self.collide


@dataclass(frozen=True)
class Ball(_Joint):
    """A ball (spherical) joint: the anchors coincide, any relative rotation."""

    _kind = "ball"


@dataclass(frozen=True)
class Weld(_Joint):
    """A weld (fixed) joint: no relative motion."""

    _kind = "weld"


@dataclass(frozen=True)
class _Axial(_Joint):
    axis: Vec = (1.0, 0.0, 0.0)
    limits: Optional[Tuple[float, float]] = None
    motor: Optional[Motor] = None
    spring: Optional[JointSpring] = None

    def _fields(self) -> dict[str, Any]:
        f = super()._fields()
        if self.motor is not None and not isinstance(self.motor, Motor):
            raise ValueError(f"invalid argument `motor`: expected a tumble.Motor, got {self.motor!r}")
        if self.spring is not None and not isinstance(self.spring, JointSpring):
            raise ValueError(f"invalid argument `spring`: expected a tumble.JointSpring, got {self.spring!r}")
        spring = None
        if self.spring is not None:
            spring = tuple(_number("spring", getattr(self.spring, k)) for k in ("stiffness", "damping", "target"))
        f.update(axis=self.axis, limits=None if self.limits is None else _pair("limits", self.limits),
                 motor=None if self.motor is None else self.motor._pair(), spring=spring)
        return f


@dataclass(frozen=True)
class Hinge(_Axial):
    """A hinge (revolute) joint about ``axis``; ``limits`` in radians within (-pi, pi), a ``Motor`` on its speed, a
    ``JointSpring`` on its angle."""

    _kind = "hinge"


@dataclass(frozen=True)
class Slider(_Axial):
    """A slider (prismatic) joint along ``axis``; ``limits`` in metres, a ``Motor`` on its speed, a ``JointSpring``
    on its travel."""

    _kind = "slider"


@dataclass(frozen=True)
class Piston(_Axial):
    """A piston (cylindrical) joint along ``axis``: B slides along it and turns about it; ``limits`` in metres, a
    ``Motor`` and a ``JointSpring`` on its travel, as a slider's; ``turn_limits`` in radians within (-pi, pi) on
    its turn about the axis."""

    turn_limits: Optional[Tuple[float, float]] = None
    _kind = "piston"

    def _fields(self) -> dict[str, Any]:
        f = super()._fields()
        f.update(turn_limits=None if self.turn_limits is None else _pair("turn_limits", self.turn_limits))
        return f


@dataclass(frozen=True)
class Drive(_Joint):
    """A drive alone (Blender's and Bullet's motor constraint): its ``Motor`` drives B's spin about ``axis``
    relative to A (``Motor(speed, max_torque=...)``, rad/s and N m) or B's anchor's slide along it
    (``Motor(speed, max_force=...)``, m/s and N); nothing else is held."""

    axis: Vec = (1.0, 0.0, 0.0)
    motor: Optional[Motor] = None

    def _fields(self) -> dict[str, Any]:
        f = super()._fields()
        if not isinstance(self.motor, Motor):
            raise ValueError(f"invalid argument `motor`: a drive needs a tumble.Motor, got {self.motor!r}")
        f.update(kind="slide-drive" if self.motor.max_force is not None else "spin-drive", axis=self.axis,
                 motor=self.motor._pair())
        return f


@dataclass(frozen=True)
class Distance(_Joint):
    """The anchors held ``length`` apart (None: their distance when added): a rigid rod, or with ``rope=True`` a
    rope that only pulls."""

    length: Optional[float] = None
    rope: bool = False

    def _fields(self) -> dict[str, Any]:
        f = super()._fields()
        if not isinstance(self.rope, bool):
            raise ValueError(f"invalid argument `rope`: expected True or False, got {self.rope!r}")
        length = None if self.length is None else _number("length", self.length)
        f.update(kind="rope" if self.rope else "distance", length=length)
        return f


Joint = _Joint
