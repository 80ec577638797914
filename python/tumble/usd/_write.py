"""USD export of a run through usd-core (``pip install "./python[usd]"``): one Xform prim per body carrying its
colliders as meshes (each identical shape written once, under the abstract class prim /Shapes, and referenced), one
per particle carrying a small sphere, with translation and orientation time-sampled at every frame (at time codes
of 24 a second, USD's default, so that a run plays at its own speed in Blender's default 24 fps scene and in tools
that honour timeCodesPerSecond; framesPerSecond is the run's frame rate; whole frames at whole time codes). A
body's prim is named by its name (made a valid, unique identifier), else body_N, and a body given a colour has it
as its meshes' display colour and opacity; collider meshes are not to be subdivided (``subdivisionScheme =
"none"``). The stage states metres and z up, tumble's own units and axes, so no root transform is needed."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._install import install_hint
from .._mesh import pivoted
from .._mesh import shape_mesh as mesh_of

if TYPE_CHECKING:
    from .._run import Run
    from .._tumble import Shape


def _pxr() -> tuple[Any, Any, Any, Any]:
    try:
        from pxr import Gf, Sdf, Usd, UsdGeom  # noqa: PLC0415
    except ImportError:
        raise ImportError(f"USD export needs usd-core: {install_hint('usd')}") from None
    return Gf, Sdf, Usd, UsdGeom


# Time codes a second: USD's default, which tools that read time codes as frames (Blender's importer) play at their
# default 24 frames a second; tools that honour timeCodesPerSecond play any rate. framesPerSecond is the run's.
TIME_CODES_PER_SECOND = 24.0
# A time code this close to a whole number, relative to it, is that whole number. A frame's time is a float64 sum of
# steps, so a whole frame's code comes out a few ulps (1e-16 relative) beside it: (t - t0) * 24 is
# 6.999999999999999 for frame 7. Tools look samples up by frame (Blender's importer reads code 7 at frame 7, usdview
# and Houdini list the codes), so a whole frame is written at the integer itself; a time meant between frames is
# further from one than this.
WHOLE = 1e-9


def whole(values: np.ndarray | float) -> np.ndarray:
    """``values`` with each one within ``WHOLE`` (relative) of an integer set to that integer."""
    values = np.asarray(values, dtype=float)
    nearest = np.round(values)
    out: np.ndarray = np.where(np.abs(values - nearest) <= WHOLE * np.abs(values), nearest, values)
    return out


def time_codes(times: np.ndarray, per_second: float = TIME_CODES_PER_SECOND) -> np.ndarray:
    """The time code of each frame: seconds since the run's first frame, times ``per_second``, whole where the
    frame is (``whole``)."""
    times = np.asarray(times, dtype=float)
    return whole((times - times[0]) * per_second) if len(times) else times


def _frame_rate(times: np.ndarray) -> float:
    """Frames a second: from the run's frame spacing (its median, so a shorter last frame does not count), whole
    where it is (24, not 24.000000000000007)."""
    if len(times) < 2:
        return 24.0
    step = float(np.median(np.diff(times)))
    return float(whole(1.0 / step)) if step > 0 else 24.0


def prim_names(names: list[str | None], valid: Any, reserved: set[str]) -> list[str]:
    """Each body's prim name: its own name made a USD identifier (a character that cannot be in one becomes "_",
    a leading digit gets a "_" before it), else "body_N"; a name taken before, or ``reserved`` (the particles'),
    gets "_2", "_3"... after it."""
    out: list[str] = []
    taken: set[str] = set(reserved)
    for b, name in enumerate(names):
        base = f"body_{b}" if name is None else "".join(c if c.isascii() and (c.isalnum() or c == "_") else "_"
                                                         for c in name)
        if not base or base[0].isdigit():
            base = "_" + base
        unique, k = base, 1
        while unique in taken or not valid(unique):
            k += 1
            unique = f"{base}_{k}"
        taken.add(unique)
        out.append(unique)
    return out


def export(run: "Run", path: Path) -> Path:
    if path.suffix.lower() not in (".usda", ".usdc", ".usd"):
        raise ValueError(f"invalid argument `path`: USD files end in .usda, .usdc or .usd, got {path.name!r}")
    Gf, Sdf, Usd, UsdGeom = _pxr()
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    codes = time_codes(run.times)
    stage.SetTimeCodesPerSecond(TIME_CODES_PER_SECOND)
    stage.SetFramesPerSecond(_frame_rate(run.times))
    stage.SetStartTimeCode(0)
    stage.SetEndTimeCode(float(codes[-1]) if len(codes) else 0.0)
    stage.SetMetadata("comment", f"tumble run: {len(run.times)} frames from t = {run.times[0]!r} s")
    root = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(root.GetPrim())
    # the distinct shapes' meshes, under an abstract class prim (never drawn itself; the colliders reference them)
    stage.CreateClassPrim("/Shapes")

    meshes: dict[str, Any] = {}

    def shape_mesh(shape: Shape, key: str) -> Any:
        """The path of `shape`'s mesh under /Shapes, written once for each distinct shape."""
        if key not in meshes:
            vertices, triangles = mesh_of(shape)  # in the shape's frame: the collider's prim places it
            mesh = UsdGeom.Mesh.Define(stage, f"/Shapes/shape_{len(meshes)}")
            mesh.CreatePointsAttr([Gf.Vec3f(*map(float, p)) for p in vertices])
            mesh.CreateFaceVertexCountsAttr([3] * len(triangles))
            mesh.CreateFaceVertexIndicesAttr([int(i) for i in triangles.reshape(-1)])
            # collision geometry is flat-faced: importers that subdivide by default (Catmull-Clark) would round it
            mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
            meshes[key] = mesh.GetPath()
        return meshes[key]

    def animated(name: str, positions: np.ndarray, orientations: np.ndarray | None) -> Any:
        xform = UsdGeom.Xform.Define(stage, f"/World/{name}")
        translate = xform.AddTranslateOp(UsdGeom.XformOp.PrecisionDouble)
        orient = xform.AddOrientOp(UsdGeom.XformOp.PrecisionDouble) if orientations is not None else None
        for k in range(len(run.times)):
            translate.Set(Gf.Vec3d(*map(float, positions[k])), Usd.TimeCode(float(codes[k])))
            if orient is not None and orientations is not None:
                w, x, y, z = map(float, orientations[k])
                orient.Set(Gf.Quatd(w, x, y, z), Usd.TimeCode(float(codes[k])))
        return xform

    names = prim_names([run.names[b] if b < len(run.names) else None for b in range(run.body_positions.shape[1])],
                       Sdf.Path.IsValidIdentifier, {f"particle_{i}" for i in range(run.particle_positions.shape[1])})
    for b in range(run.body_positions.shape[1]):
        colliders = run.shapes[b] if b < len(run.shapes) else []
        # the pivot at the body's modelled frame (a mesh's origin), not its centre of mass
        colliders, placed = pivoted(colliders, run.body_positions[:, b], run.body_orientations[:, b])
        xform = animated(names[b], placed, run.body_orientations[:, b])
        color = run.color(b)
        for c, (shape, offset, orientation) in enumerate(colliders):
            key = shape.__reduce__()[1][0]  # the shape's JSON: equal shapes share one mesh
            part = UsdGeom.Xform.Define(stage, xform.GetPath().AppendChild(f"collider_{c}"))
            part.AddTranslateOp(UsdGeom.XformOp.PrecisionDouble).Set(Gf.Vec3d(*map(float, offset)))
            w, x, y, z = map(float, orientation)
            part.AddOrientOp(UsdGeom.XformOp.PrecisionDouble).Set(Gf.Quatd(w, x, y, z))
            # a typeless prim under the collider takes the shared mesh (its type and points) by reference
            prim = stage.DefinePrim(part.GetPath().AppendChild("mesh"))
            prim.GetReferences().AddInternalReference(shape_mesh(shape, key))
            if color is not None:  # the body's colour (and opacity) over the shared mesh's, on this instance only
                gprim = UsdGeom.Gprim(prim)
                gprim.CreateDisplayColorAttr([Gf.Vec3f(*color[:3])])
                gprim.CreateDisplayOpacityAttr([float(color[3])])
    if run.particle_positions.shape[1]:
        from .._tumble import Sphere  # noqa: PLC0415

        dot = Sphere(0.01)
        for i in range(run.particle_positions.shape[1]):
            xform = animated(f"particle_{i}", run.particle_positions[:, i], None)
            stage.DefinePrim(xform.GetPath().AppendChild("mesh")).GetReferences().AddInternalReference(
                shape_mesh(dot, "particle"))
    stage.GetRootLayer().Save()
    return path
