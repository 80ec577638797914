"""Kinematic bodies from Python: ``add_body(shape, keyframes=(times, positions[, orientations]))`` follows its
keyframes in both modes (to 1e-9 m, the steps' rounding), pushes a box at its own speed, is never pushed back;
``tumble.keyframes_from`` samples a function of time; bad keyframes raise ValueError naming the argument."""

import numpy as np
import pytest

import tumble

SPEED = 1.6
TIMES = np.array([0.0, 0.2, 1.2])
PATH = np.array([[-0.7, 0.0, 0.1], [-0.7, 0.0, 0.1], [0.9, 0.0, 0.1]])


def paddle_at(t):
    """The paddle's keyframed position at t (linear between keyframes, held outside them)."""
    return np.array([np.interp(t, TIMES, PATH[:, k]) for k in range(3)])


def table(mode):
    w = tumble.World(mode=mode, **({"dt": 1.0 / 240.0} if mode == "fast" else {}))
    w.add_body(tumble.Box(half_extents=(0.5, 0.5, 0.05)), static=True, position=(0.0, 0.0, -0.05), restitution=0.0)
    box = w.add_body(tumble.Box(half_extents=(0.05, 0.05, 0.05)), density=500.0, position=(-0.3, 0.0, 0.05),
                     restitution=0.0, friction=0.4)
    paddle = w.add_body(tumble.Box(half_extents=(0.02, 0.6, 0.1)), keyframes=(TIMES, PATH), restitution=0.0,
                        name="paddle")
    return w, box, paddle


@pytest.mark.parametrize("mode", ["accurate", "fast"])
def test_a_keyframed_paddle_pushes_a_box_off_the_table(mode):
    # on the path after every step, to the steps' rounding (the engine's own state: a run's frames of a kinematic
    # body are its path's)
    probe, _, held = table(mode)
    for _ in range(90):
        probe.step(1.0 / 60.0)
        assert np.abs(probe.bodies.positions[probe.bodies.row(held)] - paddle_at(probe.time)).max() < 1e-9
    w, box, paddle = table(mode)
    run = w.run(1.5, frame_interval=1.0 / 60.0)
    b = run.bodies.index(box)
    # pushed at the paddle's speed while touching it (no restitution: contact holds); accurate mode to its contact
    # tolerance, fast mode's soft contact to 1 %
    f = int(np.searchsorted(run.times, 0.9))
    tolerance = (1e-2 if mode == "fast" else 1e-5) * SPEED
    assert abs(run.body_velocities[f, b, 0] - SPEED) < tolerance
    # and off the table by the end
    assert run.body_positions[-1, b, 2] < -0.05
    assert w.bodies.kinematic == [False, False, True]
    assert np.allclose(w.bodies.velocities[2], 0.0), "past its last keyframe it rests"


def test_a_function_of_time_sampled_into_keyframes():
    # a circle of 0.5 m radius once a second, sampled every 10 ms: followed exactly at the samples
    times = np.linspace(0.0, 1.0, 101)
    path = tumble.keyframes_from(lambda t: (0.5 * np.cos(2 * np.pi * t), 0.5 * np.sin(2 * np.pi * t), 1.0), times)
    w = tumble.World(mode="fast", dt=0.01)
    ring = w.add_body(tumble.Sphere(radius=0.1), keyframes=path)
    for k in range(1, 101):
        w.step(0.01)
        assert np.abs(w.bodies.positions[w.bodies.row(ring)] - path[1][k]).max() < 1e-9


@pytest.mark.parametrize("keyframes, named", [
    (([0.0, 0.0], [[0, 0, 0], [1, 0, 0]]), "times"),
    (([0.0, 1.0], [[0, 0, 0]]), "positions"),
    (([0.0], [[0, 0, 0]], [[0, 0, 0, 0]]), "keyframes"),
    ("a path", "keyframes"),
])
def test_bad_keyframes_name_the_argument(keyframes, named):
    w = tumble.World()
    with pytest.raises(ValueError, match=named):
        w.add_body(tumble.Sphere(radius=0.1), keyframes=keyframes)
    assert len(w.bodies) == 0


def test_what_follows_from_keyframes_cannot_be_given_too():
    w, _, paddle = table("fast")
    for kwargs, named in [({"mass": 1.0}, "mass"), ({"position": (1.0, 0.0, 0.0)}, "position"),
                          ({"static": True}, "keyframes"), ({"linear_damping": 1.0}, "linear_damping")]:
        with pytest.raises(ValueError, match=named):
            w.add_body(tumble.Sphere(radius=0.1), keyframes=(TIMES, PATH), **kwargs)
    with pytest.raises(ValueError, match="target"):
        w.add_force(paddle, (1.0, 0.0, 0.0))
