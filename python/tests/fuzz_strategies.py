"""The fuzzer's hypothesis strategies: worlds, scenes and calls with good, extreme and badly typed arguments (drawn
by ``fuzz_arguments.py``), and programs of them. Part of ``test_fuzz.py``."""

from __future__ import annotations

from typing import Any

import numpy as np

from hypothesis import strategies as st

from fuzz_arguments import (ADAPTIVE, BAD_INTS, BAD_SCALARS, FAST_DTS, HOSTILE_DURATIONS, INTEGRATORS, counts, floats,
                             good_or_bad, params, pick, quaternion, scalar, shapes, vector, weighted)
from fuzz_programs import CREATES, INF, LONG, MAX_OPS, NAN, Callback, Foreign, Op, Program, Raw, Ref, ShapeX, Steps

# ----------------------------------------------------------------------------------------------------------------
# Strategies. A call is clean (every argument good, now and then a valid extreme: a stiff spring, a tiny or huge
# body, a fast spin) or, one time in three, hostile (each argument good, extreme or badly typed). Programs shrink
# towards clean calls and fewer of them.


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
def joint_op(draw, made: frozenset, h: bool) -> Op:
    """An add_joint call: a joint of any kind between bodies or a body and the world, with its options."""
    cls = draw(st.sampled_from(["Ball", "Hinge", "Slider", "Weld", "Distance"]))
    a = pick(draw, (4, handle("b", made, h)), (1, st.just(None)))
    b = pick(draw, (4, handle("b", made, h)), (1, st.just(None)))
    optional = {"anchor_a": vector(-0.5, 0.5, h), "anchor_b": vector(-0.5, 0.5, h)}
    if h or draw(st.integers(0, 3)) == 0:
        optional["softness"] = st.tuples(scalar(1.0, 60.0, h), scalar(0.0, 5.0, h))
    if cls in ("Hinge", "Slider"):
        motor = st.builds(lambda s, m: ShapeX("Motor", (("speed", s), ("max_torque" if cls == "Hinge" else
                                                                       "max_force", m)), 0),
                          scalar(-5.0, 5.0, h), scalar(0.0, 50.0, h))
        spring = st.builds(lambda k, c: ShapeX("JointSpring", (("stiffness", k), ("damping", c)), 0),
                           scalar(1.0, 100.0, h), scalar(0.0, 5.0, h))
        optional.update({"axis": vector(-1.0, 1.0, h), "limits": st.tuples(scalar(-1.5, 0.0, h), scalar(0.0, 1.5, h)),
                         "motor": motor, "spring": spring})
    if cls == "Distance":
        optional.update({"length": scalar(0.1, 2.0, h), "rope": st.booleans()})
    chosen = (("a", a), ("b", b)) + draw(params(optional))
    if a is None or b is None:
        chosen += (("world_point", draw(vector(-2.0, 2.0, h))),)
    return Op("call", "add_joint", (("joint", ShapeX(cls, chosen, 2)),), 1)


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
        # joints in long runs only (see test_fuzz.py): with weight 0 the CI search draws what it drew before them
        (0 if not LONG else 3 if "b" in has else 1, "add_joint"), (1 if LONG and "j" in has else 0, "remove_joint"),
    ]
    name = pick(draw, *[(wt, st.just(n)) for wt, n in table if wt])
    material = {"restitution": scalar(0.0, 1.0, h), "friction": scalar(0.0, 1.5, h)}
    if LONG:  # resistance to turning and combine rules in long runs only, so that the CI search draws as before
        material["rolling_resistance"] = weighted((2, st.just(0.0)), (1, scalar(0.0, 0.5, h)))
        material["friction_combine"] = st.sampled_from([None, "average", "geometric_mean", "min", "product", "max"])

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
            "radius": weighted((1, st.just(0.0)), (1, scalar(0.0, 0.3, h))),
            # a particle does not turn: it takes no resistance to turning
            **{k: v for k, v in material.items() if k != "rolling_resistance"}})
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
    if name == "add_joint":
        return draw(joint_op(made, h))
    if name == "remove_joint":
        return _op(draw, name, (("joint", handle("j", made, h)),), {})
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
