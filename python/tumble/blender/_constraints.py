"""Blender's rigid body constraints as tumble joints: fixed as a weld, point as a ball, hinge about the constraint
object's z, slider and piston along its x, motor as drives about and along its x, and generic constraints as the
one of those their locked, limited and free axes make (a generic spring's Spring 2 spring on the joint's moving
axis as the joint's spring); each anchored at the constraint object's origin, breakable ones breaking at their
threshold. What cannot be mapped is said in ``problems``, naming the object and the setting."""

from __future__ import annotations

from typing import Any

import numpy as np

from tumble._geometry import rotation_matrix

AXES = "xyz"


def _to_body(wxyz: tuple[float, ...], v: Any) -> Any:
    """The world vector ``v`` in the frame of orientation ``wxyz``."""
    return rotation_matrix(np.asarray(wxyz, dtype=float)).T @ v


Limits = tuple[float, float] | None


def generic(c: Any) -> tuple[str, int | None, Limits, Limits] | str:
    """The tumble joint a generic constraint's axes make, as (Blender's constraint type it acts as, the axis's index
    in the constraint's frame, the limits on it, a piston's limits on its turn), or why none does. An axis is locked by a limit from 0 to 0, free
    without a limit, limited by any other."""
    def state(kind: str, i: int) -> tuple[str, tuple[float, float] | None]:
        if not getattr(c, f"use_limit_{kind}_{AXES[i]}"):
            return "free", None
        lo, hi = (float(getattr(c, f"limit_{kind}_{AXES[i]}_{end}")) for end in ("lower", "upper"))
        if lo == hi == 0.0:
            return "locked", None
        return ("limited", (lo, hi)) if lo < hi else ("locked elsewhere", (lo, hi))

    lin, ang = [state("lin", i) for i in range(3)], [state("ang", i) for i in range(3)]
    odd = [f"{kind} {AXES[i]}" for kind, axes in (("linear", lin), ("angular", ang))
           for i, (s, _) in enumerate(axes) if s == "locked elsewhere"]
    if odd:
        return f"{', '.join(odd)} held at a value other than 0 (tumble joins the bodies where they are)"
    moving = [[i for i, (s, _) in enumerate(axes) if s != "locked"] for axes in (lin, ang)]
    lm, am = moving
    if not lm and not am:
        return "FIXED", None, None, None
    if not lm and len(am) == 3 and all(s == "free" for s, _ in ang):
        return "POINT", None, None, None
    if not lm and len(am) == 1:
        return "HINGE", am[0], ang[am[0]][1], None
    if not am and len(lm) == 1:
        return "SLIDER", lm[0], lin[lm[0]][1], None
    if len(lm) == 1 and am == lm:
        return "PISTON", lm[0], lin[lm[0]][1], ang[lm[0]][1]
    free = ", ".join([f"linear {AXES[i]}" for i in lm] + [f"angular {AXES[i]}" for i in am]) or "none"
    return (f"its free and limited axes ({free}) make none of tumble's joints (weld, ball, hinge, slider, "
            "piston)")


def spring(c: Any, kind: str, axis: int, world: Any, rows: list[int], pivot: Any, turn: Any, substep: float,
           unit: float) -> Any:
    """A generic spring's springs as the spring of the joint its axes make (``kind`` about or along its axis
    ``axis``): a ``tumble.JointSpring`` towards where the bodies are (Blender sets Bullet's equilibrium there), None
    without springs, or why they cannot be mapped. Bullet's Spring 2 is a plain spring of the given stiffness and
    damping unless it lowers them (a spring sampled faster than a quarter of its angular frequency a substep, or
    damping past the effective mass over the substep): those are refused, as is Spring 1 (a motor whose speed
    follows the solver's iterations) and a spring on an axis the joint holds."""
    import tumble  # noqa: PLC0415

    on = [(k, a) for k in ("", "ang_") for a in AXES if getattr(c, f"use_spring_{k}{a}")]
    if not on:
        return None
    if c.spring_type != "SPRING2":
        return "Blender's Spring 1 is a motor whose speed follows the solver's iterations: choose Spring 2"
    wanted = {"HINGE": ("ang_", AXES[axis]), "SLIDER": ("", AXES[axis]), "PISTON": ("", AXES[axis])}.get(kind)
    if wanted is None or on != [wanted]:
        names = ", ".join(f"{'angular' if k else 'linear'} {a}" for k, a in on)
        where = {"HINGE": "its angle", "SLIDER": "its travel", "PISTON": "its travel"}.get(kind)
        joint = {"FIXED": "weld", "POINT": "ball joint"}.get(kind, kind.lower())
        return (f"springs on {names}: the {joint} these axes make has a spring on {where} alone"
                if where else f"springs on {names}: the {joint} these axes make has no spring")
    name = f"{wanted[0]}{wanted[1]}"
    rotational = wanted[0] == "ang_"
    scale = unit * unit if rotational else 1.0  # angular stiffness and damping are per Blender unit squared
    stiffness = float(getattr(c, f"spring_stiffness_{name}")) * scale
    damping = float(getattr(c, f"spring_damping_{name}")) * scale
    # Bullet's effective mass: the lighter end's (an angular spring's: its mass at its lever to the constraint's
    # origin plus its moment about the axis); a passive end has none
    direction = turn[:, axis]
    masses = []
    for r in rows:
        m = float(world.bodies.masses[r])
        if not np.isfinite(m):
            continue
        if rotational:
            lever = float(np.sum((world.bodies.positions[r] - pivot) ** 2))
            m = m * lever + 1.0 / float(np.linalg.norm(np.linalg.solve(world.bodies.inertias[r], direction)))
        masses.append(m)
    m = min(masses)
    axis_name = f"{'angular' if rotational else 'linear'} {wanted[1]}"
    if np.sqrt(stiffness / m) * substep > 0.25:
        return (f"stiffness {axis_name}: Bullet lowers a spring whose sqrt(k / m) times the substep passes 0.25 "
                f"(here {np.sqrt(stiffness / m) * substep:.3g}); soften it or take more substeps")
    if damping * substep > m:
        return (f"damping {axis_name}: Bullet lowers damping past the effective mass over the substep "
                f"({m / substep:.3g}); lower it or take more substeps")
    return tumble.JointSpring(stiffness, damping, 0.0)


def constraints(world: Any, scene: Any, rbw: Any, handles: dict[str, Any], problems: list[str],
                 notes: list[str]) -> None:
    """The rigid body world's constraints as tumble joints: fixed as a weld, point as a ball, hinge about the
    constraint object's z (its z angle limits as the hinge's), slider and piston along its x (its x limits), each
    anchored at the constraint object's origin; a breakable one breaks at its threshold over the substep."""
    import tumble  # noqa: PLC0415

    unit = float(scene.unit_settings.scale_length) or 1.0
    kinds = {"FIXED": tumble.Weld, "POINT": tumble.Ball, "HINGE": tumble.Hinge, "SLIDER": tumble.Slider,
             "PISTON": tumble.Piston, "MOTOR": tumble.Drive}
    # Bullet's motor gives at most its impulse each substep, and breaks a constraint at its threshold impulse in one:
    # those over the substep are forces and torques
    substep = rbw.time_scale / (scene.render.fps / scene.render.fps_base) / rbw.substeps_per_frame
    objects = sorted((o for o in rbw.constraints.objects if o.rigid_body_constraint is not None),
                     key=lambda o: o.name) if rbw.constraints is not None else []
    for obj in objects:
        c = obj.rigid_body_constraint
        if not c.enabled:
            continue
        before = len(problems)
        kind, generic_axis, generic_limits, generic_turn = c.type, None, None, None
        if c.type in ("GENERIC", "GENERIC_SPRING"):
            acts = generic(c)
            if isinstance(acts, str):
                problems.append(f"{obj.name}: limits: {acts}")
            else:
                kind, generic_axis, generic_limits, generic_turn = acts
        if kind not in kinds and kind not in ("GENERIC", "GENERIC_SPRING"):
            problems.append(f"{obj.name}: constraint type: {c.type} is not one tumble takes yet (fixed, point, "
                            "hinge, slider, piston, motor, generic)")
        ends = []
        for which in (c.object1, c.object2):
            if which is None or which.name not in handles:
                problems.append(f"{obj.name}: objects: {which.name if which else 'none'} is not a rigid body of "
                                "the world")
            else:
                ends.append(handles[which.name])
        if len(problems) > before:
            continue
        if c.disable_collisions and any(o.rigid_body.type == "PASSIVE" for o in (c.object1, c.object2)):
            notes.append(f"{obj.name}: disable collisions: tumble keeps a joint's moving body touching a passive one "
                         "(only two moving bodies a joint joins never touch)")
        location, rotation, _ = obj.matrix_world.decompose()
        pivot = np.array(location, dtype=float) * unit
        rows = [world.bodies.row(h) for h in ends]
        poses = [(world.bodies.positions[r], tuple(world.bodies.orientations[r])) for r in rows]
        anchors = [_to_body(q, pivot - x) for x, q in poses]
        fields: dict[str, Any] = {"anchor_a": tuple(anchors[0]), "anchor_b": tuple(anchors[1]),
                                  "collide": not c.disable_collisions}
        if c.use_breaking:
            # Bullet breaks a constraint once one of its rows' impulse in a substep reaches the threshold: that
            # over the substep bounds tumble's force (N) and torque (N m) alike
            bound = float(c.breaking_threshold) / substep
            fields["breaking"] = tumble.Breaking(force=bound * unit, torque=bound * unit * unit)
            if c.type == "FIXED" and c.disable_collisions:
                # a breakable Fixed constraint between pieces is glue (Cell Fracture's, or "Fracture with tumble"'s):
                # the pieces it binds are one piece for collision while it holds
                fields["cluster"] = True
        turn = np.array(rotation.to_matrix(), dtype=float)
        if c.type in ("GENERIC", "GENERIC_SPRING"):
            if generic_axis is not None:
                fields["axis"] = tuple(_to_body(poses[0][1], turn[:, generic_axis]))
            if generic_limits is not None:
                scale = 1.0 if kind == "HINGE" else unit
                fields["limits"] = (generic_limits[0] * scale, generic_limits[1] * scale)
            if generic_turn is not None:
                fields["turn_limits"] = generic_turn
            if c.type == "GENERIC_SPRING":
                springs = spring(c, kind, generic_axis if generic_axis is not None else 0, world, rows, pivot, turn,
                                 substep, unit)
                if isinstance(springs, str):
                    problems.append(f"{obj.name}: {springs}")
                    continue
                if springs is not None:
                    fields["spring"] = springs
        elif c.type == "HINGE":
            fields["axis"] = tuple(_to_body(poses[0][1], turn[:, 2]))
            if c.use_limit_ang_z:
                fields["limits"] = (float(c.limit_ang_z_lower), float(c.limit_ang_z_upper))
        elif c.type in ("SLIDER", "PISTON"):
            fields["axis"] = tuple(_to_body(poses[0][1], turn[:, 0]))
            if c.use_limit_lin_x:
                fields["limits"] = (float(c.limit_lin_x_lower) * unit, float(c.limit_lin_x_upper) * unit)
            if c.type == "PISTON" and c.use_limit_ang_x:
                fields["turn_limits"] = (float(c.limit_ang_x_lower), float(c.limit_ang_x_upper))
        try:
            if c.type == "MOTOR":  # a drive about the constraint's x, and one along it, each where enabled
                axis = tuple(_to_body(poses[0][1], turn[:, 0]))
                for on, motor in ((c.use_motor_ang, tumble.Motor(float(c.motor_ang_target_velocity),
                                                                 max_torque=float(c.motor_ang_max_impulse) / substep)),
                                  (c.use_motor_lin, tumble.Motor(float(c.motor_lin_target_velocity) * unit,
                                                                 max_force=float(c.motor_lin_max_impulse) / substep))):
                    if on:
                        world.add_joint(tumble.Drive(ends[0], ends[1], axis=axis, motor=motor, **fields))
            else:
                world.add_joint(kinds[kind](ends[0], ends[1], **fields))
        except ValueError as error:
            problems.append(f"{obj.name}: {error}")
