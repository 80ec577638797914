"""Batches: ``tumble.rollout`` runs copies of a world from many states at once on a Rust thread pool (the interpreter
lock released) and returns a :class:`Batch` of stacked arrays."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from ._errors import named_arguments
from ._progress import Progress, progress as _progress
from ._run import Run, looks_of
from ._tumble import State, World, _rollout

# The per-frame arrays of a run, stacked (N, F, ...) over a batch.
STACKED = (
    "particle_positions",
    "particle_velocities",
    "body_positions",
    "body_orientations",
    "body_velocities",
    "body_angular_velocities",
    "kinetic_energy",
    "potential_energy",
    "energy",
    "momentum",
    "angular_momentum",
    "penetration",
)


@dataclass
class Batch:
    """The runs of a batch, in the order of its states. ``times`` (F,) are the frames' times (the same for every
    run); each per-frame array of :class:`Run` comes stacked with a leading axis over the runs, e.g.
    ``body_positions`` (N, F, B, 3) and ``energy`` (N, F). Arrays of varying length (``step_times``,
    ``step_sizes``, ``contact_events``) and the reports are in ``runs[k]``."""

    runs: list[Run]

    @property
    def times(self) -> np.ndarray:
        """(F,) frame times."""
        return self.runs[0].times if self.runs else np.zeros(0)

    def __len__(self) -> int:
        return len(self.runs)

    def __getattr__(self, name: str) -> np.ndarray:
        if name in STACKED:
            return np.stack([getattr(r, name) for r in self.runs]) if self.runs else np.zeros(0)
        raise AttributeError(name)

    def __repr__(self) -> str:
        frames = len(self.times)
        return f"Batch({len(self.runs)} runs, {frames} frames each)"


def rollout(
    world: World,
    states: Sequence[State],
    duration: float,
    frame_interval: float | None = None,
    threads: int | None = None,
    progress: bool | Callable[[float], None] = False,
) -> Batch:
    """Runs a copy of ``world`` from each of ``states`` (``World.get_state``, edited with ``State.replace`` as
    wished) for ``duration`` seconds, recording frames every ``frame_interval`` (default 1/60 s), on ``threads``
    threads (default: one per core), and returns a :class:`Batch`. The copies run in Rust with the interpreter lock
    released; each gives bit for bit the run that ``world.set_state(state); world.run(...)`` gives, whatever the
    thread count. ``world`` itself is not changed. A bad state raises ValueError naming the array and ``states[k]``;
    a copy that fails raises SimulationError naming it. ``progress=True`` shows the fraction of copies done; Ctrl-C
    stops the batch. Force callbacks are shared by the copies and called from several threads (holding the
    interpreter lock): they must not keep state."""
    if not isinstance(world, World):
        raise TypeError(f"invalid argument `world`: expected a tumble.World, got {type(world).__name__}")
    try:
        states = list(states)
    except TypeError:
        raise TypeError(f"invalid argument `states`: expected a sequence of tumble.State, got {states!r}") from None
    for k, s in enumerate(states):
        if not isinstance(s, State):
            raise ValueError(f"invalid argument `states`: states[{k}] is {type(s).__name__}, not a tumble.State")
    shown = Progress("rollout") if progress is True else _progress(progress)
    try:
        data = named_arguments(_rollout)(world, states, duration, frame_interval, threads, shown)
    finally:
        if isinstance(shown, Progress):
            shown.close()
    shapes, links, looks, joints = world._body_shapes(), world._links(), looks_of(world), world._link_joints()
    return Batch([Run.from_dict(d, shapes, links, looks=looks, link_joints=joints) for d in data])
