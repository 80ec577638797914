"""Baking: the scene's rigid body world run in tumble and its motion written back as keyframes, whole F-curves at
once (``keyframe_points.add`` and ``foreach_set``), so that playback, render and the timeline work as after
Blender's own bake; the rigid body world is then switched off, so that the keyframes play. The bake's progress shows
in the terminal (tumble's bar, or lines in a log) and, given Blender's window manager, in its progress indicator."""

from __future__ import annotations

import sys
import time
from typing import Any, Callable

import numpy as np
import numpy.typing as npt

from tumble._geometry import rotation_matrices
from tumble._progress import AUTO_DELAY, Progress, progress as _progress

from ._read import world_from_scene

Array = npt.NDArray[np.float64]

# The simulation's share of the bake's progress; writing the keyframes, a body at a time (whole F-curves at once,
# quick beside the simulation), the rest.
SIMULATING = 0.95


class BakeProgress(Progress):
    """The bake's progress, shown by ``shown`` (tumble's display, the caller's callable, or None) and by Blender's
    window manager (``progress_begin`` / ``progress_update`` / ``progress_end``, None for none): the run's fractions
    scaled to ``SIMULATING``, then the keyframes written, to 1. A ``Progress`` so that ``World.run`` writes its hint
    above the bar; ``World.run`` closes it after the run, which leaves it open: ``finish`` ends it."""

    def __init__(self, shown: Progress | Callable[[float], None] | None, manager: Any = None) -> None:
        # no display of its own (Progress.__init__ would open a bar): it forwards to ``shown``
        self._shown = shown
        self._manager = manager
        if manager is not None:
            manager.progress_begin(0.0, 1.0)

    def __call__(self, fraction: float) -> None:
        """The run's fraction done (0 to 1)."""
        self.show(SIMULATING * fraction)

    def show(self, fraction: float) -> None:
        """The bake's fraction done (0 to 1)."""
        if self._shown is not None:
            self._shown(fraction)
        if self._manager is not None:
            self._manager.progress_update(fraction)

    def write(self, line: str) -> None:
        """A line above the bar, or in the log (standard error without a display of tumble's)."""
        if isinstance(self._shown, Progress):
            self._shown.write(line)
        else:
            sys.stderr.write(f"tumble: {line}\n")

    def close(self) -> None:
        """Left open when the run ends: the keyframes are still to write."""

    def finish(self) -> None:
        """Ends the display and Blender's progress indicator."""
        if isinstance(self._shown, Progress):
            self._shown.close()
        if self._manager is not None:
            self._manager.progress_end()


def display(progress: bool | Callable[[float], None] | None) -> Progress | Callable[[float], None] | None:
    """The terminal's display for the bake's ``progress``, as ``World.run`` takes it (a bar labelled "bake")."""
    if progress is None:
        return Progress(label="bake", quiet_log=True, delay=AUTO_DELAY)
    if progress is True:
        return Progress(label="bake")
    return _progress(progress)


def _curves(obj: Any) -> Any:
    """A fresh action with a slot for ``obj``, assigned to it; returns its channel bag (Blender 4.4+ actions)."""
    import bpy  # noqa: PLC0415
    from bpy_extras import anim_utils  # noqa: PLC0415

    data = obj.animation_data or obj.animation_data_create()
    action = bpy.data.actions.new(name=f"{obj.name} (tumble)")
    slot = action.slots.new(id_type="OBJECT", name=obj.name)
    data.action = action
    data.action_slot = slot
    return anim_utils.action_ensure_channelbag_for_slot(action, slot)


def _write(bag: Any, path: str, frames: Array, values: Array) -> None:
    """One F-curve per column of ``values`` (F, n) on ``path``, keyed at ``frames``, linear between keys."""
    for index in range(values.shape[1]):
        curve = bag.fcurves.new(path, index=index)
        curve.keyframe_points.add(len(frames))
        curve.keyframe_points.foreach_set("co", np.c_[frames, values[:, index]].astype(np.float32).ravel())
        curve.keyframe_points.foreach_set("interpolation", [1] * len(frames))  # 'LINEAR'
        curve.update()


def bake(scene: Any = None, frame_start: int | None = None, frame_end: int | None = None,
         progress: bool | Callable[[float], None] | None = None, window_manager: Any = None,
         **world_options: Any) -> Any:
    """Bakes ``scene``'s rigid body world (the current scene by default) with tumble over its rigid body cache's
    frame range (or ``frame_start`` to ``frame_end``), writing each active body's location and rotation as
    keyframes and switching the rigid body world off; ``world_options`` go to ``tumble.World``. Returns tumble's
    report of the run, with the bake's time split (``bake_reading_seconds``, ``bake_simulating_seconds``,
    ``bake_writing_seconds``), ``bake_notes`` (the approximations made) and ``bake_broken_at`` (the frames at which
    breakable constraints broke). Raises
    ``BlenderSceneError`` naming every object and setting tumble cannot take.

    ``progress`` takes what ``World.run``'s does: None (the default) a bar on a terminal once the bake has taken two
    seconds, with the time left, and nothing in a log; True a bar from the start (plain lines where standard error
    is a log); False nothing; a callable is called with the fraction of the bake done, rising to 1 when the
    keyframes are written (an exception from it stops the bake; raised during the run, as Ctrl-C there, before any
    keyframe is written).
    ``window_manager`` (Blender's ``context.window_manager``, as the add-on's operator passes it) shows the same
    fractions in Blender's progress indicator (``progress_begin``, ``progress_update``, ``progress_end``)."""
    import bpy  # noqa: PLC0415

    shown = BakeProgress(display(progress), window_manager)
    try:
        return _bake(scene or bpy.context.scene, frame_start, frame_end, shown, world_options)
    finally:
        shown.finish()


def _bake(scene: Any, frame_start: int | None, frame_end: int | None, shown: BakeProgress,
          world_options: dict[str, Any]) -> Any:
    """``bake``'s work, its progress shown by ``shown``."""
    clock = time.perf_counter()
    mapped = world_from_scene(scene, **world_options)
    start = mapped.frame_start if frame_start is None else int(frame_start)
    end = mapped.frame_end if frame_end is None else int(frame_end)
    if end <= start:
        raise ValueError(f"invalid argument `frame_end`: must be after frame_start ({start}), got {end}")
    read = time.perf_counter() - clock
    clock = time.perf_counter()
    run = run_with_switches(mapped, start, end, shown)
    simulated = time.perf_counter() - clock
    clock = time.perf_counter()
    write_keyframes(scene, mapped, run, start, shown)
    scene.rigidbody_world.enabled = False
    shown.show(1.0)
    written = time.perf_counter() - clock
    frames = start + np.arange(len(run.times))
    from tumble._report import Report  # noqa: PLC0415

    split = {"bake_reading_seconds": read, "bake_simulating_seconds": simulated, "bake_writing_seconds": written}
    # the frames (from the start, fractional) at which breakable constraints broke
    broke = [start + float(t - run.times[0]) / mapped.frame_time for t in run.joint_break_times]
    lines = [f"bake: reading {read:.3f} s, simulating {simulated:.3f} s, writing {written:.3f} s "
             f"({len(frames)} frames of {len(mapped.moving)} bodies)"]
    if broke:
        lines.append(f"bake: {len(broke)} constraints broke, the first at frame {broke[0]:.2f}")
    text = run.report._text + "\n" + "\n".join(lines + [f"note: {n}" for n in mapped.notes])
    return Report({**run.report.as_dict(), **split, "bake_notes": list(mapped.notes), "bake_broken_at": broke,
                   "_text": text})


def write_keyframes(scene: Any, mapped: Any, run: Any, start: int, shown: Any = None) -> None:
    """Writes ``run`` (of ``mapped.world`` or a copy of it) as keyframes of each moving object of ``scene`` from
    frame ``start``: its origin's location and its rotation in the object's rotation mode."""
    from mathutils import Quaternion  # noqa: PLC0415

    frames = (start + np.arange(len(run.times))).astype(np.float64)
    for written_bodies, name in enumerate(mapped.moving):
        if shown is not None:
            shown.show(SIMULATING + (1.0 - SIMULATING) * written_bodies / len(mapped.moving))
        obj = scene.objects[name]
        location, wxyz = object_poses(scene, mapped, run, name)
        bag = _curves(obj)
        _write(bag, "location", frames, location)
        if obj.rotation_mode == "QUATERNION":
            _write(bag, "rotation_quaternion", frames, wxyz)
        elif obj.rotation_mode == "AXIS_ANGLE":
            obj.rotation_mode = "QUATERNION"
            _write(bag, "rotation_quaternion", frames, wxyz)
        else:  # Euler angles in the object's order, each frame's chosen nearest the last's (no flips)
            angles, last = [], None
            for q in wxyz:
                e = Quaternion(tuple(q)).to_euler(obj.rotation_mode, last) if last else \
                    Quaternion(tuple(q)).to_euler(obj.rotation_mode)
                angles.append(tuple(e))
                last = e
            _write(bag, "rotation_euler", frames, np.array(angles))


def object_poses(scene: Any, mapped: Any, run: Any, name: str) -> tuple[np.ndarray, np.ndarray]:
    """Object ``name``'s location (in the scene's units) and turn (w, x, y, z) at each frame of ``run``: its origin
    where its body's pose puts it."""
    unit = float(scene.unit_settings.scale_length) or 1.0
    column = mapped.world.bodies.row(mapped.handles[name])
    wxyz = run.body_orientations[:, column]
    origin = run.body_positions[:, column] + rotation_matrices(wxyz) @ mapped.origins[name]
    return origin / unit, wxyz


def run_with_switches(mapped: Any, start: int, end: int, shown: Any) -> Any:
    """The mapped world's run from frame ``start`` to ``end``: in one call, or, where objects' "Animated" is switched
    during it (``mapped.switches``), a call up to each such frame, the objects let go there (``World.release``) or
    taken over to follow their animation from there (``World.hold``), and the runs joined."""
    from tumble._geometry import rotation_matrix  # noqa: PLC0415
    from tumble._run import Run  # noqa: PLC0415

    world, frame_time = mapped.world, mapped.frame_time
    stops = sorted({f for changes in mapped.switches.values() for f, _ in changes if start < f < end})
    bounds = [start, *stops, end]
    runs: list[Any] = []
    for k, (a, b) in enumerate(zip(bounds, bounds[1:])):
        if k > 0:
            for name, changes in mapped.switches.items():
                for frame, animated in changes:
                    if frame == a:
                        _switch(mapped, name, animated, runs[-1], rotation_matrix)
        share = (a - start) / (end - start), (b - a) / (end - start)
        runs.append(world.run((b - a) * frame_time, frame_time,
                              progress=lambda f, s=share: shown(s[0] + s[1] * f)))
    return runs[0] if len(runs) == 1 else Run.join(runs)


def _switch(mapped: Any, name: str, animated: bool, run: Any, rotation_matrix: Any) -> None:
    """Object ``name``'s "Animated" switched at the end of ``run``: on, its body follows the object's animation (its
    centre of mass where the animation puts its origin); off, it is let go as it moved, its origin in its new body
    frame kept for the keyframes."""
    world = mapped.world
    handle = mapped.handles[name]
    row = world.bodies.row(handle)
    if animated:
        times, locations, rotations = mapped.paths[name]
        centres = locations - np.einsum("kij,j->ki", rotation_matrices(rotations), mapped.origins[name])
        world.hold(handle, (times, centres, rotations))
        return
    # the object's origin now, from the frame its keyframes pose; then from its centre of mass
    turn = rotation_matrix(run.body_orientations[-1, row])
    origin = run.body_positions[-1, row] + turn @ mapped.origins[name]
    world.release(handle, density=mapped.densities[name])
    mapped.origins[name] = turn.T @ (origin - world.bodies.positions[row])
