"""Fuzzing the Python API with hypothesis (issue 11): bad input gets a clear error naming the argument, never a
panic, an abort, a hang or a NaN; a failed call leaves the world bit for bit unchanged; reruns are bit-for-bit
identical.

Hypothesis generates programs: a world (``World(...)`` with random mode, integrator and options, or a built-in
scene with random parameters), then up to a dozen calls drawn from every public method (building, removing,
setting state, switching mode and integrator, stepping, running, reading state and reports, shape methods) with
good, extreme (nan, inf, -0.0, 5e-324, 1e300, 1e308, ...) and badly typed arguments, handles from another world
and stale handles. Each program runs in a worker subprocess (address space limited to 4 GB), three times:

1. as generated, checking after every call that it returned or raised ValueError, TypeError or
   tumble.SimulationError (anything else, pyo3's PanicException included, fails); that a ValueError or TypeError
   names one of the call's arguments; that calls with a stale, foreign or wrong-kind handle fail; after a success,
   that the state (positions, orientations, velocities, time, energies, momenta) and the returned values are
   finite; after a failure, that the state is bit for bit as before the call (handles, plan, mode included);
2. again on fresh worlds: every outcome and the final state must be the same bits;
3. without the calls that failed: the final state must be the same bits, since a failed call changes nothing,
   hidden state (contact caches, warm starts, step sizes, sleep) included.

A worker that dies (an abort, a segfault, an allocation failure) or does not answer within
``TUMBLE_FUZZ_TIMEOUT`` seconds (default 20) per execution is a failure too, so hypothesis shrinks crashes and hangs
like any other failure. Every call's work is bounded by its budget (``max_steps``, by default 1e6 integrator steps,
contact steps and convex solves): on these small scenes the costliest calls, accurate-mode piles of millimetre
bodies, spend it in about 200 s and end in its clear error, so a long run that should report only calls past their
budget uses ``TUMBLE_FUZZ_TIMEOUT=300``. Every failure message carries a runnable Python reproducer of the shrunk program.

Failures are reported by kind (one exception class each, so that hypothesis shrinks each kind separately): Panic,
Crash, Hang, WrongExceptionType, ArgumentNotNamed, AcceptedBadArgument (a stale, foreign or wrong-kind handle, a
callback that is not callable), NonFiniteState, NonFiniteResult, FailedCallChangedState, NotRepeatable,
FailedCallChangedHiddenState, CallbackErrorLost, SwallowedCallbackError, WrongTime, BadResult.

Sizes:

    python3 -m pytest python/tests/test_fuzz.py                              # CI: fixed seed, under a minute
    TUMBLE_FUZZ_EXAMPLES=5000 TUMBLE_FUZZ_TIMEOUT=300 python3 -m pytest python/tests/test_fuzz.py  # long run
    TUMBLE_FUZZ_EXAMPLES=5000 TUMBLE_FUZZ_SEED=123 python3 -m pytest ...     # long run, given seed

The CI size (150 programs, 100 shape programs) is derandomized so that CI is reproducible; it takes under a minute
when nothing fails (shrinking a failure takes up to a few minutes more, a hang the longest). ``TUMBLE_FUZZ_EXAMPLES``
sets the number of programs of ``test_programs`` (a quarter of it for ``test_shape_programs``);
``TUMBLE_FUZZ_TIMEOUT`` the hang limit; ``TUMBLE_FUZZ_IGNORE=ArgumentNotNamed,...`` ignores failures of those kinds
and runs on past them, to look beyond known failures.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import os
import pickle
import re
import select
import signal
import struct
import subprocess
import sys
import tempfile
from typing import Any

import numpy as np

import pytest
from hypothesis import HealthCheck, given, seed, settings
from hypothesis import strategies as st

import tumble

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
"""
FOREIGN_COUNT = {"p": 4, "b": 4, "s": 2, "l": 2}

# Parameter names of every callable, for "the error names an argument".
SIGNATURES = {
    "World": "gravity integrator rtol atol dt step_doubling tolerance mode linear_solver newton max_steps sleep threads "
    "contact_tolerance solver substeps",
    "set_integrator": "integrator rtol atol dt step_doubling tolerance linear_solver newton max_steps",
    "set_mode": "mode dt sleep contact_tolerance solver substeps",
    "threads": "threads",
    "add_ground": "height restitution friction",
    "add_particle": "mass position velocity damping stiffness anchor radius restitution friction",
    "add_body": "shape density mass inertia position orientation velocity angular_velocity restitution friction "
    "static linear_damping angular_damping colliders",
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
    "cloth": "n size mass stiffness damping pin_stiffness",
    "spinning_top": "",
    "bouncing_ball": "restitution radius height",
    "tumbling_box": "",
    "dominoes": "count spacing",
    "pyramid": "layers",
    "cloth_drape": "n size",
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
}
CREATES = {"add_particle": "p", "add_body": "b", "add_ground": "b", "add_spring": "s", "add_force": "l",
           "add_torque": "l", "add_force_callback": "l"}
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


# ----------------------------------------------------------------------------------------------------------------
# Executing a program (in the worker).


class Failure(Exception):
    def __init__(self, kind: str, message: str) -> None:
        super().__init__(message)
        self.kind = kind
        self.message = message


def _canon(v: Any) -> bytes:
    """Bit-exact bytes of a value (NaN-safe: NaN payloads compare by bits)."""
    if isinstance(v, np.ndarray):
        return repr((v.dtype.str, v.shape)).encode() + np.ascontiguousarray(v).tobytes()
    if isinstance(v, (float, np.floating)):
        return b"f" + struct.pack("<d", float(v))
    if isinstance(v, (list, tuple)):
        return b"(" + b",".join(_canon(x) for x in v) + b")"
    if isinstance(v, dict):
        return b"{" + b",".join(repr(k).encode() + b":" + _canon(x) for k, x in v.items()) + b"}"
    return repr(v).encode()


def _numbers(v: Any, path: str = ""):
    """Every float in a value, with where it is."""
    if isinstance(v, np.ndarray):
        if v.dtype.kind in "fc":
            yield path, v
    elif isinstance(v, (float, np.floating)):
        yield path, np.float64(v)
    elif isinstance(v, (list, tuple)):
        for k, x in enumerate(v):
            yield from _numbers(x, f"{path}[{k}]")
    elif isinstance(v, dict):
        for k, x in v.items():
            yield from _numbers(x, f"{path}[{k!r}]")


def _non_finite(v: Any) -> list[str]:
    return [p or "value" for p, a in _numbers(v) if not np.all(np.isfinite(a))]


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


def _diff(a: list, b: list) -> list[str]:
    out = []
    for (name, x), (_, y) in zip(a, b):
        if _canon(x) != _canon(y):
            out.append(f"{name}: {_short(x)} -> {_short(y)}")
    return out


def _short(v: Any) -> str:
    s = repr(v).replace("\n", " ")
    return s if len(s) < 300 else s[:300] + "..."


def _digest(v: Any) -> str:
    """A digest of a call's result (what is deterministic of it)."""
    if isinstance(v, tumble.Run):
        v = [(f.name, getattr(v, f.name)) for f in dataclasses.fields(v) if f.name not in ("report", "shapes")]
    elif isinstance(v, tumble.Report):
        return "report"
    elif isinstance(v, tuple) and v and isinstance(v[0], str):
        return repr(v)
    return hashlib.sha1(_canon(v)).hexdigest()[:16]


def _normalized(message: str) -> str:
    return re.sub(r"0x[0-9a-fA-F]+", "0x?", message)


def _names_an_argument(message: str, names: set[str]) -> bool:
    return any(re.search(rf"[`'\"]{re.escape(n)}[`'\"]", message) for n in names)


class Execution:
    """One execution of a program on fresh worlds; `skip` holds indices of ops to leave out."""

    def __init__(self, program: Program, skip: frozenset = frozenset(), log: str | None = None) -> None:
        self.program = program
        self.skip = skip
        self.log = open(log, "w", buffering=1) if log else None  # noqa: SIM115
        self.ns: dict[str, Any] = {}
        exec(PREAMBLE, self.ns)  # noqa: S102
        exec(FOREIGN_WORLD, self.ns)  # noqa: S102
        self.ns["CallbackError"] = CallbackError  # one class in the worker and its reproducer
        self.ns["_raise"] = _raise
        self.entries: list[tuple[str, str]] = []  # (source, outcome) for the reproducer
        self.trace: list[tuple] = []
        self.handles: dict[str, list[str]] = {k: [] for k in "pbsl"}
        self.deps: dict[str, set[str]] = {}
        self.removed: set[str] = set()
        self.uses_foreign = False
        self.fast_dt = 1 / 240
        self.final: list | None = None
        self.failures: list[tuple[str, str]] = []  # those of kinds in IGNORE

    # --- rendering

    def render(self, v: Any, ctx: dict) -> str:
        if isinstance(v, Ref):
            names = self.handles[v.kind]
            if not names:
                return self.render(Foreign(v.kind, v.i), ctx)
            name = names[v.i % len(names)]
            ctx.setdefault("refs", []).append(name)
            if name in self.removed:
                ctx["reasons"].append(f"{name} was removed")
            return name
        if isinstance(v, Foreign):
            self.uses_foreign = True
            ctx["reasons"].append("a handle of another world")
            return f"w2{v.kind}[{v.i % FOREIGN_COUNT[v.kind]}]"
        if isinstance(v, Raw):
            return v.text
        if isinstance(v, Steps):
            return _float_src(v.k * self.fast_dt)
        if isinstance(v, ShapeX):
            ctx["names"].update(SIGNATURES[v.cls])
            return f"tumble.{v.cls}({self.render_params(v.params, v.npos, ctx)})"
        if isinstance(v, Callback):
            return self.render_callback(v, ctx)
        if isinstance(v, bool) or v is None:
            return repr(v)
        if isinstance(v, int):
            return _int_src(v)
        if isinstance(v, float):
            return _float_src(v)
        if isinstance(v, np.ndarray):
            if v.size == 0:
                return f"np.zeros({v.shape}, dtype=np.{v.dtype.name})"
            return f"np.array({self.render(v.tolist(), ctx)}, dtype=np.{v.dtype.name})"
        if isinstance(v, np.generic):
            return f"np.{type(v).__name__}({self.render(v.item(), ctx)})"
        if isinstance(v, tuple):
            inner = ", ".join(self.render(x, ctx) for x in v)
            return f"({inner},)" if len(v) == 1 else f"({inner})"
        if isinstance(v, list):
            return "[" + ", ".join(self.render(x, ctx) for x in v) + "]"
        if isinstance(v, dict):
            return "{" + ", ".join(f"{k!r}: {self.render(x, ctx)}" for k, x in v.items()) + "}"
        return repr(v)

    def render_callback(self, c: Callback, ctx: dict) -> str:
        k, p = c.kind, c.payload
        if k == "const":
            return f"lambda t, x, v: {self.render(p, ctx)}"
        if k == "spring":
            return f"lambda t, x, v: -{_float_src(p)} * x - 0.5 * v"
        if k == "late":
            when, value = p
            return f"lambda t, x, v: {self.render(value, ctx)} if t > {_float_src(when)} else (0.0, 0.0, 1.0)"
        if k == "raise":
            ctx["raises"] = True
            return "_raise"
        if k == "reenter":
            return f"lambda t, x, v: ({p}, (0.0, 0.0, 0.0))[1]"
        if k == "progress":
            return "lambda fraction: None"
        if k == "not callable":
            ctx["reasons"].append("the callback is not callable")
            return self.render(p, ctx)
        raise AssertionError(k)

    def render_params(self, params: tuple, npos: int, ctx: dict, method: str | None = None) -> str:
        parts = []
        for k, (name, value) in enumerate(params):
            if method is not None and (method, name) in HANDLE_PARAMS:
                kinds = HANDLE_PARAMS[(method, name)]
                if isinstance(value, (Ref, Foreign)):
                    if value.kind not in kinds:
                        ctx["reasons"].append(f"`{name}` is a {value.kind} handle")
                elif not (value is None and name == "b"):
                    ctx["reasons"].append(f"`{name}` is not a handle")
            if method == "run" and name == "progress":
                if not (value is None or isinstance(value, (bool, Callback))):
                    ctx["reasons"].append("`progress` is neither a bool nor callable")
                if isinstance(value, Callback) and value.kind == "raise":
                    ctx["progress raises"] = True
            src = self.render(value, ctx)
            parts.append(src if k < npos else f"{name}={src}")
        return ", ".join(parts)

    def render_op(self, op: Op) -> tuple[str, dict]:
        ctx: dict[str, Any] = {"reasons": [], "names": set(SIGNATURES.get(op.name, [])), "op": op}
        if op.kind == "world":
            return f"w = tumble.World({self.render_params(op.params, op.npos, ctx)})", ctx
        if op.kind == "scene":
            return f"w = tumble.scenes.{op.name}({self.render_params(op.params, op.npos, ctx)})", ctx
        if op.kind == "set":
            return f"w.{op.name} = {self.render(op.params[0][1], ctx)}", ctx
        if op.kind == "read":
            return f"_r = {op.name}", ctx
        if op.kind == "shape":
            ctx["names"].add("shape")
            shape = self.render(op.params[0][1], ctx)
            if op.name == "kind":
                return f"_r = {shape}.kind, repr({shape})", ctx
            return f"_r = {shape}.{op.name}({self.render_params(op.params[1:], op.npos, ctx)})", ctx
        args = self.render_params(op.params, op.npos, ctx, op.name)
        if op.name in CREATES:
            kind = CREATES[op.name]
            target = f"{kind}{len(self.handles[kind])}"
            ctx["creates"] = (kind, target)
            return f"{target} = w.{op.name}({args})", ctx
        if op.name == "run":
            return f"_r = w.run({args})", ctx
        return f"w.{op.name}({args})", ctx

    # --- running

    def reproducer(self, note: str = "") -> str:
        return assemble(self.entries, self.uses_foreign, note)

    def fail(self, kind: str, what: str) -> None:
        message = f"{what}\n\nReproducer:\n{assemble(self.entries, self.uses_foreign, kind, last=True)}"
        if kind in IGNORE:
            self.failures.append((kind, message))
            return
        raise Failure(kind, message)

    def run(self) -> None:
        if self.log:
            self.log.write("P " + str(int(self.uses_foreign)) + "\n")
        self.step_op(-1, self.program.init)
        for i, op in enumerate(self.program.ops):
            if i not in self.skip:
                self.step_op(i, op)
        self.final = snapshot(self.ns["w"])
        if self.log:
            self.log.close()

    def step_op(self, index: int, op: Op) -> None:
        ns = self.ns
        line, ctx = self.render_op(op)
        init = op.kind in ("world", "scene")
        before = None if init else snapshot(ns["w"])
        time_before = None if init else ns["w"].time
        ns["_r"] = None
        raised_before = _RAISED[0]
        if self.log:
            self.log.write(f"F {int(self.uses_foreign)}\nC {line}\n")
        self.entries.append((line, ""))
        try:
            exec(compile(line, "<fuzz>", "exec"), ns)  # noqa: S102
            error = None
        except BaseException as e:  # noqa: BLE001 - PanicException is a BaseException
            error = e
        callback_raised = _RAISED[0] != raised_before
        if error is None:
            self.entries[-1] = (line, "ok")
            if self.log:
                self.log.write("O\n")
            self.after_success(index, op, ctx, line, time_before, callback_raised)
        else:
            message = f"{type(error).__name__}: {_short(str(error))}"
            self.entries[-1] = (line, message)
            if self.log:
                self.log.write(f"E {message}\n")
            self.after_failure(index, op, ctx, error, before, callback_raised)
            if init:  # continue on a default world of the same mode
                mode = dict(op.params).get("mode")
                fallback = 'w = tumble.World(mode="fast")' if mode == "fast" else "w = tumble.World()"
                self.entries.append((fallback, "ok"))
                if self.log:
                    self.log.write(f"C {fallback}\nO\n")
                exec(fallback, ns)  # noqa: S102
                self.fast_dt = 1 / 240
                after = snapshot(ns["w"])
                self.check_finite(after, "the fallback world")

    def check_finite(self, snap: list, after: str) -> None:
        bad = [f"{name} = {_short(v)}" for name, v in snap if _non_finite(v)]
        if bad:
            self.fail("NonFiniteState", f"non-finite state after {after}:\n  " + "\n  ".join(bad))
            return False
        return True

    def after_success(self, index, op, ctx, line, time_before, callback_raised) -> None:
        ns, w = self.ns, self.ns["w"]
        if ctx["reasons"]:
            self.fail("AcceptedBadArgument", f"`{line}` succeeded although " + "; ".join(ctx["reasons"]))
        if callback_raised:
            self.fail("SwallowedCallbackError", f"a callback raised during `{line}`, which succeeded")
        snap = snapshot(w)
        self.check_finite(snap, f"`{line}`")
        result = ns.get("_r")
        bad = _non_finite(_result_numbers(result))
        if bad:
            self.fail("NonFiniteResult", f"`{line}` returned non-finite values at {bad[:5]}: {_short(result)}")
        self.check_result(op, line, result, time_before, w)
        if "creates" in ctx:
            kind, name = ctx["creates"]
            self.handles[kind].append(name)
            self.deps[name] = set(ctx.get("refs", []))
        if op.name == "remove" and op.kind == "call" and ctx.get("refs"):
            target = ctx["refs"][0]
            self.removed |= {target} | {n for n, d in self.deps.items() if target in d}
        if op.kind == "world" or op.name == "set_mode":
            self.track_fast_dt(op)
        if op.kind == "scene":
            self.fast_dt = 1 / 480 if op.name == "cloth_drape" else 1 / 240
            # the scene's particles and bodies, for the calls that follow
            line = "sp, sb = w.particle_handles(), w.body_handles()"
            self.entries.append((line, "ok"))
            if self.log:
                self.log.write(f"C {line}\nO\n")
            exec(line, ns)  # noqa: S102
            self.handles["p"] = [f"sp[{k}]" for k in range(len(ns["sp"]))]
            self.handles["b"] = [f"sb[{k}]" for k in range(len(ns["sb"]))]
        # a report holds wall-clock times: not compared
        self.trace.append((index, "ok", "report" if "report" in op.name else _digest(result)))

    def track_fast_dt(self, op: Op) -> None:
        params = dict(op.params)
        if params.get("mode") == "fast":
            dt = params.get("dt")
            self.fast_dt = float(dt) if isinstance(dt, (float, int)) and dt is not None else 1 / 240

    def check_result(self, op, line, result, time_before, w) -> None:
        if op.kind != "call" or op.name not in STEPPING:
            if op.kind == "shape" and op.name == "triangle_mesh":
                vertices, triangles = result
                if vertices.ndim != 2 or vertices.shape[1] != 3 or triangles.ndim != 2 or triangles.shape[1] != 3:
                    self.fail("BadResult", f"`{line}` returned shapes {vertices.shape}, {triangles.shape}")
                if triangles.size and (triangles.min() < 0 or triangles.max() >= len(vertices)):
                    self.fail("BadResult", f"`{line}` returned triangle indices out of range")
            return
        duration = dict(op.params).get("dt" if op.name == "step" else "duration")
        expected = _as_float(duration, self.fast_dt)
        if expected is not None and math.isfinite(time_before + expected):
            if abs(w.time - (time_before + expected)) > 1e-9 * max(1.0, abs(time_before + expected)):
                self.fail("WrongTime", f"after `{line}` from t = {time_before!r}, w.time = {w.time!r}")
        if op.name == "run":
            times = result.times
            if times.size == 0 or times[-1] != w.time or np.any(np.diff(times) < 0):
                self.fail("BadResult", f"`{line}`: frame times {_short(times)}, w.time = {w.time!r}")

    def after_failure(self, index, op, ctx, error, before, callback_raised) -> None:
        line = self.entries[-1][0]
        described = f"`{line}` raised {type(error).__module__}.{type(error).__name__}: {_short(str(error))}"
        if type(error).__name__ == "PanicException":
            self.fail("Panic", described)
        allowed = isinstance(error, (ValueError, TypeError, tumble.SimulationError)) or (
            isinstance(error, CallbackError) and ctx.get("progress raises")
        )
        if not allowed:
            self.fail("WrongExceptionType", described)
        if isinstance(error, (ValueError, TypeError)) and not _names_an_argument(str(error), ctx["names"]):
            self.fail("ArgumentNotNamed", f"{described}\n(names none of {sorted(ctx['names'])})")
        if callback_raised and not (
            isinstance(error, CallbackError)
            or (isinstance(error, tumble.SimulationError) and isinstance(error.__cause__, CallbackError))
        ):
            self.fail("CallbackErrorLost", f"a callback raised CallbackError, but {described} has cause "
                      f"{error.__cause__!r}")
        if before is not None:
            after = snapshot(self.ns["w"])
            changed = _diff(before, after)
            if changed:
                self.fail("FailedCallChangedState", f"{described}\nand changed the state:\n  " + "\n  ".join(changed))
        self.trace.append((index, "error", type(error).__name__, _normalized(str(error))))


def _as_float(v: Any, fast_dt: float) -> float | None:
    if isinstance(v, Steps):
        return v.k * fast_dt
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, float, np.integer, np.floating)):
        return None
    try:
        return float(v)
    except OverflowError:
        return None


def _result_numbers(result: Any) -> Any:
    if isinstance(result, tumble.Run):
        return [getattr(result, f.name) for f in dataclasses.fields(result) if f.name not in ("report", "shapes")] + [
            _result_numbers(result.report)
        ]
    if isinstance(result, tumble.Report):
        return [v for v in result.as_dict().values() if isinstance(v, float)]
    if isinstance(result, (list, tuple)):
        return [_result_numbers(x) for x in result]
    if isinstance(result, dict):
        return {k: _result_numbers(x) for k, x in result.items()}
    if isinstance(result, (float, np.ndarray, np.floating)):
        return result
    return None


_RAISED = [0]


def _raise(*args: Any) -> None:
    _RAISED[0] += 1
    raise CallbackError("raised by a test callback")


def assemble(entries: list[tuple[str, str]], uses_foreign: bool, note: str = "", last: bool = False) -> str:
    """A runnable reproducer: calls that raised are wrapped in try/except; `note` marks the call without an outcome
    (the one that crashed or hung) or, with `last`, the last call."""
    lines = [PREAMBLE.rstrip()]
    if uses_foreign:
        lines.append(FOREIGN_WORLD.rstrip())
    for k, (src, outcome) in enumerate(entries):
        mark = f"  # <- {note}" if note and (outcome == "" or (last and k == len(entries) - 1)) else ""
        if outcome in ("", "ok"):
            lines.append(src + mark)
        else:
            lines.append(f"try:{mark}\n    {src}\nexcept Exception as e:  # {outcome}\n    print(repr(e))")
    return "\n".join(lines)


def read_log(path: str) -> tuple[list[tuple[str, str]], bool]:
    entries: list[tuple[str, str]] = []
    uses_foreign = False
    try:
        with open(path) as f:
            text = f.read()
    except OSError:
        return entries, uses_foreign
    for raw in text.splitlines():
        tag, _, rest = raw.partition(" ")
        if tag == "P":
            entries, uses_foreign = [], False
        elif tag == "F":
            uses_foreign = uses_foreign or rest == "1"
        elif tag == "C":
            entries.append((rest, ""))
        elif tag == "O" and entries:
            entries[-1] = (entries[-1][0], "ok")
        elif tag == "E" and entries:
            entries[-1] = (entries[-1][0], rest)
    return entries, uses_foreign


def check_program(program: Program, log: str | None, phase=lambda name: None) -> list[tuple[str, str]]:
    """Runs the three executions; returns the failures found, as (kind, message): the first one stops the checks
    unless its kind is in IGNORE."""
    first = Execution(program, log=log)
    try:
        later = _compare_executions(program, log, phase, first)
    except Failure as f:
        later = [(f.kind, f.message)]
    return first.failures + later


def _compare_executions(program: Program, log: str | None, phase, first: Execution) -> list[tuple[str, str]]:
    first.run()
    phase("rerun")
    second = Execution(program, log=log)
    second.run()
    changed = _diff(first.final, second.final)
    calls = [f"{a} != {b}" for a, b in zip(first.trace, second.trace) if a != b][:3]
    if changed or calls or len(first.trace) != len(second.trace):
        return [("NotRepeatable", "a rerun on fresh worlds differs:\n  " + "\n  ".join(changed + calls)
                 + "\n\nReproducer:\n" + first.reproducer())]
    failed = frozenset(t[0] for t in first.trace if t[1] == "error" and t[0] >= 0)
    if not failed:
        return []
    phase("without failed calls")
    third = Execution(program, skip=failed, log=log)
    try:
        third.run()
    except Failure as f:
        return [("FailedCallChangedHiddenState", "without its failed calls, the program fails differently:\n"
                 f"{f.message}\n\nOriginal:\n{first.reproducer()}")]
    kept = [t for t in first.trace if t[0] not in failed]
    changed = _diff(first.final, third.final)
    calls = [f"{a} != {b}" for a, b in zip(kept, third.trace) if a != b][:3]
    if changed or calls:
        return [("FailedCallChangedHiddenState", "the same program without its failed calls (the try/except "
                 "blocks) ends differently:\n  " + "\n  ".join(changed + calls) + "\n\nReproducer:\n"
                 + first.reproducer())]
    return []


# ----------------------------------------------------------------------------------------------------------------
# The worker process and its client.


def _send(fd: int, obj: Any) -> None:
    data = pickle.dumps(obj)
    os.write(fd, struct.pack("<Q", len(data)) + data)


def _read_exact(fd: int, n: int, deadline: float | None) -> bytes | None:
    import time

    out = b""
    while len(out) < n:
        if deadline is not None:
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([fd], [], [], left)[0]:
                raise TimeoutError
        chunk = os.read(fd, n - len(out))
        if not chunk:
            return None
        out += chunk
    return out


def _recv(fd: int, deadline: float | None = None) -> Any:
    head = _read_exact(fd, 8, deadline)
    if head is None:
        return None
    body = _read_exact(fd, struct.unpack("<Q", head)[0], deadline)
    return None if body is None else pickle.loads(body)


def worker_main(log: str) -> None:
    out = os.dup(1)
    os.dup2(2, 1)  # stray prints go to stderr, not into the frames
    while True:
        program = _recv(0)
        if program is None:
            return
        os.ftruncate(2, 0)
        os.lseek(2, 0, os.SEEK_SET)
        try:
            result = check_program(program, log, lambda name: _send(out, ("phase", name)))
        except BaseException:  # noqa: BLE001 - a bug of this file, reported as such
            import traceback

            result = [("HarnessError", traceback.format_exc())]
        _send(out, result)


def _limit() -> None:
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))


class FuzzFailure(AssertionError):
    """A property the fuzz suite checks does not hold."""


_KINDS: dict[str, type] = {}


def failure_class(kind: str) -> type:
    # One class per kind, so that hypothesis tells the kinds apart and shrinks each.
    if kind not in _KINDS:
        _KINDS[kind] = type(kind, (FuzzFailure,), {"__module__": __name__})
    return _KINDS[kind]


class Worker:
    """A subprocess that runs programs; restarted after it dies or hangs."""

    def __init__(self, timeout: float = TIMEOUT) -> None:
        self.timeout = timeout
        self.dir = tempfile.mkdtemp(prefix="tumble-fuzz-")
        self.log = os.path.join(self.dir, "calls.log")
        self.err = os.path.join(self.dir, "stderr.txt")
        self.proc: subprocess.Popen | None = None

    def start(self) -> None:
        env = dict(os.environ, RUST_BACKTRACE="0", PYTHONFAULTHANDLER="1")
        with open(self.err, "wb") as err:
            self.proc = subprocess.Popen(  # noqa: S603
                [sys.executable, os.path.abspath(__file__), "--worker", self.log],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                stderr=err,
                preexec_fn=_limit,  # noqa: PLW1509
                env=env,
            )

    def stop(self) -> None:
        if self.proc is not None:
            if self.proc.poll() is None:
                self.proc.kill()
            self.proc.wait()
            self.proc.stdin.close()
            self.proc.stdout.close()
            self.proc = None

    def stderr_tail(self) -> str:
        try:
            with open(self.err, "rb") as f:
                return f.read()[-3000:].decode(errors="replace").strip()
        except OSError:
            return ""

    def check(self, program: Program) -> None:
        """Raises the first failure of the program (of a kind not in IGNORE)."""
        failures = [(kind, message) for kind, message in self.run(program) if kind not in IGNORE]
        if failures:
            kind, message = failures[0]
            others = sorted({k for k, _ in failures[1:]})
            raise failure_class(kind)(message + (f"\n\n(and later: {', '.join(others)})" if others else ""))

    def run(self, program: Program) -> list[tuple[str, str]]:
        """The program's failures, a crash or a hang included."""
        try:
            self._run(program)
        except FuzzFailure as f:
            return [(type(f).__name__, str(f))]
        return self.result

    def _run(self, program: Program) -> None:
        import time

        if self.proc is None or self.proc.poll() is not None:
            self.stop()
            self.start()
        try:
            _send(self.proc.stdin.fileno(), program)
            phase = "first run"
            while True:
                msg = _recv(self.proc.stdout.fileno(), time.monotonic() + self.timeout)
                if msg is None:
                    raise BrokenPipeError
                if msg and msg[0] == "phase":
                    phase = msg[1]
                    continue
                self.result = msg
                return
        except TimeoutError:
            self.stop()
            entries, foreign = read_log(self.log)
            raise failure_class("Hang")(
                f"no answer within {self.timeout:g} s ({phase}); the last call of the reproducer did not return:\n"
                + assemble(entries, foreign, "hangs")
            ) from None
        except (BrokenPipeError, ConnectionResetError):
            self.proc.wait()
            code = self.proc.returncode
            how = f"signal {signal.Signals(-code).name}" if code < 0 else f"exit code {code}"
            entries, foreign = read_log(self.log)
            tail = self.stderr_tail()
            self.stop()
            raise failure_class("Crash")(
                f"the worker process died with {how} ({phase}); its stderr ends with:\n{tail}\n\nReproducer:\n"
                + assemble(entries, foreign, "crashes")
            ) from None


# ----------------------------------------------------------------------------------------------------------------
# Strategies. A call is clean (every argument good, now and then a valid extreme: a stiff spring, a tiny or huge
# body, a fast spin) or, one time in three, hostile (each argument good, extreme or badly typed). Programs shrink
# towards clean calls and fewer of them.

INTEGRATORS = ["euler", "euler-variable", "midpoint", "rk4", "ab4", "am4", "implicit-euler", "dopri5", "dop853",
               "symplectic-euler", "verlet", "rodas4", "radau5"]
ADAPTIVE = {"dopri5", "dop853", "rodas4", "radau5", "am4"}
EXTREME = [NAN, INF, -INF, -0.0, 0.0, 5e-324, -5e-324, 1e-300, 1e300, -1e300, 1e308, -1e308,
           1.7976931348623157e308, -1.0, 1e-9, 1e9, 1e16]
BAD_SCALARS = [None, "1.0", "abc", [1.0], (1.0, 2.0), 10**400, -(10**400), 2**64, Raw("1j"), np.float32("nan"),
               np.float64(1e308), np.int64(-1), Raw("object()"), Raw("{}")]
BAD_VECTORS = [None, (1.0, 2.0), (1.0, 2.0, 3.0, 4.0), "abc", Raw("np.zeros((1, 3))"), np.array([1, 2, 3]),
               [[1.0, 2.0, 3.0]], 5.0, Raw("{}"), Raw("np.array(['1', '2', '3'])"), (1.0, 2.0, "3"),
               [None, 0.0, 0.0], (10**400, 0.0, 0.0), Raw("iter([1.0, 2.0, 3.0])")]
BAD_QUATS = [(0.0, 0.0, 0.0, 0.0), (NAN, 0.0, 0.0, 0.0), (INF, 0.0, 0.0, 0.0), (1e300, 1e300, 0.0, 0.0),
             (5e-324, 0.0, 0.0, 0.0), (1.0, 0.0, 0.0), None, "abc", (1.0, 0.0, 0.0, 0.0, 0.0), (-0.0, 0.0, 0.0, -0.0)]
BAD_INTS = [-1, 0, 2**32, 2**64, 10**9, 1.5, NAN, INF, "8", None]
HOSTILE_DURATIONS = [1e300, INF, NAN, 0.0, -0.0, -1.0, 5e-324, 1e-300, 1e6, 1e16]
FAST_DTS = [1 / 240, 1 / 120, 1 / 60, 1 / 480]


def pick(draw, *options):
    """One of `options` ((weight, strategy or value), ...); shrinks towards the first."""
    total = sum(weight for weight, _ in options)
    r = draw(st.integers(0, total - 1))
    for weight, option in options:
        if r < weight:
            return draw(option) if isinstance(option, st.SearchStrategy) else option
        r -= weight
    raise AssertionError


@st.composite
def weighted(draw, *options):
    """`pick` as a strategy."""
    return pick(draw, *options)


def floats(lo: float, hi: float):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False, allow_subnormal=False)


@st.composite
def scalar(draw, lo: float, hi: float, hostile: bool, wide: tuple | None = None):
    """A float in [lo, hi]; with `wide`, now and then one in that valid but extreme range."""
    good = floats(lo, hi) if wide is None else weighted((9, floats(lo, hi)), (1, floats(*wide)))
    if not hostile:
        return draw(good)
    return pick(draw, (10, good), (6, st.sampled_from(EXTREME)), (4, st.sampled_from(BAD_SCALARS)))


@st.composite
def vector(draw, lo: float, hi: float, hostile: bool, n: int = 3, wide: tuple | None = None):
    component = floats(lo, hi) if wide is None else weighted((9, floats(lo, hi)), (1, floats(*wide)))
    good = st.tuples(*[component] * n)
    if not hostile:
        return pick(draw, (9, good), (1, good.map(lambda v: np.array(v, dtype=np.float64))))
    kind = pick(draw, (6, st.just("good")), (5, st.just("one")), (1, st.just("all")), (4, st.just("bad")))
    if kind == "good":
        return draw(good)
    if kind == "one":
        v = list(draw(good))
        v[draw(st.integers(0, n - 1))] = draw(st.sampled_from(EXTREME))
        return tuple(v)
    if kind == "all":
        return (draw(st.sampled_from(EXTREME)),) * n
    return draw(st.sampled_from(BAD_QUATS if n == 4 else BAD_VECTORS))


def quaternion(hostile: bool):
    return vector(-1.0, 1.0, hostile, 4)


@st.composite
def counts(draw, lo: int, hi: int, hostile: bool):
    if not hostile:
        return draw(st.integers(lo, hi))
    return pick(draw, (10, st.integers(lo, hi)), (6, st.sampled_from(BAD_INTS)))


@st.composite
def params(draw, spec: dict) -> tuple:
    """Some of the optional parameters in `spec` (name -> strategy)."""
    return tuple((name, draw(strategy)) for name, strategy in spec.items() if draw(st.booleans()))


def good_or_bad(draw, good: list, hostile: bool):
    if not hostile:
        return draw(st.sampled_from(good))
    return pick(draw, (8, st.sampled_from(good)), (4, st.sampled_from(EXTREME + BAD_SCALARS)))


CUBE = [(x, y, z) for x in (-0.3, 0.3) for y in (-0.2, 0.2) for z in (-0.25, 0.25)]
TETRA_V = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)]
TETRA_T = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
QUAD_V = [(-2.0, -2.0, 0.0), (2.0, -2.0, 0.0), (2.0, 2.0, 0.0), (-2.0, 2.0, 0.0)]
QUAD_T = [(0, 1, 2), (0, 2, 3)]
BAD_HULLS = [
    [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)],  # flat
    [(0, 0, 0)] * 5,
    [(0, 0, 0), (1, 0, 0), (0, 1, 0)],
    [],
    np.zeros((0, 3)),
    np.zeros((5, 2)),
    [tuple(1e300 * c for c in q) for q in CUBE],
    [tuple(1e-300 * c for c in q) for q in CUBE],
    [tuple(5e-324 if c > 0 else 0.0 for c in q) for q in CUBE],
    [tuple(1e-9 * c for c in q) for q in CUBE],
    "abc",
    [[]],
    [(NAN, NAN, NAN)] * 4,
    [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, INF)],
]
BAD_MESHES = [
    (np.eye(3), np.array([[0, 1]])),
    (QUAD_V, [(0, 1, 7)]),
    (QUAD_V, [(0, 1, -1)]),
    (QUAD_V, np.array([[0, 1, 2**32 + 2]], dtype=np.int64)),
    (QUAD_V, [(0.0, 1.5, 2.0)]),
    (QUAD_V, []),
    ([], []),
    (np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)),
    ([(NAN, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)], [(0, 1, 2)]),
    ([(1e300, 0.0, 0.0), (-1e300, 0.0, 0.0), (0.0, 1e300, 0.0)], [(0, 1, 2)]),
    ([(0.0, 0.0, 0.0)] * 3, [(0, 1, 2)]),
    (QUAD_V, [(0, 0, 0)]),
    (QUAD_V, "abc"),
    (QUAD_V, np.array([[0, 1, 2]], dtype=np.uint64)),
]


@st.composite
def hull_points(draw, hostile: bool):
    n = draw(st.integers(4, 12))
    good = st.lists(st.tuples(*[floats(-0.5, 0.5)] * 3), min_size=n, max_size=n)
    options = [(6, st.just(CUBE)), (6, good), (2, good.map(lambda p: np.array(p, dtype=np.float64)))]
    if hostile:
        options.append((6, st.sampled_from(BAD_HULLS)))
    return pick(draw, *options)


@st.composite
def shapes(draw, hostile: bool, valid_type: bool = False, static: bool = True):
    """A shape constructor call (TriMesh only if `static`); hostile: with bad arguments, or not a shape at all."""
    kind = draw(st.integers(0, 5 if static else 4))
    npos = draw(st.sampled_from([99, 0]))
    size = {"wide": (1e-3, 50.0)}
    if kind == 0:
        return ShapeX("Sphere", (("radius", draw(scalar(0.05, 0.8, hostile, **size))),), npos)
    if kind == 1:
        return ShapeX("Box", (("half_extents", draw(vector(0.05, 0.8, hostile, **size))),), npos)
    if kind in (2, 3):
        cls = "Capsule" if kind == 2 else "Cylinder"
        return ShapeX(cls, (("half_height", draw(scalar(0.05, 0.8, hostile, **size))),
                            ("radius", draw(scalar(0.05, 0.5, hostile, **size)))), npos)
    if kind == 4:
        return ShapeX("ConvexHull", (("points", draw(hull_points(hostile))),), npos)
    if hostile and not valid_type and draw(st.integers(0, 3)) == 0:
        return draw(st.sampled_from([Raw('"sphere"'), 1.0, Raw("tumble.World()"), Raw("tumble.Sphere")]))
    meshes = [(8, st.sampled_from([(TETRA_V, TETRA_T), (QUAD_V, QUAD_T)])),
              (2, st.just((np.array(QUAD_V), np.array(QUAD_T, dtype=np.int64))))]
    v, t = pick(draw, *(meshes + ([(6, st.sampled_from(BAD_MESHES))] if hostile else [])))
    return ShapeX("TriMesh", (("vertices", v), ("triangles", t)), npos)


@st.composite
def handle(draw, kinds: str, made: frozenset, hostile: bool):
    """A handle parameter taking `kinds`, preferring kinds the program made (`made`)."""
    usable = [k for k in kinds if k in made] or list(kinds)
    good = st.builds(Ref, st.sampled_from(usable), st.integers(0, 5))
    if not hostile:
        return draw(good)
    return pick(
        draw,
        (6, good),
        (3, st.builds(Ref, st.sampled_from(list("pbsl")), st.integers(0, 5))),
        (2, st.builds(Foreign, st.sampled_from(list("pbsl")), st.integers(0, 3))),
        (1, st.sampled_from([None, 0, "p0", Raw("tumble.ParticleHandle"), (0, 0)])),
    )


@st.composite
def callbacks(draw, body: bool, hostile: bool):
    vec = st.tuples(*[floats(-20, 20)] * 3)
    good = [(6, st.builds(lambda v: Callback("const", v), vec)),
            (3, st.builds(lambda k: Callback("spring", k), floats(0.0, 100.0)))]
    if body:
        good.append((3, st.builds(lambda f, t: Callback("const", (f, t)), vec, st.tuples(*[floats(-5, 5)] * 3))))
    if not hostile:
        return pick(draw, *good)
    return pick(
        draw,
        *good,
        (4, st.builds(lambda v: Callback("const", v), vector(-20.0, 20.0, True))),
        (2, st.builds(lambda f, t: Callback("const", (f, t)), vector(-20.0, 20.0, True), vector(-5.0, 5.0, True))),
        (2, st.builds(lambda t, v: Callback("late", (t, v)), floats(0.0, 0.5),
                      st.sampled_from([(0.0, 0.0, NAN), (INF, 0.0, 0.0), (1e308, 1e308, 1e308), None, "abc"]))),
        (2, st.just(Callback("raise"))),
        (2, st.builds(lambda v: Callback("const", v), st.sampled_from(
            [None, "abc", (1.0, 2.0), [[1.0, 2.0, 3.0]], Raw("np.zeros((2, 3))"), ((1.0, 2.0, 3.0), (4.0, 5.0)),
             Raw("np.array([1.0, 2.0, 3.0])"), Raw("x"), Raw("x * nan"), Raw("(x, v)"), Raw("1e200 * x")]))),
        (1, st.builds(lambda e: Callback("reenter", e), st.sampled_from(
            ["w.step(0.01)", "w.time", "w.add_particle()", "w.particles.positions", "w.remove(w.body_handles()[0])"]))),
        (1, st.builds(lambda v: Callback("not callable", v), st.sampled_from([None, 5, "f", (1.0, 2.0, 3.0)]))),
    )


@st.composite
def durations(draw, mode: str, hostile: bool, kmax: int, fixed: list):
    """k steps of fast mode's dt, or (accurate mode) a round duration; hostile: anything."""
    options = [(10, st.builds(Steps, st.integers(1, kmax)))]
    if mode != "fast":
        options.append((6, st.sampled_from(fixed)))
    if hostile:
        options += [(8, st.sampled_from(HOSTILE_DURATIONS)), (2, st.sampled_from(BAD_SCALARS))]
    return pick(draw, *options)


@st.composite
def integrator_options(draw, hostile: bool):
    """Integrator options that fit the method (hostile: now and then ones that do not, or bad values)."""
    out: dict[str, Any] = {}
    method = draw(st.sampled_from(INTEGRATORS))
    if hostile and draw(st.integers(0, 3)) == 0:
        method = draw(st.sampled_from(["nope", "", 3, None, "RK4"]))
    if draw(st.integers(0, 5)) > 0:
        out["integrator"] = method
    if method in ADAPTIVE and draw(st.booleans()):
        out["rtol"] = good_or_bad(draw, [1e-3, 1e-6, 1e-8], hostile)
        out["atol"] = good_or_bad(draw, [1e-6, 1e-9], hostile)
    if (method not in ADAPTIVE and draw(st.booleans())) or (hostile and draw(st.integers(0, 3)) == 0):
        out["dt"] = good_or_bad(draw, [1 / 240, 1 / 1000, 0.01, 1 / 60], hostile)
    if method not in ADAPTIVE - {"am4"} and method != "ab4" and draw(st.integers(0, 5)) == 0 or (
            hostile and draw(st.integers(0, 5)) == 0):
        out["step_doubling"] = True if not hostile else draw(st.sampled_from([True, False, None, "yes", 2]))
        out["tolerance"] = good_or_bad(draw, [1e-4, 1e-6], hostile)
    if method == "euler-variable" and draw(st.booleans()):
        out["tolerance"] = good_or_bad(draw, [1e-3, 1e-5], hostile)
    if method == "implicit-euler" or (hostile and draw(st.integers(0, 5)) == 0):
        if draw(st.booleans()):
            out["linear_solver"] = draw(st.sampled_from(["direct", "iterative"] + (["lu", None, 3] if hostile else [])))
        if draw(st.booleans()):
            out["newton"] = draw(st.sampled_from([True, False] + ([None, "no"] if hostile else [])))
    if draw(st.integers(0, 6)) == 0:
        out["max_steps"] = draw(st.sampled_from([100, 1000, 100000] + (BAD_INTS if hostile else [])))
    return tuple(out.items())


@st.composite
def contact_options(draw, mode, hostile: bool):
    """Each mode's contact options: fast mode's solver and substeps, accurate mode's contact tolerance (hostile: now
    and then the other mode's, or bad values)."""
    out: dict[str, Any] = {}
    if mode == "fast" and draw(st.integers(0, 2)) == 0 or hostile and draw(st.integers(0, 5)) == 0:
        out["solver"] = draw(st.sampled_from(["soft", "exact"] + (["nope", None, 3, "SOFT"] if hostile else [])))
    if (mode == "fast" and out.get("solver", "soft") == "soft" and draw(st.integers(0, 3)) == 0
            or hostile and draw(st.integers(0, 5)) == 0):
        out["substeps"] = draw(st.sampled_from([1, 2, 4, 16] + ([0, -1, 1001, 2.5, "8", None] if hostile else [])))
    if mode != "fast" and draw(st.integers(0, 4)) == 0 or hostile and draw(st.integers(0, 5)) == 0:
        out["contact_tolerance"] = good_or_bad(draw, [1e-4, 1e-6, 1e-8], hostile)
    return tuple(out.items())


@st.composite
def world_options(draw):
    hostile = draw(st.integers(0, 2)) == 2
    mode = draw(st.sampled_from(["accurate", "fast"]))
    if hostile and draw(st.integers(0, 3)) == 0:
        mode = draw(st.sampled_from(["sideways", None, 1, "FAST"]))
    out: dict[str, Any] = {}
    if mode != "accurate" or draw(st.booleans()):
        out["mode"] = mode
    if mode != "fast" and draw(st.booleans()) or hostile and draw(st.integers(0, 5)) == 0:
        out.update(draw(integrator_options(hostile)))
    if mode == "fast" and draw(st.booleans()):
        out["dt"] = good_or_bad(draw, FAST_DTS, hostile)
    if mode == "fast" and draw(st.integers(0, 3)) == 0 or hostile and draw(st.integers(0, 5)) == 0:
        out["sleep"] = draw(st.sampled_from([True, False] + ([None, "yes", 2] if hostile else [])))
    out.update(draw(contact_options(mode, hostile)))
    if mode == "fast" and draw(st.integers(0, 5)) == 0:
        out["step_doubling"] = True if not hostile else draw(st.sampled_from([True, False, None, "yes"]))
    if draw(st.integers(0, 3)) == 0:
        out["gravity"] = draw(vector(-20.0, 20.0, hostile))
    if draw(st.integers(0, 5)) == 0:
        out["threads"] = draw(st.sampled_from([0, 1, 2] + ([-1, 2**64, 1.5, "2", None, 100000] if hostile else [])))
    return Op("world", "World", tuple(out.items()))


SCENE_SIZE = {"cloth": "n", "dominoes": "count", "pyramid": "layers", "cloth_drape": "n"}
SCENE_MADE = {"cloth": "ps", "spinning_top": "bs", "bouncing_ball": "b", "tumbling_box": "b", "dominoes": "b",
              "pyramid": "b", "cloth_drape": "pb"}


@st.composite
def scene(draw):
    hostile = draw(st.integers(0, 2)) == 2
    name = draw(st.sampled_from(list(SCENE_MADE)))
    h = hostile
    spec = {
        "cloth": {"n": counts(2, 5, h), "size": scalar(0.2, 2.0, h), "mass": scalar(0.05, 2.0, h),
                  "stiffness": scalar(10.0, 1e4, h, (1e4, 1e8)), "damping": scalar(0.0, 2.0, h),
                  "pin_stiffness": scalar(10.0, 1e5, h)},
        "spinning_top": {},
        "bouncing_ball": {"restitution": scalar(0.0, 1.0, h), "radius": scalar(0.05, 0.5, h, (1e-3, 10.0)),
                          "height": scalar(0.2, 3.0, h)},
        "tumbling_box": {},
        "dominoes": {"count": counts(1, 6, h), "spacing": scalar(0.2, 1.0, h)},
        "pyramid": {"layers": counts(1, 4, h)},
        "cloth_drape": {"n": counts(2, 6, h), "size": scalar(0.3, 2.0, h)},
    }[name]
    chosen = draw(params(spec))
    if name in SCENE_SIZE and SCENE_SIZE[name] not in dict(chosen):
        # the defaults are big scenes: keep them small
        chosen = ((SCENE_SIZE[name], draw(st.integers(2, 4))),) + chosen
    return Op("scene", name, chosen)


def _op(draw, name: str, required: tuple, optional: dict) -> Op:
    chosen = tuple((k, draw(v)) for k, v in required) + draw(params(optional))
    return Op("call", name, chosen, draw(st.integers(0, len(required))))


@st.composite
def operation(draw, made: frozenset, mode: str, shapes_only: bool = False):
    """One call, given the kinds of handles the program has made so far and the mode it is probably in."""
    h = hostile = draw(st.integers(0, 2)) == 2
    has = set(made)
    table = [(2, "shape")] if shapes_only else [
        (3, "add_particle"), (4, "add_body"), (1, "add_ground"), (3 if has & {"p", "b"} else 1, "add_spring"),
        (1, "add_force"), (1 if "b" in has else 0, "add_torque"), (2, "add_force_callback"), (1, "remove"),
        (1 if "p" in has else 0, "set_particle_state"), (1 if "b" in has else 0, "set_body_state"),
        (1, "set_mode"), (1 if mode != "fast" or hostile else 0, "set_integrator"), (5, "step"), (2, "run"),
        (1, "read"), (1, "threads"), (2, "shape"),
    ]
    name = pick(draw, *[(wt, st.just(n)) for wt, n in table if wt])
    material = {"restitution": scalar(0.0, 1.0, h), "friction": scalar(0.0, 1.5, h)}

    if name == "shape":
        method = draw(st.sampled_from(["mass_properties", "triangle_mesh", "kind", "halfspace"]))
        if method == "halfspace":  # the shapes of the world's bodies, the ground's half-space included
            shape, method = Raw(f"_shape_of(w, {draw(st.integers(0, 3))})"), "triangle_mesh"
        else:
            shape = draw(shapes(h, valid_type=True))
        if method == "mass_properties":
            return Op("shape", method, (("shape", shape), ("density", draw(scalar(1.0, 5000.0, h)))),
                      draw(st.integers(0, 1)))
        if method == "kind":
            return Op("shape", method, (("shape", shape),))
        subdivisions = st.integers(3, 24) if not h else weighted(
            (8, st.integers(3, 24)), (4, st.sampled_from([0, 1, 2, -1, 100000, 10**9, 2**32, 2**64, NAN, 1.5, "8",
                                                          None])))
        mesh = draw(params({"subdivisions": subdivisions, "extent": scalar(1.0, 20.0, h, (1e-3, 1e4))}))
        return Op("shape", "triangle_mesh", (("shape", shape),) + mesh, 0)
    if name == "add_particle":
        return _op(draw, name, (), {
            "mass": scalar(0.05, 10.0, h, (1e-4, 1e4)), "position": vector(-2.0, 2.0, h),
            "velocity": vector(-5.0, 5.0, h, wide=(-1e4, 1e4)), "damping": scalar(0.0, 2.0, h),
            "stiffness": scalar(0.0, 100.0, h, (100.0, 1e8)), "anchor": vector(-2.0, 2.0, h),
            "radius": weighted((1, st.just(0.0)), (1, scalar(0.0, 0.3, h))), **material})
    if name == "add_body":
        kind = pick(draw, (7, st.just("dynamic")), (2, st.just("static")), (2, st.just("inertia")))
        shape = None if kind == "inertia" else draw(shapes(h, static=kind == "static"))
        body = {"position": vector(-2.0, 2.0, h), "orientation": quaternion(h),
                "velocity": vector(-5.0, 5.0, h, wide=(-1e4, 1e4)),
                "angular_velocity": vector(-10.0, 10.0, h, wide=(-1e3, 1e3)),
                "linear_damping": scalar(0.0, 1.0, h), "angular_damping": scalar(0.0, 1.0, h), **material,
                "colliders": st.lists(st.one_of(st.tuples(shapes(h, static=False), vector(-0.5, 0.5, h)),
                                                st.tuples(shapes(h, static=False), vector(-0.5, 0.5, h),
                                                          quaternion(h))), max_size=2)}
        if h:
            body["colliders"] = st.one_of(body["colliders"], st.sampled_from(
                [None, "abc", [1.0], [(Raw("tumble.Sphere(0.1)"),)]]))
            body["static"] = st.sampled_from([True, False, None, "yes"])
        inertia = st.builds(lambda a, b, c: np.diag([a, b, c]), *[floats(0.01, 5.0)] * 3)
        if h:
            inertia = st.one_of(inertia, st.sampled_from(
                [[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]], np.diag([1.0, -1.0, 1.0]), np.full((3, 3), NAN),
                 np.eye(3) * 1e300, np.eye(3) * 5e-324, np.eye(2), None, "abc"]))
        mass = scalar(0.1, 50.0, h, (1e-4, 1e5))
        if kind == "dynamic":
            extra = draw(weighted((3, st.tuples(st.tuples(st.just("density"), scalar(100.0, 3000.0, h, (1.0, 1e5))))),
                                  (1, st.tuples(st.tuples(st.just("mass"), mass))), (1, st.just(()))))
        elif kind == "static":
            extra = (("static", True),)
        else:
            extra = (("mass", draw(mass)), ("inertia", draw(inertia)))
        if h:
            extra += draw(params({"density": scalar(100.0, 3000.0, h), "mass": mass, "inertia": inertia}))
        rest = draw(params(body))
        return Op("call", name, (("shape", shape),) + tuple(dict(extra + rest).items()), draw(st.integers(0, 1)))
    if name == "add_ground":
        return _op(draw, name, (), {"height": scalar(-1.0, 1.0, h), **material})
    if name == "add_spring":
        a = draw(handle("pb", made, h))
        b = pick(draw, (3, handle("pb", made, h)), (1, st.just(None)))
        optional = {"stiffness": weighted((8, floats(0.1, 1000.0)), (2, st.sampled_from([1e4, 1e6, 1e8, 1e10])))
                    if not h else scalar(0.1, 1000.0, h),
                    "damping": scalar(0.0, 10.0, h), "rest_length": scalar(0.0, 2.0, h)}
        if h or getattr(a, "kind", "") == "b":
            optional["anchor_a"] = vector(-0.5, 0.5, h)
        if h or getattr(b, "kind", "") == "b":
            optional["anchor_b"] = vector(-0.5, 0.5, h)
        chosen = (("a", a), ("b", b)) + draw(params(optional))
        if b is None or (h and draw(st.integers(0, 4)) == 0):
            chosen += (("world_point", draw(vector(-2.0, 2.0, h))),)
        return Op("call", name, chosen, draw(st.integers(0, 2)))
    if name == "add_force":
        target = draw(handle("pb", made, h))
        optional = {"at": vector(-0.5, 0.5, h)} if h or getattr(target, "kind", "") == "b" else {}
        op = _op(draw, name, (("target", st.just(target)), ("force", vector(-50.0, 50.0, h))), optional)
        return op
    if name == "add_torque":
        return _op(draw, name, (("body", handle("b", made, h)), ("torque", vector(-10.0, 10.0, h))), {})
    if name == "add_force_callback":
        target = draw(handle("pb", made, h))
        callback = draw(callbacks(getattr(target, "kind", "") == "b", h))
        return Op("call", name, (("target", target), ("callback", callback)), draw(st.integers(0, 2)))
    if name == "remove":
        return _op(draw, name, (("handle", handle("pbsl", made, h)),), {})
    if name == "set_particle_state":
        return _op(draw, name, (("particle", handle("p", made, h)),),
                   {"position": vector(-2.0, 2.0, h), "velocity": vector(-5.0, 5.0, h)})
    if name == "set_body_state":
        return _op(draw, name, (("body", handle("b", made, h)),),
                   {"position": vector(-2.0, 2.0, h), "orientation": quaternion(h), "velocity": vector(-5.0, 5.0, h),
                    "angular_velocity": vector(-10.0, 10.0, h)})
    if name == "set_mode":
        new = draw(st.sampled_from(["fast", "accurate"]))
        if h and draw(st.integers(0, 3)) == 0:
            new = draw(st.sampled_from(["sideways", None, 2]))
        chosen: tuple = (("mode", new),)
        if new == "fast" and draw(st.booleans()) or h and draw(st.integers(0, 3)) == 0:
            chosen += (("dt", good_or_bad(draw, FAST_DTS, h)),)
        if new == "fast" and draw(st.booleans()) or h and draw(st.integers(0, 3)) == 0:
            chosen += (("sleep", draw(st.sampled_from([True, False] + ([None, "yes"] if h else [])))),)
        chosen += draw(contact_options(new, h))
        return Op("call", name, chosen, draw(st.integers(0, 1)))
    if name == "set_integrator":
        return Op("call", name, draw(integrator_options(h)))
    if name == "step":
        return Op("call", name, (("dt", draw(durations(mode, h, 60, [0.01, 0.05, 0.1, 0.25, 1 / 60]))),),
                  draw(st.integers(0, 1)))
    if name == "run":
        duration = draw(durations(mode, h, 240, [0.1, 0.25, 0.5, 1.0]))
        frames = [(6, st.builds(Steps, st.integers(1, 24)))] + ([(2, st.sampled_from([1 / 60, 0.1, None]))]
                                                              if mode != "fast" else [])
        if h:
            frames.append((3, st.sampled_from([0.0, -1.0, NAN, INF, 1e-300, 5e-324, 1e300, "abc"])))
        progress = [False, None, Callback("progress")] + ([True, Callback("raise"), 5, "yes"] if h else [])
        optional = draw(params({"frame_interval": weighted(*frames), "progress": st.sampled_from(progress)}))
        return Op("call", name, (("duration", duration),) + optional, draw(st.integers(0, 1)))
    if name == "threads":
        return Op("set", "threads", (("threads", draw(st.sampled_from(
            [0, 1, 2] + ([4, -1, 2**64, 1.5, "2", None, 100000] if h else [])))),))
    return Op("read", draw(st.sampled_from([
        "w.time", "w.gravity", "w.mode", "w.threads", "w.plan()", "w.report", "w.report.as_dict()", "str(w.report)",
        "w.kinetic_energy()", "w.potential_energy()", "w.momentum()", "w.angular_momentum()", "w.particle_handles()",
        "w.body_handles()", "w._body_shapes()", "w.particles.positions", "w.bodies.orientations", "len(w.bodies)",
        "w.contacts()", "w.get_state().body_momenta", "w.set_state(w.get_state())",
    ])))


@st.composite
def pile(draw):
    """Bodies stacked, in layers or dropped onto a ground, as add_body calls: contact-rich scenes with now and then
    a valid extreme (1 mm bodies, a mass ratio up to 1e6, overlapping starts, a 1 km base)."""
    ops = [Op("call", "add_ground", ())] if draw(st.integers(0, 3)) > 0 else []
    half = draw(st.sampled_from([0.2, 0.05, 0.5, 0.001]))
    layout = draw(st.sampled_from(["stack", "layers", "drop"]))
    n = draw(st.integers(2, 8 if layout != "stack" else 4))
    ratio = draw(st.sampled_from([1.0, 10.0, 1e3, 1e6]))
    gap = draw(st.sampled_from([0.0, 1e-6, 0.01, -0.1])) * half
    if draw(st.integers(0, 5)) == 0:  # a 1 km base, static or not
        big = 500.0
        ops.append(Op("call", "add_body", (("shape", ShapeX("Box", (("half_extents", (big, big, big)),))),
                                           ("position", (0.0, 0.0, big)),
                                           ("static", True) if draw(st.booleans()) else ("density", 1000.0)), 1))
        floor = 2 * big
    else:
        floor = 0.0
    for k in range(n):
        if layout == "stack":
            x, y, z = draw(floats(-0.3, 0.3)) * half, draw(floats(-0.3, 0.3)) * half, (2 * k + 1) * half
        elif layout == "layers":
            layer, slot = divmod(k, 4)
            x, y = (slot % 2) * 2.2 * half + layer * 1.1 * half, (slot // 2) * 2.2 * half
            z = (2 * layer + 1) * half
        else:
            x, y, z = draw(floats(-4, 4)) * half, draw(floats(-4, 4)) * half, draw(floats(1, 10)) * half
        kind = draw(st.sampled_from(["Box", "Box", "Sphere", "Capsule", "Cylinder", "ConvexHull"]))
        shape = {
            "Box": ShapeX("Box", (("half_extents", (half, half, half)),)),
            "Sphere": ShapeX("Sphere", (("radius", half),)),
            "Capsule": ShapeX("Capsule", (("half_height", half / 2), ("radius", half / 2))),
            "Cylinder": ShapeX("Cylinder", (("half_height", half), ("radius", half))),
            "ConvexHull": ShapeX("ConvexHull", (("points", [(sx * half, sy * half, sz * half) for sx in (-1, 1)
                                                            for sy in (-1, 1) for sz in (-1, 1)]),)),
        }[kind]
        density = 1000.0 * (ratio if (k % 2 == 1) else 1.0)
        body: tuple = (("shape", shape), ("density", density), ("position", (x, y, floor + z + (k + 1) * gap)))
        if draw(st.integers(0, 3)) == 0:
            body += (("orientation", draw(st.tuples(floats(0.9, 1.0), *[floats(-0.1, 0.1)] * 3))),)
        if draw(st.integers(0, 3)) == 0:
            body += (("velocity", draw(st.tuples(*[floats(-2.0, 2.0)] * 3))),)
        ops.append(Op("call", "add_body", body, 1))
    return ops


@st.composite
def programs(draw, shapes_only: bool = False):
    if shapes_only:
        init = Op("world", "World", ())
    else:
        init = pick(draw, (3, world_options()), (1, scene()))
    if init.kind == "scene":
        made, mode = set(SCENE_MADE[init.name]), "accurate" if init.name in ("cloth", "spinning_top",
                                                                           "bouncing_ball") else "fast"
    else:
        made, mode = set(), dict(init.params).get("mode", "accurate")
    ops = []
    for _ in range(draw(st.integers(0, MAX_OPS))):
        if not shapes_only and draw(st.integers(0, 11)) == 0:
            new = draw(pile())
        else:
            new = [draw(operation(frozenset(made), mode, shapes_only))]
        for op in new:
            ops.append(op)
            if op.name in CREATES:
                made.add(CREATES[op.name])
            if op.name == "set_mode":
                mode = dict(op.params)["mode"]
    return Program(init, tuple(ops))


# ----------------------------------------------------------------------------------------------------------------
# The tests.

if __name__ != "__main__":

    def _settings(examples: int):
        return settings(
            max_examples=examples,
            deadline=None,  # hangs are the worker's timeout: a deadline cannot stop a call that never returns
            database=None,
            derandomize=not LONG,
            print_blob=True,
            suppress_health_check=list(HealthCheck),
        )

    def _seeded(test):
        if LONG and os.environ.get("TUMBLE_FUZZ_SEED"):
            return seed(int(os.environ["TUMBLE_FUZZ_SEED"]))(test)
        return test

    @pytest.fixture(scope="module")
    def worker():
        w = Worker()
        yield w
        w.stop()

    def test_harness_accepts_a_good_program(worker):
        """The checks themselves: a program of good calls passes (no false alarms)."""
        program = Program(
            Op("world", "World", (("mode", "fast"),)),
            (
                Op("call", "add_ground", ()),
                Op("call", "add_body", (("shape", ShapeX("Box", (("half_extents", (0.2, 0.2, 0.2)),))),
                                        ("position", (0.0, 0.0, 0.5))), 1),
                Op("call", "add_particle", (("position", (1.0, 0.0, 1.0)),)),
                Op("call", "add_spring", (("a", Ref("p", 0)), ("b", Ref("b", 1)), ("stiffness", 50.0)), 2),
                Op("call", "add_force_callback", (("target", Ref("b", 1)), ("callback", Callback("spring", 3.0))), 2),
                Op("call", "step", (("dt", Steps(12)),), 1),
                Op("call", "step", (("dt", 0.01),), 1),  # fails: not a whole number of steps
                Op("call", "remove", (("handle", Ref("s", 0)),), 1),
                Op("call", "run", (("duration", Steps(24)), ("frame_interval", Steps(6))), 1),
                Op("read", "w.report"),
            ),
        )
        worker.check(program)

    @pytest.mark.parametrize(
        "expression, kind",
        [("1 / 0", "WrongExceptionType"), ("__import__('os').abort()", "Crash"),
         ("__import__('time').sleep(60)", "Hang")],
    )
    def test_harness_reports_failures(expression, kind):
        """The checks themselves: an exception of the wrong type, a crash and a hang are reported with a
        reproducer."""
        worker = Worker(timeout=3.0)
        try:
            failures = worker.run(Program(Op("world", "World", ()), (Op("read", expression),)))
        finally:
            worker.stop()
        assert [k for k, _ in failures] == [kind]
        assert expression in failures[0][1] and "eproducer" in failures[0][1]

    @_seeded
    @_settings(EXAMPLES or 150)
    @given(program=programs())
    def test_programs(worker, program):
        """Random worlds and scenes, random calls: no panic, abort, hang or NaN; failed calls change nothing;
        reruns are identical."""
        worker.check(program)

    @_seeded
    @_settings(max(EXAMPLES // 4, 1) if LONG else 100)
    @given(program=programs(shapes_only=True))
    def test_shape_programs(worker, program):
        """Shapes and their methods, with bounded and unbounded arguments."""
        worker.check(program)


if __name__ == "__main__" and len(sys.argv) == 3 and sys.argv[1] == "--worker":
    worker_main(sys.argv[2])
