"""Contact from Python: both modes on closed forms, grounds, particle radii, compound colliders, the contact
fields of reports and runs, the built-in contact scenes, and the errors of the new arguments."""

import math

import numpy as np
import pytest

import tumble

G = 9.81


@pytest.mark.parametrize("solver", ["soft", "exact"])
def test_fast_mode_box_lands_and_sleeps(solver):
    w = tumble.World(mode="fast", dt=1 / 240, solver=solver)
    assert w.mode == "fast" and w.plan()["mode"] == "fast"
    w.add_ground(height=0.0, restitution=0.0, friction=0.5)
    w.add_body(tumble.Box(half_extents=(0.5, 0.5, 0.5)), density=1000.0, position=(0, 0, 2), restitution=0.0)
    run = w.run(2.0, 1 / 60)
    # It rests on its face: the centre 0.5 m up (to 1e-4 m: the exact solver's contact slop; the soft step's spring
    # holds a resting box about g / (2 pi 480 Hz)^2 = 1.1e-6 m deep, 8 substeps of 1/240 s), and asleep.
    assert abs(w.bodies.positions[1, 2] - 0.5) < 1e-4
    r = run.report
    assert r.collisions >= 1 and r.sleepers == 1 and r.collision_checks > 0
    assert run.penetration.shape == run.times.shape
    stage = {"soft": "contact-soft-step", "exact": "contact-cone-program"}[solver]
    assert stage in w.plan()["stages"]
    assert (r.qp_solves > 0) == (solver == "exact"), "clarabel runs for the exact solver only"
    # the soft step reports how far its steps ended from the exact contact conditions: a landing box, whose springs
    # take up its weight over a few steps, leaves some; the exact solver meets them and reports none
    assert (r.contact_residual > 0) == (solver == "soft") and r.contact_residual < 0.1


def test_fast_mode_step_doubling_reports_a_free_fall_step_error_of_g_h2_over_4n():
    # Semi-implicit Euler in n substeps: a step and its two halves differ by g h^2 / (4 n) in free fall (the Rust
    # test derives it); the estimate changes nothing in the run itself.
    h = 1 / 240
    runs = []
    for doubling in (True, False):
        w = tumble.World(mode="fast", dt=h, step_doubling=doubling, substeps=8)
        w.add_body(tumble.Box((0.1, 0.1, 0.1)), position=(0, 0, 50), velocity=(1, 0, 2))
        w.step(0.5)
        runs.append((w.report.step_error, w.bodies.positions.copy()))
    assert abs(runs[0][0] - G * h * h / 32) < 1e-13 and runs[1][0] is None
    assert np.array_equal(runs[0][1], runs[1][1])


def test_the_report_gives_a_sliding_box_energy_loss_as_its_kinetic_energy():
    # A 0.5 m box of 500 kg/m^3 (62.5 kg) sent at 3 m/s on a floor of friction 0.5 stops after 0.61 s: the energy
    # lost is m v^2 / 2 = 281.25 J. Fast mode's soft contact settles it by about 4.3e-6 m, accurate mode holds its
    # height to the 1e-6 m contact tolerance: both within m g 1e-5 m = 6e-3 J. No fast step adds energy.
    for mode in ("fast", "accurate"):
        options = {"contact_tolerance": 1e-6} if mode == "accurate" else {}
        w = tumble.World(mode=mode, **options)
        w.add_ground(restitution=0.0, friction=0.5)
        w.add_body(tumble.Box((0.25, 0.25, 0.25)), density=500.0, position=(0, 0, 0.25), velocity=(3, 0, 0),
                   restitution=0.0, friction=0.5)
        r = w.run(1.0, 0.1).report
        assert abs(r.energy_change + 281.25) < 62.5 * G * 1e-5, (mode, r.energy_change)
        if mode == "fast":
            assert 0.0 <= r.energy_gain < 62.5 * G * 1e-5
        else:
            assert r.energy_gain is None


def test_fast_mode_solver_options_name_themselves():
    with pytest.raises(ValueError, match="`solver`"):
        tumble.World(mode="fast", solver="nope")
    with pytest.raises(ValueError, match="`solver`"):
        tumble.World(solver="soft")  # accurate mode has no fast solver
    with pytest.raises(ValueError, match="`substeps`"):
        tumble.World(mode="fast", solver="exact", substeps=4)
    with pytest.raises(ValueError, match="`substeps`"):
        tumble.World(mode="fast", substeps=0)
    w = tumble.World(mode="fast", substeps=16)
    w.add_ground()
    w.add_body(tumble.Sphere(0.5), position=(0, 0, 1))
    assert "contact-soft-step" in w.plan()["stages"]
    w.set_mode("fast", solver="exact")
    assert "contact-cone-program" in w.plan()["stages"] and "contact-soft-step" not in w.plan()["stages"]


def test_accurate_mode_ball_bounces_where_and_when_the_closed_form_says():
    w = tumble.World(integrator="dopri5", rtol=1e-10, atol=1e-12)
    w.add_ground(restitution=0.8, friction=0.0)
    w.add_body(tumble.Sphere(0.1), density=1000.0, position=(0, 0, 1.1), restitution=0.8, friction=0.0)
    run = w.run(1.5, 1e-3)
    # first impact at sqrt(2 h / g) to the bisection tolerance (1e-10 s)
    assert abs(run.contact_events[0] - math.sqrt(2 / G)) < 1e-9
    # apex of the first flight from a frame inside it (ballistic): 0.8^2 m to 1e-6
    f = int(round((math.sqrt(2 / G) + 0.3) / 1e-3))
    z, vz = run.body_positions[f, 1, 2], run.body_velocities[f, 1, 2]
    assert abs(z - 0.1 + vz * vz / (2 * G) - 0.64) < 1e-6
    assert run.report.qp_solves == 0, "a lone bouncing ball needs no QP"
    assert {"collision-detection", "bisection", "impulses", "contact-cone-program"} <= set(w.plan()["stages"])


def test_particles_with_a_radius_land_on_the_ground_and_without_one_fall_through():
    w = tumble.World(mode="fast", dt=1 / 240)
    w.add_ground()
    w.add_particle(position=(0, 0, 1), radius=0.05, restitution=0.0)
    w.add_particle(position=(1, 0, 1))
    w.run(1.5, 0.5)
    z = w.particles.positions[:, 2]
    assert abs(z[0] - 0.05) < 1e-4 and z[1] < -1.0


def test_compound_colliders_add_their_mass_and_all_reach_the_gltf(tmp_path):
    w = tumble.World()
    r, d = 0.2, 1000.0
    b = w.add_body(tumble.Sphere(r), density=d, colliders=[(tumble.Sphere(r), (1.0, 0.0, 0.0))])
    # two balls 1 m apart: twice the mass, centre of mass halfway (so the body sits at the first ball + 0.5 m)
    one = 4 / 3 * math.pi * r**3 * d
    run = w.run(0.1, 0.05)
    assert len(run.shapes[0]) == 2
    offsets = sorted(o[0] for _, o, _ in run.shapes[0])
    assert np.allclose(offsets, [-0.5, 0.5])
    path = run.export_gltf(tmp_path / "dumbbell.glb")
    import pygltflib  # noqa: PLC0415

    gltf = pygltflib.GLTF2().load(str(path))
    mesh_vertices = gltf.accessors[gltf.meshes[gltf.nodes[1].mesh].primitives[0].attributes.POSITION]
    # a ball tessellated with 24 segments reaches r cos(pi / 24) along x
    assert mesh_vertices.max[0] - mesh_vertices.min[0] > 1.0 + 2 * r * math.cos(math.pi / 24) - 1e-6, "both balls"
    assert b is not None and one > 0


def test_report_and_run_carry_the_contact_fields():
    w = tumble.scenes.dominoes(count=3)
    run = w.run(1.0, 1 / 30)
    fields = run.report.as_dict()
    for key in ("qp_solves", "collisions", "impulses", "bisection_steps", "collision_checks", "islands", "sleepers",
                "max_penetration", "contact_residual", "collision_seconds", "contact_seconds",
                "program_seconds"):
        assert key in fields
    assert "narrow-phase pair tests" in str(run.report)
    assert run.contact_events.shape == (0,), "fast mode has no events"


@pytest.mark.parametrize(
    "build",
    [
        lambda: tumble.scenes.bouncing_ball(),
        lambda: tumble.scenes.tumbling_box(),
        lambda: tumble.scenes.dominoes(count=4),
        lambda: tumble.scenes.pyramid(layers=3),
        lambda: tumble.scenes.cloth_drape(n=4),
    ],
)
def test_contact_scenes_run(build):
    w = build()
    run = w.run(1.5, 0.05)
    assert np.all(np.isfinite(run.energy)) and run.report.collision_checks > 0


def test_bad_contact_arguments_name_themselves():
    w = tumble.World()
    cases = [
        (lambda: tumble.World(mode="fast", dt=-1.0), "`dt`"),
        (lambda: w.set_mode("sideways"), "`mode`"),
        (lambda: w.add_ground(height=float("nan")), "`height`"),
        (lambda: w.add_ground(restitution=1.5), "`restitution`"),
        (lambda: w.add_particle(radius=-1.0), "`radius`"),
        (lambda: w.add_particle(friction=-0.1), "`friction`"),
        (lambda: w.add_body(tumble.Sphere(1.0), colliders=[(tumble.Sphere(1.0),)]), "`colliders`"),
        (lambda: w.add_body(tumble.Sphere(1.0), colliders=[(tumble.Sphere(1.0), (0, 0, float("inf")))]), "`colliders`"),
        (lambda: tumble.scenes.dominoes(count=0), "`count`"),
    ]
    for call, name in cases:
        with pytest.raises(ValueError, match=name):
            call()


def test_accurate_mode_has_coulomb_friction_under_error_control():
    # A 0.5 m cube thrown at 2 m/s on a floor with mu = 0.5 stops after v^2 / (2 mu g); at a contact tolerance of
    # 1e-6 m the Rust test measures 1.1e-8 relative, so 1e-6 here leaves room for nothing but a real regression.
    w = tumble.World(contact_tolerance=1e-6)
    w.add_ground(restitution=0.0, friction=0.5)
    box = w.add_body(tumble.Box((0.25, 0.25, 0.25)), position=(0, 0, 0.25), velocity=(2, 0, 0),
                     restitution=0.0, friction=0.5)
    run = w.run(0.6, 0.1)
    exact = 2.0**2 / (2 * 0.5 * 9.81)
    assert abs(run.body_positions[-1, box.index, 0] - exact) < 1e-6 * exact
    assert run.report.contact_steps > 0 and run.report.contact_error <= 1e-6
    with pytest.raises(ValueError, match="`contact_tolerance`"):
        tumble.World(mode="fast", contact_tolerance=1e-6)
    with pytest.raises(ValueError, match="`contact_tolerance`"):
        tumble.World(contact_tolerance=-1.0)


def test_the_benchmark_scenes_meet_their_closed_forms_in_accurate_mode():
    # The slide stops at v^2 / (2 mu g) and the sphere rolls (5/7) g sin t^2 / 2 in 1 s; at the default contact
    # tolerance (1e-6 of the scene's size) both were measured within 1e-11 m, bound 1e-6 m (about the tolerance).
    # (body 0 is the static ground, body 1 the scene's)
    slide = tumble.scenes.benchmark("slide")
    slide.step(1.0)
    assert abs(slide.bodies.positions[1, 0] - 2.0 ** 2 / (2 * 0.5 * G)) < 1e-6
    roll = tumble.scenes.benchmark("roll")
    roll.step(1.0)
    assert abs(roll.bodies.positions[1, 0] - 5 / 7 * G * math.sin(math.radians(30)) / 2) < 1e-6
    # the incline at 20 degrees sticks (tan 20 < 0.5)
    stick = tumble.scenes.benchmark("incline", degrees=20.0)
    stick.step(2.0)
    assert abs(stick.bodies.positions[1, 0]) < 1e-9
    with pytest.raises(ValueError, match="name"):
        tumble.scenes.benchmark("pyramid")
    with pytest.raises(ValueError, match="degrees"):
        tumble.scenes.benchmark("incline", degrees=95.0)
