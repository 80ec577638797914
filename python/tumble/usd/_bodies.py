"""USD Physics in, a rigid body prim (RigidBodyAPI) and its colliders as a tumble body: dynamic with MassAPI's mass,
density (else its material's, else 1000 kg/m^3), centre of mass and principal inertia, and its velocities; static
where the rigid body is disabled; kinematic, following the prim's own animation, where kinematicEnabled is set."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ._shapes import DEFAULT_DENSITY, Frames, quaternion
from ._values import value

Array = np.ndarray


def _set(value: Any, unset: Any) -> Any:
    """A MassAPI value, or None where it holds the schema's 'not set' (0, or -inf for the centre of mass)."""
    if value is None:
        return None
    v = np.asarray(value, dtype=float)
    return None if np.all(v == unset) else value


def _mass_api(prim: Any) -> tuple[Any, Any, Any, Any, Array]:
    """(mass, density, centre of mass, diagonal inertia, principal axes as a matrix), each None where not set."""
    from pxr import UsdPhysics  # noqa: PLC0415

    if not prim.HasAPI(UsdPhysics.MassAPI):
        return None, None, None, None, np.eye(3)
    api = UsdPhysics.MassAPI(prim)
    axes = value(api.GetPrincipalAxesAttr())
    turn = np.eye(3)
    if axes is not None:
        from .._geometry import rotation_matrix  # noqa: PLC0415

        turn = rotation_matrix(axes)
    return (_set(value(api.GetMassAttr()), 0.0), _set(value(api.GetDensityAttr()), 0.0),
            _set(value(api.GetCenterOfMassAttr()), -math.inf), _set(value(api.GetDiagonalInertiaAttr()), 0.0), turn)


def _velocities(prim: Any, frames: Frames) -> tuple[Array, Array]:
    """The body's velocity (m/s) and angular velocity (rad/s) in tumble's world axes: the schema gives them in the
    prim's parent's space, in stage units a second and degrees a second."""
    from pxr import UsdPhysics  # noqa: PLC0415

    from ._read import _world_matrix  # noqa: PLC0415

    api = UsdPhysics.RigidBodyAPI(prim)
    parent = prim.GetParent()
    turn = frames.pose(_world_matrix(parent))[1] if parent and not parent.IsPseudoRoot() else frames.up
    v = np.asarray(value(api.GetVelocityAttr(), np.zeros(3)), dtype=float)
    w = np.asarray(value(api.GetAngularVelocityAttr(), np.zeros(3)), dtype=float)
    return turn @ v * frames.metres, turn @ np.radians(w)


def add_rigid_body(world: Any, stage: Any, prim: Any, collider_prims: list[Any], frames: Frames,
                   problems: list[str], notes: list[str]) -> Any | None:
    """Adds the body of rigid body prim ``prim`` with the colliders ``collider_prims``; its handle, or None where
    it cannot be taken (said in ``problems``); approximations made are said in ``notes``."""
    from pxr import UsdPhysics  # noqa: PLC0415

    from ._read import _animation, _collider, _one_material, _relative, _world_matrix  # noqa: PLC0415

    path = str(prim.GetPath())
    api = UsdPhysics.RigidBodyAPI(prim)
    kinematic = bool(api.GetKinematicEnabledAttr().Get())
    static = api.GetRigidBodyEnabledAttr().Get() is False and not kinematic
    for c in collider_prims:
        if c != prim and c.HasAPI(UsdPhysics.MassAPI):
            problems.append(f"{c.GetPath()}: MassAPI: on a collider (tumble takes a body's mass from the body's "
                            "MassAPI, its colliders' densities or materials)")
    parts = [_collider(c, frames, static, problems, notes) for c in collider_prims]
    if any(p is None for p in parts):
        return None
    kept = [p for p in parts if p is not None]
    x_b, r_b, scale = frames.pose(_world_matrix(prim))
    mass, density, centre, diagonal, axes = _mass_api(prim)
    friction, restitution, material_density = (_one_material(path, [p[3] for p in kept], problems) if kept
                                               else (0.5, 0.0, None))
    common: dict[str, Any] = dict(friction=friction, restitution=restitution, name=path)
    if not kept and (static or kinematic or mass is None or diagonal is None):
        problems.append(f"{path}: RigidBodyAPI: a body without a collider needs physics:mass and "
                        "physics:diagonalInertia (and moves)")
        return None
    try:
        if not kept:
            return _by_mass_and_inertia(world, prim, [], x_b, r_b, scale, frames, mass, centre, diagonal, axes,
                                        common)
        (shape0, x0, r0, _), rest = kept[0], kept[1:]
        extra = [(s, *_relative(x0, r0, x, r)) for s, x, r, _ in rest] or None
        if static:
            return world.add_body(shape0, static=True, position=tuple(x0), orientation=quaternion(r0),
                                  colliders=extra, **common)
        if kinematic:
            times, codes = _animation(stage, prim, frames)
            at, turn = r_b.T @ (x0 - x_b), r_b.T @ r0  # the first shape's frame on the body
            poses = [frames.pose(_world_matrix(prim, code)) for code in codes]
            positions = np.array([x + r @ at for x, r, _ in poses])
            orientations = np.array([quaternion(r @ turn) for _, r, _ in poses])
            return world.add_body(shape0, keyframes=(times, positions, orientations), colliders=extra, **common)
        if diagonal is not None:
            if mass is None:
                problems.append(f"{path}: physics:diagonalInertia: given without physics:mass")
                return None
            return _by_mass_and_inertia(world, prim, kept, x_b, r_b, scale, frames, mass, centre, diagonal, axes,
                                        common)
        if centre is not None:
            problems.append(f"{path}: physics:centerOfMass: tumble takes a centre of mass with physics:mass and "
                            "physics:diagonalInertia, else its shapes'")
            return None
        amount: dict[str, float] = {}
        if mass is not None:
            amount["mass"] = float(mass) * frames.kilograms
        else:
            d = density if density is not None else material_density
            amount["density"] = (float(d) * frames.kilograms / frames.metres**3 if d is not None
                                 else DEFAULT_DENSITY)
        import tumble  # noqa: PLC0415

        # a body of a mesh or of several colliders is placed by its first shape's frame, any other by its centre
        by_frame = extra is not None or isinstance(shape0, tumble.Mesh)
        position = x0 if by_frame else x0 + r0 @ np.asarray(shape0.mass_properties(1.0)["center_of_mass"])
        handle = world.add_body(shape0, position=tuple(position), orientation=quaternion(r0), colliders=extra,
                                **amount, **common)
    except ValueError as error:
        problems.append(f"{path}: {error}")
        return None
    v, w = _velocities(prim, frames)
    if np.any(v) or np.any(w):
        row = world.bodies.row(handle)
        com = np.asarray(world.bodies.positions[row])
        # the schema's velocity is the prim origin's: the centre of mass moves at v + w x (c - x)
        world.set_body_state(handle, velocity=tuple(v + np.cross(w, com - x_b)), angular_velocity=tuple(w))
    return handle


def _by_mass_and_inertia(world: Any, prim: Any, parts: list[Any], x_b: Array, r_b: Array, scale: Array,
                         frames: Frames, mass: float, centre: Any, diagonal: Any, axes: Array,
                         common: dict[str, Any]) -> Any:
    """A body of the given mass and principal inertia (about axes turned by principalAxes in the prim's frame), its
    centre of mass given (in the prim's local space) or its one shape's, its colliders posed about that centre."""
    from ._read import _relative  # noqa: PLC0415

    path = str(prim.GetPath())
    if centre is not None:
        com = x_b + r_b @ (np.asarray(centre, dtype=float) * scale * frames.metres)
    elif len(parts) <= 1:
        com = x_b if not parts else parts[0][1] + parts[0][2] @ np.asarray(
            parts[0][0].mass_properties(1.0)["center_of_mass"])
    else:
        raise ValueError(f"physics:centerOfMass: {path} has several colliders and a given inertia: give its "
                         "centre of mass too")
    inertia = axes @ np.diag(np.asarray(diagonal, dtype=float)) @ axes.T * frames.kilograms * frames.metres**2
    colliders = [(s, *_relative(com, r_b, x, r)) for s, x, r, _ in parts] or None
    v, w = _velocities(prim, frames)
    return world.add_body(None, mass=float(mass) * frames.kilograms, inertia=inertia.tolist(),
                          position=tuple(com), orientation=quaternion(r_b), colliders=colliders,
                          velocity=tuple(v + np.cross(w, com - x_b)), angular_velocity=tuple(w), **common)
