"""Saving, loading and pickling worlds from Python: every object and state to the bit; a world loaded from JSON or
binary or unpickled continues as the original, bit for bit, in both modes (the files carry the engine's memory);
one saved with ``memory=False`` (the scene alone, hand-editable) as the original started afresh from its state; bad
files raise ValueError naming the field."""

import json
import pickle

import numpy as np
import pytest

import tumble


def scene(mode: str) -> tumble.World:
    """Random boxes, spheres and a hull dropped on a ground, a particle on a spring and a constant force."""
    rng = np.random.default_rng(5)
    w = tumble.World(mode="fast", dt=1 / 240) if mode == "fast" else tumble.World()
    w.add_ground(restitution=0.3, friction=0.7)
    shapes = [tumble.Box(half_extents=(0.1, 0.15, 0.05)), tumble.Sphere(0.1),
              tumble.ConvexHull(rng.uniform(-0.1, 0.1, (10, 3)))]
    bodies = [w.add_body(s, density=rng.uniform(300, 2000), position=(0.4 * k, 0, 0.3 + 0.3 * k),
                         angular_velocity=rng.uniform(-2, 2, 3)) for k, s in enumerate(shapes)]
    p = w.add_particle(mass=0.2, position=(1.5, 0, 1.0))
    w.add_spring(p, bodies[0], stiffness=20.0, damping=0.1, anchor_b=(0.1, 0, 0))
    w.add_force(bodies[1], force=(0.3, 0, 0))
    return w


def arrays(w: tumble.World) -> bytes:
    return b"".join(a.tobytes() for a in (w.bodies.positions, w.bodies.orientations, w.bodies.velocities,
                                         w.bodies.angular_velocities, w.particles.positions, np.array([w.time])))


def afresh(w: tumble.World) -> tumble.World:
    """The world started afresh from its own state (as a loaded one is)."""
    import copy
    c = copy.deepcopy(w)
    c.set_state(c.get_state().replace())
    return c


@pytest.mark.parametrize("mode", ["accurate", "fast"])
@pytest.mark.parametrize("how", ["json", "binary", "pickle", "json scene", "binary scene"])
def test_save_load_continue(mode, how, tmp_path):
    w = scene(mode)
    w.step(0.75)  # the bodies touch: warm starts, lagged impulses, a touching phase
    if how == "pickle":
        loaded = pickle.loads(pickle.dumps(w))
    else:
        name = "world.json" if how.startswith("json") else "world.tumble"
        path = w.save(tmp_path / name, memory=not how.endswith("scene"))
        if how == "json scene":
            assert json.loads(path.read_text())["memory"] is None, "the scene alone holds no memory"
        loaded = tumble.World.load(path)
    assert type(loaded) is tumble.World
    assert arrays(loaded) == arrays(w)
    # a file with the engine's memory (and pickle) continues as the original; the scene alone starts the engine
    # afresh from the saved state, which goes another way (so the memory is what carried the others)
    import copy
    original, started_afresh = copy.deepcopy(w), afresh(w)
    for x in (original, started_afresh, loaded):
        x.step(0.25)
    assert arrays(original) != arrays(started_afresh)
    assert arrays(loaded) == arrays(started_afresh if how.endswith("scene") else original)
    loaded.reset()
    w.reset()
    assert arrays(loaded) == arrays(w), "the start travels with the file"


def test_a_scene_written_by_hand():
    text = json.dumps({
        "format": "tumble-scene", "version": 1, "gravity": [0, 0, -9.81],
        "particles": [{"mass": 2.0, "position": [0, 0, 1], "velocity": [1, 0, 0]}],
    })
    w = tumble.World.from_json(text)
    w.step(0.5)
    x = w.particles.positions[0]
    # free flight: x = v t, z = 1 - g t^2 / 2 (Dormand-Prince integrates a polynomial of degree 2 exactly, to
    # rounding: bound 1e-12)
    assert abs(x[0] - 0.5) < 1e-12 and abs(x[2] - (1 - 9.81 * 0.125)) < 1e-12


def test_bad_files_raise_value_errors_naming_the_field(tmp_path):
    w = scene("fast")
    good = json.loads(w.to_json())
    cases = {
        "version": {**good, "version": 7},
        "bodies": {**good, "bodies": [{**good["bodies"][1], "mass": -2.0}]},
        "torus": {**good, "bodies": [{"colliders": [{"shape": {"torus": {"radius": 1}}}], "density": 1.0}]},
        "colour": {**good, "colour": "red"},
    }
    for name, scene_file in cases.items():
        with pytest.raises(ValueError, match=name):
            tumble.World.from_json(json.dumps(scene_file))
    with pytest.raises(ValueError, match="file"):
        tumble.World.from_json(w.to_json().replace('"mass": 0.2', '"mass": NaN'))
    data = w._to_bytes()
    (tmp_path / "cut.tumble").write_bytes(data[: len(data) // 2])
    with pytest.raises(ValueError, match="file"):
        tumble.World.load(tmp_path / "cut.tumble")
    with pytest.raises(FileNotFoundError):
        tumble.World.load(tmp_path / "missing.tumble")
    w.add_force_callback(w.bodies.handles[1], lambda t, x, v: (0.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="loads"):
        pickle.dumps(w)


def test_a_run_pickles_saves_and_has_a_short_repr(tmp_path):
    w = scene("fast")
    run = w.run(0.5)
    assert len(repr(run)) < 200 and "frames" in repr(run)
    copies = [pickle.loads(pickle.dumps(run)), tumble.Run.load(run.save(tmp_path / "run.npz"))]
    for other in copies:
        for name in ("times", "body_positions", "body_orientations", "energy", "step_sizes", "penetration"):
            assert getattr(other, name).tobytes() == getattr(run, name).tobytes(), name
        assert other.bodies == run.bodies and other.particles == run.particles
        assert other.report == run.report
        kinds = [[type(s).__name__ for s, _, _ in body] for body in other.shapes]
        assert len(kinds) == len(run.shapes)
        hull = other.shapes[3][0][0]
        assert np.allclose(hull.triangle_mesh()[0], run.shapes[3][0][0].triangle_mesh()[0], rtol=0, atol=0)
    table = np.loadtxt(run.to_csv(tmp_path / "run.csv"), delimiter=",", skiprows=1)
    assert table.shape == (run.frames, 11)
    # written with repr: the CSV's numbers are the run's, to the bit
    assert table[:, 0].tobytes() == run.times.tobytes() and table[:, 3].tobytes() == run.energy.tobytes()
