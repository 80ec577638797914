"""Executing a fuzz program in the worker: run each call, check what it must not do (panic, hang, NaN, change
the world on failure), and compare reruns. Part of ``test_fuzz.py``."""

from __future__ import annotations

import dataclasses
import math
import re
from typing import Any

import numpy as np


import tumble

from fuzz_programs import (CREATES, FOREIGN_COUNT, FOREIGN_WORLD, HANDLE_PARAMS, IGNORE, PREAMBLE, SIGNATURES,
                           STEPPING, Callback, CallbackError, Foreign, Op, Program, Raw, Ref, ShapeX, Steps,
                           _float_src, _int_src)
from fuzz_saved import check_saved
from fuzz_snapshot import Failure, diff, digest, non_finite, short, snapshot

# ----------------------------------------------------------------------------------------------------------------
# Executing a program (in the worker).


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
        self.handles: dict[str, list[str]] = {k: [] for k in "pbslj"}
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
            message = f"{type(error).__name__}: {short(str(error))}"
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
        bad = [f"{name} = {short(v)}" for name, v in snap if non_finite(v)]
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
        bad = non_finite(_result_numbers(result))
        if bad:
            self.fail("NonFiniteResult", f"`{line}` returned non-finite values at {bad[:5]}: {short(result)}")
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
        self.trace.append((index, "ok", "report" if "report" in op.name else digest(result)))

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
                self.fail("BadResult", f"`{line}`: frame times {short(times)}, w.time = {w.time!r}")

    def after_failure(self, index, op, ctx, error, before, callback_raised) -> None:
        line = self.entries[-1][0]
        described = f"`{line}` raised {type(error).__module__}.{type(error).__name__}: {short(str(error))}"
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
        if isinstance(error, CallbackError) and ctx.get("progress raises"):
            # a run its progress callable stopped by raising (not Ctrl-C) fails: the frames done ride on the error,
            # and the world is as it was (checked below)
            kept = getattr(error, "run", None)
            if op.name == "run" and (kept is None or kept.interrupted):
                self.fail("FailedRunLostFrames", f"{described}\nkept {kept!r}, w.time = {self.ns['w'].time!r}")
        if before is not None:
            after = snapshot(self.ns["w"])
            changed = diff(before, after)
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
    phase("saved and loaded")
    saved = check_saved(first)
    if saved:
        return saved
    phase("rerun")
    second = Execution(program, log=log)
    second.run()
    changed = diff(first.final, second.final)
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
    changed = diff(first.final, third.final)
    calls = [f"{a} != {b}" for a, b in zip(kept, third.trace) if a != b][:3]
    if changed or calls:
        return [("FailedCallChangedHiddenState", "the same program without its failed calls (the try/except "
                 "blocks) ends differently:\n  " + "\n  ".join(changed + calls) + "\n\nReproducer:\n"
                 + first.reproducer())]
    return []
