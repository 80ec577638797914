"""The interactive 3-D viewer of a run (``Run.show``, ``World.show``) and its static export (``Run.export_viewer``),
built on viser (``pip install "./python[viewer]"`` from the clone): a web server in a background thread that drives
viser's prebuilt three.js client from Python.

The scene: each distinct collider shape is meshed once and drawn as one batched (instanced) mesh with an instance per
collider, posed every frame from its body's pose; half-spaces are a large square with a grid under the scene;
bodies without colliders are small axes; particles a point cloud; springs (orange) and joints (purple) line
segments; each frame's contacts red points with short normals. The GUI panel beside it: play/pause, a frame slider
to scrub, playback speed, looping, the time, and plots of energy (kinetic, potential, total) and of the largest
penetration (when the run has contacts); with joints, the largest gap between the anchors of a ball, hinge or weld
joint per frame (from the bodies' poses) and the run's largest joint error from the report.

The static export is viser's own: the scene's messages recorded frame after frame and embedded with viser's client
in one self-contained HTML file, which a browser plays from disk (``file://``, no server) with viser's playback bar
(play/pause, scrub, speed). viser records only the scene, not the GUI panel, so the export has no plots.
"""

from __future__ import annotations

import contextlib
import io
import threading
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._geometry import normal_links
from .._install import install_hint
from ._scene import Scene

if TYPE_CHECKING:
    from .._run import Run
    from .._world import World

def _viser() -> Any:
    try:
        import viser  # noqa: PLC0415
    except ImportError:
        raise ImportError(f"the viewer needs viser: {install_hint('viewer')}") from None
    return viser


def _server(viser: Any, host: str, port: int, label: str | None) -> Any:
    """A viser server, without the banner it prints on start."""
    with contextlib.redirect_stdout(io.StringIO()):
        return viser.ViserServer(host=host, port=port, label=label, verbose=False)


def _stop(server: Any) -> None:
    """Stops a viser server, without its goodbye line."""
    with contextlib.redirect_stdout(io.StringIO()):
        server.stop()


def check_arguments(port: object, block: object, host: object) -> int:
    """Checks the viewer's arguments (ValueError naming a bad one); returns ``port`` as an int (0 lets the system
    choose a free port)."""
    if isinstance(port, bool) or not isinstance(port, (int, np.integer)) or not 0 <= int(port) <= 65535:
        raise ValueError(f"invalid argument `port`: expected a whole number from 0 to 65535, got {port!r}")
    if not isinstance(block, bool):
        raise ValueError(f"invalid argument `block`: expected True or False, got {block!r}")
    if not isinstance(host, str) or not host.strip():
        raise ValueError(f"invalid argument `host`: expected a host name or address, got {host!r}")
    return int(port)


def _length_unit(largest: float) -> tuple[str, float]:
    """The unit (m, mm, µm or nm) in which ``largest`` metres reads as a number from 0.1 up, and its factor."""
    for unit, scale in (("m", 1.0), ("mm", 1e3), ("µm", 1e6)):
        if largest * scale >= 0.1:
            return unit, scale
    return "nm", 1e9


def _axes(*series: np.ndarray) -> tuple[dict[str, Any], dict[str, Any]]:
    """uPlot's time axis and a value axis wide enough for the values' labels (uPlot's default cuts long ones)."""
    largest = max((float(np.nanmax(np.abs(s))) for s in series if np.any(np.isfinite(s))), default=0.0)
    return {}, {"size": max(50, 30 + 7 * len(f"{largest:,.0f}"))}


class Viewer:
    """A live viewer of a run in the browser at ``url``, until ``stop()`` (a context manager stops it on exit).

    ``seek(frame)`` shows a frame, ``play()`` and ``pause()`` play it at ``speed`` times real time; the browser's
    panel does the same. ``server`` is the viser server, for adding to the scene."""

    def __init__(self, run: "Run", port: int = 8080, host: str = "127.0.0.1") -> None:
        port = check_arguments(port, False, host)
        viser = _viser()
        if run.frames == 0:
            raise ValueError("invalid argument `run`: the run has no frames to show")
        self.run = run
        self._lock = threading.RLock()
        self._stopped = threading.Event()
        self._playing = False
        self._clock = 0.0  # playback time since the first frame, s
        self._frame = 0
        name = run.name or "tumble run"
        self.server = server = _server(viser, host, port, "tumble viewer")
        try:
            self.scene = Scene(server, run)
            self._gui(viser, name)
            self._show(0)
        except BaseException:
            _stop(server)
            raise
        shown = "localhost" if host in ("0.0.0.0", "::") else host
        self.url = f"http://{shown}:{server.get_port()}"
        self._thread = threading.Thread(target=self._loop, name="tumble-viewer", daemon=True)
        self._thread.start()

    def _gui(self, viser: Any, name: str) -> None:
        gui, run = self.server.gui, self.run
        gui.configure_theme(show_share_button=False, control_width="medium")
        gui.main_panel.dock_right()  # beside the scene, not over it
        self._title = gui.add_markdown("")
        last = max(1, run.frames - 1)
        self._button = gui.add_button("Play", icon=viser.Icon.PLAYER_PLAY, disabled=run.frames < 2)
        self._slider = gui.add_slider("Frame", 0, last, 1, 0, disabled=run.frames < 2)
        self._speed = gui.add_slider("Speed", 0.05, 4.0, 0.05, 1.0)
        self._repeat = gui.add_checkbox("Loop", True)
        labels = self.scene.labels
        if labels:
            names = gui.add_checkbox("Names", all(label.visible for _, label in labels))

            def toggle(_: Any) -> None:
                for _, label in labels:
                    label.visible = names.value

            names.on_update(toggle)
        self._button.on_click(lambda _: self.pause() if self._playing else self.play())
        self._slider.on_update(lambda _: self._scrubbed())
        t = np.asarray(run.times, dtype=float)
        x_axis: dict[str, Any] = {"x": {"time": False}}
        self.plots: list[str] = []  # the titles of the plots beside the scene, in order
        if run.frames >= 2:
            series = ({"label": "t (s)"}, {"label": "kinetic", "stroke": "#e74c3c", "width": 2},
                      {"label": "potential", "stroke": "#3498db", "width": 2},
                      {"label": "total", "stroke": "#222222", "width": 2})
            self.plots.append("Energy (J)")
            with gui.add_folder("Energy (J)"):
                energies = (run.kinetic_energy, run.potential_energy, run.energy)
                gui.add_uplot((t, *energies), series, scales=x_axis, axes=_axes(*energies), aspect=1.6)
            if int(np.sum(run.contact_counts)):
                unit, scale = _length_unit(float(np.nanmax(run.penetration)))
                self.plots.append(f"Largest penetration ({unit})")
                with gui.add_folder(f"Largest penetration ({unit})"):
                    depth = scale * np.asarray(run.penetration, dtype=float)
                    gui.add_uplot((t, depth), ({"label": "t (s)"}, {"label": "penetration", "stroke": "#c0392b",
                                  "width": 2}), scales=x_axis, axes=_axes(depth), aspect=1.6)
        else:
            gui.add_markdown(f"Energy: kinetic {float(run.kinetic_energy[0]):.6g} J, potential "
                             f"{float(run.potential_energy[0]):.6g} J, total {float(run.energy[0]):.6g} J  \n"
                             f"Largest penetration: {float(run.penetration[0]):.3g} m "
                             f"({int(run.contact_counts[0])} contacts)")
        if any(kind != "spring" for kind, _, _ in run.links):
            from .._plots import joint_gaps  # noqa: PLC0415

            gaps = joint_gaps(run)
            if gaps is not None and run.frames >= 2:
                unit, scale = _length_unit(max(float(np.nanmax(gaps)), 1e-300))
                self.plots.append(f"Joint gap ({unit})")
                with gui.add_folder(f"Joint gap ({unit})"):
                    gap = scale * gaps
                    gui.add_uplot((t, gap), ({"label": "t (s)"}, {"label": "ball, hinge, weld anchors apart",
                                  "stroke": "#7b3fc8", "width": 2}), scales=x_axis, axes=_axes(gap), aspect=1.6)
            fields = run.report.as_dict()
            error, angle = fields.get("joint_error"), fields.get("joint_angle_error")
            text = "not reported" if error is None else f"{error:.3g} m" + (
                "" if angle is None else f", {angle:.3g} rad")
            gui.add_markdown(f"Joints: the run's largest joint error {text} (from the report)")
        self._name = name

    def _show(self, k: int) -> None:
        """Poses the scene at frame ``k`` and updates the title."""
        with self._lock:
            self._frame = k
            with self.server.atomic():
                self.scene.pose(k)
                self._title.content = (f"**{self._name}**  \nt = {float(self.run.times[k]):.3f} s, "
                                       f"frame {k} of {self.run.frames - 1}")

    def _scrubbed(self) -> None:
        """The frame slider moved (in a browser or by ``seek``): show its frame from there."""
        with self._lock:
            k = int(self._slider.value)
            if k != self._frame:
                self._clock = float(self.run.times[k] - self.run.times[0])
                self._show(k)

    def _loop(self) -> None:
        """Plays: about 60 times a second, moves the slider to the frame of the playback clock."""
        last = time.perf_counter()
        times = np.asarray(self.run.times, dtype=float)
        while not self._stopped.wait(1 / 60):
            now = time.perf_counter()
            elapsed, last = now - last, now
            if not self._playing:
                continue
            with self._lock:
                clock = self._clock + elapsed * float(self._speed.value)
                if clock > times[-1] - times[0]:
                    if self._repeat.value:
                        clock = 0.0
                    else:
                        clock = float(times[-1] - times[0])
                        self.pause()
                k = int(np.searchsorted(times, times[0] + clock, side="right")) - 1
                self._slider.value = k  # calls _scrubbed, which resets the clock to the frame's time
                self._clock = clock

    @property
    def frame(self) -> int:
        """The frame shown."""
        return self._frame

    @property
    def playing(self) -> bool:
        """Whether the run plays."""
        return self._playing

    def seek(self, frame: int) -> None:
        """Shows ``frame`` (negative counts from the end), as the slider does."""
        frames = self.run.frames
        if isinstance(frame, bool) or not isinstance(frame, (int, np.integer)) or not -frames <= frame < frames:
            raise ValueError(f"invalid argument `frame`: the run has {frames} frames, got {frame!r}")
        with self._lock:
            self._slider.value = int(frame) % frames

    def play(self) -> None:
        """Plays from the frame shown (from the start if it is the last)."""
        if self.run.frames < 2:
            return
        with self._lock:
            if self._frame == self.run.frames - 1:
                self.seek(0)
            self._playing = True
            self._button.label, self._button.icon = "Pause", _viser().Icon.PLAYER_PAUSE

    def pause(self) -> None:
        """Stops playing, keeping the frame shown."""
        with self._lock:
            self._playing = False
            self._button.label, self._button.icon = "Play", _viser().Icon.PLAYER_PLAY

    def wait(self) -> None:
        """Blocks until Ctrl-C (or ``stop`` from another thread), then stops the server."""
        try:
            while not self._stopped.wait(0.25):
                pass
        except KeyboardInterrupt:
            pass
        finally:
            self.stop()

    def stop(self) -> None:
        """Stops the server (the page loses its connection). Calling it again does nothing."""
        if self._stopped.is_set():
            return
        self._stopped.set()
        self._thread.join(timeout=2.0)
        _stop(self.server)

    def __enter__(self) -> "Viewer":
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()

    def __repr__(self) -> str:
        state = "stopped" if self._stopped.is_set() else "playing" if self._playing else "paused"
        return f"Viewer({self.url}, frame {self._frame} of {self.run.frames - 1}, {state})"


def show(run: "Run", port: int = 8080, block: bool = True, host: str = "127.0.0.1") -> Viewer:
    """``Run.show``: serves the viewer; with ``block`` prints its address and waits for Ctrl-C."""
    check_arguments(port, block, host)
    viewer = Viewer(run, port, host)
    if block:
        print(f"tumble viewer: {viewer.url} (Ctrl-C stops it)", flush=True)
        viewer.wait()
    return viewer


def export(run: "Run", path: Path) -> Path:
    """``Run.export_viewer``: the run recorded frame by frame into one HTML file with viser's client."""
    if path.suffix.lower() not in (".html", ".htm"):
        raise ValueError(f"invalid argument `path`: the viewer is an HTML file (.html), got {path.name!r}")
    if run.frames == 0:
        raise ValueError("invalid argument `run`: the run has no frames to export")
    viser = _viser()
    # viser records what a server sends; this one listens on a free local port only while it records
    server = _server(viser, "127.0.0.1", 0, None)
    try:
        scene = Scene(server, run)
        scene.pose(0)
        recording = server.get_scene_serializer()
        for k in range(1, run.frames):
            recording.insert_sleep(max(0.0, float(run.times[k] - run.times[k - 1])))
            with server.atomic():
                scene.pose(k)
        path.write_text(recording.as_html(), encoding="utf-8")
    finally:
        _stop(server)
    return path


def snapshot(world: "World") -> "Run":
    """A one-frame run of the world as it is now, with its current contacts (``World.show`` without a duration)."""
    from .._run import Run  # noqa: PLC0415

    contacts = world.contacts()
    points = np.asarray(contacts["points"], dtype=float).reshape(-1, 3)
    normals = np.asarray(contacts["normals"], dtype=float).reshape(-1, 3)
    gaps = np.asarray(contacts.get("gaps", []), dtype=float)
    kinetic, potential = float(world.kinetic_energy()), float(world.potential_energy())

    def frame(a: Any, width: int) -> np.ndarray:
        return np.asarray(a, dtype=float).reshape(1, -1, width)

    empty = np.zeros(0)
    return Run(
        times=np.array([float(world.time)]),
        particle_positions=frame(world.particles.positions, 3),
        particle_velocities=frame(world.particles.velocities, 3),
        body_positions=frame(world.bodies.positions, 3), body_orientations=frame(world.bodies.orientations, 4),
        body_velocities=frame(world.bodies.velocities, 3),
        body_angular_velocities=frame(world.bodies.angular_velocities, 3),
        kinetic_energy=np.array([kinetic]), potential_energy=np.array([potential]),
        energy=np.array([kinetic + potential]), momentum=frame(world.momentum(), 3)[0],
        angular_momentum=frame(world.angular_momentum(), 3)[0], step_times=empty, step_sizes=empty,
        penetration=np.array([max(0.0, -float(gaps.min())) if len(gaps) else 0.0]), contact_events=empty,
        contact_counts=np.array([len(points)], dtype=np.int64), contact_points=np.stack([points, normals], axis=1),
        joint_break_times=empty, report=world.report, particles=world.particles.handles, bodies=world.bodies.handles,
        shapes=world._body_shapes(), links=normal_links(world._links()), names=world.bodies.names,
        colors=world.bodies.colors)
