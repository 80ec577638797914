"""What a new user tries first: options that do not apply or make no sense are refused by name (a static body's
velocity, tolerances given to step doubling, a step of infinity), and a surface changed between steps
(``World.set_material``) acts from the next step on in both modes and travels with copies, pickles and files."""

import copy
import math
import pickle

import numpy as np
import pytest

import tumble

G = 9.81


@pytest.mark.parametrize("kwargs, name", [
    (dict(step_doubling=True, integrator="rk4", rtol=math.nan), "rtol"),
    (dict(step_doubling=True, integrator="rk4", rtol=1e-6), "rtol"),
    (dict(step_doubling=True, integrator="rk4", atol=1e-9), "atol"),
    (dict(atol=-1.0), "atol"),
    (dict(atol=math.inf), "atol"),
    (dict(rtol=math.nan), "rtol"),
    (dict(dt=math.inf), "dt"),
    (dict(integrator="rk4", dt=math.nan), "dt"),
    (dict(integrator="euler-variable", atol=1e-9), "atol"),
])
def test_integrator_options_that_make_no_sense_are_refused_by_name(kwargs, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        tumble.World(**kwargs)
    w = tumble.World()
    with pytest.raises(ValueError, match=f"`{name}`"):
        w.set_integrator(**kwargs)


def test_set_integrator_names_dt_not_the_first_step():
    with pytest.raises(ValueError) as e:
        tumble.World().set_integrator(dt=math.inf)
    assert "`dt`" in str(e.value) and "initial_step" not in str(e.value)


def test_a_static_body_takes_no_velocity():
    w = tumble.World()
    with pytest.raises(ValueError, match="`velocity`"):
        w.add_body(tumble.Sphere(0.5), static=True, velocity=(1, 0, 0))
    with pytest.raises(ValueError, match="`angular_velocity`"):
        w.add_body(tumble.Sphere(0.5), static=True, angular_velocity=(0, 0, 1))
    assert len(w.bodies) == 0
    wall = w.add_body(tumble.Box(half_extents=(1, 1, 1)), static=True, position=(0, 0, -1))
    with pytest.raises(ValueError, match="`velocity`"):
        w.set_body_state(wall, velocity=(0, 0, 1))
    np.testing.assert_array_equal(w.bodies.positions[0], [0, 0, -1])
    w.set_body_state(wall, position=(0, 0, -2))  # moving its pose is allowed
    np.testing.assert_array_equal(w.bodies.positions[0], [0, 0, -2])


def sliding(mode: str) -> tuple[tumble.World, object]:
    """A 0.2 m cube sliding at 2 m/s along x on a ground of friction 1, itself frictionless."""
    w = tumble.World(mode="fast", dt=1 / 240) if mode == "fast" else tumble.World()
    w.add_ground(restitution=0.0, friction=1.0)
    b = w.add_body(tumble.Box(half_extents=(0.1, 0.1, 0.1)), density=500.0, position=(0, 0, 0.1),
                   velocity=(2.0, 0, 0), restitution=0.0, friction=0.0)
    return w, b


# accurate mode holds Coulomb's law to its contact tolerance: 1e-5 m/s; fast mode's soft friction rows converge
# within a few per cent of the change (2% of mu g t)
TOLERANCE = {"accurate": 1e-5, "fast": 0.02 * 0.5 * G * 0.25}


@pytest.mark.parametrize("mode", ["accurate", "fast"])
def test_friction_set_between_steps_decelerates_at_mu_g(mode):
    w, b = sliding(mode)
    w.step(0.25)
    v0 = w.bodies.velocities[w.bodies.row(b), 0]
    assert abs(v0 - 2.0) < TOLERANCE[mode], "frictionless: the speed is kept"
    w.set_material(b, friction=0.25)  # mu = sqrt(0.25 * 1) = 0.5 with the ground
    w.step(0.25)
    v1 = w.bodies.velocities[w.bodies.row(b), 0]
    assert abs(v1 - (v0 - 0.5 * G * 0.25)) < TOLERANCE[mode], (v0, v1)


@pytest.mark.parametrize("mode", ["accurate", "fast"])
def test_a_changed_material_travels_with_copies_pickles_and_files(mode, tmp_path):
    w, b = sliding(mode)
    w.step(0.1)
    w.set_material(b, friction=0.4, restitution=0.2)
    others = [copy.copy(w), pickle.loads(pickle.dumps(w)), tumble.World.load(w.save(tmp_path / "w.json")),
              tumble.World.load(w.save(tmp_path / "w.tumble"))]
    for x in [w] + others:
        x.step(0.2)
    for other in others:
        np.testing.assert_array_equal(other.bodies.positions, w.bodies.positions)
        np.testing.assert_array_equal(other.bodies.velocities, w.bodies.velocities)


def test_a_bad_material_is_refused_by_name_and_changes_nothing():
    w, b = sliding("accurate")
    w.step(0.05)
    before = w.to_json(memory=False)
    for kwargs, name in [(dict(friction=-1.0), "friction"), (dict(restitution=2.0), "restitution"),
                         (dict(friction=math.nan), "friction")]:
        with pytest.raises(ValueError, match=name):
            w.set_material(b, **kwargs)
    with pytest.raises(TypeError, match="friction"):
        w.set_material(b, friction="sticky")
    with pytest.raises(ValueError, match="handle"):
        w.set_material(object(), friction=0.1)
    assert w.to_json(memory=False) == before


def _report(**world) -> tumble.Report:
    w = tumble.World(**world)
    w.add_ground()
    w.add_body(tumble.Box((0.1, 0.1, 0.1)), position=(0, 0, 0.3))
    return w.run(0.5).report


@pytest.mark.parametrize("world, mode, error", [
    ({}, "accurate", "contact steps at most"),
    ({"mode": "fast"}, "fast", "not estimated"),
    ({"mode": "fast", "step_doubling": True}, "fast", "its two halves by at most"),
])
def test_a_report_says_which_mode_ran_and_gives_one_error_line_in_metres(world, mode, error):
    """The report opens with the mode (and when to pick the other), then one error line a user can compare with
    what they asked for; the integrator's internals and the soft step's residual are in ``details()``."""
    report = _report(**world)
    lines = str(report).splitlines()
    assert lines[0].startswith(f"mode             {mode}")
    other = "fast" if mode == "accurate" else "accurate"
    assert f'mode="{other}"' in lines[0], "says how to pick the other mode"
    errors = [line for line in lines if line.startswith("error")]
    assert len(errors) == 1 and error in errors[0], errors
    assert "residual" not in str(report) and "error estimate   " not in str(report)
    assert "stages ran" in report.details() and "force loops" in report.details()
    if mode == "fast":
        assert "soft step        residual" in report.details()
