"""``Run``: the frames of a run as numpy arrays, with a plot, an animated preview, glTF export, and saving to
``.npz`` (whole) and CSV (its per-frame scalars); a run pickles."""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from ._errors import as_path
from ._geometry import rotation_matrices
from ._report import Report

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ._geometry import Link
    from ._tumble import BodyHandle, JointHandle, ParticleHandle, Shape
    from .viewer._viewer import Viewer

# A body's colliders: each shape with its position and orientation (w, x, y, z) in the body's frame.
Colliders = list[tuple["Shape", list[float], list[float]]]


# The per-frame and per-step arrays a run holds (what .npz files carry).
ARRAYS = (
    "times", "particle_positions", "particle_velocities", "body_positions", "body_orientations", "body_velocities",
    "body_angular_velocities", "kinetic_energy", "potential_energy", "energy", "momentum", "angular_momentum",
    "step_times", "step_sizes", "penetration", "contact_events", "contact_counts", "contact_points",
    "joint_break_times",
)


def rgba(c: Any) -> tuple[float, float, float, float]:
    """A colour's four components as floats."""
    r, g, b, a = map(float, c)
    return (r, g, b, a)


def looks_of(world: Any) -> tuple[list[str | None], list[Any]]:
    """A world's bodies' names and colours, in row order, as a run keeps them."""
    return world._body_names(), world._body_colors()


@dataclass(repr=False)
class Run:
    """Frames of a run. Arrays are frame-major: ``particle_positions`` is (F, P, 3), ``body_orientations``
    (F, B, 4) as (w, x, y, z); particles and bodies appear in the order of ``particles`` and ``bodies``.
    ``step_times`` and ``step_sizes`` hold every accepted integrator step (a span where everything sleeps is no
    step: the clock jumps over it, and the sizes of a run that slept sum to less than its duration); ``penetration`` (F,) the largest
    penetration among the contacts at each frame; ``contact_events`` the times of accurate mode's contact events
    (collisions located by bisection); ``joint_breaks`` the joints that broke during the run, in order, and
    ``joint_break_times`` when; ``contact_counts`` (F,) how many contacts each frame has and
    ``contact_points`` (C, 2, 3) each contact's point and normal, frame after frame (``contacts(frame)`` picks a
    frame's). ``links`` lists the springs and joints to draw (``link_segments``; ``link_ends`` the time at which each
    link whose joint broke ended, by link), ``name`` the scene's name;
    ``names`` and ``colors`` each body's name and linear RGBA colour as given to ``add_body`` (None where not given),
    which the exporters and the viewer use; ``interrupted`` whether Ctrl-C stopped the run (its frames those done,
    the world left at the last)."""

    times: np.ndarray
    particle_positions: np.ndarray
    particle_velocities: np.ndarray
    body_positions: np.ndarray
    body_orientations: np.ndarray
    body_velocities: np.ndarray
    body_angular_velocities: np.ndarray
    kinetic_energy: np.ndarray
    potential_energy: np.ndarray
    energy: np.ndarray
    momentum: np.ndarray
    angular_momentum: np.ndarray
    step_times: np.ndarray
    step_sizes: np.ndarray
    penetration: np.ndarray
    contact_events: np.ndarray
    contact_counts: np.ndarray
    contact_points: np.ndarray
    joint_break_times: np.ndarray
    report: Report
    particles: list[ParticleHandle]
    bodies: list[BodyHandle]
    joint_breaks: list[JointHandle] = field(default_factory=list)
    shapes: list[Colliders] = field(default_factory=list, repr=False)
    links: list[Link] = field(default_factory=list, repr=False)
    name: str = ""
    names: list[str | None] = field(default_factory=list, repr=False)
    colors: list[tuple[float, float, float, float] | None] = field(default_factory=list, repr=False)
    link_ends: dict[int, float] = field(default_factory=dict, repr=False)
    interrupted: bool = False

    @classmethod
    def from_dict(cls, data: dict[str, Any], shapes: list[Colliders] | None = None, links: list[Any] | None = None,
                  name: str = "", looks: tuple[list[Any], list[Any]] | None = None,
                  link_joints: list[Any] | None = None) -> "Run":
        """A run from the arrays a world's run gives, with its bodies' ``shapes``, its ``links`` and each link's
        joint (``link_joints``, None for a spring: a joint that broke in the run ends its link there)."""
        data = dict(data)
        broke = dict(zip(data.get("joint_breaks", []), data.get("joint_break_times", [])))
        ends = {i: float(broke[j]) for i, j in enumerate(link_joints or []) if j is not None and j in broke}
        data["report"] = Report(data["report"])
        data["interrupted"] = bool(data.get("interrupted", False))
        data["contact_counts"] = np.asarray(data["contact_counts"], dtype=np.int64)
        from ._geometry import normal_links  # noqa: PLC0415

        names, colors = looks or ([], [])
        return cls(**data, shapes=shapes or [], links=normal_links(links or []), name=name, names=list(names),
                   colors=[None if c is None else rgba(c) for c in colors], link_ends=ends)

    @classmethod
    def join(cls, runs: Sequence["Run"]) -> "Run":
        """One run of ``runs`` made one after another by the same world (each starting where the last ended, the
        same particles and bodies): their frames in order, the frame where one ends and the next begins once (the
        next's: a body taken over there by ``World.hold`` is on its keyframes from that frame). A body
        released from keyframes in between (``World.release``) is drawn by its shapes as they are at the end, its
        earlier positions moved to its centre of mass. The steps, events and breaks in order; the report, links
        and looks are the last run's. ValueError naming ``runs`` where they do not follow on."""
        runs = list(runs)
        if not runs or not all(isinstance(r, Run) for r in runs):
            raise ValueError(f"invalid argument `runs`: expected one or more tumble.Run, got {runs!r}")
        last = runs[-1]
        for a, b in zip(runs, runs[1:]):
            if a.particles != b.particles or a.bodies != b.bodies:
                raise ValueError("invalid argument `runs`: they do not hold the same particles and bodies")
            if a.times[-1] != b.times[0]:
                raise ValueError(f"invalid argument `runs`: one ends at {a.times[-1]} s and the next begins at "
                                 f"{b.times[0]} s")
        frames: dict[str, list[np.ndarray]] = {name: [] for name in ARRAYS}
        for k, r in enumerate(runs):
            # the frame where one run ends and the next begins: the next's (a body taken over there is on its keys)
            cut = 0 if k == len(runs) - 1 else 1
            positions = r.body_positions.copy()
            for j, (mine, final) in enumerate(zip(r.shapes, last.shapes)):
                if mine and final and not np.allclose(mine[0][1], final[0][1]):
                    # the body frame moved in the body (to the centre of mass): where the last run's frame was
                    shift = np.asarray(mine[0][1], dtype=float) - np.asarray(final[0][1], dtype=float)
                    positions[:, j] += np.einsum("fij,j->fi", rotation_matrices(r.body_orientations[:, j]), shift)
            for name in ARRAYS:
                value = positions if name == "body_positions" else getattr(r, name)
                if name == "contact_points":
                    value = value[:int(r.contact_counts[:len(r.contact_counts) - cut].sum())]
                elif name in ("step_times", "step_sizes", "contact_events", "joint_break_times"):
                    pass
                else:
                    value = value[:len(value) - cut]
                frames[name].append(value)
        arrays = {name: np.concatenate(parts) for name, parts in frames.items()}
        return cls(**arrays, report=last.report, particles=list(last.particles), bodies=list(last.bodies),
                   joint_breaks=[h for r in runs for h in r.joint_breaks], shapes=last.shapes, links=last.links,
                   name=last.name, names=last.names, colors=last.colors, link_ends=last.link_ends,
                   interrupted=any(r.interrupted for r in runs))

    def label(self, body: int) -> str:
        """Body ``body``'s name (its column in the arrays), or ``"body N"`` where it was given none."""
        name = self.names[body] if body < len(self.names) else None
        return name if name is not None else f"body {body}"

    def color(self, body: int) -> tuple[float, float, float, float] | None:
        """Body ``body``'s linear RGBA colour, or None where it was given none."""
        return self.colors[body] if body < len(self.colors) else None

    def _column(self, handle: BodyHandle | ParticleHandle, particles: bool, array: str) -> np.ndarray:
        """A copy of the frames (F, n) of ``handle``'s column of the body (or particle) array ``array``."""
        from ._tumble import BodyHandle, ParticleHandle  # noqa: PLC0415

        if isinstance(handle, BodyHandle):
            held: list[Any] = self.bodies
            kind, name = "bodies", f"body_{array}"
        elif particles and isinstance(handle, ParticleHandle):
            held, kind, name = self.particles, "particles", f"particle_{array}"
        else:
            wanted = "a BodyHandle or a ParticleHandle" if particles else "a BodyHandle (only bodies have it)"
            raise TypeError(f"invalid argument `handle`: expected {wanted}, got {handle!r}")
        try:
            column = held.index(handle)
        except ValueError:
            raise ValueError(f"invalid argument `handle`: {handle!r} is not one of the run's {len(held)} {kind} (a "
                             f"handle of another world, or added after the run or removed before it)") from None
        frames = getattr(self, name)
        if frames.ndim != 3:  # a run saved before the array existed
            raise ValueError(f"invalid argument `handle`: the run holds no {name}")
        return np.array(frames[:, column])

    def positions_of(self, handle: BodyHandle | ParticleHandle) -> np.ndarray:
        """The positions (F, 3) of a body (its centre of mass, as ``body_positions``) or a particle, frame by
        frame, by its handle: the column of ``body_positions`` or ``particle_positions`` the handle has in this run
        (a static body, such as ``add_ground``'s, has one too). A copy. Raises ValueError for a handle the run does
        not hold (another world's, or one added after the run or removed before it), TypeError for anything but a
        handle. Works on a run read back by ``Run.load`` with the handles of the world that ran it."""
        return self._column(handle, True, "positions")

    def orientations_of(self, handle: BodyHandle) -> np.ndarray:
        """The orientations (F, 4) of a body, frame by frame, by its handle: unit quaternions stored (w, x, y, z),
        scalar first, as ``body_orientations`` (the order of Blender's ``mathutils.Quaternion``; glTF and SciPy
        store (x, y, z, w)). A copy. Raises as ``positions_of`` does, and TypeError for a particle."""
        return self._column(handle, False, "orientations")

    def velocities_of(self, handle: BodyHandle | ParticleHandle) -> np.ndarray:
        """The velocities (F, 3) of a body (its centre of mass, as ``body_velocities``) or a particle, frame by
        frame, by its handle. A copy. Raises as ``positions_of`` does."""
        return self._column(handle, True, "velocities")

    def angular_velocities_of(self, handle: BodyHandle) -> np.ndarray:
        """The angular velocities (F, 3) of a body in world axes (rad/s), frame by frame, by its handle, as
        ``body_angular_velocities``. A copy. Raises as ``orientations_of`` does."""
        return self._column(handle, False, "angular_velocities")

    def contacts(self, frame: int) -> np.ndarray:
        """The contacts at ``frame`` as a (C, 2, 3) array: each contact's point and unit normal."""
        if not -self.frames <= frame < self.frames:
            raise ValueError(f"invalid argument `frame`: the run has {self.frames} frames, got {frame}")
        frame %= self.frames
        start = int(self.contact_counts[:frame].sum())
        return self.contact_points[start:start + int(self.contact_counts[frame])]

    def link_segments(self, frame: int) -> np.ndarray:
        """The springs and joints at ``frame`` as an (L, 2, 3) array of line segments, in the order of ``links``."""
        from ._geometry import link_segments  # noqa: PLC0415

        return link_segments(self, frame)

    @property
    def frames(self) -> int:
        """Number of frames."""
        return len(self.times)

    def __repr__(self) -> str:
        span = f"{self.times[0]:g} to {self.times[-1]:g} s" if len(self.times) else "empty"
        return (f"Run({self.frames} frames, {span}, {len(self.bodies)} bodies, {len(self.particles)} particles, "
                f"{len(self.step_times)} steps, {self.report.wall_seconds:.3g} s of work)")

    def save(self, path: str | Path) -> Path:
        """Saves the whole run as a compressed ``.npz``: every array, the report, the handles and the bodies'
        shapes (``Run.load`` reads it back equal). Returns the path."""
        path = as_path(path)

        def handles(hs: list[ParticleHandle] | list[BodyHandle] | list[JointHandle]) -> np.ndarray:
            return np.array([[h.world, h.index, h.generation] for h in hs], dtype=np.uint64).reshape(-1, 3)

        shapes = [[(s.__reduce__()[1][0], list(map(float, p)), list(map(float, q))) for s, p, q in body]
                  for body in self.shapes]
        report = {**self.report._fields, "_text": self.report._text, "_details": self.report._details}
        np.savez_compressed(path, **{name: getattr(self, name) for name in ARRAYS},
                            particles=handles(self.particles), bodies=handles(self.bodies),
                            joint_breaks=handles(self.joint_breaks),
                            report=np.array(json.dumps(report)), shapes=np.array(json.dumps(shapes)),
                            links=np.array(json.dumps(self.links)), name=np.array(self.name),
                            looks=np.array(json.dumps([self.names, self.colors])),
                            link_ends=np.array(json.dumps(sorted(self.link_ends.items()))),
                            interrupted=np.array(self.interrupted))
        return path if path.suffix == ".npz" else path.with_name(path.name + ".npz")

    @classmethod
    def load(cls, path: str | Path) -> "Run":
        """A run saved by ``save``."""
        from ._geometry import normal_links  # noqa: PLC0415
        from ._tumble import _handle, _shape_from_json  # noqa: PLC0415

        with np.load(as_path(path), allow_pickle=False) as data:
            arrays = {name: data[name] if name in data else np.zeros(0) for name in ARRAYS}
            def handles(kind: str, a: np.ndarray) -> list[Any]:
                return [_handle(kind, int(w), int(i), int(g)) for w, i, g in a]

            particles = handles("ParticleHandle", data["particles"])
            bodies = handles("BodyHandle", data["bodies"])
            breaks = handles("JointHandle", data["joint_breaks"]) if "joint_breaks" in data else []
            report = Report(json.loads(str(data["report"])))
            shapes = [[(_shape_from_json(s), p, q) for s, p, q in body] for body in json.loads(str(data["shapes"]))]
            links = normal_links(json.loads(str(data["links"])))
            name = str(data["name"])
            names, colors = json.loads(str(data["looks"])) if "looks" in data else ([], [])
            ends = json.loads(str(data["link_ends"])) if "link_ends" in data else []
            link_ends = {int(i): float(t) for i, t in ends}
            interrupted = bool(data["interrupted"]) if "interrupted" in data else False
        return cls(**arrays, report=report, particles=particles, bodies=bodies, joint_breaks=breaks, shapes=shapes,
                   links=links, name=name, names=names, colors=[None if c is None else rgba(c) for c in colors],
                   link_ends=link_ends, interrupted=interrupted)

    def to_csv(self, path: str | Path) -> Path:
        """Writes the per-frame scalars as CSV, a row a frame: time, kinetic, potential and total energy, momentum
        and angular momentum (x, y, z each) and the largest penetration. Returns the path."""
        path = as_path(path)
        with path.open("w", newline="") as out:
            w = csv.writer(out)
            w.writerow(["time", "kinetic_energy", "potential_energy", "energy", "momentum_x", "momentum_y",
                        "momentum_z", "angular_momentum_x", "angular_momentum_y", "angular_momentum_z",
                        "penetration"])
            for k in range(self.frames):
                w.writerow([repr(float(v)) for v in (self.times[k], self.kinetic_energy[k], self.potential_energy[k],
                                                     self.energy[k], *self.momentum[k], *self.angular_momentum[k],
                                                     self.penetration[k])])
        return path

    def plot(self, path: str | Path | None = None) -> Figure:
        """Plots energy (kinetic, potential, total), the largest penetration and the step size over time (contact
        events marked); saves it to ``path`` (any format matplotlib writes) if given, and returns the figure."""
        from ._plots import plot_run  # noqa: PLC0415 - matplotlib loads only when asked

        return plot_run(self, path)

    def animate(self, path: str | Path, fps: float | None = None, size: float = 5.0, title: str | None = None,
                camera: dict[str, Any] | None = None, zoom: float = 1.0, contacts: bool = True) -> Path:
        """Writes a preview of the run as an animated GIF (``.gif``) or, when ffmpeg is installed, an MP4
        (``.mp4``): the bodies in their colours (a palette's for bodies given none) shaded by face with their edges,
        nearer faces hiding those behind, the floor, springs and joints as lines, particles as dots and contacts as
        red points (those behind a face hidden; ``contacts=False`` leaves them out), framed on the scene, with
        ``title`` (default: the scene's ``name``) and the time on every frame. The camera is orthographic with z
        up: by default it looks down from the side (the floor at the bottom); ``camera={"position": (x, y, z),
        "target": (x, y, z)}`` looks from ``position`` towards ``target`` (default: the middle of the scene; only
        the direction counts), the picture centred on the target; ``zoom`` enlarges the picture about its middle (2:
        twice as large). ``fps`` frames a second (default: the run's frame rate, at most 30); a frame is held until
        the next one's time, and frames where nothing moves are merged into one. ``size`` is the longer side in
        inches at 128 pixels an inch. Returns the path."""
        from .export._preview import write_preview  # noqa: PLC0415

        return write_preview(self, as_path(path), fps, size, title, camera, zoom, contacts)

    def export_usd(self, path: str | Path, over: str | Path | None = None) -> Path:
        """Writes the run as USD (``.usda`` text, ``.usdc`` binary) through usd-core (``pip install
        "./python[usd]"``): one prim per body with its colliders' meshes (each distinct shape written once and
        referenced), translation and orientation time-sampled at every frame, the stage in metres with z up.
        Houdini, Omniverse and Blender read it. With ``over`` (the stage a world was read from by
        ``World.from_usd``), a layer over that stage instead: the run's time samples on the original rigid body
        prims, in the stage's units, axes and time codes. Returns the path."""
        if over is not None:
            from .usd._over import export_over  # noqa: PLC0415

            target = as_path(path)
            if target.suffix.lower() not in (".usda", ".usdc", ".usd"):
                raise ValueError(f"invalid argument `path`: USD files end in .usda, .usdc or .usd, got {target.name!r}")
            return export_over(self, target, as_path(over))
        from .usd._write import export  # noqa: PLC0415

        return export(self, as_path(path))

    def export_gltf(self, path: str | Path) -> Path:
        """Writes the run as binary glTF 2.0 (``.glb``) that Blender and web viewers play: a node per body, particle,
        spring and joint, their translation and rotation (and the links' length) keyed at every frame, under a root
        node that turns tumble's z-up to glTF's y-up. Bodies with identical colliders share one mesh; each spring or
        joint is a thin cylinder stretched between its ends, each joint's anchors small spheres; materials are plain
        named colours (static bodies grey, moving ones a colour per distinct collider set, particles, springs and
        joints one colour each). A run that diverged is written up to its last finite frame. Returns the path."""
        from .export._gltf import export  # noqa: PLC0415

        return export(self, as_path(path))

    def show(self, port: int = 8080, block: bool = True, host: str = "127.0.0.1") -> Viewer:
        """Shows the run in an interactive 3-D viewer in the browser at ``http://127.0.0.1:8080`` (viser: ``pip
        install "./python[viewer]"``): the bodies' colliders, particles, springs and joints, each frame's contacts;
        play, pause, scrub and playback speed, with energy and penetration plotted beside the scene. ``port`` 0
        takes a free port (a taken one, the next free one: ``Viewer.url`` says which); ``host="0.0.0.0"`` serves
        other machines too. With ``block`` it prints the address and serves until Ctrl-C; without, it returns the
        ``Viewer`` at once (``viewer.stop()`` ends it)."""
        from .viewer._viewer import show  # noqa: PLC0415

        return show(self, port, block, host)

    def export_viewer(self, path: str | Path) -> Path:
        """Writes the viewer's scene, recorded frame by frame, as one self-contained HTML file (``.html``, viser's
        client and the recording in it) that a browser opens from disk, no server, and plays with play/pause,
        scrubbing and speed; no plots (viser records the scene only). Returns the path."""
        from .viewer._viewer import export  # noqa: PLC0415

        return export(self, as_path(path))
