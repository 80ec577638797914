"""USD Physics in, its parts: a stage's units and axes as tumble's, a collider prim's shape (UsdGeom Cube, Sphere,
Capsule, Cylinder, Cone, Mesh with MeshCollisionAPI's approximation) and its physics material, and the error that
lists what cannot be mapped (``_read.py`` reads the world). Approximations made go to a list of notes."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._install import install_hint
from ._values import shown, value

# The sides of the pyramid whose hull stands for a cone (tumble has no cone primitive).
CONE_SIDES = 64
# PhysX's default material where none is bound (static and dynamic friction 0.5, restitution 0), and its density.
DEFAULT_FRICTION, DEFAULT_RESTITUTION, DEFAULT_DENSITY = 0.5, 0.0, 1000.0
Array = np.ndarray


class UsdSceneError(ValueError):
    """A stage tumble cannot read as it is: ``problems`` lists each, as "prim path: attribute: why"."""

    def __init__(self, problems: list[str]) -> None:
        super().__init__("the stage cannot be read as a tumble world:\n  " + "\n  ".join(problems))
        self.problems = problems


def _pxr() -> Any:
    try:
        import pxr  # noqa: PLC0415
        from pxr import Gf, Usd, UsdGeom, UsdPhysics, UsdShade  # noqa: F401, PLC0415
    except ImportError:
        raise ImportError(f"reading USD needs usd-core: {install_hint('usd')}") from None
    return pxr


@dataclass
class Frames:
    """A stage's units and axes: ``up`` turns stage vectors into tumble's z-up ones; lengths times ``metres``,
    masses times ``kilograms``."""

    up: Array
    metres: float
    kilograms: float

    def pose(self, matrix: Any) -> tuple[Array, Array, Array]:
        """A world matrix (Gf.Matrix4d, row vectors) as tumble's position (m), rotation matrix and the scale along
        the prim's own axes (stage units)."""
        m = np.array(matrix, dtype=float)
        a = m[:3, :3].T  # column vectors: world = a @ local
        scale = np.linalg.norm(a, axis=0)
        rotation = a / np.where(scale > 0, scale, 1.0)
        return self.up @ m[3, :3] * self.metres, self.up @ rotation, scale


def quaternion(r: Array) -> tuple[float, float, float, float]:
    """A rotation matrix's unit quaternion (w, x, y, z) (Shepperd's method, the largest component first)."""
    t = np.trace(r)
    if t > 0:
        s = 2.0 * math.sqrt(1.0 + t)
        q = (0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s)
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k])
        v = [0.0, 0.0, 0.0]
        v[i], v[j], v[k] = 0.25 * s, (r[j, i] + r[i, j]) / s, (r[k, i] + r[i, k]) / s
        q = ((r[k, j] - r[j, k]) / s, *v)
    n = math.sqrt(sum(c * c for c in q))
    w, x, y, z = (c / n for c in q)
    return (w, x, y, z) if w >= 0 else (-w, -x, -y, -z)


# tumble's capsules and cylinders lie along z; a USD axis token turns z onto that axis
_AXIS_TURN = {"Z": np.eye(3), "X": np.array([[0.0, 0, 1], [0, 1, 0], [-1, 0, 0]]),
              "Y": np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]])}
_AXIS_INDEX = {"X": 0, "Y": 1, "Z": 2}


def _get(prim: Any, name: str, default: Any = None) -> Any:
    return value(prim.GetAttribute(name), default)


def shape_of(prim: Any, scale: Array, metres: float, problems: list[str], static: bool,
             notes: list[str]) -> tuple[Any, Array, Array]:
    """The tumble shape of a collider prim at ``scale`` (its world scale along its own axes), with the shape's pose
    in the prim's frame (position in metres, rotation); None where it cannot be taken (said in ``problems``); an
    approximation made is said in ``notes``."""
    import tumble  # noqa: PLC0415
    from pxr import UsdGeom, UsdPhysics  # noqa: PLC0415

    path, s = str(prim.GetPath()), scale * metres
    none = (None, np.zeros(3), np.eye(3))
    kind = prim.GetTypeName()

    def even(axes: list[int], what: str) -> float | None:
        if np.ptp(s[axes]) > 1e-9 * s[axes].max():
            texts = [shown(v) for v in scale]
            if len({texts[i] for i in axes}) == 1:  # apart by less than float32 shows (double ops): in full
                texts = [repr(float(v)) for v in scale]
            problems.append(f"{path}: xformOp:scale: a {what} scaled unevenly ({', '.join(texts)}) is not one "
                            "tumble takes")
            return None
        return float(s[axes].mean())

    if kind == "Cube":
        return tumble.Box(half_extents=tuple(0.5 * float(_get(prim, "size", 2.0)) * s)), np.zeros(3), np.eye(3)
    if kind == "Sphere":
        k = even([0, 1, 2], "sphere")
        return (none if k is None else (tumble.Sphere(radius=float(_get(prim, "radius", 1.0)) * k),
                                        np.zeros(3), np.eye(3)))
    if kind in ("Capsule", "Cylinder", "Cone"):
        axis = str(_get(prim, "axis", "Z"))
        along = _AXIS_INDEX[axis]
        k = even([i for i in range(3) if i != along], kind.lower())
        if k is None:
            return none
        defaults = {"Capsule": (0.5, 1.0), "Cylinder": (1.0, 2.0), "Cone": (1.0, 2.0)}[kind]
        radius = float(_get(prim, "radius", defaults[0])) * k
        height = float(_get(prim, "height", defaults[1])) * s[along]
        turn = _AXIS_TURN[axis]
        if kind == "Capsule":
            return tumble.Capsule(half_height=0.5 * height, radius=radius), np.zeros(3), turn
        if kind == "Cylinder":
            return tumble.Cylinder(half_height=0.5 * height, radius=radius), np.zeros(3), turn
        notes.append(f"{path}: Cone: taken as the hull of a {CONE_SIDES}-sided pyramid (tumble has no cone)")
        angles = np.linspace(0.0, 2 * np.pi, CONE_SIDES, endpoint=False)
        base = np.c_[radius * np.cos(angles), radius * np.sin(angles), np.full(CONE_SIDES, -0.5 * height)]
        return tumble.ConvexHull(np.vstack([base, [0.0, 0.0, 0.5 * height]])), np.zeros(3), turn
    if kind == "Mesh":
        mesh = UsdGeom.Mesh(prim)
        points = np.reshape(value(mesh.GetPointsAttr(), np.zeros((0, 3))), (-1, 3)) * s
        counts = list(mesh.GetFaceVertexCountsAttr().Get() or [])
        indices = list(mesh.GetFaceVertexIndicesAttr().Get() or [])
        triangles, at = [], 0
        for n in counts:  # each polygon as a fan
            triangles += [(indices[at], indices[at + i], indices[at + i + 1]) for i in range(1, n - 1)]
            at += n
        approximation = "none"
        if prim.HasAPI(UsdPhysics.MeshCollisionAPI):
            approximation = str(UsdPhysics.MeshCollisionAPI(prim).GetApproximationAttr().Get() or "none")
        if str(_get(prim, "orientation", "rightHanded")) == "leftHanded":
            triangles = [(a, c, b) for a, b, c in triangles]
        try:
            if approximation == "convexHull":
                return tumble.ConvexHull(points), np.zeros(3), np.eye(3)
            if approximation in ("boundingCube", "boundingSphere"):
                low, high = points.min(axis=0), points.max(axis=0)
                centre = 0.5 * (low + high)
                if approximation == "boundingCube":
                    return tumble.Box(half_extents=tuple(0.5 * (high - low))), centre, np.eye(3)
                return tumble.Sphere(radius=float(np.linalg.norm(points - centre, axis=1).max())), centre, np.eye(3)
            if approximation == "convexDecomposition":
                return tumble.Mesh(points, np.array(triangles), name=prim.GetName()), np.zeros(3), np.eye(3)
            if approximation == "none":
                if not static:
                    problems.append(f"{path}: physics:approximation: \"none\" (exact triangles) moves only on a "
                                    "static collider in tumble: use convexDecomposition or convexHull")
                    return none
                try:
                    return tumble.Mesh(points, np.array(triangles), name=prim.GetName()), np.zeros(3), np.eye(3)
                except ValueError:  # not a closed solid: a triangle soup, as a static body may have
                    return tumble.TriMesh(points, np.array(triangles)), np.zeros(3), np.eye(3)
        except ValueError as error:
            problems.append(f"{path}: points: {error}")
            return none
        problems.append(f"{path}: physics:approximation: \"{approximation}\" is not one tumble takes (none, "
                        "convexHull, convexDecomposition, boundingCube, boundingSphere)")
        return none
    problems.append(f"{path}: CollisionAPI: a {kind or 'typeless'} prim is not a shape tumble takes (Cube, Sphere, "
                    "Capsule, Cylinder, Cone, Mesh)")
    return none


def material_of(prim: Any, notes: list[str]) -> tuple[float, float, float | None]:
    """The physics material bound to a collider prim (purpose "physics", else all purposes): (friction,
    restitution, density in stage units or None); PhysX's defaults where none is bound. tumble's friction is one
    Coulomb coefficient, for sliding and sticking: the dynamic one, said in ``notes`` where the static differs."""
    from pxr import UsdPhysics, UsdShade  # noqa: PLC0415

    binding = UsdShade.MaterialBindingAPI(prim)
    material = None
    for purpose in ("physics", UsdShade.Tokens.allPurpose):
        found, _ = binding.ComputeBoundMaterial(materialPurpose=purpose)
        if found and found.GetPrim().HasAPI(UsdPhysics.MaterialAPI):
            material = found.GetPrim()
            break
    if material is None:
        return DEFAULT_FRICTION, DEFAULT_RESTITUTION, None
    api = UsdPhysics.MaterialAPI(material)
    static = value(api.GetStaticFrictionAttr(), DEFAULT_FRICTION)
    dynamic = value(api.GetDynamicFrictionAttr(), DEFAULT_FRICTION)
    if static != dynamic:
        notes.append(f"{material.GetPath()}: physics:staticFriction: {shown(static)} differs from "
                     f"physics:dynamicFriction {shown(dynamic)}: tumble takes the dynamic one (its friction is one "
                     "Coulomb coefficient, for sliding and sticking)")
    density = value(api.GetDensityAttr())
    return dynamic, value(api.GetRestitutionAttr(), DEFAULT_RESTITUTION), density if density else None
