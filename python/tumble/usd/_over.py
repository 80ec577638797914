"""A run written back onto the stage it was read from (``Run.export_usd(path, over=source)``): a new layer that
has the source as its sublayer and, on each rigid body prim a run's body is named by, an override of its transform
(translate, orient and scale ops of its own) time-sampled at every frame, in the source's units, axes and time codes
(whole frames at whole ones), local to the prim's parent; a kinematic prim keeps its own animation. Tools that open
the layer (Houdini, Omniverse, usdview) play the run on the original scene."""

from __future__ import annotations

import os
import warnings
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .._geometry import rotation_matrix
from ._shapes import _pxr, quaternion

if TYPE_CHECKING:
    from .._run import Run


def export_over(run: "Run", path: Path, source: Path) -> Path:
    _pxr()
    from pxr import Gf, Sdf, Usd, UsdGeom, UsdPhysics  # noqa: PLC0415

    from ._write import time_codes  # noqa: PLC0415
    from ._read import _world_matrix, frames_of, read_stage  # noqa: PLC0415
    from ._values import UsdImportWarning  # noqa: PLC0415

    src = Usd.Stage.Open(str(source))
    if src is None:
        raise ValueError(f"invalid argument `over`: {source} is not a USD stage usd-core can open")
    frames = frames_of(src)
    # the bodies as the stage starts: where each body's frame sits on its prim's (its approximations were said when
    # the world was read)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UsdImportWarning)
        start, handles = read_stage(source)
    if path.exists():
        path.unlink()
    layer = Sdf.Layer.CreateNew(str(path))
    layer.subLayerPaths.append(os.path.relpath(source.resolve(), path.resolve().parent))
    stage = Usd.Stage.Open(layer)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.GetStageUpAxis(src))
    UsdGeom.SetStageMetersPerUnit(stage, UsdGeom.GetStageMetersPerUnit(src))
    tcps = src.GetTimeCodesPerSecond() or 24.0
    stage.SetTimeCodesPerSecond(tcps)
    stage.SetFramesPerSecond(src.GetFramesPerSecond() or tcps)
    codes = src.GetStartTimeCode() + time_codes(run.times, tcps)
    stage.SetStartTimeCode(float(codes[0]))
    stage.SetEndTimeCode(float(codes[-1]))
    written = 0
    for b, name in enumerate(run.names):
        prim = src.GetPrimAtPath(name) if name and Sdf.Path.IsValidPathString(name) else None
        if prim is None or not prim.IsValid() or not prim.HasAPI(UsdPhysics.RigidBodyAPI) or name not in handles:
            continue
        if UsdPhysics.RigidBodyAPI(prim).GetKinematicEnabledAttr().Get():
            continue  # a kinematic body follows the prim's own animation: that stays as it is
        row = start.bodies.row(handles[name])
        x0, r0 = np.asarray(start.bodies.positions[row]), rotation_matrix(np.asarray(start.bodies.orientations[row]))
        xp, rp, scale = frames.pose(_world_matrix(prim))
        at, turn = r0.T @ (xp - x0), r0.T @ rp  # the prim's frame on the body
        parent = prim.GetParent()
        into_parent = np.linalg.inv(np.array(_world_matrix(parent), dtype=float)) if not parent.IsPseudoRoot() \
            else np.eye(4)
        xform = UsdGeom.Xformable(stage.OverridePrim(name))
        xform.ClearXformOpOrder()
        ops = (xform.AddTranslateOp(UsdGeom.XformOp.PrecisionDouble, "tumble"),
               xform.AddOrientOp(UsdGeom.XformOp.PrecisionDouble, "tumble"),
               xform.AddScaleOp(UsdGeom.XformOp.PrecisionDouble, "tumble"))
        for k, code in enumerate(codes):
            rb = rotation_matrix(run.body_orientations[k, b])
            x, r = run.body_positions[k, b] + rb @ at, rb @ turn
            # to the stage's axes and units, as a row-vector matrix, then local to the parent
            world = np.eye(4)
            world[:3, :3] = (frames.up.T @ r * scale).T
            world[3, :3] = frames.up.T @ x / frames.metres
            local = world @ into_parent
            columns = local[:3, :3].T
            size = np.linalg.norm(columns, axis=0)
            time = Usd.TimeCode(float(code))
            ops[0].Set(Gf.Vec3d(*map(float, local[3, :3])), time)
            ops[1].Set(Gf.Quatd(*quaternion(columns / size)), time)
            ops[2].Set(Gf.Vec3d(*map(float, size)), time)
        written += 1
    if written == 0:
        raise ValueError(f"invalid argument `over`: no body of the run is named by a rigid body prim of {source} "
                         "(a world read by World.from_usd names its bodies by their prim paths)")
    layer.Save()
    return path
