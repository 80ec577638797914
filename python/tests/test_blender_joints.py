"""The Blender bake's constraints (``tumble.blender``, headless with Blender as a module, the ``blender`` extra): a
hinged door and a chain of point constraints baked; every constraint type and its limits, and generic constraints,
mapped to the tumble joint that runs the same bits as the world built in Python; what tumble's joints lack refused
by name."""

import math

import numpy as np
import pytest

import tumble

bpy = pytest.importorskip("bpy", reason="Blender as a module is the `blender` extra")
import tumble.blender as tb  # noqa: E402
from blender_scenes import (  # noqa: E402
    DT, FPS, assert_keyed_like, blender_body, damping, empty_scene, f32, ground, keyed, python_ground, python_world,
)


def test_a_hinged_door_bakes_as_the_same_world_built_in_python():
    scene = empty_scene(60)
    frame = blender_body("cube", "frame", (0, 0, 2), "BOX", size=0.05)
    frame.rigid_body.type = "PASSIVE"
    door = blender_body("cube", "door", (0.8, 0, 2), "BOX", size=1.0, mass=5.0)
    bpy.ops.object.empty_add(location=(0.25, 0, 2))
    hinge = bpy.context.active_object
    hinge.name = "hinge"
    bpy.ops.rigidbody.constraint_add(type="HINGE")
    hinge.rigid_body_constraint.object1, hinge.rigid_body_constraint.object2 = frame, door
    hinge.rotation_euler = (math.pi / 2, 0, 0)  # its z along the world's -y: the door swings down about y
    report = tb.bake(scene)
    assert any("disable collisions" in n for n in report.bake_notes), "the passive end's collisions are said"
    x = keyed(door, range(1, 61))
    assert x[-1, 2] < x[0, 2] - 0.3, "the door swung down"
    # its centre stays 0.55 m from the hinge's line (the soft step's joints hold to a millimetre)
    np.testing.assert_allclose(np.linalg.norm((x - (0.25, 0.0, 2.0))[:, [0, 2]], axis=1), 0.55, atol=1e-3)
    # the same door in Python: the hinge's anchors in each body's frame, its axis in the frame's (the empty's z as
    # Blender's matrix holds it: float32, so a few 1e-8 off the world's -y)
    w = python_world()
    f = w.add_body(tumble.Box(half_extents=(f32(0.025),) * 3), static=True, position=(0.0, 0.0, 2.0), friction=0.5)
    d = w.add_body(tumble.Box(half_extents=(0.5, 0.5, 0.5)), mass=5.0, position=(f32(0.8), 0.0, 2.0), friction=0.5,
                   **damping(5.0, 5.0 / 6.0, f32(0.04), f32(0.1)))
    axis = tuple(float(v) for v in hinge.matrix_world.decompose()[1].to_matrix().col[2])
    w.add_joint(tumble.Hinge(f, d, anchor_a=(0.25, 0.0, 0.0), anchor_b=(0.25 - f32(0.8), 0.0, 0.0), axis=axis))
    run = w.run(59 / FPS, 1 / FPS)
    assert_keyed_like(door, run, w.bodies.row(d), range(1, 61))


def test_a_chain_of_point_constraints_holds_together():
    scene = empty_scene(60)
    top = blender_body("cube", "anchor", (0, 0, 3), "BOX", size=0.1)
    top.rigid_body.type = "PASSIVE"
    links = [blender_body("sphere", f"link {k}", (0.2 * (k + 1), 0, 3), "SPHERE", size=0.05, mass=0.2)
             for k in range(4)]
    for k, (a, b) in enumerate(zip([top] + links[:-1], links)):
        bpy.ops.object.empty_add(location=(0.2 * k + 0.1, 0, 3))
        pin = bpy.context.active_object
        pin.name = f"pin {k}"
        bpy.ops.rigidbody.constraint_add(type="POINT")
        pin.rigid_body_constraint.object1, pin.rigid_body_constraint.object2 = a, b
    tb.bake(scene)
    ends = [keyed(o, range(1, 61)) for o in links]
    # the first link stays 0.1 m from its pin on the fixed anchor, and neighbours no farther than their two pins'
    # 0.1 m each apart (the soft step's joints hold to a millimetre)
    np.testing.assert_allclose(np.linalg.norm(ends[0] - (0.1, 0.0, 3.0), axis=1), 0.1, atol=1e-3)
    for a, b in zip(ends, ends[1:]):
        assert (np.linalg.norm(a - b, axis=1) <= 0.2 + 1e-3).all()
    assert ends[-1][:, 2].min() < 3.0 - 0.5, "the chain swung down"


def test_constraints_tumble_lacks_are_refused():
    scene = empty_scene(10)
    a = blender_body("cube", "a", (0, 0, 1), "BOX")
    b = blender_body("cube", "b", (1.5, 0, 1), "BOX")
    bpy.ops.object.empty_add(location=(0.75, 0, 1))
    pin = bpy.context.active_object
    pin.name = "generic"
    bpy.ops.rigidbody.constraint_add(type="GENERIC")
    pin.rigid_body_constraint.object1, pin.rigid_body_constraint.object2 = a, b
    with pytest.raises(tb.BlenderSceneError) as caught:
        tb.world_from_scene(scene)
    problems = caught.value.problems
    # a generic constraint free on every axis is none of tumble's joints
    assert any(p.startswith("generic: limits") for p in problems), problems


def test_a_breakable_constraint_breaks_as_the_same_joint_does_in_tumble():
    """The hung box's point constraint made breakable at an impulse of 0.02 N s a substep (12 N over Blender's
    1/600 s substep: the swing's pull passes it on the way down): the bake is the world built in Python with a
    ball joint breaking at 12 N, to the bit, and the box flies off, where an unbreakable one keeps it 0.25 m from
    the pivot."""
    threshold = 0.02

    def breakable(c):
        c.use_breaking, c.breaking_threshold = True, threshold

    mapped, _ = _hung_scene("POINT", breakable)
    world, box = mapped.world, mapped.handles["box"]
    run = world.run(1.0, 1 / FPS)
    assert len(run.joint_breaks) == 1
    w = python_world()
    a = w.add_body(tumble.Box(half_extents=(f32(0.025),) * 3), static=True, position=(0.0, 0.0, 2.0), friction=0.5)
    b = w.add_body(tumble.Box(half_extents=(f32(0.1),) * 3), mass=1.0, position=(f32(0.5), 0.0, 2.0), friction=0.5,
                   **damping(1.0, 1.0 * (2 * f32(0.2)**2) / 12, f32(0.04), f32(0.1)))
    bound = f32(threshold) / DT
    w.add_joint(tumble.Ball(a, b, anchor_a=(0.25, 0.0, 0.0), anchor_b=(0.25 - f32(0.5), 0.0, 0.0),
                            breaking=tumble.Breaking(force=bound, torque=bound)))
    want = w.run(1.0, 1 / FPS)
    np.testing.assert_array_equal(run.body_positions[:, world.bodies.row(box)], want.body_positions[:, w.bodies.row(b)])
    np.testing.assert_array_equal(run.joint_break_times, want.joint_break_times)
    # baked, the report says when it broke (the scene's 60 frames: at the same time as the run's)
    report = tb.bake(bpy.context.scene)
    assert len(report.bake_broken_at) == 1
    assert abs(report.bake_broken_at[0] - (1 + run.joint_break_times[0] * FPS)) < 1e-6
    held, _ = _hung("POINT", _set())
    reach = np.linalg.norm(run.body_positions[-1, world.bodies.row(box)] - (0.25, 0.0, 2.0))
    assert reach > 0.5 and abs(np.linalg.norm(held[-1] - (0.25, 0.0, 2.0)) - 0.25) < 1e-2


@pytest.mark.parametrize("kind, limits", [("POINT", None), ("FIXED", None), ("HINGE", None), ("HINGE", (-0.3, 0.3)),
                                          ("SLIDER", None), ("SLIDER", (-0.1, 0.2)), ("PISTON", (-0.1, 0.2)),
                                          ("MOTOR", None)])
def test_each_constraint_type_and_limit_maps_to_the_same_joint_in_tumble(kind, limits):
    """A box hung off a passive anchor by one constraint (its object's z along the world's -y, x along the world's
    -z): the mapped world runs to the same bits as the world built in Python with tumble's joint for it, and every
    type and limit gives its own motion."""
    def setup(c):
        if limits is not None and kind == "HINGE":
            c.use_limit_ang_z, c.limit_ang_z_lower, c.limit_ang_z_upper = True, *limits
        if kind == "MOTOR":  # a spin about the constraint's x (the world's -z) at 2 rad/s
            c.use_motor_ang, c.motor_ang_target_velocity, c.motor_ang_max_impulse = True, 2.0, 0.001
        if limits is not None and kind in ("SLIDER", "PISTON"):
            c.use_limit_lin_x, c.limit_lin_x_lower, c.limit_lin_x_upper = True, *limits

    mapped, pin = _hung_scene(kind, setup)
    world, box = mapped.world, mapped.handles["box"]
    run = world.run(1.0, 1 / FPS)
    w = python_world()
    a = w.add_body(tumble.Box(half_extents=(f32(0.025),) * 3), static=True, position=(0.0, 0.0, 2.0), friction=0.5)
    b = w.add_body(tumble.Box(half_extents=(f32(0.1),) * 3), mass=1.0, position=(f32(0.5), 0.0, 2.0), friction=0.5,
                   **damping(1.0, 1.0 * (2 * f32(0.2)**2) / 12, f32(0.04), f32(0.1)))
    turn = np.array(pin.matrix_world.decompose()[1].to_matrix(), dtype=float)
    at = dict(anchor_a=(0.25, 0.0, 0.0), anchor_b=(0.25 - f32(0.5), 0.0, 0.0))
    lim = None if limits is None else tuple(float(np.float32(v)) for v in limits)
    joint = {"POINT": lambda: tumble.Ball(a, b, **at), "FIXED": lambda: tumble.Weld(a, b, **at),
             "HINGE": lambda: tumble.Hinge(a, b, axis=tuple(turn[:, 2]), limits=lim, **at),
             "SLIDER": lambda: tumble.Slider(a, b, axis=tuple(turn[:, 0]), limits=lim, **at),
             "PISTON": lambda: tumble.Piston(a, b, axis=tuple(turn[:, 0]), limits=lim, **at),
             # Bullet's largest impulse a substep, over the substep: the largest torque
             "MOTOR": lambda: tumble.Drive(a, b, axis=tuple(turn[:, 0]), **at,
                                           motor=tumble.Motor(2.0, max_torque=f32(0.001) / DT))}[kind]()
    w.add_joint(joint)
    want = w.run(1.0, 1 / FPS)
    np.testing.assert_array_equal(run.body_positions[:, world.bodies.row(box)], want.body_positions[:, w.bodies.row(b)])
    np.testing.assert_array_equal(run.body_orientations[:, world.bodies.row(box)],
                                  want.body_orientations[:, w.bodies.row(b)])
    if kind == "MOTOR":  # it falls freely, spinning up about the vertical to the motor's speed
        spin = run.body_angular_velocities[-1, world.bodies.row(box)]
        assert abs(abs(spin[2]) - 2.0) < 1e-6 and run.body_positions[-1, world.bodies.row(box), 2] < 2.0 - 4.0
    ENDS[(kind, limits)] = run.body_positions[-1, world.bodies.row(box)]
    # a limit changes the motion, and so does a weld against a ball joint (a ball joint and a hinge across the
    # swing's plane move alike here: nothing pushes out of it)
    for pair in (("HINGE", None), ("HINGE", (-0.3, 0.3))), (("SLIDER", None), ("SLIDER", (-0.1, 0.2))), \
            (("POINT", None), ("FIXED", None)):
        if all(p in ENDS for p in pair):
            assert np.abs(ENDS[pair[0]] - ENDS[pair[1]]).max() > 1e-3, f"{pair} move alike"


ENDS: dict = {}


def _hung_scene(kind, setup, rotation=(math.pi / 2, math.pi / 2, 0)):
    """A box hung off a passive anchor by one constraint of ``kind`` (its object's z along the world's -y, x along
    the world's -z), set up by ``setup``: the mapped world and the constraint's object."""
    scene = empty_scene(60)
    anchor = blender_body("cube", "anchor", (0, 0, 2), "BOX", size=0.05)
    anchor.rigid_body.type = "PASSIVE"
    box = blender_body("cube", "box", (0.5, 0, 2), "BOX", size=0.2, mass=1.0)
    bpy.ops.object.empty_add(location=(0.25, 0, 2))
    pin = bpy.context.active_object
    bpy.ops.rigidbody.constraint_add(type=kind)
    c = pin.rigid_body_constraint
    c.object1, c.object2 = anchor, box
    pin.rotation_euler = rotation
    setup(c)
    bpy.context.view_layer.update()
    return tb.world_from_scene(scene), pin


def _hung(kind, setup, rotation=(math.pi / 2, math.pi / 2, 0)):
    """The box's positions and orientations over a second of ``_hung_scene``'s mapped world."""
    mapped, _ = _hung_scene(kind, setup, rotation)
    run = mapped.world.run(1.0, 1 / FPS)
    row = mapped.world.bodies.row(mapped.handles["box"])
    return run.body_positions[:, row], run.body_orientations[:, row]


def _lock(c, linear, angular):
    """Locks (a 0 to 0 limit) the generic constraint's axes but those ``linear`` and ``angular`` map to limits
    (None: free)."""
    for kind, free in (("lin", linear), ("ang", angular)):
        for axis in "xyz":
            limit = free.get(axis, (0.0, 0.0))
            setattr(c, f"use_limit_{kind}_{axis}", limit is not None)
            if limit is not None:
                setattr(c, f"limit_{kind}_{axis}_lower", limit[0])
                setattr(c, f"limit_{kind}_{axis}_upper", limit[1])


def _set(**values):
    def setup(c):
        for k, v in values.items():
            setattr(c, k, v)
    return setup


@pytest.mark.parametrize("generic, same", [
    ({"linear": {}, "angular": {}}, ("FIXED", _set())),
    ({"linear": {}, "angular": {"x": None, "y": None, "z": None}}, ("POINT", _set())),
    ({"linear": {}, "angular": {"z": (-0.3, 0.3)}},
     ("HINGE", _set(use_limit_ang_z=True, limit_ang_z_lower=-0.3, limit_ang_z_upper=0.3))),
    ({"linear": {"x": (-0.1, 0.2)}, "angular": {}},
     ("SLIDER", _set(use_limit_lin_x=True, limit_lin_x_lower=-0.1, limit_lin_x_upper=0.2))),
    ({"linear": {"x": (-0.1, 0.2)}, "angular": {"x": None}},
     ("PISTON", _set(use_limit_lin_x=True, limit_lin_x_lower=-0.1, limit_lin_x_upper=0.2))),
])
def test_a_generic_constraint_is_the_joint_its_locked_and_free_axes_make(generic, same):
    for kind in ("GENERIC", "GENERIC_SPRING"):
        got = _hung(kind, lambda c: _lock(c, generic["linear"], generic["angular"]))
        want = _hung(*same)
        np.testing.assert_array_equal(got[0], want[0])
        np.testing.assert_array_equal(got[1], want[1])


def test_a_generic_constraint_no_joint_matches_is_refused_naming_its_axes():
    scene = empty_scene(10)
    a = blender_body("cube", "a", (0, 0, 1), "BOX")
    b = blender_body("cube", "b", (1.5, 0, 1), "BOX")
    bpy.ops.object.empty_add(location=(0.75, 0, 1))
    pin = bpy.context.active_object
    pin.name = "six"
    bpy.ops.rigidbody.constraint_add(type="GENERIC_SPRING")
    c = pin.rigid_body_constraint
    c.object1, c.object2 = a, b
    _lock(c, {"x": None, "y": None}, {})
    with pytest.raises(tb.BlenderSceneError) as caught:
        tb.world_from_scene(scene)
    problems = caught.value.problems
    assert any(p.startswith("six: limits") and "linear x, linear y" in p for p in problems), problems


def _hinge_spring(c, stiffness=2.0, damping=0.05, spring_type="SPRING2"):
    """A generic spring free about its z alone (a hinge) with a spring about that axis."""
    _lock(c, {}, {"z": None})
    c.spring_type = spring_type
    c.use_spring_ang_z, c.spring_stiffness_ang_z, c.spring_damping_ang_z = True, stiffness, damping


def test_a_generic_spring_on_its_hinge_axis_is_the_hinges_spring():
    """The hung box on a generic spring that makes a hinge, with a Spring 2 spring of 2 N m/rad and 0.05 N m s/rad
    about the hinge's axis: the mapped world runs to the same bits as the tumble hinge with that joint spring
    (towards where the bodies start, Bullet's equilibrium), and the spring changes the swing."""
    mapped, pin = _hung_scene("GENERIC_SPRING", _hinge_spring)
    world, box = mapped.world, mapped.handles["box"]
    run = world.run(1.0, 1 / FPS)
    w = python_world()
    a = w.add_body(tumble.Box(half_extents=(f32(0.025),) * 3), static=True, position=(0.0, 0.0, 2.0), friction=0.5)
    b = w.add_body(tumble.Box(half_extents=(f32(0.1),) * 3), mass=1.0, position=(f32(0.5), 0.0, 2.0), friction=0.5,
                   **damping(1.0, 1.0 * (2 * f32(0.2)**2) / 12, f32(0.04), f32(0.1)))
    turn = np.array(pin.matrix_world.decompose()[1].to_matrix(), dtype=float)
    w.add_joint(tumble.Hinge(a, b, anchor_a=(0.25, 0.0, 0.0), anchor_b=(0.25 - f32(0.5), 0.0, 0.0),
                             axis=tuple(turn[:, 2]), spring=tumble.JointSpring(2.0, f32(0.05), 0.0)))
    want = w.run(1.0, 1 / FPS)
    np.testing.assert_array_equal(run.body_positions[:, world.bodies.row(box)], want.body_positions[:, w.bodies.row(b)])
    free, _ = _hung("GENERIC_SPRING", lambda c: _lock(c, {}, {"z": None}))
    assert np.abs(free[-1] - run.body_positions[-1, world.bodies.row(box)]).max() > 1e-2, "the spring holds it up"


@pytest.mark.parametrize("setup, said", [
    (lambda c: _hinge_spring(c, spring_type="SPRING1"), "Spring 1"),
    (lambda c: (_hinge_spring(c), setattr(c, "use_spring_x", True)), "springs on linear x"),
    (lambda c: _hinge_spring(c, stiffness=1e5), "stiffness angular z"),
    (lambda c: _hinge_spring(c, damping=1e3), "damping angular z"),
])
def test_a_generic_springs_springs_tumble_cannot_match_are_refused(setup, said):
    with pytest.raises(tb.BlenderSceneError) as caught:
        _hung_scene("GENERIC_SPRING", setup)
    assert any(said in p for p in caught.value.problems), caught.value.problems


def _tied_scene(disable_collisions):
    """A cube 0.5 m above a slab resting on the ground, joined to it by a slider along the vertical (the
    constraint object's x turned up), with "disable collisions" as given: the mapped world."""
    scene = empty_scene(60)
    ground()
    slab = blender_body("cube", "slab", (0, 0, 0.1), "BOX", size=1.0, mass=10.0)
    slab.scale = (1.0, 1.0, 0.2)
    cube = blender_body("cube", "cube", (0, 0, 0.8), "BOX", size=0.2, mass=1.0)
    bpy.ops.object.empty_add(location=(0, 0, 0.8))
    pin = bpy.context.active_object
    bpy.ops.rigidbody.constraint_add(type="SLIDER")
    c = pin.rigid_body_constraint
    c.object1, c.object2, c.disable_collisions = slab, cube, disable_collisions
    pin.rotation_euler = (0, -math.pi / 2, 0)  # its x along the world's z
    bpy.context.view_layer.update()
    return tb.world_from_scene(scene)


def test_disable_collisions_off_lets_the_joined_bodies_collide():
    """With "disable collisions" off the cube slides down onto the slab it is joined to and stays there, as the
    tumble slider with collide=True does; with it on (Blender's default) the cube slides through the slab to the
    ground."""
    heights = {}
    for disable in (False, True):
        mapped = _tied_scene(disable)
        run = mapped.world.run(1.5, 1 / FPS)
        heights[disable] = run.body_positions[-1, mapped.world.bodies.row(mapped.handles["cube"]), 2]
    # on the slab's top (0.2 m) or the ground, at the cube's half height; within the soft contacts' 1 cm
    assert abs(heights[False] - 0.3) < 1e-2 and abs(heights[True] - 0.1) < 1e-2, heights
    w = python_world()
    python_ground(w)
    a = w.add_body(tumble.Box(half_extents=(0.5, 0.5, f32(0.1))), mass=10.0, position=(0.0, 0.0, f32(0.1)),
                   friction=0.5, **damping(10.0, 10.0 * (2 * (1.0 + f32(0.2) ** 2) + 2.0) / 36, f32(0.04), f32(0.1)))
    b = w.add_body(tumble.Box(half_extents=(f32(0.1),) * 3), mass=1.0, position=(0.0, 0.0, f32(0.8)), friction=0.5,
                   **damping(1.0, 1.0 * (2 * f32(0.2) ** 2) / 12, f32(0.04), f32(0.1)))
    w.add_joint(tumble.Slider(a, b, anchor_a=(0.0, 0.0, f32(0.8) - f32(0.1)), anchor_b=(0.0, 0.0, 0.0),
                              axis=(0.0, 0.0, 1.0), collide=True))
    want = w.run(1.5, 1 / FPS)
    # (the slab's float32 scale and mean moment differ in the last bits: the heights agree to 1e-6 m of rest)
    assert abs(want.body_positions[-1, w.bodies.row(b), 2] - heights[False]) < 1e-6


def test_a_pistons_turn_limits_stop_its_swing_as_tumbles_do():
    """The hung box on a piston whose axis is horizontal (the constraint's x along the world's y): the box swings
    down about it, and the piston's angular x limits (-0.3 to 0.3 rad) stop the swing; the mapped world runs to
    the same bits as the tumble piston with those turn limits, and as a generic constraint free along x and
    limited about it; without the limits it swings on."""
    across = (0.0, 0.0, math.pi / 2)

    def limited(c):
        c.use_limit_ang_x, c.limit_ang_x_lower, c.limit_ang_x_upper = True, -0.3, 0.3

    mapped, pin = _hung_scene("PISTON", limited, across)
    world, box = mapped.world, mapped.handles["box"]
    run = world.run(1.0, 1 / FPS)
    w = python_world()
    a = w.add_body(tumble.Box(half_extents=(f32(0.025),) * 3), static=True, position=(0.0, 0.0, 2.0), friction=0.5)
    b = w.add_body(tumble.Box(half_extents=(f32(0.1),) * 3), mass=1.0, position=(f32(0.5), 0.0, 2.0), friction=0.5,
                   **damping(1.0, 1.0 * (2 * f32(0.2)**2) / 12, f32(0.04), f32(0.1)))
    turn = np.array(pin.matrix_world.decompose()[1].to_matrix(), dtype=float)
    w.add_joint(tumble.Piston(a, b, anchor_a=(0.25, 0.0, 0.0), anchor_b=(0.25 - f32(0.5), 0.0, 0.0),
                              axis=tuple(turn[:, 0]), turn_limits=(f32(-0.3), f32(0.3))))
    want = w.run(1.0, 1 / FPS)
    got = run.body_positions[:, world.bodies.row(box)]
    np.testing.assert_array_equal(got, want.body_positions[:, w.bodies.row(b)])
    generic, _ = _hung("GENERIC", lambda c: _lock(c, {"x": None}, {"x": (-0.3, 0.3)}), across)
    np.testing.assert_array_equal(generic, got)
    # the box's centre, 0.25 m from the axis, drops by 0.25 sin(0.3) at the limit (the soft step's joints hold to a
    # millimetre); unlimited, it swings through the bottom
    assert abs((2.0 - got[-1, 2]) - 0.25 * math.sin(0.3)) < 2e-3, got[-1]
    free, _ = _hung("PISTON", _set(), across)
    assert free[:, 2].min() < 2.0 - 0.2
