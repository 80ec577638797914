"""The Blender bake (``tumble.blender``), headless with Blender as a module (the ``blender`` extra): scenes built
through Blender's own operators, baked with tumble, their keyframes against a tumble world of the same scene built
directly in Python; each mapped setting changing the bake as the same change in tumble does; what cannot be mapped
refused naming the object and the setting; the add-on's operator. Keyframes are float32 in Blender (F-curve points),
so poses are compared to float32's rounding: 2e-7 of the coordinate's size (the issue's 1e-9 m is below float32's
resolution at a metre)."""

import math

import numpy as np
import pytest

import tumble

bpy = pytest.importorskip("bpy", reason="Blender as a module is the `blender` extra")
import tumble.blender as tb  # noqa: E402
from blender_scenes import (  # noqa: E402
    FPS, SUBSTEPS, assert_keyed_like, blender_body, damping, empty_scene, f32, ground, keyed, python_ground,
    python_world,
)


def test_a_bouncing_ball_bakes_as_the_same_world_built_in_python():
    scene = empty_scene(90)
    ground(restitution=1.0)
    ball = blender_body("sphere", "ball", (0, 0, 1), "SPHERE", size=0.1, restitution=0.8, mass=0.5)
    report = tb.bake(scene)
    assert report.bake_simulating_seconds > 0 and report.steps == 89 * SUBSTEPS
    assert not scene.rigidbody_world.enabled, "the world is switched off so that the keyframes play"
    # the same scene in Python, with Blender's numbers and Bullet's product rule
    w = python_world()
    python_ground(w, restitution=1.0)
    sphere = tumble.Sphere(radius=0.1)
    moment = sphere.mass_properties(1.0)["inertia"][0][0] * 0.5 / sphere.mass_properties(1.0)["mass"]
    b = w.add_body(sphere, mass=0.5, position=(0.0, 0.0, 1.0), restitution=0.8, friction=0.5,
                   **damping(0.5, moment))
    run = w.run(89 / FPS, 1 / FPS)
    assert_keyed_like(ball, run, w.bodies.row(b), range(1, 91))
    assert keyed(ball, [1])[0][2] == pytest.approx(1.0)
    # it bounced: up again after the first impact (about frame 27)
    z = keyed(ball, range(1, 91))[:, 2]
    assert z.argmin() < 40 and z[60] > z[z.argmin()] + 0.2


def test_a_stack_of_cubes_bakes_as_the_same_world_built_in_python():
    scene = empty_scene(60)
    ground()
    cubes = [blender_body("cube", f"cube {k}", (0, 0, 0.5 + k * 1.0), "BOX", mass=2.0) for k in range(3)]
    tb.bake(scene)
    w = python_world()
    python_ground(w)
    box = tumble.Box(half_extents=(0.5, 0.5, 0.5))
    moment = 2.0 / 6.0  # m a^2 / 6 for a unit cube
    hs = [w.add_body(box, mass=2.0, position=(0.0, 0.0, 0.5 + k), friction=0.5, **damping(2.0, moment))
          for k in range(3)]
    run = w.run(59 / FPS, 1 / FPS)
    for obj, h in zip(cubes, hs):
        assert_keyed_like(obj, run, w.bodies.row(h), range(1, 61))


@pytest.mark.parametrize("setting, value, python", [
    ("mass", 3.0, "mass"), ("friction", 0.2, "friction"), ("restitution", 0.5, "restitution"),
    ("linear_damping", 0.3, "linear_damping"),
])
def test_each_setting_changes_the_bake_as_the_same_change_in_tumble(setting, value, python):
    """A box thrown along a floor: one Blender setting changed gives the world built in Python with tumble's
    mapping of it (friction and restitution by the product rule, damping as a decay)."""
    def blender_run(**settings):
        scene = empty_scene(60)
        ground(restitution=1.0)
        box = blender_body("cube", "box", (0, 0, 0.6), "BOX", size=0.4, **{"mass": 1.0, **settings})
        box.rigid_body.angular_damping = 0.0
        mapped = tb.world_from_scene(scene)
        w = mapped.world
        w.set_body_state(mapped.handles["box"], velocity=(2.0, 0.0, -1.0))
        return w.run(1.0, 1 / FPS), w.bodies.row(mapped.handles["box"])

    def python_run(**settings):
        # Blender's properties are float32: the same numbers as Blender holds them
        given = {"mass": 1.0, "friction": 0.5, "restitution": 0.0, "linear_damping": 0.04, **settings}
        mass, mu, e, d = (float(np.float32(given[k])) for k in ("mass", "friction", "restitution", "linear_damping"))
        w = python_world()
        python_ground(w, restitution=1.0)
        h = w.add_body(tumble.Box(half_extents=(f32(0.2),) * 3), mass=mass, position=(0.0, 0.0, f32(0.6)),
                       velocity=(2.0, 0.0, -1.0), friction=mu, restitution=e,
                       linear_damping=-mass * math.log(1 - d))
        return w.run(1.0, 1 / FPS), w.bodies.row(h)

    (before, rb), (after, ra) = blender_run(), blender_run(**{setting: value})
    (want_before, pb), (want_after, pa) = python_run(), python_run(**{python: value})
    np.testing.assert_array_equal(before.body_positions[:, rb], want_before.body_positions[:, pb])
    np.testing.assert_array_equal(after.body_positions[:, ra], want_after.body_positions[:, pa])
    # the change matters (a body's mass alone does not change its own fall and slide: its momentum it does)
    moved = np.abs(after.body_positions[:, ra] - before.body_positions[:, rb]).max()
    pushed = np.abs(after.momentum - before.momentum).max()
    assert (pushed if setting == "mass" else moved) > 1e-3, "the change matters"


def test_shapes_map_to_tumbles():
    scene = empty_scene(10)
    blender_body("cube", "box", (0, 0, 1), "BOX", size=0.5)
    for shape in ("SPHERE", "CAPSULE", "CYLINDER", "CONE", "CONVEX_HULL", "MESH"):
        blender_body("cube", shape.lower(), (2, 0, 1), shape, size=0.5)
    mapped = tb.world_from_scene(scene)
    assert sorted(mapped.handles) == sorted(["box", "sphere", "capsule", "cylinder", "cone", "convex_hull", "mesh"])
    assert any("cone" in n for n in mapped.notes), "the cone's approximation is said"
    # a cube as a hull and as a mesh has the box's mass properties: same centre, same origin
    rows = {n: mapped.world.bodies.row(h) for n, h in mapped.handles.items()}
    for n in ("convex_hull", "mesh"):
        np.testing.assert_allclose(mapped.world.bodies.positions[rows[n]], (2.0, 0.0, 1.0), atol=1e-12)


@pytest.mark.parametrize("change, named", [
    (lambda o, s: setattr(o.rigid_body, "enabled", False), "box: dynamic"),
    (lambda o, s: setattr(o.rigid_body, "collision_shape", "COMPOUND"), "box: collision shape"),
    (lambda o, s: setattr(o.rigid_body, "use_start_deactivated", True), "box: start deactivated"),
])
def test_what_cannot_be_mapped_is_refused_naming_object_and_setting(change, named):
    scene = empty_scene(10)
    ground()
    box = blender_body("cube", "box", (0, 0, 1), "BOX")
    change(box, scene)
    with pytest.raises(tb.BlenderSceneError) as caught:
        tb.bake(scene)
    assert any(p.startswith(named) for p in caught.value.problems), caught.value.problems
    assert scene.rigidbody_world.enabled and box.animation_data is None, "nothing was written"


def test_bouncy_spheres_among_cubes_bake_as_the_same_world_built_with_the_product_rule():
    """Four spheres of bounciness 0.6 dropped onto each other among cubes of 0 on a ground of 1 (pairs Blender
    combines as products, which no single "larger of the two" gives: 0.6 off the ground, 0.36 off each other, 0 off
    a cube): the bake equals the world built in Python with the product rule, bit for bit, and the lowest sphere
    bounces off the ground."""
    scene = empty_scene(60)
    ground(restitution=1.0)
    spheres = [blender_body("sphere", f"Ball_{k}", (0.01 * k, 0, 1.0 + 0.3 * k), "SPHERE", size=0.1,
                            restitution=0.6, mass=0.5) for k in range(4)]
    cubes = [blender_body("cube", f"Cube_{k}", (2.0 * k - 1.0, 2.0, 0.5), "BOX", restitution=0.0, mass=2.0)
             for k in range(2)]
    tb.bake(scene)

    def python_run(**rules: str):
        w = python_world()
        w.set_combine_rules(**rules) if rules else None
        # Blender sizes a sphere shape by the object's dimensions (its UV sphere's, in float32)
        sphere = tumble.Sphere(radius=float(np.asarray(spheres[0].dimensions).max() / 2))
        moment = sphere.mass_properties(1.0)["inertia"][0][0] * 0.5 / sphere.mass_properties(1.0)["mass"]
        damped = {"linear": f32(0.04), "angular": f32(0.1)}
        balls = [w.add_body(sphere, mass=0.5, position=(f32(0.01 * k), 0.0, f32(1.0 + 0.3 * k)),
                            restitution=f32(0.6), friction=0.5, **damping(0.5, moment, **damped)) for k in range(4)]
        box = tumble.Box(half_extents=(0.5, 0.5, 0.5))
        boxes = [w.add_body(box, mass=2.0, position=(2.0 * k - 1.0, 2.0, 0.5), restitution=0.0, friction=0.5,
                            **damping(2.0, 2.0 / 6.0, **damped)) for k in range(2)]
        python_ground(w, restitution=1.0)  # the bake adds its objects by name: "ground" after "Ball_*" and "Cube_*"
        return w.run(59 / FPS, 1 / FPS), [w.bodies.row(h) for h in balls + boxes]

    run, rows = python_run()
    for obj, row in zip(spheres + cubes, rows):
        assert_keyed_like(obj, run, row, range(1, 61))
    # the rule matters here: with tumble's default rules (the larger restitution) the spheres move otherwise
    other, _ = python_run(friction="geometric_mean", restitution="max")
    assert np.abs(other.body_positions - run.body_positions).max() > 1e-3


def test_the_add_on_bakes_from_its_operator():
    scene = empty_scene(30)
    ground()
    box = blender_body("cube", "box", (0, 0, 2), "BOX")
    tb.register()
    try:
        assert bpy.ops.tumble.bake("EXEC_DEFAULT", frame_start=1, frame_end=30) == {"FINISHED"}
    finally:
        tb.unregister()
    curves = box.animation_data.action
    assert curves is not None
    assert keyed(box, [30])[0][2] < 2.0 - 0.5, "the box fell"


def test_collision_collections_are_collision_groups():
    """A box only in collection 2 falls through a ground only in collection 1; in both, it lands."""
    def drop(collections):
        scene = empty_scene(60)
        floor = ground()
        box = blender_body("cube", "box", (0, 0, 1), "BOX", size=0.5)
        floor.rigid_body.collision_collections = [k == 0 for k in range(20)]
        box.rigid_body.collision_collections = [k in collections for k in range(20)]
        mapped = tb.world_from_scene(scene)
        assert mapped.world.bodies.collision_groups[mapped.world.bodies.row(mapped.handles["box"])] == \
            sum(1 << k for k in collections)
        tb.bake(scene)
        return keyed(box, [60])[0][2]

    assert drop({1}) < -1.0, "no collection in common: through the ground"
    assert drop({0, 1}) == pytest.approx(0.25, abs=1e-3), "collection 1 in common: on the ground"


def paddle_scene(animated=True):
    """A 0.2 m box on the ground and a paddle keyframed (linear) from x = -1 at frame 1 to x = 1 at frame 61,
    across the box: Blender's Animated rigid body."""
    scene = empty_scene(90)
    ground()
    box = blender_body("cube", "box", (0, 0, 0.1), "BOX", size=0.2, restitution=0.0)
    paddle = blender_body("cube", "paddle", (-1, 0, 0.2), "BOX", size=0.4, restitution=0.0, kinematic=animated)
    paddle.scale = (0.1, 2.0, 1.0)
    for frame, x in ((1, -1.0), (61, 1.0)):
        paddle.location.x = x
        paddle.keyframe_insert("location", frame=frame)
    for curve in paddle.animation_data.action.layers[0].strips[0].channelbag(paddle.animation_data.action_slot).fcurves:
        for point in curve.keyframe_points:
            point.interpolation = "LINEAR"
    return scene, box, paddle


def test_an_animated_paddle_pushes_a_box_as_a_kinematic_body_in_tumble():
    scene, box, paddle = paddle_scene()
    mapped = tb.world_from_scene(scene)
    assert mapped.world.bodies.kinematic[mapped.world.bodies.row(mapped.handles["paddle"])]
    assert "paddle" not in mapped.moving, "an animated object keeps its own animation"
    tb.bake(scene)
    # the same scene in Python: the paddle (a 0.04 x 0.8 x 0.4 m box) along the same line, 2 m in 1 s
    w = python_world()
    python_ground(w)
    b = w.add_body(tumble.Box(half_extents=(0.1, 0.1, 0.1)), mass=1.0, position=(0.0, 0.0, 0.1), restitution=0.0,
                   friction=0.5, **damping(1.0, 1.0 * (0.2**2 + 0.2**2) / 12))
    # the paddle's path as Blender evaluates its F-curves (float32), on the line -1 + 2 t to that rounding
    times = np.arange(90) / FPS
    line = keyed(paddle, range(1, 91))
    assert np.abs(line[:, 0] - np.clip(-1.0 + 2.0 * times, -1.0, 1.0)).max() < 1e-6
    w.add_body(tumble.Box(half_extents=(f32(0.2) * f32(0.1), f32(0.2) * 2.0, f32(0.2))), keyframes=(times, line),
               restitution=0.0, friction=0.5)
    run = w.run(89 / FPS, frame_interval=1.0 / FPS)
    assert keyed(box, [90])[0][0] > 0.5, "the paddle pushed the box along"
    # the animated object's F-curves are Blender's own; the box's bake is the Python world's
    assert_keyed_like(box, run, w.bodies.row(b), range(1, 91))
    assert keyed(paddle, [31])[0][0] == pytest.approx(0.0, abs=1e-6), "the paddle's own animation is untouched"


def test_without_animated_the_paddle_stays_put():
    scene, box, paddle = paddle_scene(animated=False)
    paddle.rigid_body.type = "PASSIVE"
    tb.bake(scene)
    assert abs(keyed(box, [90])[0][0]) < 1e-6, "a passive paddle that does not follow its keys pushes nothing"


def test_a_ball_in_a_cup_mesh_bakes_as_the_same_world_built_in_python():
    """A passive cup of Blender's Mesh collision shape (a revolved profile made a Blender mesh): tumble takes its
    exact triangles; a ball dropped into it off its axis stays in."""
    profile = [(0.0, 0.0), (0.05, 0.0), (0.05, 0.08), (0.045, 0.08), (0.045, 0.005), (0.0, 0.005)]
    cup_mesh = tumble.Mesh.revolve(profile, segments=32, name="cup")
    scene = empty_scene(60)
    data = bpy.data.meshes.new("cup")
    data.from_pydata([tuple(map(float, v)) for v in cup_mesh.vertices], [], [tuple(map(int, t))
                                                                              for t in cup_mesh.triangles])
    cup = bpy.data.objects.new("cup", data)
    scene.collection.objects.link(cup)
    bpy.context.view_layer.objects.active = cup
    cup.select_set(True)
    bpy.ops.rigidbody.object_add(type="PASSIVE")
    cup.rigid_body.collision_shape = "MESH"
    ball = blender_body("sphere", "ball", (0.01, 0, 0.15), "SPHERE", size=0.015, mass=0.02)
    mapped = tb.world_from_scene(scene)
    assert mapped.world.bodies.names is not None
    tb.bake(scene)
    w = python_world()
    vertices = np.asarray(cup_mesh.vertices, dtype=np.float32).astype(float)  # as Blender holds them
    w.add_body(tumble.Mesh(vertices, np.asarray(cup_mesh.triangles), name="cup"), static=True, friction=0.5,
               restitution=0.0)
    sphere = tumble.Sphere(radius=f32(0.015))
    moment = sphere.mass_properties(1.0)["inertia"][0][0] * 0.02 / sphere.mass_properties(1.0)["mass"]
    b = w.add_body(sphere, mass=f32(0.02), position=(f32(0.01), 0.0, f32(0.15)), friction=0.5, restitution=0.0,
                   **damping(f32(0.02), moment))
    run = w.run(59 / FPS, 1 / FPS)
    assert_keyed_like(ball, run, w.bodies.row(b), range(1, 61))
    x, y, z = keyed(ball, [60])[0]
    assert 0.005 < z < 0.08 and math.hypot(x, y) < 0.045, "the ball stays in the cup"


def key_animated(obj, keys):
    """Keys ``obj``'s location and "Animated" at each ``(frame, location, animated)``: the location linear between
    keys, the switch held from its key on."""
    for frame, location, animated in keys:
        obj.location = location
        obj.keyframe_insert("location", frame=frame)
        obj.rigid_body.kinematic = animated
        obj.keyframe_insert("rigid_body.kinematic", frame=frame)
    for curve in obj.animation_data.action.layers[0].strips[0].channelbag(obj.animation_data.action_slot).fcurves:
        for point in curve.keyframe_points:
            point.interpolation = "LINEAR" if curve.data_path == "location" else "CONSTANT"


def test_an_animated_box_switched_to_dynamic_mid_shot_flies_on_as_it_moved():
    """A box keyed to slide along x at 1 m per 30 frames (2 m/s at 60 fps), 1 m up, its "Animated" switched off at
    frame 32: the bake lets it go there (World.release) with the speed it had coming there, and it flies on from
    where it was: x = 1 + 1/30 + 2 t, z = 1 - g t^2 / 2 (fast mode's semi-implicit Euler within g h t / 2 of the
    parabola at Blender's 1/600 s step; 2 cm is ample)."""
    scene = empty_scene(61)
    box = blender_body("cube", "box", (0, 0, 1), "BOX", size=0.2, mass=1.0)
    box.rigid_body.kinematic = True
    key_animated(box, [(1, (0.0, 0.0, 1.0), True), (31, (1.0, 0.0, 1.0), True), (32, (1.0 + 1 / 30, 0.0, 1.0), False)])
    mapped = tb.world_from_scene(scene)
    assert mapped.switches == {"box": [(32, False)]} and mapped.densities == {"box": pytest.approx(1.0 / 0.008)}
    tb.bake(scene)
    x, _, z = keyed(box, [61])[0]
    t = (61 - 32) / FPS
    assert x == pytest.approx(1.0 + 1 / 30 + 2.0 * t, abs=1e-4)  # float32 keyframes
    assert z == pytest.approx(1.0 - 0.5 * 9.81 * t * t, abs=0.02)
    assert keyed(box, [16])[0][0] == pytest.approx(0.5, abs=1e-5)  # on its keys before


def test_a_falling_box_keyed_animated_mid_shot_follows_its_animation_from_there():
    """A box falling freely from 1 m up, its "Animated" keyed on at frame 40 where its keys carry it from (0.5, 0, 2)
    to (1.5, 0, 2) by frame 60, and off again at frame 60: before frame 40 it falls (z = 1 - g t^2 / 2, within 2 cm
    as above), from 40 to 60 it is on its keys (float32 keyframes: 1e-4), and after 60 it is let go moving as its
    keys had it, 3 m/s along x, damped as the body was (Blender's "Animated" both ways: World.hold, then World.release)."""
    scene = empty_scene(70)
    box = blender_body("cube", "box", (0, 0, 1), "BOX", size=0.2, mass=1.0)
    key_animated(box, [(1, (0.0, 0.0, 1.0), False), (40, (0.5, 0.0, 2.0), True), (60, (1.5, 0.0, 2.0), False)])
    mapped = tb.world_from_scene(scene)
    assert mapped.switches == {"box": [(40, True), (60, False)]}
    tb.bake(scene)
    t = (39 - 1) / FPS
    x, _, z = keyed(box, [39])[0]
    assert x == pytest.approx(0.0, abs=1e-6) and z == pytest.approx(1.0 - 0.5 * 9.81 * t * t, abs=0.02)
    for frame in (40, 50, 60):
        assert keyed(box, [frame])[0] == pytest.approx((0.5 + (frame - 40) / 20, 0.0, 2.0), abs=1e-4)
    # let go at 3 m/s, slowed by Blender's linear damping (kept from its start as a dynamic body): a decay rate c
    c, t = -math.log(1.0 - box.rigid_body.linear_damping), 10 / FPS
    x, _, _ = keyed(box, [70])[0]
    assert x == pytest.approx(1.5 + 3.0 * (1.0 - math.exp(-c * t)) / c, abs=1e-4)
