"""USD export: a run of bodies (shared shapes) and particles written as .usda and .usdc and read back with
usd-core: metres and z up in the stage's metadata, one prim per body and particle, each distinct shape written once,
and the poses at several frames equal to the run's (to float64 rounding: USD stores the doubles as given); whole
frames at whole time codes, in a run of its own and in a layer over a stage."""

import numpy as np
import pytest

import tumble

pxr = pytest.importorskip("pxr", reason="usd-core is the `usd` extra")
from pxr import Gf, Usd, UsdGeom, UsdPhysics  # noqa: E402

from tumble.usd._write import time_codes  # noqa: E402


def a_run() -> tumble.Run:
    w = tumble.World(mode="fast", dt=1 / 240)
    w.add_ground(restitution=0.2, friction=0.5)
    for k in range(3):  # three boxes of one shape: one mesh
        w.add_body(tumble.Box(half_extents=(0.2, 0.2, 0.2)), density=500.0, position=(0.5 * k, 0.0, 0.5 + 0.3 * k),
                   angular_velocity=(0.0, 1.0 + k, 0.5))
    w.add_body(tumble.Sphere(radius=0.1), density=500.0, position=(0.0, 1.0, 1.0))
    w.add_particle(position=(0.0, -1.0, 1.0), velocity=(1.0, 0.0, 2.0))
    return w.run(duration=0.5, frame_interval=1 / 60)


@pytest.mark.parametrize("suffix", [".usda", ".usdc"])
def test_a_run_reads_back_from_usd_with_its_poses(tmp_path, suffix):
    run = a_run()
    path = run.export_usd(tmp_path / f"run{suffix}")
    stage = Usd.Stage.Open(str(path))
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.z
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    # time codes of 24 a second (USD's default, what Blender plays them at), frames at the run's 60 a second
    assert stage.GetTimeCodesPerSecond() == 24.0 and stage.GetFramesPerSecond() == pytest.approx(60.0)
    assert stage.GetEndTimeCode() == pytest.approx((run.times[-1] - run.times[0]) * 24.0, rel=1e-15)
    code = time_codes(run.times)
    bodies = run.body_positions.shape[1]
    # the ground's half-space and the boxes' one shape and the sphere: three meshes (plus the particle's)
    shapes = stage.GetPrimAtPath("/Shapes").GetAllChildren()
    assert len(shapes) == 4
    for frame in (0, len(run.times) // 2, len(run.times) - 1):
        for b in range(bodies):
            prim = stage.GetPrimAtPath(f"/World/body_{b}")
            m = UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(Usd.TimeCode(float(code[frame])))
            # a 4x4 row-vector matrix: the translation is its last row
            t = np.array(m.ExtractTranslation())
            assert np.allclose(t, run.body_positions[frame, b], rtol=0, atol=1e-12), (frame, b)
            q = m.ExtractRotationQuat()
            mine = run.body_orientations[frame, b]
            theirs = np.array([q.GetReal(), *q.GetImaginary()])
            # the same rotation (q and -q are one), to the rounding of a matrix round trip
            assert min(np.abs(theirs - mine).max(), np.abs(theirs + mine).max()) < 1e-9, (frame, b)
        prim = stage.GetPrimAtPath("/World/particle_0")
        t = np.array(UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(Usd.TimeCode(float(code[frame]))).ExtractTranslation())
        assert np.allclose(t, run.particle_positions[frame, 0], rtol=0, atol=1e-12)
    # a collider's mesh resolves through its reference: a box is 8 corners and 12 triangles
    mesh = UsdGeom.Mesh(stage.GetPrimAtPath("/World/body_1/collider_0/mesh"))
    assert len(mesh.GetPointsAttr().Get()) == 8 and list(mesh.GetFaceVertexCountsAttr().Get()) == [3] * 12


def test_a_wrong_suffix_is_refused_by_name(tmp_path):
    with pytest.raises(ValueError, match="path"):
        a_run().export_usd(tmp_path / "run.glb")


def test_a_60_fps_run_lasts_as_long_in_a_24_fps_blender_scene(tmp_path):
    """Blender's USD importer reads time codes as frames of its scene: at 24 time codes a second a run plays at its
    own speed in Blender's default 24 fps scene. A ball dropped from 1 m, recorded at 60 frames a second for 1 s,
    imported with ``bpy``: at each of the scene's frames f it is where the run had it at f / 24 s (float32 in
    Blender's matrices: 1e-6 m), and the animation ends at frame 24."""
    bpy = pytest.importorskip("bpy", reason="Blender as a module is the `blender` extra")
    w = tumble.World(mode="fast", dt=1 / 240)
    w.add_ground()
    w.add_body(tumble.Sphere(radius=0.1), density=500.0, position=(0.0, 0.0, 1.0), name="ball")
    run = w.run(duration=1.0, frame_interval=1 / 60)
    path = run.export_usd(tmp_path / "drop.usda")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps, scene.render.fps_base = 24, 1.0
    bpy.ops.wm.usd_import(filepath=str(path), set_frame_range=True)
    ball = bpy.data.objects["ball"]
    assert scene.frame_end == 24
    for f in (0, 6, 10, 12, 24):  # frames 6 and 12 fall on the run's frames 15 and 30, 10 on 25
        scene.frame_set(f)
        k = int(round(f / 24 * 60))
        assert abs(run.times[k] - run.times[0] - f / 24) < 1e-12
        np.testing.assert_allclose(np.array(ball.matrix_world.translation), run.body_positions[k, 1], atol=1e-6)


def a_later_run(world: tumble.World) -> tumble.Run:
    """A second run of ``world``, 1 s at 24 frames a second from t = 0.3 s: its frames' times are float64 sums, so
    (t - 0.3) * 24 comes out 6.999999999999999 or 13.999999999999998 codes for whole frames 7 and 14."""
    world.run(duration=0.3, frame_interval=0.3)
    return world.run(duration=1.0, frame_interval=1 / 24)


def test_whole_frames_are_written_at_whole_time_codes(tmp_path):
    w = tumble.World(mode="fast", dt=1 / 240)
    w.add_ground()
    w.add_body(tumble.Sphere(radius=0.1), density=500.0, position=(0.0, 0.0, 1.0), name="ball")
    stage = Usd.Stage.Open(str(a_later_run(w).export_usd(tmp_path / "whole.usda")))
    # exactly: a frame is keyed at the integer a tool looks it up by, not a few ulps beside it
    for name in ("body_0", "ball"):
        assert stage.GetPrimAtPath(f"/World/{name}").GetAttribute("xformOp:translate").GetTimeSamples() == \
            [float(k) for k in range(25)], name
    assert stage.GetEndTimeCode() == 24.0 and stage.GetFramesPerSecond() == 24.0
    # a time between frames stays where it is
    assert list(time_codes(np.array([0.0, 0.3 / 24, 1.0]))) == [0.0, 0.3 / 24 * 24, 24.0]


def test_a_layer_over_a_stage_writes_whole_frames_at_whole_time_codes(tmp_path):
    source = tmp_path / "ball.usda"
    stage = Usd.Stage.CreateNew(str(source))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdPhysics.Scene.Define(stage, "/physicsScene")
    ball = UsdGeom.Sphere.Define(stage, "/World/ball")
    ball.AddTranslateOp(UsdGeom.XformOp.PrecisionDouble).Set(Gf.Vec3d(0.0, 0.0, 1.0))
    UsdPhysics.CollisionAPI.Apply(ball.GetPrim())
    UsdPhysics.RigidBodyAPI.Apply(ball.GetPrim())
    stage.GetRootLayer().Save()
    world, _ = tumble.World.from_usd(source, mode="fast", dt=1 / 240)
    layered = Usd.Stage.Open(str(a_later_run(world).export_usd(tmp_path / "over.usda", over=source)))
    # exactly, as in a run of its own: the source starts at time code 0 and has 24 a second
    samples = layered.GetPrimAtPath("/World/ball").GetAttribute("xformOp:translate:tumble").GetTimeSamples()
    assert samples == [float(k) for k in range(25)] and layered.GetEndTimeCode() == 24.0
