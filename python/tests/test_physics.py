"""The physics from Python against closed forms (the same checks the Rust tests make)."""

import numpy as np
import pytest

import tumble
from conftest import damped

G = np.array([0.0, 0.0, -9.81])


@pytest.mark.parametrize("settings", [dict(integrator="rk4", dt=0.01), dict(integrator="dopri5", rtol=1e-8, atol=1e-10)])
def test_projectile(settings):
    # Quadratic in t: RK4 and Dormand-Prince are exact up to round-off (1e-10 over 121 frames).
    w = tumble.World(**settings)
    x0, v0 = np.array([0.0, 1.0, 2.0]), np.array([3.0, -1.0, 7.0])
    w.add_particle(mass=0.3, position=x0, velocity=v0)
    run = w.run(2.0, 1 / 60)
    t = run.times[:, None]
    np.testing.assert_allclose(run.particle_positions[:, 0], x0 + v0 * t + 0.5 * G * t**2, atol=1e-10, rtol=0)
    np.testing.assert_allclose(run.particle_velocities[:, 0], v0 + G * t, atol=1e-10, rtol=0)
    np.testing.assert_allclose(w.particles.positions[0], x0 + v0 * 2.0 + 0.5 * G * 4.0, atol=1e-10, rtol=0)


@pytest.mark.parametrize("damping", [0.8, 4.0, 10.0], ids=["under", "critical", "over"])
def test_damped_particle(damping):
    # No gravity, mass 1, h = 4: Dormand-Prince at 1e-11 follows the closed form to 1e-8.
    w = tumble.World(gravity=(0, 0, 0), integrator="dopri5", rtol=1e-11, atol=1e-11)
    x0, v0 = (1.0, -0.5, 0.25), (0.0, 2.0, -1.0)
    w.add_particle(mass=1.0, position=x0, velocity=v0, damping=damping, stiffness=4.0)
    run = w.run(5.0, 0.05)
    for f, t in enumerate(run.times):
        for k in range(3):
            x, v = damped(t, x0[k], v0[k], 1.0, damping, 4.0)
            assert abs(run.particle_positions[f, 0, k] - x) < 1e-8
            assert abs(run.particle_velocities[f, 0, k] - v) < 1e-8


def test_torque_free_body_conserves_and_flips():
    # I = diag(1, 2, 3), near the intermediate axis, 100 s at 1e-12: energy and |L| to 1e-10; the body-frame
    # angular velocity about the middle axis changes sign repeatedly.
    w = tumble.World(gravity=(0, 0, 0), integrator="dopri5", rtol=1e-12, atol=1e-12)
    w.add_body(None, mass=1.0, inertia=np.diag([1.0, 2.0, 3.0]), angular_velocity=(0.01, 1.0, 0.0))
    run = w.run(100.0, 0.05)
    e, l = run.energy, np.linalg.norm(run.angular_momentum, axis=1)
    assert np.max(np.abs(e / e[0] - 1)) < 1e-10
    assert np.max(np.abs(l / l[0] - 1)) < 1e-10
    wx, wy, wz = run.body_orientations[:, 0, 1], run.body_orientations[:, 0, 2], run.body_orientations[:, 0, 3]
    ww = run.body_orientations[:, 0, 0]
    omega = run.body_angular_velocities[:, 0]
    # Body-frame y component of omega: the second row of R^T applied to omega.
    r_col_y = np.stack([2 * (wx * wy + ww * wz), 1 - 2 * (wx**2 + wz**2), 2 * (wy * wz - ww * wx)], axis=1)
    body_y = np.sum(r_col_y * omega, axis=1)
    flips = np.count_nonzero(np.diff(np.sign(body_y)) != 0)
    assert flips >= 4


def test_force_off_centre_gives_the_chapters_torque():
    # F fixed in world axes at a body point r: P(t) = F t exactly; L(t) = (r x F) t to first order (after 1 ms
    # the ball has turned ~1e-6 rad, hence 1e-5).
    w = tumble.World(gravity=(0, 0, 0), integrator="dopri5", rtol=1e-12, atol=1e-12)
    b = w.add_body(tumble.Sphere(0.5), density=1000.0)
    force, at = np.array([100.0, 0.0, 0.0]), np.array([0.0, 0.5, 0.0])
    w.add_force(b, force, at=at)
    w.step(1e-3)
    mass = tumble.Sphere(0.5).mass_properties(1000.0)["mass"]
    np.testing.assert_allclose(w.bodies.velocities[0], force * 1e-3 / mass, rtol=1e-12)
    inertia = 0.4 * mass * 0.25
    np.testing.assert_allclose(w.bodies.angular_velocities[0], np.cross(at, force) * 1e-3 / inertia, rtol=1e-5)


def test_momentum_conserved_by_springs():
    # Two masses and a spring in free space: momentum is constant to round-off.
    w = tumble.World(gravity=(0, 0, 0), integrator="dopri5", rtol=1e-10, atol=1e-10)
    a = w.add_particle(mass=1.0, position=(-0.9, 0, 0), velocity=(0, 1, 0))
    b = w.add_particle(mass=3.0, position=(0.6, 0, 0), velocity=(0, 1, 0))
    w.add_spring(a, b, stiffness=50.0, rest_length=1.0)
    run = w.run(3.0, 0.01)
    np.testing.assert_allclose(run.momentum, np.tile(run.momentum[0], (run.frames, 1)), atol=1e-12)
