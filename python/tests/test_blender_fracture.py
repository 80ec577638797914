"""Fracture in Blender: "Fracture with tumble" cuts a mesh object into glued pieces (rigid bodies whose masses add
up to the object's, Fixed breakable constraints at the shared faces, their thresholds the faces' force bounds
over a substep); the bake maps them back to welds that bind the pieces into one piece, which holds standing and
breaks when hit. Skipped where Blender as a module (the ``blender`` extra) is absent."""

import numpy as np
import pytest

import tumble

bpy = pytest.importorskip("bpy", reason="Blender as a module is the `blender` extra")
import tumble.blender as tb  # noqa: E402
from blender_scenes import DT, blender_body, empty_scene, ground  # noqa: E402


def slab_scene(strength):
    """A 0.6 x 0.2 x 0.4 m slab of 24 kg standing on the ground, cut into 8 glued pieces."""
    scene = empty_scene(60)
    ground()
    slab = blender_body("cube", "slab", (0, 0, 0.2), "CONVEX_HULL", size=1.0, mass=24.0)
    slab.scale = (0.6, 0.2, 0.4)
    bpy.context.view_layer.update()
    tb.register()
    try:
        bpy.context.view_layer.objects.active = slab
        assert bpy.ops.tumble.fracture("EXEC_DEFAULT", pieces=8, seed=1, strength=strength) == {"FINISHED"}
    finally:
        tb.unregister()
    return scene, slab


def test_the_pieces_and_their_glue_are_made_as_asked():
    scene, slab = slab_scene(1e6)
    pieces = [o for o in scene.objects if o.name.startswith("slab.") and o.type == "MESH"]
    glue = [o for o in scene.objects if o.rigid_body_constraint is not None]
    assert len(pieces) == 8 and all(p.rigid_body.type == "ACTIVE" for p in pieces)
    # the masses add up to the slab's (each piece's volume at the slab's density; float32 masses)
    assert sum(p.rigid_body.mass for p in pieces) == pytest.approx(24.0, rel=1e-6)
    assert slab.hide_get() and slab.name not in scene.rigidbody_world.collection.objects
    # each constraint a face's bound: strength x area as an impulse over Blender's substep (the slab cut again as
    # the operator cut it: its mesh scaled as the object is; float32 thresholds)
    slab.data.calc_loop_triangles()
    scale = np.array(tuple(slab.matrix_world.decompose()[2]))
    whole = tumble.Mesh(np.array([tuple(v.co) for v in slab.data.vertices]) * scale,
                        np.array([tuple(t.vertices) for t in slab.data.loop_triangles]), name="slab")
    want = sorted(force * DT for *_, force, _ in tumble.bonds(whole.fracture(pieces=8, seed=1), 1e6))
    got = sorted(c.rigid_body_constraint.breaking_threshold for c in glue)
    assert len(got) == len(want) and np.allclose(got, want, rtol=1e-6)
    assert all(c.rigid_body_constraint.type == "FIXED" and c.rigid_body_constraint.use_breaking for c in glue)


def test_the_glued_slab_stands_and_a_weak_one_is_broken_by_a_ball():
    scene, _ = slab_scene(1e6)
    mapped = tb.world_from_scene(scene)
    run = mapped.world.run(1.0)
    assert not run.joint_break_times.size, "glued at 1 MPa, the slab stands"
    scene, _ = slab_scene(2e3)
    ball = blender_body("sphere", "ball", (0, -1.0, 0.2), "SPHERE", size=0.08, mass=20.0)
    mapped = tb.world_from_scene(scene)
    mapped.world.set_body_state(mapped.handles[ball.name], velocity=(0.0, 8.0, 0.0))
    run = mapped.world.run(1.0)
    assert run.joint_break_times.size > 0, "hit by a 20 kg ball at 8 m/s, the weak glue breaks"


def test_a_bad_object_or_strength_is_refused_by_name():
    scene = empty_scene(10)
    bpy.ops.object.empty_add()
    with pytest.raises(ValueError, match="`obj`"):
        tb.fracture(bpy.context.active_object, pieces=4, scene=scene)
    slab = blender_body("cube", "slab", (0, 0, 1), "BOX")
    with pytest.raises(ValueError, match="`strength`"):
        tb.fracture(slab, pieces=4, strength=0.0, scene=scene)
    with pytest.raises(ValueError, match="`pieces`"):
        tb.fracture(slab, pieces=0, scene=scene)
