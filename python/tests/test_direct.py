"""tumble.direct: each goal met on a small scene with a known answer, bounds respected, an unmeetable goal ending
with the best found and saying so, bad arguments refused by name, and the same answer on any thread count."""

import math

import numpy as np
import pytest

import tumble
import tumble.direct as td

G = 9.81


def thrown():
    """A ball in free flight from (0, 0, 1) at (2, 0, 3) m/s, nothing to touch."""
    w = tumble.World()
    b = w.add_body(tumble.Sphere(0.05), position=(0, 0, 1), velocity=(2, 0, 3))
    return w, b


def test_a_keyframed_pose_is_reached_by_the_closed_form_launch_velocity():
    """At t = 0.8 s the ball must be at the point (2.5, 0, 3.5) m/s reaches: the only velocity that does. Within
    1 cm of the point, each component is within 0.01 / 0.8 m/s of the closed form."""
    w, b = thrown()
    target = (2.0, 0.0, 1 + 3.5 * 0.8 - 0.5 * G * 0.8**2)
    found = td.search(w, vary={b: td.Vary(velocity=1.0)}, goal=td.pose_at(b, 0.8, target, within=0.01),
                      duration=1.0, tries=256, seed=0)
    assert found.met and found.cost == 0.0 and found.tries <= 256
    v = found.world.bodies.velocities[found.world.bodies.row(b)]
    assert np.abs(v - [2.5, 0.0, 3.5]).max() <= 0.01 / 0.8
    # every alternative within the bounds (1 m/s along each axis from the start), the world asked about unchanged
    for a in found.alternatives:
        assert np.abs(a.world.bodies.velocities[a.world.bodies.row(b)] - [2, 0, 3]).max() <= 1.0 + 1e-12
    np.testing.assert_array_equal(w.bodies.velocities[w.bodies.row(b)], [2, 0, 3])
    # the world found runs to the same bits as the search's run of it
    np.testing.assert_array_equal(found.world.run(1.0).body_positions, found.run.body_positions)


def test_passing_through_a_region_and_touching_a_body_are_met():
    w, b = thrown()
    centre = (1.0, 0.5, 2.0)
    found = td.search(w, vary={b: td.Vary(velocity=2.0)}, goal=td.passes_through(b, centre, 0.02, before=1.0),
                      duration=1.0, tries=256)
    assert found.met
    path = found.run.positions_of(b)[found.run.times <= 1.0]
    assert np.linalg.norm(path - centre, axis=1).min() <= 0.02
    # touching: a second ball hung still at (1, 0, 1.5) (no gravity on it: it is static)
    other = w.add_body(tumble.Sphere(0.1), position=(1.0, 0.0, 1.5), static=True)
    found = td.search(w, vary={b: td.Vary(velocity=2.0)}, goal=td.touches(b, other, before=0.8), duration=0.8,
                      tries=256)
    assert found.met


def test_a_die_thrown_onto_the_floor_ends_with_the_face_asked_for_up():
    w = tumble.World(mode="fast")
    w.add_ground(friction=0.6)
    die = w.add_body(tumble.Box((0.05, 0.05, 0.05)), position=(0, 0, 0.3), velocity=(1.0, 0, 0),
                     angular_velocity=(3, 5, 1))
    for axis, name in [((1, 0, 0), "+x"), ((0, 0, -1), "-z")]:
        found = td.search(w, vary={die: td.Vary(orientation=180.0, spin=10.0)}, goal=td.face_up(die, axis),
                          duration=2.0, tries=128, seed=1)
        assert found.met, found.report
        assert tumble.up_axis(found.run.orientations_of(die)[-1]) == name


def test_a_box_slides_to_rest_at_a_target():
    """A box sliding on friction 0.5 stops after v^2 / (2 mu g): the search finds the speed that stops it 1 m on."""
    w = tumble.World(mode="fast")
    w.add_ground(friction=0.5)
    box = w.add_body(tumble.Box((0.1, 0.1, 0.1)), position=(0, 0, 0.1), velocity=(2.0, 0, 0), friction=0.5)
    found = td.search(w, vary={box: td.Vary(velocity=1.5)}, goal=td.rest_at(box, (1.0, 0.0, 0.1), within=0.01),
                      duration=2.0, tries=256)
    assert found.met, found.report
    assert np.linalg.norm(found.run.positions_of(box)[-1] - [1.0, 0.0, 0.1]) <= 0.01


def test_an_unmeetable_goal_ends_with_the_best_found_and_says_so():
    w, b = thrown()
    far = td.passes_through(b, (50.0, 0.0, 1.0), 0.01, before=1.0)  # 50 m away in a second: beyond the bounds
    found = td.search(w, vary={b: td.Vary(velocity=1.0)}, goal=far, duration=1.0, tries=40)
    assert not found.met and found.tries == 40 and found.cost > 40.0
    assert "not met" in found.report
    # a goal of the user's: their cost function, and two goals at once
    both = td.pose_at(b, 0.5, (1.0, 0.0, 1 + 1.5 - 0.5 * G * 0.25), within=0.05) & (lambda run: 0.0)
    assert td.search(w, vary={b: td.Vary(velocity=0.5)}, goal=both, duration=0.5, tries=64).met


def test_the_same_seed_gives_the_same_answer_on_one_and_two_threads():
    w, b = thrown()
    goal = td.pose_at(b, 0.8, (2.0, 0.1, 1.0), within=0.05)
    one = td.search(w, vary={b: td.Vary(velocity=1.0)}, goal=goal, duration=1.0, tries=96, seed=3, threads=1)
    two = td.search(w, vary={b: td.Vary(velocity=1.0)}, goal=goal, duration=1.0, tries=96, seed=3, threads=2)
    assert one.tries == two.tries and [a.cost for a in one.alternatives] == [a.cost for a in two.alternatives]
    np.testing.assert_array_equal(one.run.body_positions, two.run.body_positions)


def test_bad_arguments_are_refused_by_name(tmp_path):
    w, b = thrown()
    goal = td.pose_at(b, 0.5, (1, 0, 1))
    stranger = tumble.World().add_body(tumble.Sphere(0.1))
    for kwargs, name in [(dict(vary={b: td.Vary()}), "vary"), (dict(vary={b: 1.0}), "vary"), (dict(vary=[]), "vary"),
                         (dict(vary={stranger: td.Vary(velocity=1.0)}), "vary"), (dict(goal="six"), "goal"),
                         (dict(backend="cores"), "backend"), (dict(tries=0), "tries"), (dict(seconds=-1.0), "seconds"),
                         (dict(duration=0.0), "duration")]:
        args = dict(vary={b: td.Vary(velocity=1.0)}, goal=goal, duration=0.5, tries=8) | kwargs
        with pytest.raises(ValueError, match=f"`{name}`"):
            td.search(w, **args)
    for kwargs, name in [(dict(velocity=-1.0), "velocity"), (dict(orientation=math.nan), "orientation"),
                         (dict(friction=(0.5, 0.2)), "friction"), (dict(restitution=(0.0, 2.0)), "restitution")]:
        with pytest.raises(ValueError, match=f"`{name}`"):
            td.Vary(**kwargs)
    for make, name in [(lambda: td.rest_at(b, (0, 0)), "position"), (lambda: td.face_up(b, (0, 0, 0)), "axis"),
                       (lambda: td.passes_through(b, (0, 0, 0), -1.0), "radius"),
                       (lambda: td.pose_at(b, -1.0, (0, 0, 0)), "time")]:
        with pytest.raises(ValueError, match=f"`{name}`"):
            make()


def test_the_answer_comes_with_a_contact_sheet_and_its_robustness(tmp_path):
    w = tumble.World(mode="fast")
    w.add_ground(friction=0.5)
    box = w.add_body(tumble.Box((0.1, 0.1, 0.1)), position=(0, 0, 0.1), velocity=(2.0, 0, 0), friction=0.5)
    goal = td.rest_at(box, (0.6, 0.0, 0.1), within=0.02)
    found = td.search(w, vary={box: td.Vary(velocity=1.0, friction=(0.3, 0.7))}, goal=goal, duration=2.0,
                      tries=64, keep=4)
    from PIL import Image

    sheet = Image.open(found.contact_sheet(tmp_path / "sheet.png"))
    assert sheet.size[0] >= 4 * 100 and len(found.alternatives) == 4
    share = found.robustness(goal, 2.0, twins=4, size=1e-4)
    assert 0.0 <= share <= 1.0


def test_ray_and_dask_give_the_threads_answer():
    """The tries travel as the world's bytes and the point to try; each backend gives the same runs, so the same
    answer (CI installs both extras)."""
    w, b = thrown()
    goal = td.pose_at(b, 0.8, (2.0, 0.1, 1.0), within=0.05)
    kwargs = dict(vary={b: td.Vary(velocity=1.0)}, goal=goal, duration=1.0, tries=24, seed=5)
    local = td.search(w, **kwargs)
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as c, \
            distributed.Client(c):
        on_dask = td.search(w, backend="dask", **kwargs)
    ray = pytest.importorskip("ray")
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        on_ray = td.search(w, backend="ray", **kwargs)
    finally:
        ray.shutdown()
    for other in (on_dask, on_ray):
        assert [a.cost for a in other.alternatives] == [a.cost for a in local.alternatives]
        np.testing.assert_array_equal(other.run.body_positions, local.run.body_positions)


def test_sensitivity_tells_a_held_outcome_from_a_chaotic_one():
    """A ball in free flight ends exactly as far from its twin as it started (ratio 1, to rounding); a box tumbling
    onto a pile of dice amplifies a micrometre into far more."""
    w, _ = thrown()
    free = td.sensitivity(w, 1.0, twins=4, size=1e-6)
    assert free["ratio"] == pytest.approx(1.0, abs=1e-6)  # a shift of the start carries unchanged, to rounding
    w = tumble.World(mode="fast")
    w.add_ground(friction=0.5, restitution=0.3)
    for k in range(6):
        w.add_body(tumble.Box((0.05, 0.05, 0.05)), position=(0.02 * k, 0.0, 0.06 + 0.11 * k),
                   angular_velocity=(2.0 * k, 1.0, 0.5))
    chaotic = td.sensitivity(w, 2.0, twins=4, size=1e-6)
    assert chaotic["ratio"] > 100.0, chaotic


def test_robust_answers_come_first_when_asked():
    w, b = thrown()
    found = td.search(w, vary={b: td.Vary(velocity=1.0)}, goal=td.pose_at(b, 0.8, (2.0, 0.0, 0.7), within=0.05),
                      duration=1.0, tries=128, robust=3)
    met = [a for a in found.alternatives if a.met]
    assert met and all(a.robustness is not None and 0.0 <= a.robustness <= 1.0 for a in met)
    assert [a.robustness for a in met] == sorted((a.robustness for a in met), reverse=True)
