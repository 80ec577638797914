"""The Blender bake's progress: ``tumble.blender.bake(progress=...)`` takes what ``World.run``'s progress takes (a
callable gets the fractions of the bake, rising to 1; True writes lines to a log; False nothing), and Blender's
window manager shows the same fractions in its progress indicator, begun and ended around the bake, as the add-on's
operator asks. Headless with Blender as a module (the ``blender`` extra)."""

import pytest

bpy = pytest.importorskip("bpy", reason="Blender as a module is the `blender` extra")
import tumble.blender as tb  # noqa: E402
from tumble.blender import _bake  # noqa: E402
from blender_scenes import blender_body, empty_scene, ground  # noqa: E402


class WindowManager:
    """A stand-in for Blender's window manager that records the progress calls (in background Blender they draw
    nothing to look at)."""

    def __init__(self):
        self.calls = []

    def progress_begin(self, low, high):
        self.calls.append(("begin", low, high))

    def progress_update(self, value):
        self.calls.append(("update", value))

    def progress_end(self):
        self.calls.append(("end",))

    def updates(self):
        return [c[1] for c in self.calls if c[0] == "update"]


def falling_boxes(frames=60):
    scene = empty_scene(frames)
    ground()
    for k in range(3):
        blender_body("cube", f"box {k}", (k * 2.0, 0, 1 + k), "BOX", size=0.5)
    return scene


def rising_to_one(fractions):
    assert len(fractions) >= 3, "more than the start and the end"
    assert all(b >= a for a, b in zip(fractions, fractions[1:])), "never back"
    assert 0.0 <= fractions[0] < 1.0 and fractions[-1] == 1.0


def test_a_callable_gets_the_fractions_of_the_bake_rising_to_one():
    scene = falling_boxes()
    fractions = []
    report = tb.bake(scene, progress=fractions.append)
    rising_to_one(fractions)
    # the run's fractions come first, the keyframes' last (a box each)
    assert max(f for f in fractions if f < 1.0) >= _bake.SIMULATING
    assert sum(_bake.SIMULATING < f < 1.0 for f in fractions) == 2, "boxes 2 and 3 of 3"
    assert report.bake_writing_seconds >= 0 and not scene.rigidbody_world.enabled


def test_the_window_manager_shows_the_same_fractions():
    scene = falling_boxes()
    fractions, manager = [], WindowManager()
    tb.bake(scene, progress=fractions.append, window_manager=manager)
    assert manager.calls[0] == ("begin", 0.0, 1.0) and manager.calls[-1] == ("end",)
    assert [c[0] for c in manager.calls[1:-1]] == ["update"] * (len(manager.calls) - 2)
    rising_to_one(manager.updates())
    assert manager.updates() == fractions


def test_blenders_own_window_manager_takes_the_progress():
    """In background Blender the window manager's progress calls are there and do nothing visible."""
    scene = falling_boxes(20)
    tb.bake(scene, window_manager=bpy.context.window_manager)
    assert not scene.rigidbody_world.enabled


def test_the_progress_ends_when_the_bake_stops():
    scene = falling_boxes()
    manager = WindowManager()

    def stop(fraction):
        if fraction > 0.1:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        tb.bake(scene, progress=stop, window_manager=manager)
    assert manager.calls[-1] == ("end",)
    assert scene.rigidbody_world.enabled, "no keyframes written: the rigid body world is left on"
    assert all(o.animation_data is None for o in scene.objects)


def test_true_writes_lines_to_a_log_and_false_nothing(capsys):
    """Standard error is no terminal under pytest: the display writes plain lines, the last at 100 %."""
    tb.bake(falling_boxes(), progress=True)
    err = capsys.readouterr().err
    assert "bake 100% done after" in err and "\r" not in err
    tb.bake(falling_boxes(), progress=False)
    tb.bake(falling_boxes())  # the default: nothing in a log
    assert "bake" not in capsys.readouterr().err


def test_a_bad_progress_is_refused_naming_it():
    with pytest.raises(ValueError, match="invalid argument `progress`"):
        tb.bake(falling_boxes(), progress="yes")


def test_the_operator_shows_its_progress_in_the_window_manager(monkeypatch):
    """The add-on's operator bakes with its context's window manager and a progress display."""
    scene = falling_boxes(30)
    seen = {}
    real = _bake.bake

    def recording(*args, **kwargs):
        seen.update(kwargs)
        return real(*args, **kwargs)

    monkeypatch.setattr(_bake, "bake", recording)
    tb.register()
    try:
        assert bpy.ops.tumble.bake("EXEC_DEFAULT", frame_start=1, frame_end=30) == {"FINISHED"}
    finally:
        tb.unregister()
    assert seen["window_manager"] == bpy.context.window_manager
    assert seen["progress"] is True
    assert not scene.rigidbody_world.enabled
