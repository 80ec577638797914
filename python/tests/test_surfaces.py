"""Surfaces from Python: combine rules per world and per surface, rolling and torsional resistance against their
closed forms in both modes, kept by copies and files, and bad values refused by name."""

import copy

import numpy as np
import pytest

import tumble

G = 9.81


def dropped(e_ball: float, e_ground: float, **world: str) -> float:
    """The rebound speed over the arrival speed of a ball dropped 1 m onto a ground (accurate mode)."""
    w = tumble.World(**world)
    w.add_ground(restitution=e_ground, friction=0.0)
    b = w.add_body(tumble.Sphere(0.1), position=(0, 0, 1.1), restitution=e_ball, friction=0.0)
    w.step(0.5)  # the impact at sqrt(2 / g) = 0.4515 s, no apex before 0.5 s
    v = w.bodies.velocities[w.bodies.row(b), 2]
    return (v + G * (0.5 - np.sqrt(2 / G))) / np.sqrt(2 * G)


@pytest.mark.parametrize("rule, want", [
    (None, 0.8), ("product", 0.4), ("min", 0.5), ("average", 0.65), ("geometric_mean", np.sqrt(0.4)), ("max", 0.8),
])
def test_a_worlds_restitution_rule_sets_the_bounce(rule, want):
    world = {} if rule is None else {"restitution_combine": rule}
    # accurate mode applies Newton's law at the located impact: the rebound exact to rounding
    assert dropped(0.5, 0.8, **world) == pytest.approx(want, abs=1e-9)


def test_a_surfaces_own_rule_comes_before_the_worlds_and_world_gives_it_back():
    w = tumble.World()
    w.add_ground(restitution=0.8, friction=0.0)
    b = w.add_body(tumble.Sphere(0.1), position=(0, 0, 1.1), restitution=0.5, friction=0.0,
                   restitution_combine="product")
    w.step(0.5)
    v = w.bodies.velocities[w.bodies.row(b), 2] + G * (0.5 - np.sqrt(2 / G))
    assert v / np.sqrt(2 * G) == pytest.approx(0.4, abs=1e-9)
    w.reset()
    w.set_material(b, restitution_combine="world")
    w.step(0.5)
    v = w.bodies.velocities[w.bodies.row(b), 2] + G * (0.5 - np.sqrt(2 / G))
    assert v / np.sqrt(2 * G) == pytest.approx(0.8, abs=1e-9)


@pytest.mark.parametrize("mode", ["accurate", "fast"])
def test_rolling_resistance_slows_a_ball_at_five_sevenths_of_it_times_g(mode):
    """A solid ball rolling at 1 m/s with rolling resistance 0.1 (the floor has none; the pair takes the larger)
    slows at a = 5/7 0.1 g and stops after v^2 / (2 a)."""
    w = tumble.World(mode=mode)
    w.add_ground(friction=0.5)
    b = w.add_body(tumble.Sphere(0.1), position=(0, 0, 0.1), velocity=(1, 0, 0), angular_velocity=(0, 10, 0),
                   friction=0.5, rolling_resistance=0.1)
    a = 5 / 7 * 0.1 * G
    run = w.run(2.0)
    t = np.minimum(run.times, 1 / a)
    x = run.positions_of(b)[:, 0]
    # frames within 1 mm of x = v t - a t^2 / 2 (then at rest): accurate mode's frames interpolate within contact
    # steps of up to 50 ms (a h^2 / 8 = 2e-4 m) and the steps' local errors (3.5e-5 m each) add over forty of
    # them; fast mode lags the bound by a substep
    assert np.abs(x - (t - a * t**2 / 2)).max() < 1e-3
    # at rest where the closed form stops, to a tenth of a millimetre (three contact tolerances; fast mode's 2e-5)
    assert x[-1] == pytest.approx(1 / (2 * a), abs=1e-4)
    assert np.abs(run.velocities_of(b)[-1]).max() < 1e-6


def test_resistance_and_rules_are_kept_by_copies_and_files(tmp_path):
    w = tumble.World(friction_combine="product", restitution_combine="min")
    w.add_ground()
    b = w.add_body(tumble.Sphere(0.1), position=(0, 0, 0.1), velocity=(1, 0, 0), angular_velocity=(0, 10, 0),
                   rolling_resistance=0.2, torsional_resistance=0.1, friction_combine="max")
    want = copy.deepcopy(w).run(0.5).body_positions
    loaded = tumble.World.load(w.save(tmp_path / "w.json"))
    np.testing.assert_array_equal(loaded.run(0.5).body_positions, want)
    np.testing.assert_array_equal(w.run(0.5).body_positions, want)
    assert b is not None


def test_bad_surfaces_are_refused_by_name():
    w = tumble.World()
    b = w.add_body(tumble.Sphere(0.1))
    for kwargs, name in [({"rolling_resistance": -1.0}, "rolling_resistance"),
                         ({"torsional_resistance": float("nan")}, "torsional_resistance"),
                         ({"friction_combine": "mean"}, "friction_combine"),
                         ({"restitution_combine": "sum"}, "restitution_combine")]:
        with pytest.raises(ValueError, match=name):
            w.add_body(tumble.Sphere(0.1), **kwargs)
        with pytest.raises(ValueError, match=name):
            w.set_material(b, **kwargs)
    with pytest.raises(ValueError, match="friction_combine"):
        tumble.World(friction_combine="geometric")


def test_a_worlds_rules_are_read_and_set():
    w = tumble.World(friction_combine="product")
    assert w.combine_rules == {"friction": "product", "restitution": "max"}
    w.set_combine_rules(restitution="average")
    assert w.combine_rules == {"friction": "product", "restitution": "average"}
    with pytest.raises(ValueError, match="restitution"):
        w.set_combine_rules(restitution="mean")
    assert w.combine_rules["restitution"] == "average"
