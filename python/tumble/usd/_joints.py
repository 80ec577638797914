"""USD Physics in, joints: revolute (a hinge about its axis token in the joint frame, limits in degrees), prismatic
(a slider, limits in stage units), spherical (a ball, no cone limits), fixed (a weld) and distance (a rod where the
minimum and maximum distances agree, a rope with only a maximum) joints, their angular or linear DriveAPI as a joint
spring (stiffness and damping towards the target position) or a motor (a target velocity up to the maximum force).
The two ends' joint frames must coincide in the stage as authored (where tumble's zero angle and travel are)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .._geometry import rotation_matrix
from ._shapes import Frames
from ._values import shown, value

Array = np.ndarray
_AXES = {"X": 0, "Y": 1, "Z": 2}


def _frame(stage: Any, rel: Any, pos: Any, rot: Any, frames: Frames) -> tuple[Any, Array, Array]:
    """A joint end: its body prim (or None: the world) and its joint frame's world pose in tumble's axes."""
    from ._read import _world_matrix  # noqa: PLC0415

    targets = rel.GetTargets()
    local = np.asarray(value(pos, np.zeros(3)), dtype=float)
    q = value(rot)
    turn = rotation_matrix(q) if q is not None else np.eye(3)
    if not targets:
        return None, frames.up @ local * frames.metres, frames.up @ turn
    target = stage.GetPrimAtPath(targets[0])
    x, r, scale = frames.pose(_world_matrix(target))
    return target, x + r @ (local * scale * frames.metres), r @ turn


def _drive(prim: Any, instance: str, angular: bool, frames: Frames, problems: list[str]) -> dict[str, Any]:
    """A DriveAPI instance as tumble's ``spring`` or ``motor`` field (none when the joint has no such drive)."""
    import tumble  # noqa: PLC0415
    from pxr import UsdPhysics  # noqa: PLC0415

    if not prim.HasAPI(UsdPhysics.DriveAPI, instance):
        return {}
    path = f"{prim.GetPath()}: drive:{instance}"
    drive = UsdPhysics.DriveAPI.Get(prim, instance)
    if str(drive.GetTypeAttr().Get() or "force") != "force":
        problems.append(f"{path}:physics:type: an acceleration drive is not taken (tumble's drives are forces)")
        return {}
    # angles in degrees, torques in stage units: to radians, N m and N
    per_angle = 180.0 / math.pi if angular else 1.0
    force = frames.kilograms * frames.metres ** (2 if angular else 1)
    length = 1.0 / frames.metres if not angular else 1.0
    stiffness = value(drive.GetStiffnessAttr(), 0.0) * force * length * per_angle
    damping = value(drive.GetDampingAttr(), 0.0) * force * length * per_angle
    target = value(drive.GetTargetPositionAttr(), 0.0) / per_angle / length
    speed = value(drive.GetTargetVelocityAttr(), 0.0) / per_angle / length
    limit = value(drive.GetMaxForceAttr())
    if stiffness > 0.0 or (damping > 0.0 and speed == 0.0):
        if speed != 0.0:
            problems.append(f"{path}:physics:targetVelocity: a drive with stiffness and a target velocity is not "
                            "taken (tumble's joint springs pull towards a position)")
        return {"spring": tumble.JointSpring(stiffness=stiffness, damping=damping, target=target)}
    if speed != 0.0:
        if limit is None or not math.isfinite(limit):
            problems.append(f"{path}:physics:maxForce: a velocity drive needs a finite maximum force in tumble "
                            "(its motor holds the speed up to it)")
            return {}
        bound = float(limit) * force
        return {"motor": tumble.Motor(speed=speed, max_torque=bound) if angular else
                tumble.Motor(speed=speed, max_force=bound)}
    return {}


def add_joints(world: Any, stage: Any, handles: dict[str, Any], frames: Frames, problems: list[str]) -> None:
    """Adds the stage's joints between the bodies of ``handles`` (by prim path)."""
    import tumble  # noqa: PLC0415
    from pxr import UsdPhysics  # noqa: PLC0415

    kinds = [(UsdPhysics.RevoluteJoint, "revolute"), (UsdPhysics.PrismaticJoint, "prismatic"),
             (UsdPhysics.SphericalJoint, "spherical"), (UsdPhysics.FixedJoint, "fixed"),
             (UsdPhysics.DistanceJoint, "distance")]
    for prim in stage.Traverse():
        if not prim.IsA(UsdPhysics.Joint):
            continue
        path, joint = str(prim.GetPath()), UsdPhysics.Joint(prim)
        if joint.GetJointEnabledAttr().Get() is False:
            continue
        kind = next((name for schema, name in kinds if prim.IsA(schema)), None)
        before = len(problems)
        if kind is None:
            problems.append(f"{path}: {prim.GetTypeName()}: a generic (D6) joint is not taken yet (revolute, "
                            "prismatic, spherical, fixed, distance)")
            continue
        # the force (mass distance / s^2) and torque (mass distance^2 / s^2) past which the joint breaks
        bounds = []
        for name, power in (("breakForce", 1), ("breakTorque", 2)):
            bound = value(prim.GetAttribute(f"physics:{name}"))
            finite = bound is not None and math.isfinite(bound)
            bounds.append(bound * frames.kilograms * frames.metres ** power if finite else math.inf)
        (pa, xa, ra), (pb, xb, rb) = (_frame(stage, joint.GetBody0Rel(), joint.GetLocalPos0Attr(),
                                             joint.GetLocalRot0Attr(), frames),
                                      _frame(stage, joint.GetBody1Rel(), joint.GetLocalPos1Attr(),
                                             joint.GetLocalRot1Attr(), frames))
        size = 1.0 + float(np.abs(xa).max())
        if kind != "distance" and np.linalg.norm(xa - xb) > 1e-6 * size:  # a distance joint's ends are apart
            problems.append(f"{path}: physics:localPos1: the joint's frames are {np.linalg.norm(xa - xb):.3g} m "
                            "apart in the stage (tumble joins them where they are)")
        if kind != "spherical" and kind != "distance" and np.abs(ra.T @ rb - np.eye(3)).max() > 1e-6:
            problems.append(f"{path}: physics:localRot1: the joint's frames are turned apart in the stage (tumble's "
                            "zero angle is where they are)")
        ends = []
        for end in (pa, pb):
            handle = handles.get(str(end.GetPath())) if end is not None else None
            if end is not None and handle is None:
                problems.append(f"{path}: physics:body: {end.GetPath()} is not a body of the world")
            ends.append(handle)
        if len(problems) > before:
            continue
        fields: dict[str, Any] = {"collide": bool(joint.GetCollisionEnabledAttr().Get())}
        if any(math.isfinite(b) for b in bounds):
            fields["breaking"] = tumble.Breaking(force=bounds[0], torque=bounds[1])
        rows = [world.bodies.row(h) if h is not None else None for h in ends]
        for k, (row, x) in enumerate(zip(rows, (xa, xb))):
            if row is None:
                fields["world_point"] = tuple(x)
            else:
                q = np.asarray(world.bodies.orientations[row])
                fields["anchor_b" if k else "anchor_a"] = tuple(rotation_matrix(q).T @ (x - world.bodies.positions[row]))
        if kind in ("revolute", "prismatic"):
            axis = ra[:, _AXES[str(joint.GetPrim().GetAttribute("physics:axis").Get() or "X")]]
            if rows[0] is not None:
                axis = rotation_matrix(np.asarray(world.bodies.orientations[rows[0]])).T @ axis
            fields["axis"] = tuple(axis)
            lower = value(prim.GetAttribute("physics:lowerLimit"))
            upper = value(prim.GetAttribute("physics:upperLimit"))
            if lower is not None and upper is not None and math.isfinite(lower) and math.isfinite(upper):
                scale = math.pi / 180.0 if kind == "revolute" else frames.metres
                fields["limits"] = (float(lower) * scale, float(upper) * scale)
            elif (lower is not None and math.isfinite(lower)) or (upper is not None and math.isfinite(upper)):
                problems.append(f"{path}: physics:lowerLimit: a joint limited on one side is not taken (give both "
                                "limits)")
                continue
            fields.update(_drive(prim, "angular" if kind == "revolute" else "linear", kind == "revolute", frames,
                                 problems))
        elif kind == "spherical":
            cones = [value(prim.GetAttribute(f"physics:coneAngle{k}Limit")) for k in (0, 1)]
            if any(c is not None and 0.0 <= c < 180.0 for c in cones):
                problems.append(f"{path}: physics:coneAngle0Limit: a ball joint's cone limits are not taken yet")
                continue
        elif kind == "distance":
            low, high = (value(prim.GetAttribute(f"physics:{n}Distance")) for n in ("min", "max"))
            low = None if low is None or low < 0 else low * frames.metres
            high = None if high is None or high < 0 else high * frames.metres
            if high is None or (low is not None and abs(low - high) > 1e-12 * (1.0 + high) and low > 0.0):
                given = " to ".join("none" if d is None else shown(d) for d in (low, high))
                problems.append(f"{path}: physics:minDistance: tumble holds a distance ({given} m given): "
                                "equal limits (a rod) or a maximum alone (a rope)")
                continue
            fields.update(length=high, rope=low is None or low == 0.0 and high > 0.0)
        make = {"revolute": tumble.Hinge, "prismatic": tumble.Slider, "spherical": tumble.Ball,
                "fixed": tumble.Weld, "distance": tumble.Distance}[kind]
        try:
            world.add_joint(make(ends[0], ends[1], **fields))
        except ValueError as error:
            problems.append(f"{path}: {error}")
