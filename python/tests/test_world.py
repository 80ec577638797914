"""The World's contract from Python: arrays, plans, reports, progress, interruption, the GIL, and the same
numbers as the Rust library."""

import _thread
import signal
import threading
import time

import numpy as np
import pytest

import tumble


def test_state_arrays_are_numpy():
    w = tumble.World()
    w.add_particle(position=(1, 2, 3))
    w.add_particle(position=(4, 5, 6), velocity=(1, 0, 0))
    w.add_body(tumble.Box(half_extents=(0.5, 0.5, 0.5)), density=1000.0, position=(0, 0, 2), orientation=(0, 0, 0, 1))
    w.add_body(None, static=True, position=(0, 0, -1))
    assert w.particles.positions.shape == (2, 3) and w.particles.positions.dtype == np.float64
    np.testing.assert_array_equal(w.particles.positions, [[1, 2, 3], [4, 5, 6]])
    np.testing.assert_array_equal(w.particles.velocities[1], [1, 0, 0])
    assert w.bodies.positions.shape == (2, 3) and w.bodies.orientations.shape == (2, 4)
    np.testing.assert_allclose(w.bodies.orientations[0], [0, 0, 0, 1])
    assert w.bodies.velocities.shape == (2, 3) and w.bodies.angular_velocities.shape == (2, 3)
    run = w.run(0.5, 0.1)
    assert run.particle_positions.shape == (6, 2, 3)
    assert run.body_orientations.shape == (6, 2, 4)
    assert run.energy.shape == (6,) and run.momentum.shape == (6, 3)
    np.testing.assert_array_equal(run.body_positions[:, 1], np.tile([0, 0, -1.0], (6, 1)))


def test_plan_leaves_out_what_the_scene_does_not_need():
    w = tumble.World(integrator="rk4", dt=0.01)
    for i in range(4):
        w.add_particle(position=(i, 0, 0))
    plan = w.plan()
    assert plan["state_len"] == 24 and "rotation" not in plan["stages"] and plan["jacobian"] is None
    w.step(0.1)
    report = w.report
    assert report.jacobians == 0 and report.spring_evaluations == 0 and report.callback_calls == 0
    assert report.qp_solves == 0 and report.collisions == 0
    w.add_body(tumble.Sphere(0.2), density=100.0)
    assert w.plan()["state_len"] == 24 + 13
    assert "rotation" in w.plan()["stages"]


def test_report_is_a_plain_dataclass():
    w = tumble.World()
    w.add_particle()
    run = w.run(1.0, 0.1)
    assert isinstance(run.report, tumble.Report)
    assert run.report.steps > 0 and run.report.rhs_evals >= 6 * run.report.steps
    assert run.report.error_estimate is not None
    assert "dopri5" in str(run.report)
    assert run.report.as_dict()["steps"] == run.report.steps
    assert len(run.step_sizes) == run.report.steps


def test_progress_and_interruption():
    w = tumble.scenes.cloth(n=6)
    seen = []
    run = w.run(1.0, 1 / 60, progress=seen.append)
    assert seen == sorted(seen) and seen[-1] == pytest.approx(1.0) and len(seen) > 10
    assert run.frames == 61 and not run.interrupted
    t = w.time

    def stop(fraction):
        if fraction > 0.3:
            raise KeyboardInterrupt

    # an interrupt keeps the frames done: the world is at the last of them, and the next run carries on
    with pytest.raises(KeyboardInterrupt) as caught:
        w.run(1.0, 1 / 60, progress=stop)
    kept = caught.value.run
    assert kept.interrupted and 0.3 * 61 < kept.frames < 61
    assert w.time == kept.times[-1] and kept.times[0] == t
    np.testing.assert_array_equal(w.particles.positions, kept.particle_positions[-1])
    rest = w.run(t + 1.0 - w.time, 1 / 60)
    assert rest.times[0] == kept.times[-1] and rest.times[-1] == pytest.approx(t + 1.0, abs=1e-12)

    # any other exception from the progress callable fails the call: the world as it was, the frames on the error
    def broken(fraction):
        if fraction > 0.3:
            raise ValueError("a broken progress callable")

    t, before = w.time, w.particles.positions.copy()
    with pytest.raises(ValueError, match="broken") as caught:
        w.run(1.0, 1 / 60, progress=broken)
    assert w.time == t and not caught.value.run.interrupted and caught.value.run.frames > 1
    np.testing.assert_array_equal(w.particles.positions, before)


def test_ctrl_c_during_run_keeps_the_frames_done_and_the_next_run_carries_on():
    # A real SIGINT, sent from a timer thread 0.5 s into a run of accurate mode that takes several seconds (60 boxes
    # dropped into a pile); the frames done come with the KeyboardInterrupt and the world is at the last of them (the
    # frames an interrupt keeps are bit for bit those of a run not interrupted: tests/it/long_runs.rs).
    w = tumble.World()
    w.add_ground()
    for k in range(60):
        w.add_body(tumble.Box((0.1, 0.1, 0.1)), position=(0.25 * (k % 4), 0.25 * ((k // 4) % 4), 0.15 + 0.25 * (k // 16)),
                   angular_velocity=(0.3 * (k % 3), 0.2, 0.1))
    timer = _interrupt_after(0.5)
    with pytest.raises(KeyboardInterrupt) as caught:
        w.run(10.0, 1 / 60)
    timer.join()
    kept = caught.value.run
    assert kept.interrupted and 1 < kept.frames < 601
    assert w.time == kept.times[-1]
    np.testing.assert_array_equal(w.bodies.positions[1:], kept.body_positions[-1][1:])
    assert np.all(np.diff(kept.times) > 0) and kept.times[0] == 0.0
    # the next run carries on from the last frame kept
    rest = w.run(0.1, 1 / 60)
    assert rest.times[0] == kept.times[-1] and not rest.interrupted
    assert np.all(np.isfinite(rest.body_positions))


def test_a_slow_accurate_run_says_so_once_on_standard_error(capsys):
    # A box dropped for 0.2 s whose progress callable takes fifteen times the simulated time it is told of: the run
    # takes 3 s for 0.2 s, and the line (due past two seconds, over ten times) comes once, naming fast mode.
    w = tumble.World()
    w.add_ground()
    w.add_body(tumble.Box((0.1, 0.1, 0.1)), position=(0.0, 0.0, 0.3))
    done = [0.0]

    def slow(fraction):
        time.sleep(15.0 * 0.2 * (fraction - done[0]))
        done[0] = fraction

    w.run(0.2, 1 / 200, progress=slow)
    err = capsys.readouterr().err
    assert err.count("tumble: accurate mode projects") == 1, err
    assert 'fast mode (mode "fast", steps of 1/240 s) would take about' in err
    done[0] = 0.0
    w.run(0.2, 1 / 200, progress=slow)
    assert "accurate mode projects" not in capsys.readouterr().err, "once a world"


def _interrupt_after(seconds):
    # What Ctrl-C does: the SIGINT handler's KeyboardInterrupt, raised in the main thread at its next signal check.
    # Python's own handler is put back first: a library an earlier test started (a local cluster, a browser) may
    # have left SIGINT ignored, and interrupt_main does nothing then.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(seconds, _thread.interrupt_main)
    timer.start()
    return timer


@pytest.mark.parametrize("mode", ["fast", "accurate"])
def test_ctrl_c_stops_a_long_step_and_leaves_the_world_as_it_was(mode):
    # A step that would take seconds (fast: 100 boxes kept awake for 60 s of 1/240 s steps, about 3 s; accurate: a
    # pile of 1 mm bodies hit at 1 m/s, which at a contact tolerance of 5e-9 m takes over a second for 0.25 s and
    # runs for minutes over 2 s until its budget is spent) answers Ctrl-C within a fraction of a second: the world
    # checks for signals every 50 ms of its work.
    if mode == "accurate":
        w = tumble.World(mode=mode, gravity=(-18.47, 0.0, -18.23), contact_tolerance=5e-9)
    else:
        w = tumble.World(mode=mode, sleep=False)
    w.add_ground()
    if mode == "fast":
        for k in range(100):
            w.add_body(tumble.Box((0.25, 0.25, 0.25)), position=(0.6 * (k % 10), 0.6 * (k // 10), 0.5))
        span = 60.0
    else:
        w.add_body(tumble.Sphere(0.001), position=(0.0, 0.0, 0.001))
        w.add_body(tumble.Capsule(0.0005, 0.0005), density=1e6, position=(0.0022, 0.0, 0.001))
        w.add_body(tumble.Cylinder(0.001, 0.001), position=(0.0, 0.0022, 0.001), velocity=(0.344, 1.123, 0.0))
        span = 2.0
    x = w.bodies.positions.copy()
    timer = _interrupt_after(0.3)
    clock = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        w.step(span)
    timer.join()
    # 0.3 s to the signal, then at most one contact step or fast step and a 50 ms check interval: 2 s is loose.
    assert time.perf_counter() - clock < 2.0
    assert w.time == 0.0
    np.testing.assert_array_equal(w.bodies.positions, x)


def test_run_releases_the_interpreter_lock():
    # While a run works, another Python thread keeps running: the main thread counts loop iterations during the
    # run. With the lock held it could not run at all until the run ended.
    w = tumble.scenes.cloth(n=20)
    done = threading.Event()
    worker = threading.Thread(target=lambda: (w.run(2.0, 1 / 60), done.set()))
    start = time.perf_counter()
    worker.start()
    count = 0
    while not done.is_set():
        count += 1
    worker.join()
    elapsed = time.perf_counter() - start
    assert elapsed > 0.2, "the run should take a while for this test to mean anything"
    assert count > 10_000, f"only {count} iterations in {elapsed:.2f} s"


def test_cloth_from_python_equals_cloth_from_rust():
    # Same construction order, same arithmetic: the runs agree bit for bit.
    params = dict(n=7, size=0.8, mass=0.3, stiffness=2e3, damping=0.4, pin_stiffness=2e4)
    from_python = tumble.scenes.cloth(**params).run(1.0, 1 / 30)
    from_rust = tumble.World._rust_scene("cloth", **params).run(1.0, 1 / 30)
    np.testing.assert_array_equal(from_python.particle_positions, from_rust.particle_positions)
    np.testing.assert_array_equal(from_python.energy, from_rust.energy)
    assert from_python.report.steps == from_rust.report.steps


def test_spinning_top_from_python_equals_rust():
    # A body, a spring to a body point and Radau5 with coloured finite-difference Jacobians: bit for bit too.
    from_python = tumble.scenes.spinning_top().run(1.0, 0.05)
    from_rust = tumble.World._rust_scene("spinning_top").run(1.0, 0.05)
    np.testing.assert_array_equal(from_python.body_positions, from_rust.body_positions)
    np.testing.assert_array_equal(from_python.body_orientations, from_rust.body_orientations)
    np.testing.assert_array_equal(from_python.energy, from_rust.energy)
    assert from_python.report.steps == from_rust.report.steps


def test_a_keyframed_body_released_flies_on_and_the_runs_join_into_one(tmp_path):
    """A box carried on keyframes at 1 m/s for half a second, then let go (Blender's "Animated" switched off): it
    flies on from where it was at the speed it had, the two runs join into one whose positions run on without a
    jump (the centre of mass throughout), and it exports as one."""
    w = tumble.World()
    box = w.add_body(tumble.Box((0.1, 0.2, 0.3)), keyframes=([0.0, 1.0], [(0, 0, 1), (1, 0, 1)]))
    first = w.run(0.5)
    w.release(box, density=500.0)
    second = w.run(0.5)
    run = tumble.Run.join([first, second])
    assert run.frames == first.frames + second.frames - 1 and run.times[-1] == pytest.approx(1.0)
    x = run.positions_of(box)
    # 1 m/s along x throughout; z held at 1 m, then falling as g t^2 / 2 (to the integrator's 1e-6)
    np.testing.assert_allclose(x[:, 0], run.times, atol=1e-6)
    np.testing.assert_allclose(x[:, 2], 1.0 - 0.5 * 9.81 * np.maximum(run.times - 0.5, 0.0) ** 2, atol=1e-6)
    assert run.export_gltf(tmp_path / "released.glb").stat().st_size > 0
    # and held again: it stays where it is
    w.hold(box)
    still = w.run(0.25).positions_of(box)
    np.testing.assert_array_equal(still, np.repeat(still[:1], len(still), axis=0))
    with pytest.raises(ValueError, match="`body`"):
        w.hold(box)
    with pytest.raises(ValueError, match="`runs`"):
        tumble.Run.join([first, first])


def test_a_run_can_say_how_sensitive_its_outcome_is():
    """A ball in free flight: twins a contact tolerance apart end as far apart (ratio 1); a report without the
    option has no such field."""
    w = tumble.World()
    w.add_body(tumble.Sphere(0.1), position=(0, 0, 1), velocity=(1, 0, 2))
    run = w.run(0.5, sensitivity=3)
    assert run.report.outcome_sensitivity == pytest.approx(1.0, abs=1e-6)  # a shift carries unchanged, to rounding
    assert "outcome          twins started" in str(run.report)
    assert not hasattr(w.run(0.1).report, "outcome_sensitivity")
    with pytest.raises(ValueError, match="`sensitivity`"):
        w.run(0.1, sensitivity=-1)
