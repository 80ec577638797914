"""USD export (issue 16): a run of bodies (shared shapes) and particles written as .usda and .usdc and read back with
usd-core: metres and z up in the stage's metadata, one prim per body and particle, each distinct shape written once,
and the poses at several frames equal to the run's (to float64 rounding: USD stores the doubles as given)."""

import numpy as np
import pytest

import tumble

pxr = pytest.importorskip("pxr", reason="usd-core is the `usd` extra")
from pxr import Usd, UsdGeom  # noqa: E402


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
    assert stage.GetTimeCodesPerSecond() == pytest.approx(60.0)
    assert stage.GetEndTimeCode() == len(run.times) - 1
    bodies = run.body_positions.shape[1]
    # the ground's half-space and the boxes' one shape and the sphere: three meshes (plus the particle's)
    shapes = stage.GetPrimAtPath("/Shapes").GetAllChildren()
    assert len(shapes) == 4
    for frame in (0, len(run.times) // 2, len(run.times) - 1):
        for b in range(bodies):
            prim = stage.GetPrimAtPath(f"/World/body_{b}")
            m = UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(Usd.TimeCode(frame))
            # a 4x4 row-vector matrix: the translation is its last row
            t = np.array(m.ExtractTranslation())
            assert np.allclose(t, run.body_positions[frame, b], rtol=0, atol=1e-12), (frame, b)
            q = m.ExtractRotationQuat()
            mine = run.body_orientations[frame, b]
            theirs = np.array([q.GetReal(), *q.GetImaginary()])
            # the same rotation (q and -q are one), to the rounding of a matrix round trip
            assert min(np.abs(theirs - mine).max(), np.abs(theirs + mine).max()) < 1e-9, (frame, b)
        prim = stage.GetPrimAtPath("/World/particle_0")
        t = np.array(UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(Usd.TimeCode(frame)).ExtractTranslation())
        assert np.allclose(t, run.particle_positions[frame, 0], rtol=0, atol=1e-12)
    # a collider's mesh resolves through its reference: a box is 8 corners and 12 triangles
    mesh = UsdGeom.Mesh(stage.GetPrimAtPath("/World/body_1/collider_0/mesh"))
    assert len(mesh.GetPointsAttr().Get()) == 8 and list(mesh.GetFaceVertexCountsAttr().Get()) == [3] * 12


def test_a_wrong_suffix_is_refused_by_name(tmp_path):
    with pytest.raises(ValueError, match="path"):
        a_run().export_usd(tmp_path / "run.glb")
