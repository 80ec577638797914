"""Bad input raises ValueError naming the argument; a failed step raises SimulationError and changes nothing."""

import math

import numpy as np
import pytest

import tumble


@pytest.mark.parametrize("mass", [0.0, -1.0, math.nan, math.inf])
def test_bad_mass(mass):
    with pytest.raises(ValueError, match="`mass`"):
        tumble.World().add_particle(mass=mass)


@pytest.mark.parametrize(
    "inertia",
    [[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]], np.diag([1.0, -1.0, 1.0]), np.diag([1.0, 0.0, 1.0]), np.full((3, 3), np.nan)],
    ids=["asymmetric", "indefinite", "singular", "nan"],
)
def test_bad_inertia(inertia):
    with pytest.raises(ValueError, match="`inertia`"):
        tumble.World().add_body(None, mass=1.0, inertia=inertia)


def test_bad_arguments_name_themselves():
    w = tumble.World()
    cases = [
        (lambda: w.add_particle(position=(0, math.nan, 0)), "`position`"),
        (lambda: w.add_particle(position=(0, 1)), "`position`"),
        (lambda: w.add_body(tumble.Sphere(1.0), density=-2.0), "`density`"),
        (lambda: w.add_body(tumble.Sphere(1.0), orientation=(0, 0, 0, 0)), "`orientation`"),
        (lambda: w.step(0.0), "`dt`"),
        (lambda: w.step(-1.0), "`dt`"),
        (lambda: tumble.World(integrator="rk5"), "`integrator`"),
        (lambda: tumble.World(integrator="rk4", dt=-1e-3), "`dt`"),
        (lambda: tumble.World(mode="sideways"), "`mode`"),
        (lambda: tumble.Sphere(-1.0), "`radius`"),
        (lambda: tumble.Box(half_extents=(1, 0, 1)), "`half_extents`"),
        (lambda: tumble.ConvexHull([(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)]), "`points`"),
        (lambda: tumble.TriMesh([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(0, 1, 7)]), "`triangles`"),
        (lambda: w.add_body(tumble.TriMesh([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(0, 1, 2)]), density=1.0), "`shape`"),
    ]
    for call, name in cases:
        with pytest.raises(ValueError, match=name):
            call()
    assert len(w.particles) == 0 and len(w.bodies) == 0


def test_stale_handle_after_remove():
    w = tumble.World()
    p = w.add_particle()
    q = w.add_particle(position=(1, 0, 0))
    w.add_spring(p, q, stiffness=1.0)
    w.remove(q)
    with pytest.raises(ValueError, match="no longer"):
        w.add_force(q, (1, 0, 0))
    assert len(w.particles) == 1


def stiff_cloth():
    w = tumble.scenes.cloth(n=8, stiffness=1e6, pin_stiffness=1e7, damping=1.0)
    w.set_integrator("euler", dt=1 / 60)
    return w


def test_divergence_is_a_simulation_error_and_the_world_is_unchanged():
    w = stiff_cloth()
    w.step(1 / 60)
    before_x, before_v, t = w.particles.positions.copy(), w.particles.velocities.copy(), w.time
    with pytest.raises(tumble.SimulationError, match="divergence") as info:
        w.run(5.0, 1 / 60)
    assert isinstance(info.value, RuntimeError)
    assert w.time == t
    np.testing.assert_array_equal(w.particles.positions, before_x)
    np.testing.assert_array_equal(w.particles.velocities, before_v)
    assert np.all(np.isfinite(w.particles.positions))


def test_callback_exception_is_the_cause():
    w = tumble.World()
    p = w.add_particle(velocity=(1, 0, 0))

    def wind(t, x, v):
        if t > 0.5:
            raise KeyError("anemometer")
        return (0.0, 0.0, 9.81)

    w.add_force_callback(p, wind)
    w.step(0.4)
    np.testing.assert_allclose(w.particles.positions[0], (0.4, 0.0, 0.0), atol=1e-9)
    before = w.particles.positions.copy()
    with pytest.raises(tumble.SimulationError) as info:
        w.step(0.4)
    assert isinstance(info.value.__cause__, KeyError)
    np.testing.assert_array_equal(w.particles.positions, before)
    assert w.time == pytest.approx(0.4)


def wrong_type_calls():
    """For each argument of the methods taking shapes, colliders and handles: (argument, call with an object of a
    wrong type for it)."""
    w = tumble.World(mode="fast")
    p = w.add_particle()
    b = w.add_body(tumble.Sphere(0.5), position=(0, 0, 2))
    c = w.add_body(tumble.Box((0.5, 0.5, 0.5)), position=(2, 0, 2))
    state = w.get_state()
    bad = object()
    calls = []
    body_args = ["density", "mass", "inertia", "position", "orientation", "velocity", "angular_velocity",
                 "restitution", "friction", "static", "linear_damping", "angular_damping", "colliders"]
    calls.append(("shape", lambda: w.add_body(bad)))
    for name in body_args:
        calls.append((name, lambda name=name: w.add_body(tumble.Sphere(0.5), **{name: bad})))
    calls.append(("colliders", lambda: w.add_body(tumble.Sphere(0.5), colliders=5)))
    calls.append(("colliders", lambda: w.add_body(tumble.Sphere(0.5), colliders=[(tumble.Sphere(0.1), bad)])))
    calls.append(("colliders", lambda: w.add_body(tumble.Sphere(0.5), colliders=[(bad, (0, 0, 0))])))
    calls.append(("a", lambda: w.add_spring(bad, b)))
    for name in ["b", "stiffness", "damping", "rest_length", "anchor_a", "anchor_b"]:
        calls.append((name, lambda name=name: w.add_spring(p, **{"b": b, name: bad})))
    calls.append(("world_point", lambda: w.add_spring(p, world_point=bad)))
    calls.append(("body", lambda: w.set_body_state(bad)))
    for name in ["position", "orientation", "velocity", "angular_velocity"]:
        calls.append((name, lambda name=name: w.set_body_state(b, **{name: bad})))
    calls.append(("particle", lambda: w.set_particle_state(bad)))
    calls.append(("target", lambda: w.add_force(bad, (1, 0, 0))))
    calls.append(("body", lambda: w.add_torque(bad, (1, 0, 0))))
    calls.append(("handle", lambda: w.remove(bad)))
    calls.append(("joint", lambda: w.add_joint(bad)))
    calls.append(("joint", lambda: w.remove_joint(bad)))
    for name in ["a", "b", "anchor_a", "anchor_b", "axis", "limits", "motor", "spring", "softness"]:
        calls.append((name, lambda name=name: w.add_joint(tumble.Hinge(**{"a": b, "b": c, name: bad}))))
    calls.append(("state", lambda: w.set_state(bad)))
    calls.append(("world", lambda: tumble.rollout(bad, [state], 0.1)))
    calls.append(("states", lambda: tumble.rollout(w, bad, 0.1)))
    calls.append(("duration", lambda: tumble.rollout(w, [state], bad)))
    calls.append(("path", lambda: w.save(bad)))
    calls.append(("path", lambda: tumble.World.load(bad)))
    calls.append(("params", lambda: tumble.sweep(tumble.scenes.dominoes, bad, 0.1)))
    run = tumble.World().run(0.05)
    for write in (run.save, run.to_csv, run.export_gltf, tumble.Run.load):
        calls.append(("path", lambda write=write: write(bad)))
    return w, calls


def test_a_wrong_type_for_any_argument_names_it():
    w, calls = wrong_type_calls()
    unnamed = []
    for name, call in calls:
        try:
            call()
        except (TypeError, ValueError) as error:
            if f"`{name}`" not in str(error):
                unnamed.append(f"{name}: {type(error).__name__}: {error}")
        else:
            unnamed.append(f"{name}: no error")
    assert not unnamed, "\n".join(unnamed)
    assert len(w.bodies) == 2 and len(w.particles) == 1  # nothing was added by a refused call
