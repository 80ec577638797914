"""Regression tests for what a hostile user broke from Python (issue 11), each named after what broke: a failed or
refused call raises ValueError or tumble.SimulationError naming what was wrong and leaves the world as it was."""

import math

import numpy as np
import pytest

import tumble


def state(w: tumble.World) -> list:
    """The world's state and time, comparable bit for bit (NaN-safe via bytes)."""
    b, p = w.bodies, w.particles
    arrays = (b.positions, b.orientations, b.velocities, b.angular_velocities, p.positions, p.velocities)
    return [a.tobytes() for a in arrays] + [np.float64(w.time).tobytes()]


def test_trimesh_with_bad_indices_is_refused_instead_of_panicking():
    with pytest.raises(ValueError, match="`triangles`"):
        tumble.TriMesh(np.eye(3), np.array([[0, 1]]))
    with pytest.raises(ValueError, match="`triangles`"):
        tumble.TriMesh(np.eye(3), np.array([[0, 1, 2**32]], dtype=np.int64))
    with pytest.raises(ValueError, match="`triangles`"):
        tumble.TriMesh(np.eye(3), np.array([[0, 1, -1]], dtype=np.int64))
    with pytest.raises(ValueError, match="`triangles`"):
        tumble.TriMesh(np.eye(3), np.array([[0, 1, 5]]))


@pytest.mark.parametrize(
    "build, name",
    [
        (lambda: tumble.scenes.dominoes(count=math.inf), "count"),
        (lambda: tumble.scenes.pyramid(layers=math.inf), "layers"),
        (lambda: tumble.scenes.cloth_drape(n=math.inf), "n"),
        (lambda: tumble.scenes.cloth_drape(size=1e300), "size"),
        (lambda: tumble.scenes.dominoes(count=10**9), "count"),
        # the scene's own parameters are named, not the body argument they would have become
        (lambda: tumble.scenes.bouncing_ball(height=1e300), "height"),
        (lambda: tumble.scenes.cloth(size=math.nan), "size"),
        (lambda: tumble.scenes.cloth(size=10**400), "size"),
        (lambda: tumble.scenes.cloth(size={}), "size"),
        (lambda: tumble.scenes.cloth(mass=-1.0), "mass"),
        (lambda: tumble.scenes.cloth(n="3"), "n"),
        (lambda: tumble.scenes.cloth(n=2.5), "n"),
    ],
)
def test_scene_builders_refuse_infinite_or_huge_sizes_before_allocating(build, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        build()


def test_triangle_meshes_are_bounded():
    with pytest.raises(ValueError, match="`subdivisions`"):
        tumble.Sphere(0.5).triangle_mesh(subdivisions=100000)
    with pytest.raises(ValueError, match="`extent`"):
        tumble.Sphere(0.5).triangle_mesh(extent=math.nan)
    v, t = tumble.Sphere(0.5).triangle_mesh(subdivisions=8)
    assert v.shape[1] == 3 and t.shape[1] == 3 and np.isfinite(v).all()


def test_fast_mode_values_that_overflow_are_refused_where_they_enter():
    w = tumble.World(mode="fast")
    w.add_ground()
    with pytest.raises(ValueError, match="`density`"):
        w.add_body(tumble.Sphere(0.5), density=1e300)
    with pytest.raises(ValueError, match="`linear_damping`"):
        w.add_body(tumble.Sphere(0.5), linear_damping=1e300)
    with pytest.raises(ValueError, match="`mass`"):
        w.add_particle(mass=5e-324)
    with pytest.raises(ValueError, match="`velocity`"):
        w.add_body(tumble.Sphere(0.5), velocity=(1.7e308, 0, 0))
    b = w.add_body(tumble.Sphere(0.5), position=(0, 0, 1))
    with pytest.raises(ValueError, match="`velocity`"):
        w.set_body_state(b, velocity=(1.7e308, 1.7e308, 1.7e308))
    with pytest.raises(ValueError, match="`torque`"):
        w.add_torque(b, (1e308, 0, 0))
    with pytest.raises(ValueError, match="`gravity`"):
        tumble.World(gravity=(0, 0, -1e300))


def test_a_nan_force_callback_in_fast_mode_is_a_simulation_error():
    w = tumble.World(mode="fast")
    w.add_ground()
    b = w.add_body(tumble.Box((0.5, 0.5, 0.5)), position=(0, 0, 0.6))
    w.add_force_callback(b, lambda t, x, v: (math.nan, 0.0, 0.0))
    before = state(w)
    with pytest.raises(tumble.SimulationError):
        w.step(0.1)
    assert state(w) == before


def test_time_and_steps_are_bounded():
    w = tumble.World()
    w.add_particle()
    with pytest.raises(ValueError, match="`dt`"):
        w.step(1e300)
    assert w.time == 0.0
    f = tumble.World(mode="fast")
    f.add_particle()
    with pytest.raises(ValueError, match="`dt`"):
        f.step(1e300)
    slow = tumble.World(mode="fast", dt=1e-300)
    slow.add_particle()
    with pytest.raises(ValueError, match="`dt`"):
        slow.step(1 / 60)


def test_unclear_errors_now_name_the_argument():
    with pytest.raises(ValueError, match="`integrator`"):
        tumble.World(mode="fast", integrator="nope", rtol=math.nan)
    with pytest.raises(ValueError, match="`rtol`"):
        tumble.World(rtol=math.nan)
    a, b = tumble.World(), tumble.World()
    pa = a.add_particle()
    pb = b.add_particle(mass=2.0)
    assert (pa.index, pa.generation) == (pb.index, pb.generation)
    with pytest.raises(ValueError, match="not \\(or no longer\\) in this world"):
        a.remove(pb)
    s = a.add_spring(pa, None, stiffness=10.0, world_point=(0, 0, 1))
    a.remove(s)
    with pytest.raises(ValueError, match="`handle`"):
        a.remove(s)
    assert len(a.particles) == 1


@pytest.mark.parametrize("value", [None, 1.5, "2", 2**64, -1, True])
def test_threads_of_the_wrong_type_or_range_name_the_argument(value):
    w = tumble.World()
    with pytest.raises(ValueError, match="`threads`"):
        w.threads = value
    assert w.threads == 0


def test_handles_are_named_as_the_api_names_them():
    a, b = tumble.World(), tumble.World()
    body = b.add_body(tumble.Sphere(0.1))
    with pytest.raises(ValueError, match="BodyHandle") as e:
        a.remove(body)
    assert "RigidBody" not in str(e.value)


def test_a_failed_run_gives_back_its_frames_on_the_exception():
    # RK4 at 0.01 s; the callback raises from t = 0.5 s: the frames every 0.1 s up to 0.5 s ride on the error, and
    # the world is back at t = 0.
    w = tumble.World(integrator="rk4", dt=0.01)
    p = w.add_particle()

    def push(t, x, v):
        if t > 0.5:
            raise RuntimeError("gave up")
        return (0.0, 0.0, 0.0)

    w.add_force_callback(p, push)
    with pytest.raises(tumble.SimulationError) as e:
        w.run(1.0, 0.1)
    assert w.time == 0.0
    run = e.value.run
    assert len(run.times) == 6 and run.times[-1] == pytest.approx(0.5, abs=1e-12)
    np.testing.assert_allclose(run.particle_positions[:, 0, 2], -0.5 * 9.81 * run.times**2, atol=1e-9)
