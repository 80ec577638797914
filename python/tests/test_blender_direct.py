"""Directing a Blender scene's outcome: a die dropped spinning onto the ground made to end with a face up, by
``tumble.blender.direct`` and by the add-on's operator, the answer baked as keyframes; a target's place; bad
arguments refused by name. Skipped where Blender as a module (the ``blender`` extra) is absent."""

import numpy as np
import pytest

import tumble

bpy = pytest.importorskip("bpy", reason="Blender as a module is the `blender` extra")
import tumble.blender as tb  # noqa: E402
from tumble.blender._direct import last  # noqa: E402
from blender_scenes import blender_body, empty_scene, ground  # noqa: E402


def die_scene():
    scene = empty_scene(90)
    ground()
    die = blender_body("cube", "die", (0, 0, 0.6), "BOX", size=0.2, mass=0.1)
    die.rotation_euler = (0.3, 0.5, 0.1)
    bpy.context.view_layer.update()
    return scene, die


def up_at_end(obj, frame):
    bpy.context.scene.frame_set(frame)
    return tumble.up_axis(np.array(tuple(obj.matrix_world.to_quaternion())))


def test_a_die_is_directed_to_each_face_asked_and_the_answer_baked():
    for face in ("+X", "-Z"):
        scene, die = die_scene()
        directed = tb.direct(die, face=face, vary=tumble.direct.Vary(orientation=180.0, spin=10.0), tries=64,
                             scene=scene)
        assert directed.found.met, directed.found.report
        directed.bake(0)
        assert not scene.rigidbody_world.enabled and die.animation_data.action is not None
        assert up_at_end(die, 90) == face.lower()


def test_the_operator_searches_previews_the_best_and_bakes_the_chosen():
    """The operator shows the best in the viewport without keying anything; previewing another answer poses the die
    as that answer's run at each frame; stopping puts the die back; baking keys the chosen one."""
    scene, die = die_scene()
    start = die.matrix_world.copy()
    bpy.context.view_layer.objects.active = die
    tb.register()
    try:
        assert bpy.ops.tumble.direct("EXEC_DEFAULT", face="+Y", orientation=180.0, spin=10.0, tries=64) == {"FINISHED"}
        assert die.animation_data is None or die.animation_data.action is None, "a preview keys nothing"
        assert up_at_end(die, 90) == "+y"
        directed = last[scene.name]
        k = len(directed.found.alternatives) - 1
        assert bpy.ops.tumble.direct_preview("EXEC_DEFAULT", choice=k) == {"FINISHED"}
        answer = directed.found.alternatives[k]
        row = directed.mapped.world.bodies.row(directed.mapped.handles["die"])
        for frame in (1, 30, 90):
            bpy.context.scene.frame_set(frame)
            q = np.array(tuple(die.matrix_world.to_quaternion()))
            expected = answer.run.body_orientations[frame - 1, row]
            # float32 matrices: a turn read back from one to 1e-5
            assert min(np.abs(q - expected).max(), np.abs(q + expected).max()) < 1e-5
        assert bpy.ops.tumble.direct_stop_preview("EXEC_DEFAULT") == {"FINISHED"}
        assert scene.rigidbody_world.enabled
        bpy.context.scene.frame_set(1)
        assert np.allclose(np.array(die.matrix_world), np.array(start), atol=1e-6), "put back as it was"
        assert bpy.ops.tumble.direct_bake("EXEC_DEFAULT", choice=0) == {"FINISHED"}
        assert die.animation_data.action is not None and not scene.rigidbody_world.enabled
        assert up_at_end(die, 90) == "+y"
    finally:
        tb.unregister()


def test_a_preview_is_put_away_before_the_scene_is_read_again():
    """A search started while an answer is shown reads the scene as the user set it up, not as the preview poses
    it: the same answer as the first search's."""
    scene, die = die_scene()
    vary = tumble.direct.Vary(orientation=180.0, spin=10.0)
    first = tb.direct(die, face="+X", vary=vary, tries=64, scene=scene)
    first.preview(0)
    scene.frame_set(90)
    again = tb.direct(die, face="+X", vary=vary, tries=64, scene=scene)
    assert not tumble.blender._preview.previews
    assert again.found.cost == first.found.cost and again.found.change == first.found.change


def test_a_target_place_is_reached():
    scene, die = die_scene()
    bpy.ops.object.empty_add(location=(0.3, 0.0, 0.1))
    target = bpy.context.active_object
    directed = tb.direct(die, target=target, within=0.05, vary=tumble.direct.Vary(velocity=1.0, spin=2.0),
                         tries=128, scene=scene)
    assert directed.found.met, directed.found.report
    directed.bake()
    bpy.context.scene.frame_set(90)
    assert np.linalg.norm(np.array(tuple(die.matrix_world.translation)) - (0.3, 0.0, 0.1)) <= 0.05 + 1e-6


def test_bad_arguments_are_refused_by_name():
    scene, die = die_scene()
    for kwargs, name in [(dict(), "face"), (dict(face="up"), "face")]:
        with pytest.raises(ValueError, match=f"`{name}`"):
            tb.direct(die, scene=scene, **kwargs)
    with pytest.raises(ValueError, match="`obj`"):
        tb.direct(None, face="+Z", scene=scene)
    directed = tb.direct(die, face="+Z", tries=8, scene=scene)
    for act in (directed.bake, directed.preview):
        with pytest.raises(ValueError, match="`k`"):
            act(99)
    die.rigid_body.kinematic = True
    die.keyframe_insert("rigid_body.kinematic", frame=1)
    die.rigid_body.kinematic = False
    die.keyframe_insert("rigid_body.kinematic", frame=10)
    with pytest.raises(ValueError, match="`scene`"):
        tb.direct(die, face="+Z", tries=8, scene=scene)


def test_a_target_turn_is_reached_when_asked():
    """A box slid along the ground to an empty 0.3 m on, turned 90 degrees about z: varying its start's turn, the
    search ends it on the place and turned as the empty within 5 degrees."""
    scene = empty_scene(90)
    ground()
    box = blender_body("cube", "box", (0, 0, 0.1), "BOX", size=0.2, mass=0.1)
    bpy.ops.object.empty_add(location=(0.3, 0.0, 0.1), rotation=(0.0, 0.0, np.pi / 2))
    target = bpy.context.active_object
    directed = tb.direct(box, target=target, within=0.05, angle=5.0, scene=scene,
                         vary=tumble.direct.Vary(velocity=1.0, orientation=180.0), tries=256)
    assert directed.found.met, directed.found.report
    directed.bake()
    bpy.context.scene.frame_set(90)
    turn = box.matrix_world.to_quaternion().rotation_difference(target.matrix_world.to_quaternion()).angle
    assert min(turn, 2 * np.pi - turn) <= np.radians(5.0) + 1e-6
