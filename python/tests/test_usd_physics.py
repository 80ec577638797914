"""USD Physics in and out (the ``usd`` extra): stages authored here with the UsdPhysics schema load, through
``World.from_usd``, into worlds that run as the same worlds built directly in Python (to 1e-12) (units, up
axis, gravity, shapes, masses, materials, velocities, kinematic bodies, joints with limits and drives); a run writes
back onto the stage's own prims as a layer over it (``Run.export_usd(path, over=source)``); each unsupported or bad
attribute is refused naming its prim and attribute, and each approximation made is a warning naming them; float32
values come in as typed (0.7, not 0.699999988079071)."""

import json
import math

import numpy as np
import pytest

import tumble

pxr = pytest.importorskip("pxr", reason="usd-core is the `usd` extra")
from pxr import Gf, Sdf, Usd, UsdGeom, UsdPhysics, UsdShade  # noqa: E402

DOUBLE = UsdGeom.XformOp.PrecisionDouble


def new_stage(path, up="Z", metres=1.0, gravity=None):
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z if up == "Z" else UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, metres)
    scene = UsdPhysics.Scene.Define(stage, "/physicsScene")
    if gravity is not None:
        scene.CreateGravityDirectionAttr(Gf.Vec3f(*gravity[0]))
        scene.CreateGravityMagnitudeAttr(gravity[1])
    return stage


def placed(prim_schema, translate=(0.0, 0.0, 0.0), orient=None, scale=None):
    xf = UsdGeom.Xformable(prim_schema)
    xf.AddTranslateOp(DOUBLE).Set(Gf.Vec3d(*translate))
    if orient is not None:
        xf.AddOrientOp(DOUBLE).Set(Gf.Quatd(*orient))
    if scale is not None:
        xf.AddScaleOp(DOUBLE).Set(Gf.Vec3d(*scale))
    return prim_schema.GetPrim()


def collider(prim, rigid=False, mass=None):
    UsdPhysics.CollisionAPI.Apply(prim)
    if rigid:
        UsdPhysics.RigidBodyAPI.Apply(prim)
    if mass is not None:
        UsdPhysics.MassAPI.Apply(prim).CreateMassAttr(mass)
    return prim


def physics_material(stage, path, friction, restitution, density=None):
    material = UsdShade.Material.Define(stage, path)
    api = UsdPhysics.MaterialAPI.Apply(material.GetPrim())
    api.CreateStaticFrictionAttr(friction)
    api.CreateDynamicFrictionAttr(friction)
    api.CreateRestitutionAttr(restitution)
    if density is not None:
        api.CreateDensityAttr(density)
    return material


def bind(prim, material):
    UsdShade.MaterialBindingAPI.Apply(prim).Bind(material, materialPurpose="physics")


def same_runs(a, b, duration=0.5):
    """Two worlds run alike (frames every 0.05 s): to 1e-12, the rounding of poses read from a stage's matrices
    (a quarter turn read back from its matrix differs from sqrt(1/2) in the last bit)."""
    ra, rb = a.run(duration, frame_interval=0.05), b.run(duration, frame_interval=0.05)
    assert np.abs(ra.body_positions - rb.body_positions).max() < 1e-12
    assert np.abs(ra.body_orientations - rb.body_orientations).max() < 1e-12
    return ra


def test_a_stage_of_shapes_masses_materials_and_velocities_is_the_world_built_in_python(tmp_path):
    path = tmp_path / "shapes.usda"
    stage = new_stage(path, gravity=((0.0, 0.0, -1.0), 5.0))
    ground = collider(placed(UsdGeom.Cube.Define(stage, "/World/ground"), (0.0, 0.0, -0.5), scale=(10.0, 10.0, 1.0)))
    UsdGeom.Cube(ground).CreateSizeAttr(1.0)
    box = collider(placed(UsdGeom.Cube.Define(stage, "/World/box"), (0.0, 0.0, 1.0), (1.0, 0.0, 0.0, 0.0)),
                   rigid=True, mass=2.0)
    UsdGeom.Cube(box).CreateSizeAttr(0.5)
    UsdPhysics.RigidBodyAPI(box).CreateVelocityAttr(Gf.Vec3f(0.5, 0.0, 0.0))
    UsdPhysics.RigidBodyAPI(box).CreateAngularVelocityAttr(Gf.Vec3f(0.0, 0.0, 90.0))  # degrees a second
    ball = collider(placed(UsdGeom.Sphere.Define(stage, "/World/ball"), (1.0, 0.0, 0.5)), rigid=True)
    UsdGeom.Sphere(ball).CreateRadiusAttr(0.25)
    bind(ball, physics_material(stage, "/Materials/rubber", 0.75, 0.5, density=500.0))
    pill = collider(placed(UsdGeom.Capsule.Define(stage, "/World/pill"), (-1.0, 0.0, 0.5)), rigid=True)
    UsdGeom.Capsule(pill).CreateAxisAttr("X")
    UsdGeom.Capsule(pill).CreateRadiusAttr(0.125)
    UsdGeom.Capsule(pill).CreateHeightAttr(0.5)
    stage.GetRootLayer().Save()
    world, handles = tumble.World.from_usd(path)
    assert list(handles) == ["/World/ground", "/World/box", "/World/ball", "/World/pill"]
    assert world.bodies.names == list(handles)
    # the same world in Python: PhysX's default material (0.5, 0) where none is bound, 1000 kg/m^3
    w = tumble.World(gravity=(0.0, 0.0, -5.0))
    w.add_body(tumble.Box(half_extents=(5.0, 5.0, 0.5)), static=True, position=(0.0, 0.0, -0.5), friction=0.5,
               restitution=0.0)
    w.add_body(tumble.Box(half_extents=(0.25, 0.25, 0.25)), mass=2.0, position=(0.0, 0.0, 1.0), friction=0.5,
               restitution=0.0, velocity=(0.5, 0.0, 0.0), angular_velocity=(0.0, 0.0, math.radians(90.0)))
    w.add_body(tumble.Sphere(radius=0.25), density=500.0, position=(1.0, 0.0, 0.5), friction=0.75, restitution=0.5)
    # a capsule along the stage's x: tumble's lies along z, turned a quarter about y
    w.add_body(tumble.Capsule(half_height=0.25, radius=0.125), density=1000.0, position=(-1.0, 0.0, 0.5),
               orientation=(math.sqrt(0.5), 0.0, math.sqrt(0.5), 0.0), friction=0.5, restitution=0.0)
    assert np.allclose(world.bodies.orientations, w.bodies.orientations, rtol=0, atol=1e-15)
    same_runs(world, w)


def test_units_and_the_up_axis_come_to_metres_and_z_up(tmp_path):
    # a centimetre, y-up stage: a 20 cm box 100 cm up falls 9.81 m/s^2 (the schema's default, -up)
    path = tmp_path / "cm.usda"
    stage = new_stage(path, up="Y", metres=0.01)
    box = collider(placed(UsdGeom.Cube.Define(stage, "/World/box"), (30.0, 100.0, 40.0)), rigid=True)
    UsdGeom.Cube(box).CreateSizeAttr(20.0)
    stage.GetRootLayer().Save()
    world, handles = tumble.World.from_usd(path)
    # stage (x, y, z) is tumble's (x, -z, y), in metres
    assert np.allclose(world.bodies.positions[0], (0.3, -0.4, 1.0), rtol=0, atol=1e-15)
    run = world.run(0.5, frame_interval=0.5)
    # free fall to the integrator's tolerance
    assert run.body_positions[-1, 0, 2] == pytest.approx(1.0 - 0.5 * 9.81 * 0.25, abs=1e-9)
    assert list(handles) == ["/World/box"]


def test_mass_api_centre_of_mass_and_inertia(tmp_path):
    path = tmp_path / "mass.usda"
    stage = new_stage(path, gravity=((0.0, 0.0, -1.0), 0.0))
    bar = collider(placed(UsdGeom.Cube.Define(stage, "/World/bar"), (0.0, 0.0, 1.0)), rigid=True, mass=3.0)
    UsdPhysics.MassAPI(bar).CreateDiagonalInertiaAttr(Gf.Vec3f(0.5, 0.25, 0.125))
    UsdPhysics.MassAPI(bar).CreateCenterOfMassAttr(Gf.Vec3f(0.25, 0.0, 0.0))
    UsdPhysics.RigidBodyAPI(bar).CreateAngularVelocityAttr(Gf.Vec3f(0.0, 0.0, 180.0))
    stage.GetRootLayer().Save()
    world, _ = tumble.World.from_usd(path)
    w = tumble.World(gravity=(0.0, 0.0, 0.0))
    # the cube (size 2) about a centre of mass 0.25 m along x from its centre; the prim's origin moves at w x r
    w.add_body(None, mass=3.0, inertia=np.diag([0.5, 0.25, 0.125]).tolist(), position=(0.25, 0.0, 1.0),
               colliders=[(tumble.Box(half_extents=(1.0, 1.0, 1.0)), (-0.25, 0.0, 0.0), (1.0, 0.0, 0.0, 0.0))],
               velocity=tuple(np.cross((0.0, 0.0, math.pi), (0.25, 0.0, 0.0))), angular_velocity=(0.0, 0.0, math.pi),
               friction=0.5, restitution=0.0)
    same_runs(world, w)


def test_joints_with_limits_and_drives_are_the_joints_built_in_python(tmp_path):
    path = tmp_path / "joints.usda"
    stage = new_stage(path)
    door = collider(placed(UsdGeom.Cube.Define(stage, "/World/door"), (0.5, 0.0, 1.0)), rigid=True, mass=1.0)
    UsdGeom.Cube(door).CreateSizeAttr(0.2)
    hinge = UsdPhysics.RevoluteJoint.Define(stage, "/World/hinge")
    hinge.CreateBody1Rel().SetTargets([door.GetPath()])
    hinge.CreateAxisAttr("Z")
    hinge.CreateLocalPos0Attr(Gf.Vec3f(0.0, 0.0, 1.0))  # the world's frame at the hinge
    hinge.CreateLocalPos1Attr(Gf.Vec3f(-0.5, 0.0, 0.0))  # in the door's local space
    hinge.CreateLowerLimitAttr(-45.0)
    hinge.CreateUpperLimitAttr(60.0)
    drive = UsdPhysics.DriveAPI.Apply(hinge.GetPrim(), "angular")
    drive.CreateTargetVelocityAttr(90.0)
    drive.CreateMaxForceAttr(10.0)
    puck = collider(placed(UsdGeom.Sphere.Define(stage, "/World/puck"), (0.0, 2.0, 1.0)), rigid=True, mass=0.5)
    UsdGeom.Sphere(puck).CreateRadiusAttr(0.1)
    rope = UsdPhysics.DistanceJoint.Define(stage, "/World/rope")
    rope.CreateBody1Rel().SetTargets([puck.GetPath()])
    rope.CreateLocalPos0Attr(Gf.Vec3f(0.0, 2.0, 1.0))
    rope.CreateMaxDistanceAttr(0.5)
    stage.GetRootLayer().Save()
    world, handles = tumble.World.from_usd(path)
    w = tumble.World()
    d = w.add_body(tumble.Box(half_extents=(0.1, 0.1, 0.1)), mass=1.0, position=(0.5, 0.0, 1.0), friction=0.5,
                   restitution=0.0)
    p = w.add_body(tumble.Sphere(radius=0.1), mass=0.5, position=(0.0, 2.0, 1.0), friction=0.5, restitution=0.0)
    w.add_joint(tumble.Hinge(None, d, world_point=(0.0, 0.0, 1.0), anchor_b=(-0.5, 0.0, 0.0), axis=(0.0, 0.0, 1.0),
                             limits=(math.radians(-45.0), math.radians(60.0)),
                             motor=tumble.Motor(speed=math.radians(90.0), max_torque=10.0)))
    w.add_joint(tumble.Distance(None, p, world_point=(0.0, 2.0, 1.0), anchor_b=(0.0, 0.0, 0.0), length=0.5,
                                rope=True))
    run = same_runs(world, w, duration=1.0)
    # the motor turns the door at 90 degrees a second until its 60 degree limit
    q = run.body_orientations[-1, 0]
    assert 2 * math.atan2(q[3], q[0]) == pytest.approx(math.radians(60.0), abs=1e-3)


def test_a_kinematic_body_follows_its_animation(tmp_path):
    path = tmp_path / "kinematic.usda"
    stage = new_stage(path)
    stage.SetTimeCodesPerSecond(24.0)
    paddle = collider(UsdGeom.Cube.Define(stage, "/World/paddle").GetPrim(), rigid=True)
    UsdPhysics.RigidBodyAPI(paddle).CreateKinematicEnabledAttr(True)
    op = UsdGeom.Xformable(paddle).AddTranslateOp(DOUBLE)
    for code, x in ((0.0, -1.0), (24.0, 1.0), (48.0, 1.0)):
        op.Set(Gf.Vec3d(x, 0.0, 1.0), Usd.TimeCode(code))
    stage.GetRootLayer().Save()
    world, handles = tumble.World.from_usd(path, mode="fast", dt=1 / 240)
    assert world.bodies.kinematic == [True]
    run = world.run(2.0, frame_interval=0.125)
    x = run.body_positions[:, 0, 0]
    assert np.abs(x - np.clip(-1.0 + 2.0 * run.times, -1.0, 1.0)).max() < 1e-9


def test_a_run_writes_back_onto_the_stages_own_prims(tmp_path):
    # a box under a moved, turned and scaled parent: the layer over the stage holds each frame local to the parent
    source = tmp_path / "source.usda"
    stage = new_stage(source)
    stage.SetTimeCodesPerSecond(30.0)
    collider(placed(UsdGeom.Cube.Define(stage, "/World/ground"), (0.0, 0.0, -1.0)))
    parent = placed(UsdGeom.Xform.Define(stage, "/World/rig"), (1.0, 2.0, 0.5),
                    (math.cos(0.3), 0.0, 0.0, math.sin(0.3)), (2.0, 2.0, 2.0))
    box = collider(placed(UsdGeom.Cube.Define(stage, "/World/rig/box"), (0.0, 0.0, 1.0)), rigid=True)
    UsdGeom.Cube(box).CreateSizeAttr(0.2)
    UsdPhysics.RigidBodyAPI(box).CreateVelocityAttr(Gf.Vec3f(1.0, 0.0, 0.0))
    stage.GetRootLayer().Save()
    assert parent.IsValid()
    world, handles = tumble.World.from_usd(source)
    run = world.run(1.0, frame_interval=1 / 30)
    out = run.export_usd(tmp_path / "over.usda", over=source)
    layered = Usd.Stage.Open(str(out))
    layer = layered.GetRootLayer()
    assert list(layer.subLayerPaths) == ["source.usda"]
    # only overrides: no prim is defined anew, and the body's samples are on its own prim
    assert all(spec.specifier == Sdf.SpecifierOver for spec in layer.rootPrims)
    prim = layered.GetPrimAtPath("/World/rig/box")
    b = run.bodies.index(handles["/World/rig/box"])
    for frame in (0, 12, len(run.times) - 1):
        m = UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(Usd.TimeCode(30.0 * run.times[frame]))
        assert np.allclose(np.array(m.ExtractTranslation()), run.body_positions[frame, b], rtol=0, atol=1e-12)
        q = m.RemoveScaleShear().ExtractRotationQuat()  # (the parent's scale out first)
        theirs = np.array([q.GetReal(), *q.GetImaginary()])
        mine = run.body_orientations[frame, b]
        assert min(np.abs(theirs - mine).max(), np.abs(theirs + mine).max()) < 1e-9
        # the parent's scale of 2 kept: the box is still 0.4 m wide in the world
        assert np.linalg.norm(np.array(m.GetRow3(0))) == pytest.approx(2.0, rel=1e-12)


def _refused(tmp_path, build):
    path = tmp_path / "bad.usda"
    stage = new_stage(path)
    build(stage)
    stage.GetRootLayer().Save()
    with pytest.raises(tumble.UsdSceneError) as caught:
        tumble.World.from_usd(path)
    return caught.value.problems


def _body(stage, name="/World/box", kind=UsdGeom.Cube):
    return collider(placed(kind.Define(stage, name), (0.0, 0.0, 1.0)), rigid=True)


def _generic_joint(stage):
    UsdPhysics.Joint.Define(stage, "/World/d6").CreateBody1Rel().SetTargets([_body(stage).GetPath()])


def _to_world(stage, schema, path):
    """A joint of ``schema`` at ``path`` from the world to a box at (0, 0, 1), its frames together."""
    j = schema.Define(stage, path)
    j.CreateBody1Rel().SetTargets([_body(stage).GetPath()])
    j.CreateLocalPos0Attr(Gf.Vec3f(0.0, 0.0, 1.0))
    return j


def _breakable(stage):
    _to_world(stage, UsdPhysics.FixedJoint, "/World/weld").CreateBreakForceAttr(-1.0)


def _cone_limit(stage):
    _to_world(stage, UsdPhysics.SphericalJoint, "/World/ball").CreateConeAngle0LimitAttr(30.0)


def _frames_apart(stage):
    j = UsdPhysics.FixedJoint.Define(stage, "/World/weld")
    j.CreateBody1Rel().SetTargets([_body(stage).GetPath()])


def _acceleration_drive(stage):
    j = _to_world(stage, UsdPhysics.RevoluteJoint, "/World/hinge")
    UsdPhysics.DriveAPI.Apply(j.GetPrim(), "angular").CreateTypeAttr("acceleration")


def _uneven_sphere(stage):
    s = _body(stage, "/World/ball", UsdGeom.Sphere)
    UsdGeom.Xformable(s).AddScaleOp(DOUBLE).Set(Gf.Vec3d(1.0, 2.0, 1.0))


def _approximation(value, rigid, name="/World/mesh"):
    def build(stage):
        mesh = UsdGeom.Mesh.Define(stage, name)
        mesh.CreatePointsAttr([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)])
        mesh.CreateFaceVertexCountsAttr([3, 3, 3, 3])
        mesh.CreateFaceVertexIndicesAttr([0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3])
        collider(mesh.GetPrim(), rigid=rigid)
        UsdPhysics.MeshCollisionAPI.Apply(mesh.GetPrim()).CreateApproximationAttr(value)
    return build


def _group(stage):
    _body(stage)
    UsdPhysics.CollisionGroup.Define(stage, "/World/group")


def _no_collider(stage):
    UsdPhysics.RigidBodyAPI.Apply(UsdGeom.Xform.Define(stage, "/World/empty").GetPrim())


@pytest.mark.parametrize("build, prim, attribute", [
    (_generic_joint, "/World/d6", "PhysicsJoint"),
    (_breakable, "/World/weld", "breaking"),
    (_cone_limit, "/World/ball", "physics:coneAngle0Limit"),
    (_frames_apart, "/World/weld", "physics:localPos1"),
    (_acceleration_drive, "/World/hinge", "physics:type"),
    (_uneven_sphere, "/World/ball", "xformOp:scale"),
    (_approximation("meshSimplification", True), "/World/mesh", "physics:approximation"),
    (_approximation("none", True), "/World/mesh", "physics:approximation"),
    (_group, "/World/group", "PhysicsCollisionGroup"),
    (_no_collider, "/World/empty", "RigidBodyAPI"),
])
def test_each_unsupported_or_bad_attribute_is_refused_naming_prim_and_attribute(tmp_path, build, prim, attribute):
    problems = _refused(tmp_path, build)
    assert any(p.startswith(prim + ":") and attribute in p for p in problems), problems


def _two_frictions(stage):
    m = physics_material(stage, "/Materials/m", 0.5, 0.0)
    UsdPhysics.MaterialAPI(m.GetPrim()).CreateStaticFrictionAttr(0.7)
    bind(_body(stage), m)


def _cone(stage):
    _body(stage, "/World/cone", UsdGeom.Cone)


@pytest.mark.parametrize("build, prim, attribute, said", [
    (_two_frictions, "/Materials/m", "physics:staticFriction", ["0.7 differs from", "dynamicFriction 0.5"]),
    (_cone, "/World/cone", "Cone", ["64-sided"]),
])
def test_each_approximation_is_a_warning_naming_prim_attribute_and_values(tmp_path, build, prim, attribute, said):
    path = tmp_path / "approximated.usda"
    stage = new_stage(path)
    build(stage)
    stage.GetRootLayer().Save()
    with pytest.warns(UserWarning) as caught:
        world, _ = tumble.World.from_usd(path)
    notes = [str(w.message) for w in caught]
    assert any(n.startswith(prim + ":") and attribute in n and all(s in n for s in said) for n in notes), notes
    # the values as typed into the stage: float32's 0.699999988079071 is shown as the 0.7 it was written as
    assert not any("0.6999" in n for n in notes), notes
    # tumble's one friction coefficient is the dynamic one (the material's, else PhysX's default 0.5)
    assert [b["friction"] for b in json.loads(world.to_json(memory=False))["bodies"]] == [0.5]


def test_float32_values_come_in_as_typed(tmp_path):
    """USD stores these attributes as float32: 0.7 is 0.699999988079071. Each is read as the shortest decimal that
    is the same float32, which is what was typed (any decimal of up to 6 significant digits comes back
    as itself), so the world's friction is 0.7 itself."""
    path = tmp_path / "typed.usda"
    stage = new_stage(path)
    box = _body(stage)
    UsdPhysics.MassAPI.Apply(box).CreateMassAttr(0.3)
    UsdPhysics.RigidBodyAPI(box).CreateVelocityAttr(Gf.Vec3f(0.1, 0.0, 0.0))
    bind(box, physics_material(stage, "/Materials/m", 0.7, 0.3))
    stage.GetRootLayer().Save()
    world, _ = tumble.World.from_usd(path)
    body = json.loads(world.to_json(memory=False))["bodies"][0]
    # exactly: the decimals as typed, not their float32 neighbours
    assert (body["friction"], body["restitution"], body["mass"]) == (0.7, 0.3, 0.3)
    assert world.bodies.velocities[0, 0] == 0.1
    # and so in a refusal's message: a distance joint from 0.3 to 0.7 (a rod or a rope only)
    rope = UsdPhysics.DistanceJoint.Define(stage, "/World/rope")
    rope.CreateBody1Rel().SetTargets([box.GetPath()])
    rope.CreateMinDistanceAttr(0.3)
    rope.CreateMaxDistanceAttr(0.7)
    stage.GetRootLayer().Save()
    with pytest.raises(tumble.UsdSceneError, match=r"/World/rope: physics:minDistance: .*\(0\.3 to 0\.7 m given\)"):
        tumble.World.from_usd(path)


def test_a_static_exact_mesh_and_a_hull_are_taken(tmp_path):
    path = tmp_path / "meshes.usda"
    stage = new_stage(path)
    _approximation("none", False, "/World/tetrahedron")(stage)  # static: its exact triangles
    _approximation("convexHull", True, "/World/hull")(stage)
    placed(UsdGeom.Mesh(stage.GetPrimAtPath("/World/hull")), (0.0, 0.0, 3.0))
    stage.GetRootLayer().Save()
    world, handles = tumble.World.from_usd(path)
    assert list(handles) == ["/World/tetrahedron", "/World/hull"]
    assert world.bodies.kinematic == [False, False]
    run = world.run(1.0, frame_interval=0.5)
    assert run.body_positions[-1, 1, 2] < 3.0 - 1.0, "the hull fell onto the tetrahedron's face or past it"


def test_a_run_writes_back_in_the_stages_own_units_and_axes(tmp_path):
    # a centimetre, y-up stage: a box 100 cm up falls; the samples over its prim are in centimetres, y up
    source = tmp_path / "cm.usda"
    stage = new_stage(source, up="Y", metres=0.01)
    box = collider(placed(UsdGeom.Cube.Define(stage, "/World/box"), (30.0, 100.0, 40.0)), rigid=True)
    UsdGeom.Cube(box).CreateSizeAttr(20.0)
    stage.GetRootLayer().Save()
    world, handles = tumble.World.from_usd(source)
    run = world.run(0.4, frame_interval=0.1)
    layered = Usd.Stage.Open(str(run.export_usd(tmp_path / "over.usda", over=source)))
    assert UsdGeom.GetStageUpAxis(layered) == UsdGeom.Tokens.y and UsdGeom.GetStageMetersPerUnit(layered) == 0.01
    prim = layered.GetPrimAtPath("/World/box")
    b = run.bodies.index(handles["/World/box"])
    for frame in range(len(run.times)):
        m = UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(Usd.TimeCode(24.0 * run.times[frame]))
        x, y, z = run.body_positions[frame, b]  # tumble's metres, z up: the stage's (x, z, -y) in centimetres
        assert np.allclose(np.array(m.ExtractTranslation()), (100 * x, 100 * z, -100 * y), rtol=0, atol=1e-9)
    # it fell 0.5 g t^2 = 0.785 m by 0.4 s: 78.5 cm down the stage's y
    assert np.array(UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(Usd.TimeCode(9.6)).ExtractTranslation())[1] \
        == pytest.approx(100.0 - 100 * 0.5 * 9.81 * 0.16, abs=1e-6)


def test_the_round_trip_leaves_a_kinematic_prims_animation_alone(tmp_path):
    source = tmp_path / "paddle.usda"
    stage = new_stage(source)
    paddle = collider(UsdGeom.Cube.Define(stage, "/World/paddle").GetPrim(), rigid=True)
    UsdPhysics.RigidBodyAPI(paddle).CreateKinematicEnabledAttr(True)
    op = UsdGeom.Xformable(paddle).AddTranslateOp(DOUBLE)
    for code, x in ((0.0, -1.0), (24.0, 1.0)):
        op.Set(Gf.Vec3d(x, 0.0, 3.0), Usd.TimeCode(code))
    ball = collider(placed(UsdGeom.Sphere.Define(stage, "/World/ball"), (0.0, 2.0, 1.0)), rigid=True)
    UsdGeom.Sphere(ball).CreateRadiusAttr(0.1)
    stage.GetRootLayer().Save()
    world, _ = tumble.World.from_usd(source, mode="fast", dt=1 / 240)
    out = world.run(0.5, frame_interval=0.1).export_usd(tmp_path / "over.usda", over=source)
    layer = Sdf.Layer.FindOrOpen(str(out))
    assert layer.GetPrimAtPath("/World/ball") is not None
    assert layer.GetPrimAtPath("/World/paddle") is None, "the paddle's own animation is not overridden"


def test_break_force_and_torque_are_the_joints_breaking_bounds(tmp_path):
    """A 2 kg box welded to the world with physics:breakForce 10 (below its 19.6 N weight) on a centimetre stage:
    the joint breaks at 10 N (1000 kg cm/s^2 read as 10 N) as the same weld built in Python does, and the box
    falls; a breakTorque alone bounds the torque."""
    path = tmp_path / "breaks.usda"
    stage = new_stage(path, metres=0.01)
    box = collider(placed(UsdGeom.Cube.Define(stage, "/World/box"), (0.0, 0.0, 100.0)), rigid=True, mass=2.0)
    weld = UsdPhysics.FixedJoint.Define(stage, "/World/weld")
    weld.CreateBody1Rel().SetTargets([box.GetPath()])
    weld.CreateLocalPos0Attr(Gf.Vec3f(0.0, 0.0, 100.0))
    weld.CreateBreakForceAttr(1000.0)
    stage.Save()
    world, handles = tumble.World.from_usd(path)
    run = world.run(0.5, frame_interval=0.05)
    assert len(run.joint_breaks) == 1 and world.broken_joints() == run.joint_breaks
    assert run.body_positions[-1, 0, 2] < 1.0 - 0.5, "the box fell"
    w = tumble.World()
    b = w.add_body(tumble.Box(half_extents=(0.01, 0.01, 0.01)), mass=2.0, position=(0.0, 0.0, 1.0))
    w.add_joint(tumble.Weld(None, b, world_point=(0.0, 0.0, 1.0), breaking=tumble.Breaking(force=10.0)))
    want = w.run(0.5, frame_interval=0.05)
    np.testing.assert_allclose(run.joint_break_times, want.joint_break_times, rtol=0, atol=1e-12)
    weld.GetBreakForceAttr().Clear()
    weld.CreateBreakTorqueAttr(5e5)
    stage.Save()
    world, _ = tumble.World.from_usd(path)
    assert world.run(0.5, frame_interval=0.05).joint_breaks == [], "its torque stays below 50 N m"


def test_a_joint_with_collisions_enabled_lets_its_bodies_collide(tmp_path):
    """A cube (a UsdGeom Cube, of size 2, scaled) tied to a slab below it by a slack distance joint (a rope of 1 m),
    dropped from 0.5 m above it: with physics:collisionEnabled it lands on the slab; without, it falls through the
    slab to the ground."""
    heights = []
    for enabled in (True, False):
        path = tmp_path / f"tied_{enabled}.usda"
        stage = new_stage(path)
        collider(placed(UsdGeom.Cube.Define(stage, "/World/ground"), (0.0, 0.0, -0.5), scale=(10.0, 10.0, 0.5)))
        slab = collider(placed(UsdGeom.Cube.Define(stage, "/World/slab"), (0.0, 0.0, 0.1), scale=(0.5, 0.5, 0.1)),
                        rigid=True, mass=100.0)
        cube = collider(placed(UsdGeom.Cube.Define(stage, "/World/cube"), (0.0, 0.0, 0.8), scale=(0.1, 0.1, 0.1)),
                        rigid=True, mass=4.0)
        rope = UsdPhysics.DistanceJoint.Define(stage, "/World/rope")
        rope.CreateBody0Rel().SetTargets([slab.GetPath()])
        rope.CreateBody1Rel().SetTargets([cube.GetPath()])
        rope.CreateMaxDistanceAttr(1.0)
        rope.CreateCollisionEnabledAttr(enabled)
        stage.Save()
        world, handles = tumble.World.from_usd(path)
        world.run(1.5, frame_interval=0.1)
        heights.append(world.bodies.positions[world.bodies.row(handles["/World/cube"])][2])
    # on the slab's top (0.2 m) at its half height, within the contact tolerance; or on the ground
    assert abs(heights[0] - 0.3) < 1e-3 and abs(heights[1] - 0.1) < 1e-3, heights
