"""USD Physics in (``tumble.World.from_usd``): a stage's UsdPhysics schema read into a world through usd-core. The
scene's gravity; rigid bodies (RigidBodyAPI: velocities, kinematic bodies following their animation, disabled ones
static) with MassAPI's mass, density, centre of mass and inertia; colliders (CollisionAPI) on bodies or alone
(static bodies); their physics materials; revolute, prismatic, spherical, fixed and distance joints with limits and
drives; metersPerUnit, kilogramsPerUnit and upAxis. Every body is named by its prim path, which runs carry back to
the stage (``Run.export_usd(path, over=source)``). What cannot be mapped raises ``UsdSceneError`` listing each prim
and attribute; each approximation made is a ``UsdImportWarning`` naming them. float32 attributes are read as the
decimals they were typed as (``_usd_values``)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from ._shapes import Frames, UsdSceneError, _pxr, material_of, quaternion, shape_of
from ._values import note, value

Array = np.ndarray
_Y_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])  # stage y up -> tumble z up


def frames_of(stage: Any) -> Frames:
    """The stage's units and up axis."""
    from pxr import UsdGeom, UsdPhysics  # noqa: PLC0415

    up = _Y_UP if UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.y else np.eye(3)
    return Frames(up, float(UsdGeom.GetStageMetersPerUnit(stage)), float(UsdPhysics.GetStageKilogramsPerUnit(stage)))


def _world_matrix(prim: Any, time: Any = None) -> Any:
    from pxr import Usd, UsdGeom  # noqa: PLC0415

    return UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(Usd.TimeCode.Default() if time is None else time)


def _gravity(stage: Any, frames: Frames, problems: list[str]) -> Array:
    """The physics scene's gravity in tumble's axes (m/s^2): its direction and magnitude, or -up and 9.81 m/s^2 by
    the schema's defaults; none without a physics scene."""
    from pxr import UsdPhysics  # noqa: PLC0415

    scenes = [p for p in stage.Traverse() if p.IsA(UsdPhysics.Scene)]
    if not scenes:
        return np.zeros(3)
    if len(scenes) > 1:
        problems.append(f"{scenes[1].GetPath()}: PhysicsScene: tumble runs one scene a world (also "
                        f"{scenes[0].GetPath()})")
    scene = UsdPhysics.Scene(scenes[0])
    direction = np.asarray(value(scene.GetGravityDirectionAttr(), np.zeros(3)), dtype=float)
    magnitude = value(scene.GetGravityMagnitudeAttr())
    down = frames.up @ direction if np.linalg.norm(direction) > 0 else np.array([0.0, 0.0, -1.0])
    down = down / np.linalg.norm(down)
    g = 9.81 if magnitude is None or not math.isfinite(magnitude) else float(magnitude) * frames.metres
    out: Array = down * g
    return out


def _owner(prim: Any) -> Any | None:
    """The rigid body a collider prim belongs to: its nearest ancestor (or itself) with RigidBodyAPI."""
    from pxr import UsdPhysics  # noqa: PLC0415

    p = prim
    while p and p.IsValid() and not p.IsPseudoRoot():
        if p.HasAPI(UsdPhysics.RigidBodyAPI):
            return p
        p = p.GetParent()
    return None


def _collider(prim: Any, frames: Frames, static: bool, problems: list[str],
              notes: list[str]) -> tuple[Any, Array, Array, Any] | None:
    """A collider prim as (shape, world position (m), world rotation, material), or None (said in problems); its
    approximations said in notes."""
    x, r, scale = frames.pose(_world_matrix(prim))
    shape, at, turn = shape_of(prim, scale, frames.metres, problems, static, notes)
    if shape is None:
        return None
    return shape, x + r @ at, r @ turn, material_of(prim, notes)


def _relative(x0: Array, r0: Array, x: Array, r: Array) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """The pose (x, r) in the frame (x0, r0), as a position and a quaternion (w, x, y, z)."""
    return tuple(r0.T @ (x - x0)), quaternion(r0.T @ r)


def _one_material(path: str, materials: list[tuple[float, float, float | None]],
                  problems: list[str]) -> tuple[float, float, float | None]:
    """A body's material: its colliders' must agree (tumble has one a body)."""
    if any(m[:2] != materials[0][:2] for m in materials):
        problems.append(f"{path}: material:binding: its colliders' physics materials differ (tumble has one "
                        "material a body)")
    return materials[0]


def _animation(stage: Any, prim: Any, frames: Frames) -> tuple[Array, list[Any]]:
    """The times (s) a prim's world transform is sampled at (its own and its ancestors' transform samples; the
    start time code alone when none is animated) and those time codes."""
    from pxr import Usd, UsdGeom  # noqa: PLC0415

    codes: set[float] = set()
    p = prim
    while p and p.IsValid() and not p.IsPseudoRoot():
        xformable = UsdGeom.Xformable(p)
        if xformable:
            for op in xformable.GetOrderedXformOps():
                codes.update(op.GetAttr().GetTimeSamples())
        p = p.GetParent()
    start = stage.GetStartTimeCode()
    ordered = sorted(codes) or [start]
    tcps = stage.GetTimeCodesPerSecond() or 24.0
    return np.array([(c - start) / tcps for c in ordered]), [Usd.TimeCode(c) for c in ordered]


def read_stage(path: str | Path, make: Any = None, **world_options: Any) -> tuple[Any, dict[str, Any]]:
    """The world (made by ``make``, tumble.World by default) of the stage at ``path`` and its bodies' handles by
    prim path (see the module's docstring); each approximation made a ``UsdImportWarning`` once the world is
    built."""
    _pxr()
    import tumble  # noqa: PLC0415
    from pxr import Usd, UsdPhysics  # noqa: PLC0415

    stage = Usd.Stage.Open(str(path))
    if stage is None:
        raise ValueError(f"invalid argument `path`: {path} is not a USD stage usd-core can open")
    frames = frames_of(stage)
    problems: list[str] = []
    notes: list[str] = []
    world = (make or tumble.World)(gravity=tuple(_gravity(stage, frames, problems)), **world_options)
    handles: dict[str, Any] = {}
    owned: dict[str, list[Any]] = {}
    loose: list[Any] = []
    for prim in stage.Traverse():
        if prim.HasAPI(UsdPhysics.CollisionAPI) and UsdPhysics.CollisionAPI(prim).GetCollisionEnabledAttr().Get():
            owner = _owner(prim)
            (loose if owner is None else owned.setdefault(str(owner.GetPath()), [])).append(prim)
        for api, what in ((UsdPhysics.FilteredPairsAPI, "physics:filteredPairs"),):
            if prim.HasAPI(api):
                problems.append(f"{prim.GetPath()}: {what}: filtered pairs are not taken yet")
        if prim.IsA(UsdPhysics.CollisionGroup):
            problems.append(f"{prim.GetPath()}: PhysicsCollisionGroup: collision groups are not taken yet")
    for prim in loose:  # colliders of no rigid body: static bodies
        c = _collider(prim, frames, True, problems, notes)
        if c is not None:
            shape, x, r, (friction, restitution, _) = c
            try:
                handles[str(prim.GetPath())] = world.add_body(shape, static=True, position=tuple(x),
                                                              orientation=quaternion(r), friction=friction,
                                                              restitution=restitution, name=str(prim.GetPath()))
            except ValueError as error:
                problems.append(f"{prim.GetPath()}: {error}")
    from ._bodies import add_rigid_body  # noqa: PLC0415

    for prim in stage.Traverse():
        if prim.HasAPI(UsdPhysics.RigidBodyAPI):
            handle = add_rigid_body(world, stage, prim, owned.get(str(prim.GetPath()), []), frames, problems, notes)
            if handle is not None:
                handles[str(prim.GetPath())] = handle
    from ._joints import add_joints  # noqa: PLC0415

    add_joints(world, stage, handles, frames, problems)
    if problems:
        raise UsdSceneError(problems)
    note(notes)
    return world, handles
