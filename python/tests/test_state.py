"""A world's state from Python (issue 15): arrays that cannot mislead, rows after removals, the whole state taken and
put back bit for bit, reset, and bad states refused by name with nothing changed."""

import numpy as np
import pytest

import tumble


def drop(mode: str, seed: int) -> tumble.World:
    """A seeded random drop: two to four boxes and spheres of random sizes, densities, spins and materials above a
    ground, with a particle on a spring; in accurate mode, in fast mode, or (mode "smooth") without a ground."""
    rng = np.random.default_rng(seed)
    w = tumble.World(mode="fast", dt=1 / 240) if mode == "fast" else tumble.World()
    if mode != "smooth":
        w.add_ground(restitution=rng.uniform(0, 0.5), friction=rng.uniform(0, 1))
    for k in range(2 + seed % 3):
        shape = tumble.Box(half_extents=rng.uniform(0.05, 0.2, 3)) if k % 2 else tumble.Sphere(rng.uniform(0.05, 0.2))
        w.add_body(shape, density=rng.uniform(200, 3000), position=(rng.uniform(-0.2, 0.2), 0, 0.4 + 0.5 * k),
                   angular_velocity=rng.uniform(-3, 3, 3), friction=rng.uniform(0, 1), restitution=rng.uniform(0, 0.5))
    p = w.add_particle(mass=0.5, position=(2.0, 0, 1.0), velocity=(0.3, 0, 0))
    w.add_spring(p, None, stiffness=40.0, damping=0.2, world_point=(2.0, 0, 1.5))
    return w


def snapshot(w: tumble.World) -> list[np.ndarray]:
    return [w.particles.positions, w.particles.velocities, w.bodies.positions, w.bodies.orientations,
            w.bodies.velocities, w.bodies.angular_velocities, np.array([w.time])]


def same(a: list[np.ndarray], b: list[np.ndarray]) -> bool:
    return all(x.shape == y.shape and x.tobytes() == y.tobytes() for x, y in zip(a, b))


LEG = 60 / 240  # whole steps of fast mode


def test_writing_to_a_state_array_raises_instead_of_changing_nothing():
    w = drop("accurate", 0)
    for array in [w.bodies.positions, w.bodies.orientations, w.bodies.velocities, w.bodies.angular_velocities,
                  w.particles.positions, w.particles.velocities, w.get_state().body_positions]:
        with pytest.raises(ValueError, match="read-only"):
            array[0, 0] = 5.0
    copy = w.bodies.positions.copy()  # a copy is the user's to change
    copy[1, 2] = 5.0
    assert w.bodies.positions[1, 2] != 5.0


@pytest.mark.parametrize("mode", ["accurate", "fast", "smooth"])
def test_a_state_put_back_continues_bit_for_bit(mode):
    for seed in range(3):
        w = drop(mode, seed)
        w.step(LEG)
        s = w.get_state()
        assert s.has_memory and s.time == w.time
        w.step(LEG)
        first = snapshot(w)
        w.set_state(s)
        w.step(LEG)
        assert same(snapshot(w), first), (mode, seed)


@pytest.mark.parametrize("mode", ["accurate", "fast"])
def test_an_edited_state_runs_as_a_new_world_given_it(mode):
    w = drop(mode, 4)
    w.step(LEG)
    s = w.get_state()
    moved = s.body_positions.copy()
    moved[1:] += (0.0, 0.0, 0.05)  # row 0 is the static ground, which set_state does not move
    edited = s.replace(body_positions=moved, body_momenta=s.body_momenta * 0.5)
    assert not edited.has_memory
    fresh = drop(mode, 4)
    w.set_state(edited)
    fresh.set_state(edited)
    w.step(LEG)
    fresh.step(LEG)
    assert same(snapshot(w), snapshot(fresh))
    assert w.bodies.positions[1, 2] != 0.0


@pytest.mark.parametrize("mode", ["accurate", "fast", "smooth"])
def test_reset_returns_to_the_start_and_runs_again_the_same(mode):
    w = drop(mode, 2)
    start = snapshot(w)
    w.step(LEG)
    first = snapshot(w)
    w.step(LEG)
    w.reset()
    assert w.time == 0.0 and w.report.wall_seconds == 0.0
    assert same(snapshot(w), start)
    w.step(LEG)
    assert same(snapshot(w), first)


def test_rows_after_removals_and_dead_or_foreign_handles():
    w = tumble.World()
    balls = [w.add_body(tumble.Sphere(0.1), position=(0, 0, k)) for k in range(3)]
    w.remove(balls[1])
    assert w.bodies.row(balls[2]) == 1
    assert w.bodies.positions[w.bodies.row(balls[2]), 2] == 2.0
    with pytest.raises(ValueError, match="handle"):
        w.bodies.row(balls[1])
    other = tumble.World()
    theirs = other.add_body(tumble.Sphere(0.1))
    with pytest.raises(ValueError):
        w.bodies.row(theirs)
    with pytest.raises(ValueError):
        w.set_body_state(theirs, position=(0, 0, 1))
    p = other.add_particle(mass=1.0)
    assert other.particles.row(p) == 0


def test_a_bad_state_is_refused_by_name_and_the_world_is_unchanged():
    w = drop("fast", 1)
    w.step(LEG)
    s = w.get_state()
    before = snapshot(w)
    nan = s.body_momenta.copy()
    nan[1, 0] = np.nan
    ground = s.body_positions.copy()
    ground[0, 2] = 1.0
    skew = s.body_orientations.copy()
    skew[1] *= 1.5
    bad = {
        "body_momenta": s.replace(body_momenta=nan),
        "body_positions": s.replace(body_positions=ground),
        "body_orientations": s.replace(body_orientations=skew),
        "time": s.replace(time=float("inf")),
    }
    still = s.body_orientations.copy()
    still[0] = (0.0, 1.0, 0.0, 0.0)  # the ground turned
    bad["body_orientations"] = s.replace(body_orientations=still)
    bad["body_orientations "] = s.replace(body_orientations=skew)
    for name, state in bad.items():
        name = name.strip()
        with pytest.raises(ValueError, match=name):
            w.set_state(state)
        assert same(snapshot(w), before), name
    with pytest.raises(ValueError, match="body_positions"):
        s.replace(body_positions=np.zeros((1, 3)))
    with pytest.raises(ValueError, match="velocity"):
        s.replace(velocity=np.zeros((1, 3)))
    clean = drop("fast", 1)
    clean.step(LEG)
    w.step(LEG)
    clean.step(LEG)
    assert same(snapshot(w), snapshot(clean))


@pytest.mark.parametrize("mode", ["accurate", "fast"])
def test_contacts_of_a_resting_box_carry_its_weight(mode):
    w = tumble.World(mode=mode, dt=1 / 240) if mode == "fast" else tumble.World()
    ground = w.add_ground(restitution=0.0)
    box = w.add_body(tumble.Box(half_extents=(0.1, 0.2, 0.05)), mass=3.0, position=(0, 0, 0.05), restitution=0.0)
    assert len(w.contacts()["gaps"]) == 0
    w.step(0.5)
    c = w.contacts()
    assert c["points"].shape == (4, 3) and c["normals"].shape == (4, 3)
    assert all(a == box and b == ground for a, b in zip(c["a"], c["b"]))
    assert c["bodies"] == list(zip(c["a"], c["b"]))
    # the normals point from the box into the ground; at rest the forces on the box cancel its weight (to the
    # solvers' residual and rounding: measured 1e-13 relative, bound 1e-9)
    assert np.allclose(c["normals"], [0, 0, -1], atol=1e-12)
    assert abs(c["forces"].sum() - 3.0 * 9.81) < 1e-9 * 3.0 * 9.81
    assert np.all(np.abs(c["gaps"]) < 1e-3)
    with pytest.raises(ValueError, match="read-only"):
        c["forces"][0] = 0.0
