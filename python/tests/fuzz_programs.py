"""The fuzzer's programs as data (calls, handles, callbacks; rendered to the Python source that runs) and its
settings. Part of ``test_fuzz.py``."""

from __future__ import annotations

import dataclasses
import math
import os
import sys
from typing import Any





EXAMPLES = int(os.environ.get("TUMBLE_FUZZ_EXAMPLES", "0") or 0)
LONG = EXAMPLES > 0
TIMEOUT = float(os.environ.get("TUMBLE_FUZZ_TIMEOUT", "20"))
# Failure kinds to ignore, running on past them (to look beyond known failures), e.g. "ArgumentNotNamed,Hang".
IGNORE = set(filter(None, os.environ.get("TUMBLE_FUZZ_IGNORE", "").split(",")))
MEMORY_LIMIT = 4 << 30
MAX_OPS = 12

# The classes below are pickled to the worker, which imports this file under another name: register them under one.
_MODULE = "tumble_fuzz_program"
sys.modules.setdefault(_MODULE, sys.modules[__name__])

NAN, INF = math.nan, math.inf

# ----------------------------------------------------------------------------------------------------------------
# Programs as data: rendered to Python source, which is what runs (so the reproducer is exactly what failed).


@dataclasses.dataclass(frozen=True)
class Ref:
    """The i-th handle of a kind ('p', 'b', 's', 'l') this world issued (removed ones included), modulo the count;
    a handle of another world if it issued none."""

    kind: str
    i: int


@dataclasses.dataclass(frozen=True)
class Foreign:
    """A handle of another world."""

    kind: str
    i: int


@dataclasses.dataclass(frozen=True)
class Raw:
    """Python source as is."""

    text: str


@dataclasses.dataclass(frozen=True)
class Steps:
    """k steps of fast mode's current dt (any duration in accurate mode)."""

    k: int


@dataclasses.dataclass(frozen=True)
class ShapeX:
    """A shape constructor call."""

    cls: str
    params: tuple  # ((name, value), ...)
    npos: int = 99


@dataclasses.dataclass(frozen=True)
class Callback:
    """A force callback or a run's progress callable."""

    kind: str
    payload: Any = None


@dataclasses.dataclass(frozen=True)
class Op:
    """One call. kind: 'world' (init), 'scene' (init), 'call' (w.name(...)), 'set' (w.name = ...), 'read'
    (w.name), 'shape' (shape.name(...), the shape first in params)."""

    kind: str
    name: str
    params: tuple = ()  # ((name, value), ...)
    npos: int = 0


@dataclasses.dataclass(frozen=True)
class Program:
    init: Op
    ops: tuple


for _cls in (Ref, Foreign, Raw, Steps, ShapeX, Callback, Op, Program):
    _cls.__module__ = _MODULE


class CallbackError(Exception):
    """Raised by the test's callbacks."""


CallbackError.__module__ = _MODULE

PREAMBLE = """\
import math
import numpy as np
import tumble
nan, inf = math.nan, math.inf
class CallbackError(Exception): pass
def _raise(*args): raise CallbackError("raised by a test callback")
def _shape_of(w, i):
    shapes = [s for colliders in w._body_shapes() for s, _, _ in colliders]
    return shapes[i % len(shapes)] if shapes else tumble.Sphere(1.0)
"""

FOREIGN_WORLD = """\
w2 = tumble.World()
w2p = [w2.add_particle(position=(k, 0.0, 0.0)) for k in range(3)]
w2b = [w2.add_body(tumble.Sphere(0.5), position=(k, 3.0, 0.0)) for k in range(3)]
w2s = [w2.add_spring(w2p[0], w2p[1]), w2.add_spring(w2b[0], w2b[1])]
w2l = [w2.add_force(w2p[0], (1.0, 0.0, 0.0)), w2.add_torque(w2b[0], (0.0, 0.0, 1.0))]
w2.remove(w2p[2]); w2p.append(w2.add_particle())
w2.remove(w2b[2]); w2b.append(w2.add_body(tumble.Sphere(0.5)))
w2j = [w2.add_joint(tumble.Ball(w2b[0], w2b[1]))]
"""
FOREIGN_COUNT = {"p": 4, "b": 4, "s": 2, "l": 2, "j": 1}

# Parameter names of every callable, for "the error names an argument".
SIGNATURES = {
    "World": "gravity integrator rtol atol dt step_doubling tolerance mode linear_solver newton max_steps sleep threads "
    "contact_tolerance solver substeps friction_combine restitution_combine",
    "set_integrator": "integrator rtol atol dt step_doubling tolerance linear_solver newton max_steps",
    "set_mode": "mode dt sleep contact_tolerance solver substeps",
    "threads": "threads",
    "add_ground": "height restitution friction rolling_resistance torsional_resistance friction_combine "
    "restitution_combine",
    "add_particle": "mass position velocity damping stiffness anchor radius restitution friction friction_combine "
    "restitution_combine",
    "add_body": "shape density mass inertia position orientation velocity angular_velocity restitution friction "
    "static linear_damping angular_damping colliders rolling_resistance torsional_resistance friction_combine "
    "restitution_combine",
    "add_spring": "a b stiffness damping rest_length anchor_a anchor_b world_point",
    "add_force": "target force at",
    "add_torque": "body torque",
    "add_force_callback": "target callback",
    "remove": "handle",
    "set_particle_state": "particle position velocity",
    "set_body_state": "body position orientation velocity angular_velocity",
    "step": "dt",
    "run": "duration frame_interval progress",
    "mass_properties": "density",
    "triangle_mesh": "subdivisions extent",
    "Sphere": "radius",
    "Box": "half_extents",
    "Capsule": "half_height radius",
    "Cylinder": "half_height radius",
    "ConvexHull": "points",
    "TriMesh": "vertices triangles",
    "Mesh": "vertices triangles name mesh",
    "cloth": "n size mass stiffness damping pin_stiffness",
    "spinning_top": "",
    "bouncing_ball": "restitution radius height",
    "tumbling_box": "",
    "dominoes": "count spacing",
    "pyramid": "layers",
    "cloth_drape": "n size",
    "add_joint": "joint",
    "remove_joint": "joint",
    "Ball": "a b anchor_a anchor_b world_point softness",
    "Weld": "a b anchor_a anchor_b world_point softness",
    "Hinge": "a b anchor_a anchor_b world_point softness axis limits motor spring",
    "Slider": "a b anchor_a anchor_b world_point softness axis limits motor spring",
    "Distance": "a b anchor_a anchor_b world_point softness length rope",
    "Motor": "speed max_torque max_force",
    "JointSpring": "stiffness damping target",
}
SIGNATURES = {k: v.split() for k, v in SIGNATURES.items()}

# Handle parameters and the kinds they take.
HANDLE_PARAMS = {
    ("add_spring", "a"): "pb",
    ("add_spring", "b"): "pb",
    ("add_force", "target"): "pb",
    ("add_force_callback", "target"): "pb",
    ("add_torque", "body"): "b",
    ("remove", "handle"): "pbsl",
    ("set_particle_state", "particle"): "p",
    ("set_body_state", "body"): "b",
    ("remove_joint", "joint"): "j",
}
CREATES = {"add_particle": "p", "add_body": "b", "add_ground": "b", "add_spring": "s", "add_force": "l",
           "add_torque": "l", "add_force_callback": "l", "add_joint": "j"}
STEPPING = {"step", "run"}


def _int_src(v: int) -> str:
    if abs(v) >= 1 << 20:
        for base in (2, 10):
            k = round(math.log(abs(v), base))
            if base**k == abs(v):
                return ("-" if v < 0 else "") + f"{base}**{k}"
    return repr(v)


def _float_src(v: float) -> str:
    if math.isnan(v):
        return "nan"
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    return repr(v)
