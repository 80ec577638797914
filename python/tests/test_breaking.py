"""Breakable joints from Python: ``breaking=tumble.Breaking(force=..., torque=...)`` on any joint; a pendulum's
pivot breaks where the closed form's force reaches the bound (accurate mode to 1e-8), the run lists the break,
``World.joint_broken``/``broken_joints`` say so, saved runs keep it, and bad bounds raise ValueError naming
``breaking``."""

import math

import numpy as np
import pytest

import tumble

G = 9.81
M, R, L = 2.0, 0.1, 0.8
I_P = 0.4 * M * R * R + M * L * L


def omega(theta):
    """The angular speed of the rigid pendulum released at rest from the horizontal, at theta below it."""
    return math.sqrt(2.0 * M * G * L * math.sin(theta) / I_P)


def force(theta):
    """The pivot's force on the ball at theta (N): m (a - g)."""
    s, c = math.sin(theta), math.cos(theta)
    w2, alpha = omega(theta) ** 2, M * G * L * c / I_P
    ax, az = -w2 * L * c - alpha * L * s, w2 * L * s - alpha * L * c + G
    return M * math.hypot(ax, az)


def breaking_angle(bound):
    lo, hi = 0.0, math.pi / 2
    while hi - lo > 1e-15:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if force(mid) > bound else (mid, hi)
    return hi


def pendulum(**options):
    w = tumble.World(**options)
    ball = w.add_body(mass=M, inertia=np.eye(3) * 0.4 * M * R * R, position=(L, 0.0, 0.0))
    joint = w.add_joint(tumble.Ball(None, ball, anchor_b=(-L, 0.0, 0.0),
                                    breaking=tumble.Breaking(force=2.0 * M * G)))
    return w, ball, joint


def test_a_pendulum_pivot_breaks_where_its_force_reaches_the_bound(tmp_path):
    w, ball, joint = pendulum(integrator="dopri5", rtol=1e-10, atol=1e-12)
    assert not w.joint_broken(joint)
    run = w.run(1.0, 0.01)
    assert w.joint_broken(joint) and w.broken_joints() == [joint]
    assert run.joint_breaks == [joint] and len(run.joint_break_times) == 1
    # after the break the ball spins on at the angular speed it had at the breaking angle: accurate mode locates
    # the break to its time tolerance (measured 3e-11 relative in the Rust test); bound 1e-8
    expected = omega(breaking_angle(2.0 * M * G))
    spin = np.linalg.norm(run.body_angular_velocities[-1, 0])
    assert abs(spin - expected) / expected < 1e-8
    saved = tumble.Run.load(run.save(tmp_path / "broke.npz"))
    assert saved.joint_breaks == run.joint_breaks
    assert np.array_equal(saved.joint_break_times, run.joint_break_times)


@pytest.mark.parametrize("bound", [tumble.Breaking(force=float("nan")), tumble.Breaking(force=-1.0),
                                   tumble.Breaking(), tumble.Breaking(force="strong")])
def test_bad_bounds_name_breaking(bound):
    w = tumble.World()
    ball = w.add_body(mass=1.0, inertia=np.eye(3))
    with pytest.raises(ValueError, match="breaking"):
        w.add_joint(tumble.Ball(None, ball, breaking=bound))
    with pytest.raises(ValueError, match="breaking"):
        w.add_joint(tumble.Ball(None, ball, breaking=(1.0, 2.0)))
    assert w.joint_count == 0


def test_a_broken_joint_is_no_longer_drawn(tmp_path):
    """The pendulum's link is drawn from the pivot to the ball until the break, then as a segment of no length:
    the viewer, previews and glTF draw nothing stretching after the ball; the saved run keeps it."""
    w, _, _ = pendulum(integrator="dopri5", rtol=1e-8, atol=1e-10)
    run = w.run(1.0, 0.01)
    (t_break,) = run.joint_break_times
    lengths = [np.linalg.norm(np.diff(run.link_segments(f), axis=1)) for f in range(run.frames)]
    before = [n for n, t in zip(lengths, run.times) if t < t_break]
    after = [n for n, t in zip(lengths, run.times) if t >= t_break]
    # the pivot's anchor and the ball's coincide while held: frames come from the integrator's dense output between
    # its projections, within its tolerance (measured 5.5e-9 m at rtol 1e-8); bound 1e-6 m
    assert max(before) < 1e-6 and after and max(after) == 0.0
    saved = tumble.Run.load(run.save(tmp_path / "run.npz"))
    assert saved.link_ends == run.link_ends and list(run.link_ends) == [0]


def test_collide_must_be_a_bool():
    w = tumble.World()
    ball = w.add_body(mass=1.0, inertia=np.eye(3))
    with pytest.raises(ValueError, match="collide"):
        w.add_joint(tumble.Ball(None, ball, collide="yes"))
