"""The engine layer from Python: runs repeat bit for bit (reruns, thread counts, Rust-built and Python-built
scenes), options that do not apply are ValueErrors naming them, frames do not change fast mode's physics, and the
plan names the stages that run."""

import numpy as np
import pytest

import tumble


def final_state(w: tumble.World) -> np.ndarray:
    """Every number of the world's state, flattened."""
    b, p = w.bodies, w.particles
    return np.concatenate(
        [a.ravel() for a in (b.positions, b.orientations, b.velocities, b.angular_velocities, p.positions, p.velocities)]
    )


def python_dominoes(count: int = 20, spacing: float = 0.5) -> tumble.World:
    """The dominoes scene written with the Python API, in the Rust scene's order."""
    w = tumble.World(mode="fast", dt=1 / 240)
    w.add_ground(0.0, restitution=0.1, friction=0.6)
    for k in range(count):
        w.add_body(
            tumble.Box((0.04, 0.2, 0.4)),
            density=700.0,
            position=(k * spacing, 0.0, 0.4),
            restitution=0.1,
            friction=0.4,
            angular_velocity=(0.0, 2.0, 0.0) if k == 0 else None,
        )
    return w


def test_dominoes_repeat_bit_for_bit_across_reruns_threads_and_languages():
    ends = []
    for build, threads in [(tumble.scenes.dominoes, 0), (tumble.scenes.dominoes, 0), (tumble.scenes.dominoes, 1),
                           (python_dominoes, 0)]:
        w = build()
        w.threads = threads
        w.run(6.0, 1 / 60)
        ends.append(final_state(w))
    for k, e in enumerate(ends[1:], 1):
        assert np.array_equal(ends[0], e), f"run {k} differs by up to {np.abs(ends[0] - e).max()}"


def test_the_pile_repeats_bit_for_bit_on_one_thread_and_many():
    ends = []
    for threads in (0, 1, 2):
        w = tumble.World._rust_scene("pile", side=10, layers=1)
        w.threads = threads
        w.run(1.0, 1 / 60)
        ends.append(final_state(w))
    assert all(np.array_equal(ends[0], e) for e in ends[1:])


def test_options_that_do_not_apply_raise_value_error_naming_them():
    with pytest.raises(ValueError, match="integrator"):
        tumble.World(mode="fast", integrator="radau5")
    with pytest.raises(ValueError, match="rtol"):
        tumble.World(mode="fast", rtol=1e-8)
    with pytest.raises(ValueError, match="substeps"):
        tumble.World(substeps=4)
    with pytest.raises(ValueError, match="solver"):
        tumble.World(solver="soft")
    with pytest.raises(ValueError, match="solver"):
        tumble.World(mode="fast", solver="newton")
    w = tumble.World(mode="fast", dt=1 / 120, sleep=False)
    with pytest.raises(ValueError, match="integrator"):
        w.set_integrator("rk4", dt=0.01)
    with pytest.raises(ValueError, match="dt"):
        w.set_mode("accurate", dt=0.01)
    with pytest.raises(ValueError, match="`params`"):
        tumble.World._rust_scene("pile", colour=3)
    with pytest.raises(ValueError, match="`side`"):
        tumble.World._rust_scene("pile", side=2.5)


def test_fast_frames_every_quarter_step_or_every_step_end_in_the_same_state():
    dt = 1 / 240
    ends = []
    for interval in (dt / 4, dt):
        w = tumble.scenes.dominoes(count=5)
        run = w.run(1.0, interval)
        assert np.all(np.diff(run.times) > 0) and run.times[-1] == pytest.approx(1.0, abs=1e-12)
        assert len(run.step_times) == 240 and np.all(run.step_sizes == dt)
        ends.append(final_state(w))
    assert np.array_equal(ends[0], ends[1])
    w = tumble.scenes.dominoes(count=5)
    with pytest.raises(ValueError, match="`dt`"):
        w.step(0.001)


def test_the_report_shows_the_planned_stages_running():
    w = tumble.scenes.dominoes(count=3)
    w.run(1.0)
    assert w.report.stages_ran == w.plan()["stages"]
    assert "stages ran" in w.report.details()
