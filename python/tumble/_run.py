"""``Run``: the frames of a run as numpy arrays, with a plot, an animated preview and glTF export."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ._report import Report


@dataclass
class Run:
    """Frames of a run. Arrays are frame-major: ``particle_positions`` is (F, P, 3), ``body_orientations``
    (F, B, 4) as (w, x, y, z); particles and bodies appear in the order of ``particles`` and ``bodies``.
    ``step_times`` and ``step_sizes`` hold every accepted integrator step; ``penetration`` (F,) the largest
    penetration among the contacts at each frame; ``contact_events`` the times of accurate mode's contact events
    (collisions located by bisection)."""

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
    report: Report
    particles: list
    bodies: list
    shapes: list = field(default_factory=list, repr=False)

    @classmethod
    def from_dict(cls, data: dict[str, Any], shapes: list | None = None) -> "Run":
        data = dict(data)
        data["report"] = Report(data["report"])
        return cls(**data, shapes=shapes or [])

    @property
    def frames(self) -> int:
        """Number of frames."""
        return len(self.times)

    def plot(self, path: str | Path | None = None):
        """Plots energy (kinetic, potential, total), the largest penetration and the step size over time (contact
        events marked); saves it to ``path`` (any format matplotlib writes) if given, and returns the figure."""
        from ._plots import plot_run  # noqa: PLC0415 - matplotlib loads only when asked

        return plot_run(self, path)

    def animate(self, path: str | Path, fps: float | None = None, size: float = 5.0) -> Path:
        """Writes a quick preview of particles and bodies (a 3-D scatter with each body's axes) as an animated
        GIF (``.gif``) or, when ffmpeg is installed, an MP4 (``.mp4``). Returns the path."""
        from ._plots import animate_run  # noqa: PLC0415

        return animate_run(self, Path(path), fps, size)

    def export_gltf(self, path: str | Path) -> Path:
        """Writes the run as binary glTF 2.0 (``.glb``): one node per body with its colliders' meshes and its
        translation and rotation animated over the frames (Blender and web viewers play it). Returns the path."""
        from ._gltf import export  # noqa: PLC0415

        return export(self, Path(path))
