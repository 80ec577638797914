"""The interactive 3-D viewer of a run (``Run.show``, ``World.show``) and its static export (``Run.export_viewer``),
built on viser (``pip install "tumble[viewer]"``): a web server in a background thread that drives viser's prebuilt
three.js client from Python.

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
import math
import threading
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ._geometry import normal_links, rotation_matrices

if TYPE_CHECKING:
    from ._run import Run
    from ._world import World

# body colours (a body keeps its colour across frames and runs): saturated, so that they stand out of the grey
# ground and the light background
PALETTE = np.array([(231, 76, 60), (52, 152, 219), (46, 204, 113), (155, 89, 182), (241, 196, 15),
                    (230, 126, 34), (26, 188, 156), (236, 64, 122)], dtype=np.uint8)
GROUND = (190, 190, 185)
SPRING = (230, 140, 20)
JOINT = (120, 60, 200)
CONTACT = (220, 20, 20)
PARTICLE = (70, 70, 70)


def _viser() -> Any:
    try:
        import viser  # noqa: PLC0415
    except ImportError:
        raise ImportError('the viewer needs viser: pip install "tumble[viewer]"') from None
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


def quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The products a b of quaternions (..., 4) stored (w, x, y, z)."""
    aw, ax, ay, az = np.moveaxis(np.asarray(a, dtype=float), -1, 0)
    bw, bx, by, bz = np.moveaxis(np.asarray(b, dtype=float), -1, 0)
    return np.stack([aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw], axis=-1)


def _z_to(n: np.ndarray) -> np.ndarray:
    """The quaternion (w, x, y, z) of the shortest rotation taking +z to the unit vector ``n``."""
    axis = np.cross((0.0, 0.0, 1.0), n)
    s, c = float(np.linalg.norm(axis)), float(n[2])
    if s < 1e-12:
        return np.array([1.0, 0.0, 0.0, 0.0]) if c > 0 else np.array([0.0, 1.0, 0.0, 0.0])
    half = 0.5 * math.atan2(s, c)
    return np.array([math.cos(half), *(math.sin(half) * axis / s)])


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


def _nice(x: float) -> float:
    """The number 1, 2 or 5 times a power of ten nearest below ``x`` (grid cells)."""
    p = 10.0 ** math.floor(math.log10(x))
    return max(m * p for m in (1.0, 2.0, 5.0) if m * p <= x)


class Scene:
    """A run's scene on a viser server: the nodes built once, then posed at any frame by ``pose``."""

    def __init__(self, server: Any, run: "Run") -> None:
        self.run = run
        scene = server.scene
        bodies = run.body_positions.shape[1]
        shapes = [run.shapes[b] if b < len(run.shapes) else [] for b in range(bodies)]
        # colliders grouped by shape (its JSON): each group one mesh, an instance per collider
        groups: dict[str, tuple[Any, list[tuple[int, Any, Any]]]] = {}
        planes: list[tuple[int, Any, Any, Any]] = []
        radius = np.zeros(bodies)
        for b, colliders in enumerate(shapes):
            for shape, offset, orientation in colliders:
                if shape.kind == "half-space":
                    planes.append((b, shape, offset, orientation))
                    continue
                key = shape.__reduce__()[1][0]
                groups.setdefault(key, (shape, []))[1].append((b, offset, orientation))
        meshes = {key: tuple(np.asarray(a) for a in shape.triangle_mesh()) for key, (shape, _) in groups.items()}
        for key, (_, members) in groups.items():
            extent = float(np.linalg.norm(meshes[key][0], axis=1).max(initial=0.0))
            for b, offset, _ in members:
                radius[b] = max(radius[b], extent + float(np.linalg.norm(offset)))
        self.center, self.size = _bounds(run, radius, [b for b, *_ in planes])
        size = self.size

        self.groups: list[tuple[Any, np.ndarray, np.ndarray, np.ndarray]] = []
        for i, (key, (shape, members)) in enumerate(groups.items()):
            rows = np.array([b for b, _, _ in members], dtype=np.int64)
            offsets = np.array([o for _, o, _ in members], dtype=float).reshape(-1, 3)
            rotations = np.array([q for _, _, q in members], dtype=float).reshape(-1, 4)
            handle = scene.add_batched_meshes_simple(
                f"/bodies/{shape.kind}_{i}", meshes[key][0], meshes[key][1],
                batched_wxyzs=np.tile((1.0, 0.0, 0.0, 0.0), (len(rows), 1)), batched_positions=np.zeros((len(rows), 3)),
                batched_colors=PALETTE[rows % len(PALETTE)], lod="off")
            self.groups.append((handle, rows, offsets, rotations))
        bare = np.array([b for b in range(bodies) if not shapes[b]], dtype=np.int64)
        self.axes = None if not len(bare) else (scene.add_batched_axes(
            "/bodies/axes", np.tile((1.0, 0.0, 0.0, 0.0), (len(bare), 1)), np.zeros((len(bare), 3)),
            axes_length=0.08 * size, axes_radius=0.006 * size), bare)
        for i, (b, shape, offset, orientation) in enumerate(planes):
            self._plane(scene, i, b, shape, offset, orientation)

        self.particles = None
        if run.particle_positions.shape[1]:
            self.particles = scene.add_point_cloud(
                "/particles", np.asarray(run.particle_positions[0], dtype=np.float32), PARTICLE,
                point_size=0.006 * size, point_shape="circle", precision="float32")
        self.links = None
        if run.links:
            colors = np.array([SPRING if kind == "spring" else JOINT for kind, _, _ in run.links], dtype=np.uint8)
            self.links = scene.add_line_segments(
                "/links", run.link_segments(0), np.repeat(colors[:, None, :], 2, axis=1), thickness=0.002 * size)
        self.contact_points = self.contact_normals = None
        if int(np.sum(run.contact_counts)):
            c = run.contact_points[:1]
            self.contact_points = scene.add_point_cloud(
                "/contacts/points", np.asarray(c[:, 0], dtype=np.float32), CONTACT, point_size=0.008 * size,
                point_shape="circle", precision="float32", visible=False)
            self.contact_normals = scene.add_line_segments(
                "/contacts/normals", self._normals(c), CONTACT, thickness=0.002 * size, visible=False)
        server.initial_camera.look_at = self.center
        server.initial_camera.position = self.center + size * np.array([0.35, -0.8, 0.5])
        server.initial_camera.near = max(1e-4, 1e-3 * size)
        server.initial_camera.far = max(1e3, 100.0 * size)

    def _plane(self, scene: Any, i: int, b: int, shape: Any, offset: Any, orientation: Any) -> None:
        """A half-space as an opaque square with a grid, under the scene (static: posed at the first frame)."""
        run = self.run
        # its boundary plane in the collider's frame, from the library's square of it (a triangle faces outwards)
        vertices, triangles = shape.triangle_mesh(None, 1.0)
        v = np.asarray(vertices, dtype=float)
        a, c, d = v[np.asarray(triangles, dtype=np.int64)[0]]
        normal = np.cross(c - a, d - a)
        rotation = rotation_matrices(quat_mul(run.body_orientations[0, b], orientation))
        n = rotation @ (normal / np.linalg.norm(normal))
        point = (run.body_positions[0, b] + rotation_matrices(run.body_orientations[0, b]) @ np.asarray(offset, float)
                 + rotation @ v.mean(axis=0))
        # the square's centre: the scene's centre projected onto the plane
        center = self.center - float(np.dot(self.center - point, n)) * n
        width = 3.0 * self.size + 2.0 * float(np.linalg.norm(center - point))
        cell = _nice(self.size / 10.0)
        scene.add_grid(f"/ground/plane_{i}", width, width, plane="xy", cell_size=cell, section_size=5 * cell,
                       cell_color=(160, 160, 155), section_color=(120, 120, 115), plane_color=GROUND,
                       plane_opacity=1.0, shadow_opacity=0.25, fade_distance=10.0 * width,
                       wxyz=_z_to(n), position=center)

    def _normals(self, contacts: np.ndarray) -> np.ndarray:
        return np.stack([contacts[:, 0], contacts[:, 0] + 0.04 * self.size * contacts[:, 1]], axis=1)

    def pose(self, k: int) -> None:
        """Poses every node at frame ``k``."""
        run = self.run
        positions, orientations = run.body_positions[k], run.body_orientations[k]
        rotations = rotation_matrices(orientations) if len(orientations) else np.zeros((0, 3, 3))
        for handle, rows, offsets, collider_rotations in self.groups:
            handle.batched_positions = positions[rows] + np.einsum("nij,nj->ni", rotations[rows], offsets)
            handle.batched_wxyzs = quat_mul(orientations[rows], collider_rotations)
        if self.axes is not None:
            handle, rows = self.axes
            handle.batched_positions = positions[rows]
            handle.batched_wxyzs = orientations[rows]
        if self.particles is not None:
            self.particles.points = np.asarray(run.particle_positions[k], dtype=np.float32)
        if self.links is not None:
            self.links.points = run.link_segments(k)
        if self.contact_points is not None and self.contact_normals is not None:
            c = run.contacts(k)
            if len(c):
                self.contact_points.points = np.asarray(c[:, 0], dtype=np.float32)
                self.contact_normals.points = self._normals(c)
            self.contact_points.visible = self.contact_normals.visible = bool(len(c))


def _bounds(run: "Run", radius: np.ndarray, planes: list[int]) -> tuple[np.ndarray, float]:
    """The centre and size (the diagonal of the box holding every body, collider and particle over the run, at least
    0.5 m) of the scene; bodies whose only colliders are half-spaces do not count."""
    keep = np.array([b for b in range(run.body_positions.shape[1]) if b not in planes or radius[b] > 0], dtype=np.int64)
    lows, highs = [], []
    if len(keep) and run.frames:
        r = radius[keep][None, :, None]
        lows.append((run.body_positions[:, keep] - r).reshape(-1, 3))
        highs.append((run.body_positions[:, keep] + r).reshape(-1, 3))
    if run.particle_positions.shape[1] and run.frames:
        lows.append(run.particle_positions.reshape(-1, 3))
        highs.append(run.particle_positions.reshape(-1, 3))
    if not lows:
        return np.zeros(3), 1.0
    lo, hi = np.nanmin(np.concatenate(lows), axis=0), np.nanmax(np.concatenate(highs), axis=0)
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))):
        return np.zeros(3), 1.0
    return (lo + hi) / 2, max(0.5, float(np.linalg.norm(hi - lo)))


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
            from ._plots import joint_gaps  # noqa: PLC0415

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
    from ._run import Run  # noqa: PLC0415

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
        report=world.report, particles=world.particles.handles, bodies=world.bodies.handles,
        shapes=world._body_shapes(), links=normal_links(world._links()))
