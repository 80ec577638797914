"""The plot of a run: energy over time, and beside it only what the run has: the largest penetration when there is
contact, the joints' anchor gap when there are joints, the step size when it varies. Uses matplotlib's object API
(no pyplot state), so it works without a display."""

from __future__ import annotations

import textwrap
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ._geometry import link_segments

if TYPE_CHECKING:
    from ._run import Run

# Joints whose anchors coincide when the joint holds: the distance between them is the joint's position error.
POINT_JOINTS = ("ball", "hinge", "weld")


def has_contact(run: "Run") -> bool:
    """Whether anything touched during the run."""
    return bool(run.report.collisions or np.any(run.contact_counts) or np.any(run.penetration)
                or len(run.contact_events))


def fixed_step(run: "Run") -> float | None:
    """The step size when every step had the same one (to a part in a million), else None."""
    h = np.asarray(run.step_sizes)
    if len(h) and float(np.ptp(h)) <= 1e-6 * float(h.max()):
        return float(np.median(h))
    return None


def joint_gaps(run: "Run") -> np.ndarray | None:
    """Per frame, the largest distance between the two anchors of a ball, hinge or weld joint (m); None without
    such joints."""
    rows = [i for i, (kind, _, _) in enumerate(run.links) if kind in POINT_JOINTS]
    if not rows:
        return None
    gaps = [np.linalg.norm(np.diff(link_segments(run, f)[rows], axis=1)[:, 0], axis=1).max() for f in range(run.frames)]
    return np.asarray(gaps)


def plot_run(run: "Run", path: str | Path | None) -> Figure:
    r = run.report
    gaps = joint_gaps(run)
    h = fixed_step(run)
    panels = ["energy"] + ["penetration"] * has_contact(run) + ["joints"] * (gaps is not None)
    panels += ["steps"] * (h is None and len(run.step_sizes) > 0)
    fig = Figure(figsize=(9, 1.2 + 2.4 * len(panels)), layout="constrained")
    FigureCanvasAgg(fig)
    axes: list[Axes] = list(np.atleast_1d(fig.subplots(len(panels), 1, sharex=True)))
    name = f"{run.name}: " if run.name else ""
    steps = f"fixed step {h:.4g} s" if h is not None else f"{r.steps} steps ({r.rejected} rejected)"
    # Titles wrapped to the figure's width (about 100 characters at 11 points on 9 inches).
    fig.suptitle(textwrap.fill(f"{name}{r.method}, {steps}, {r.rhs_evals} evaluations, "
                               f"{r.wall_seconds:.3g} s of work", 100), fontsize=11)
    for ax, panel in zip(axes, panels):
        ax.grid(True, which="both", alpha=0.3)
        if panel == "energy":
            ax.plot(run.times, run.kinetic_energy, label="kinetic")
            ax.plot(run.times, run.potential_energy, label="potential")
            ax.plot(run.times, run.energy, label="total", color="black", linewidth=2)
            ax.set_ylabel("energy (J)")
            ax.legend(loc="best", fontsize=9)
            change = float(run.energy[-1] - run.energy[0]) if run.frames else 0.0
            ax.set_title(f"energy: changed by {change:+.3g} J", fontsize=10, loc="left")
        elif panel == "penetration":
            ax.plot(run.times, np.asarray(run.penetration) * 1e3, color="tab:red")
            ax.set_ylabel("max penetration (mm)")
            ax.set_title(f"contact: {r.collisions} collisions, largest penetration {r.max_penetration:.2e} m",
                         fontsize=10, loc="left")
            for t in run.contact_events:
                ax.axvline(t, color="grey", linewidth=0.5, alpha=0.4)
        elif panel == "joints":
            assert gaps is not None
            ax.plot(run.times, gaps, color="tab:purple")
            ax.set_ylabel("joint gap (m)")
            ax.set_title(f"joints: the largest gap between the anchors of a ball, hinge or weld joint, at most "
                         f"{gaps.max():.2e} m", fontsize=10, loc="left")
        else:
            ax.semilogy(run.step_times, run.step_sizes, ".", markersize=3)
            ax.set_ylabel("step size (s)")
            ax.set_title(f"steps: from {min(run.step_sizes):.3g} to {max(run.step_sizes):.3g} s", fontsize=10,
                         loc="left")
    axes[-1].set_xlabel("time (s)")
    if path is not None:
        fig.savefig(path, dpi=120)
    return fig
