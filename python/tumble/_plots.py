"""Figures of a run: energy and step size over time, and an animated 3-D preview. Uses matplotlib's object API
(no pyplot state), so it works without a display."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ._geometry import rotation_matrix

if TYPE_CHECKING:
    from ._run import Run


def plot_run(run: "Run", path: str | Path | None) -> Figure:
    fig = Figure(figsize=(9, 8.5), layout="constrained")
    FigureCanvasAgg(fig)
    energy, penetration, steps = fig.subplots(3, 1, sharex=True)
    energy.plot(run.times, run.kinetic_energy, label="kinetic")
    energy.plot(run.times, run.potential_energy, label="potential")
    energy.plot(run.times, run.energy, label="total", color="black", linewidth=2)
    energy.set_ylabel("energy (J)")
    energy.legend(loc="best")
    energy.grid(True, alpha=0.3)
    r = run.report
    energy.set_title(
        f"{r.method}: {r.steps} steps ({r.rejected} rejected), {r.rhs_evals} evaluations, {r.wall_seconds:.3g} s"
    )
    penetration.plot(run.times, np.asarray(run.penetration) * 1e3, color="tab:red")
    penetration.set_ylabel("max penetration (mm)")
    penetration.grid(True, alpha=0.3)
    penetration.set_title(
        f"{r.collisions} collisions, {r.qp_solves} QP solves, {r.bisection_steps} bisection steps, "
        f"max {r.max_penetration:.2e} m"
    )
    for t in run.contact_events:
        for ax in (energy, penetration):
            ax.axvline(t, color="grey", linewidth=0.5, alpha=0.4)
    if len(run.step_sizes):
        steps.semilogy(run.step_times, run.step_sizes, ".", markersize=3)
    steps.set_ylabel("step size (s)")
    steps.set_xlabel("time (s)")
    steps.grid(True, which="both", alpha=0.3)
    if path is not None:
        fig.savefig(path, dpi=120)
    return fig


def _wireframes(run: "Run", extent: float, centre: np.ndarray) -> list[np.ndarray | None]:
    """Per body, the edges of its colliders' meshes in the body frame as an (E, 2, 3) array (None without one).
    A half-space is drawn as a square of side 2 ``extent`` on its plane, under the scene's ``centre``."""
    out: list[np.ndarray | None] = []
    for b in range(run.body_positions.shape[1]):
        colliders = run.shapes[b] if b < len(run.shapes) else []
        segments = []
        for shape, offset, orientation in colliders:
            v, t = shape.triangle_mesh(12, extent)
            v = np.asarray(v) @ rotation_matrix(np.asarray(orientation)).T + np.asarray(offset)
            if shape.kind == "half-space":
                r = rotation_matrix(run.body_orientations[0, b])
                local = r.T @ (centre - run.body_positions[0, b])
                normal = np.cross(v[1] - v[0], v[2] - v[0])
                normal /= np.linalg.norm(normal)
                v = v + local - normal * normal.dot(local)
            segments.extend(v[list(e)] for e in _feature_edges(v, np.asarray(t)))
        out.append(np.array(segments) if segments else None)
    return out


def _feature_edges(v: np.ndarray, triangles: np.ndarray) -> list[tuple[int, int]]:
    """The mesh's edges that bound a face: on one triangle only, or between triangles that are not coplanar (a box's
    face diagonals and the half-space square's diagonal are left out)."""
    normals: dict[tuple[int, int], list[np.ndarray]] = {}
    for tri in triangles:
        n = np.cross(v[tri[1]] - v[tri[0]], v[tri[2]] - v[tri[0]])
        n = n / (np.linalg.norm(n) or 1.0)
        for a, c in zip(tri, np.roll(tri, 1)):
            normals.setdefault(tuple(sorted((int(a), int(c)))), []).append(n)
    return [e for e, ns in normals.items() if len(ns) == 1 or any(np.dot(ns[0], m) < 1 - 1e-9 for m in ns[1:])]


def animate_run(run: "Run", path: Path, fps: float | None, size: float) -> Path:
    from matplotlib.animation import FFMpegWriter, FuncAnimation, writers  # noqa: PLC0415
    from mpl_toolkits.mplot3d.art3d import Line3DCollection  # noqa: PLC0415

    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise ValueError(f"invalid argument `path`: write a .gif or .mp4, got {path.name!r}")
    if suffix == ".mp4" and not writers.is_available("ffmpeg"):
        raise RuntimeError("an .mp4 preview needs ffmpeg on the PATH; write a .gif instead")
    frame_dt = float(np.median(np.diff(run.times))) if run.frames > 1 else 1.0
    fps = fps or min(30.0, 1.0 / frame_dt)
    stride = max(1, round(1.0 / (fps * frame_dt)))
    frames = list(range(0, run.frames, stride))
    moving = [b for b in range(run.body_positions.shape[1]) if np.ptp(run.body_positions[:, b], axis=0).any()]
    points = np.concatenate([run.particle_positions.reshape(-1, 3), run.body_positions[:, moving].reshape(-1, 3)])
    if len(points) == 0:
        points = run.body_positions.reshape(-1, 3)
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre, half = (lo + hi) / 2, max(float((hi - lo).max()) / 2, 0.5) * 1.2
    axis_length = 0.3 * half
    wireframes = _wireframes(run, half, centre)

    fig = Figure(figsize=(size, size))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(projection="3d")
    ax.set_box_aspect((1, 1, 1))
    for i, c in enumerate("xyz"):
        getattr(ax, f"set_{c}lim")(centre[i] - half, centre[i] + half)
        getattr(ax, f"set_{c}label")(c)
    # The axes are drawn once; each frame only moves its artists: the colliders' edges (one collection for all
    # bodies), a body frame (red, green, blue axes and a dot) for a body without shapes, and the particles.
    shaped = [b for b in range(run.body_positions.shape[1]) if wireframes[b] is not None]
    bare = [b for b in range(run.body_positions.shape[1]) if wireframes[b] is None]
    nothing = [np.array([centre, centre])]  # a collection needs a segment; this one draws nothing
    edges = Line3DCollection(nothing, colors="0.25", linewidths=0.6)
    ax.add_collection3d(edges)
    frames_axes = Line3DCollection(nothing, colors=["tab:red", "tab:green", "tab:blue"] * len(bare), linewidths=1.2)
    ax.add_collection3d(frames_axes)
    centres = ax.scatter([], [], [], s=30, color="black")
    particles = ax.scatter([], [], [], s=6, color="tab:blue")
    title = ax.set_title("")

    def draw(k: int):
        f = frames[k]
        segments = [wireframes[b] @ rotation_matrix(run.body_orientations[f, b]).T + run.body_positions[f, b]
                    for b in shaped]
        edges.set_segments(np.concatenate(segments) if segments else nothing)
        axes = []
        for b in bare:
            x, r = run.body_positions[f, b], rotation_matrix(run.body_orientations[f, b])
            axes.extend([x, x + axis_length * r[:, j]] for j in range(3))
        frames_axes.set_segments(axes or nothing)
        x = run.body_positions[f, bare]
        centres._offsets3d = (x[:, 0], x[:, 1], x[:, 2])
        p = run.particle_positions[f]
        particles._offsets3d = (p[:, 0], p[:, 1], p[:, 2])
        title.set_text(f"t = {run.times[f]:.3f} s")
        return []

    if suffix == ".gif":
        # Each frame drawn once and handed to Pillow (matplotlib's animation writer draws every frame twice).
        from PIL import Image  # noqa: PLC0415 - Pillow comes with matplotlib

        images = []
        for k in range(len(frames)):
            draw(k)
            fig.canvas.draw()
            images.append(Image.fromarray(np.asarray(fig.canvas.buffer_rgba())[..., :3]).quantize(colors=64))
        images[0].save(path, save_all=True, append_images=images[1:], duration=round(1000 / fps), loop=0)
        return path
    animation = FuncAnimation(fig, draw, frames=len(frames), blit=False)
    animation.save(str(path), writer=FFMpegWriter(fps=fps))
    return path
