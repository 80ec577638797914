"""A run read by handles: ``positions_of``, ``orientations_of``, ``velocities_of`` and ``angular_velocities_of``
give a body's (or a particle's) frames whatever its row, the ground's included; a handle the run does not hold is a
ValueError naming the argument; a run read back by ``Run.load`` answers the same handles."""

import math

import numpy as np
import pytest

import tumble

G = 9.81


def dropped_die():
    """The first script's scene: the ground added first (body row 0), then a tilted die above it."""
    w = tumble.World(mode="fast", dt=1 / 240, gravity=(0.0, 0.0, -G))
    ground = w.add_ground()
    tilt = (math.cos(0.3), math.sin(0.3), 0.0, 0.0)  # 0.6 rad about x
    die = w.add_body(tumble.Box(half_extents=(0.05, 0.05, 0.05)), density=1000.0, position=(0.0, 0.0, 0.3),
                     orientation=tilt, angular_velocity=(0.0, 2.0, 0.0))
    return w, ground, die


def test_a_body_is_read_by_its_handle_not_by_its_row():
    w, ground, die = dropped_die()
    run = w.run(1.0, 1 / 60)
    assert w.bodies.row(ground) == 0 and w.bodies.row(die) == 1
    positions, orientations = run.positions_of(die), run.orientations_of(die)
    assert positions.shape == (run.frames, 3) and orientations.shape == (run.frames, 4)
    np.testing.assert_array_equal(positions, run.body_positions[:, 1])
    np.testing.assert_array_equal(orientations, run.body_orientations[:, 1])
    np.testing.assert_array_equal(run.velocities_of(die), run.body_velocities[:, 1])
    np.testing.assert_array_equal(run.angular_velocities_of(die), run.body_angular_velocities[:, 1])
    # the ground is a body of the run too, at rest, unrotated
    np.testing.assert_array_equal(run.orientations_of(ground), np.tile([1.0, 0.0, 0.0, 0.0], (run.frames, 1)))
    assert not np.array_equal(run.orientations_of(die)[-1], run.orientations_of(ground)[-1])
    # a copy: writing to it leaves the run as it was
    positions[:] = 0.0
    assert run.body_positions[-1, 1, 2] > 0.0


def test_orientations_are_scalar_first_and_angular_velocities_in_world_axes():
    """A free cube spinning about z (a principal axis: the spin stays constant) turns by w t: its quaternion is
    (cos(w t / 2), 0, 0, sin(w t / 2)), scalar first."""
    w = tumble.World(gravity=(0.0, 0.0, 0.0), integrator="dopri5", rtol=1e-10, atol=1e-12)
    other = w.add_body(tumble.Sphere(radius=0.1), density=1000.0, position=(5.0, 0.0, 0.0))
    spin = 1.5
    cube = w.add_body(tumble.Box(half_extents=(0.1, 0.1, 0.1)), density=1000.0, position=(0.0, 0.0, 1.0),
                      velocity=(0.5, 0.0, 0.0), angular_velocity=(0.0, 0.0, spin))
    run = w.run(2.0, 0.1)
    t = run.times
    half = spin * t / 2
    want = np.stack([np.cos(half), 0 * t, 0 * t, np.sin(half)], axis=1)
    # the integrator's tolerances (rtol 1e-10 over 2 s of steps) and the quaternion's renormalisation
    np.testing.assert_allclose(run.orientations_of(cube), want, atol=1e-8)
    np.testing.assert_allclose(run.angular_velocities_of(cube), np.tile([0.0, 0.0, spin], (len(t), 1)), atol=1e-8)
    # uniform motion along x: the same tolerances
    np.testing.assert_allclose(run.positions_of(cube)[:, 0], 0.5 * t, atol=1e-8)
    np.testing.assert_allclose(run.velocities_of(cube), np.tile([0.5, 0.0, 0.0], (len(t), 1)), atol=1e-8)
    np.testing.assert_array_equal(run.positions_of(other), np.tile([5.0, 0.0, 0.0], (len(t), 1)))


def test_a_particle_is_read_by_its_handle():
    w = tumble.World(gravity=(0.0, 0.0, -G), integrator="dopri5", rtol=1e-10, atol=1e-12)
    w.add_particle(mass=1.0, position=(9.0, 9.0, 9.0))
    p = w.add_particle(mass=1.0, position=(0.0, 0.0, 10.0), velocity=(1.0, 0.0, 2.0))
    body = w.add_body(tumble.Sphere(radius=0.1), density=1000.0, position=(3.0, 0.0, 0.0))
    run = w.run(1.0, 0.05)
    t = run.times[:, None]
    # free fall in closed form; a polynomial of degree 2, which dopri5 integrates to rounding
    np.testing.assert_allclose(run.positions_of(p), [0.0, 0.0, 10.0] + t * [1.0, 0.0, 2.0] - 0.5 * G * t**2 * [0, 0, 1],
                               atol=1e-10)
    np.testing.assert_allclose(run.velocities_of(p), [1.0, 0.0, 2.0] - G * t * [0, 0, 1], atol=1e-10)
    np.testing.assert_array_equal(run.positions_of(p), run.particle_positions[:, 1])
    # a body and a particle are told apart by their kind, whatever their indices
    np.testing.assert_array_equal(run.positions_of(body), run.body_positions[:, 0])


def test_a_handle_the_run_does_not_hold_is_a_value_error_naming_the_argument():
    w, ground, die = dropped_die()
    run = w.run(0.1, 1 / 60)
    later = w.add_body(tumble.Sphere(radius=0.1), density=1000.0, position=(1.0, 0.0, 1.0))
    stranger = tumble.World().add_body(tumble.Sphere(radius=0.1), density=1.0)
    for handle in (later, stranger):
        for read in (run.positions_of, run.orientations_of, run.velocities_of, run.angular_velocities_of):
            with pytest.raises(ValueError, match=r"`handle`: BodyHandle.*not one of the run's 2 bodies"):
                read(handle)
    particle = w.add_particle(mass=1.0)
    with pytest.raises(ValueError, match="`handle`.*not one of the run's 0 particles"):
        run.positions_of(particle)
    # what is no handle, and a particle where only bodies have the quantity, are type errors naming it
    with pytest.raises(TypeError, match="`handle`: expected a BodyHandle or a ParticleHandle, got 1"):
        run.positions_of(1)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="`handle`: expected a BodyHandle"):
        run.orientations_of(particle)  # type: ignore[arg-type]


def test_a_loaded_run_answers_the_same_handles(tmp_path):
    w, ground, die = dropped_die()
    p = w.add_particle(mass=1.0, position=(1.0, 0.0, 1.0))
    run = w.run(0.5, 1 / 60)
    loaded = tumble.Run.load(run.save(tmp_path / "die.npz"))
    for read in ("positions_of", "orientations_of", "velocities_of", "angular_velocities_of"):
        np.testing.assert_array_equal(getattr(loaded, read)(die), getattr(run, read)(die))
    np.testing.assert_array_equal(loaded.positions_of(p), run.positions_of(p))
    np.testing.assert_array_equal(loaded.velocities_of(p), run.velocities_of(p))
    with pytest.raises(ValueError, match="`handle`"):
        loaded.positions_of(tumble.World().add_body(tumble.Sphere(radius=0.1), density=1.0))
