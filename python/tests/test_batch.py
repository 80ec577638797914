"""Batches and copies from Python (issue 15): ``tumble.rollout`` equals the same runs one after another bit for bit
on any thread count and leaves the world alone; ``copy.deepcopy`` continues bit for bit; bad input is refused."""

import copy

import numpy as np
import pytest

import tumble


def scene(mode: str, seed: int) -> tumble.World:
    """Three random boxes and spheres dropped on a ground (random sizes, densities, spins, materials)."""
    rng = np.random.default_rng(seed)
    w = tumble.World(mode="fast", dt=1 / 240) if mode == "fast" else tumble.World()
    w.add_ground(restitution=rng.uniform(0, 0.5), friction=rng.uniform(0.2, 1))
    for k in range(3):
        shape = tumble.Box(half_extents=rng.uniform(0.05, 0.15, 3)) if k % 2 else tumble.Sphere(rng.uniform(0.05, 0.15))
        w.add_body(shape, density=rng.uniform(300, 3000), position=(0.4 * k, 0, 0.3 + 0.2 * k),
                   angular_velocity=rng.uniform(-3, 3, 3), friction=rng.uniform(0.2, 1))
    return w


def states_of(w: tumble.World, count: int, seed: int) -> list:
    """The world's state and ``count - 1`` copies with random pushes given to its bodies (not the ground)."""
    rng = np.random.default_rng(seed)
    s = w.get_state()
    out = [s]
    for _ in range(count - 1):
        push = rng.uniform(-1, 1, s.body_momenta.shape)
        push[0] = 0.0
        out.append(s.replace(body_momenta=s.body_momenta + push))
    return out


FIELDS = ("times", "body_positions", "body_orientations", "body_velocities", "energy", "penetration")


@pytest.mark.parametrize("mode", ["fast", "accurate"])
def test_a_batch_equals_the_runs_one_after_another_bit_for_bit(mode):
    w = scene(mode, 7)
    w.step(0.25)
    states = states_of(w, 8, 7)
    before = w.bodies.positions.copy()
    one_by_one = []
    reference = copy.deepcopy(w)
    for s in states:
        reference.set_state(s)
        one_by_one.append(reference.run(0.5))
    for threads in (1, 2, None):
        batch = tumble.rollout(w, states, 0.5, threads=threads)
        assert len(batch) == 8
        assert batch.body_positions.shape == (8, len(batch.times), 4, 3)
        for k, run in enumerate(one_by_one):
            for name in FIELDS:
                got = getattr(batch.runs[k], name)
                assert got.tobytes() == getattr(run, name).tobytes(), (threads, k, name)
            assert batch.energy[k].tobytes() == run.energy.tobytes()
    assert w.bodies.positions.tobytes() == before.tobytes(), "the world itself is untouched"


def test_a_copy_continues_bit_for_bit_and_answers_to_the_handles():
    w = scene("fast", 3)
    w.step(0.25)
    twin = copy.deepcopy(w)
    same = copy.copy(w)
    for world in (w, twin, same):
        world.step(0.5)
    assert twin.bodies.positions.tobytes() == w.bodies.positions.tobytes()
    assert same.bodies.positions.tobytes() == w.bodies.positions.tobytes()
    handle = w.bodies.handles[1]
    twin.set_body_state(handle, velocity=(0.0, 0.0, 3.0))  # the copy's body, not the original's
    assert twin.bodies.velocities[1, 2] == 3.0 and w.bodies.velocities[1, 2] != 3.0


def test_bad_batches_are_refused_by_name():
    w = scene("fast", 1)
    w.step(0.25)
    s = w.get_state()
    with pytest.raises(ValueError, match="states"):
        tumble.rollout(w, [s, "not a state"], 0.5)
    moved = s.body_positions.copy()
    moved[1, 0] = np.inf
    with pytest.raises(ValueError, match=r"states\[1\]"):
        tumble.rollout(w, [s, s.replace(body_positions=moved)], 0.5)
    with pytest.raises(ValueError, match="duration"):
        tumble.rollout(w, [s], -1.0)
    with pytest.raises(ValueError, match="duration"):
        tumble.rollout(w, [s], 0.3 / 240)  # not a whole number of fast mode's steps
    other = scene("fast", 2)
    other.add_body(tumble.Sphere(0.1), position=(5, 0, 1))
    with pytest.raises(ValueError, match="body_positions"):
        tumble.rollout(w, [other.get_state()], 0.5)
    assert len(tumble.rollout(w, [], 0.5)) == 0
