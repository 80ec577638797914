"""What a directed search gives back: the best world (built, ready to run or bake), its run and cost, the k best
alternatives ("many worlds"), each with how far it changed the user's start, a contact sheet of them, a report, and
the robustness of an answer (the share of twins started a little apart that still meet the goal)."""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np


@dataclass
class Try:
    """One start tried: its point of the search space, the cost of its run, the run, and its change (0: the user's
    start, 1: every bound at its limit)."""

    u: np.ndarray
    cost: float
    run: Any
    change: float


@dataclass
class Alternative:
    """One of the best starts: the ``world`` built at it, its ``run`` and ``cost``, and its ``change`` from the
    user's start (the root mean square of its variations over their bounds: 0 the start, 1 every bound at its
    limit)."""

    world: Any
    run: Any
    cost: float
    change: float
    u: np.ndarray = field(repr=False)
    #: the share of close twins that also meet the goal, where the search measured it (``robust=``)
    robustness: float | None = None

    @property
    def met(self) -> bool:
        return self.cost == 0.0


@dataclass
class Found:
    """A search's answer: ``met`` (whether a try met the goal), the best ``world``, ``run``, ``cost`` and
    ``change``, the ``alternatives`` (the best ones, best first), ``tries`` and ``seconds``."""

    alternatives: list[Alternative]
    tries: int
    seconds: float
    met_count: int
    _space: Any = field(repr=False)
    _start: Any = field(repr=False)

    @classmethod
    def of(cls, world: Any, space: Any, done: list[Try], keep: int, seconds: float) -> Found:
        # met first, the smallest change among them; then by cost
        ranked = sorted(done, key=lambda t: (t.cost > 0.0, t.cost if t.cost > 0.0 else t.change, t.change))
        alternatives = []
        for t in ranked[:keep]:
            w = copy.copy(world)
            space.apply(t.u, w)
            alternatives.append(Alternative(w, t.run, t.cost, t.change, t.u))
        return cls(alternatives, len(done), seconds, sum(t.cost == 0.0 for t in done), space, world)

    @property
    def best(self) -> Alternative:
        return self.alternatives[0]

    @property
    def met(self) -> bool:
        return self.best.met

    @property
    def world(self) -> Any:
        return self.best.world

    @property
    def run(self) -> Any:
        return self.best.run

    @property
    def cost(self) -> float:
        return self.best.cost

    @property
    def change(self) -> float:
        return self.best.change

    @property
    def report(self) -> str:
        """A few lines: tries, wall time, how many met the goal, the best cost and change."""
        said = "met" if self.met else "not met: the best found is given"
        return (f"goal             {said}\n"
                f"tries            {self.tries} in {self.seconds:.3f} s, {self.met_count} met the goal\n"
                f"best             cost {self.cost:.3e} m, change {self.change:.3f} of the bounds")

    def __str__(self) -> str:
        return self.report

    def robustness(self, goal: Any, duration: float, twins: int = 16, size: float = 1e-3, seed: int = 0) -> float:
        """The share of ``twins`` starts around the best one, each of its variations moved by up to ``size`` of its
        bound, whose runs of ``duration`` still meet ``goal``: near 1, the outcome holds; well below, it is chaotic
        and a small error (the method's, or a change of tolerance) may change it."""
        from ._goals import as_goal  # noqa: PLC0415

        return share_of_twins(self._start, self._space, self.best.u, as_goal(goal), duration, twins, size, seed)

    def prefer_robust(self, goal: Any, duration: float, twins: int, size: float = 1e-3) -> None:
        """Measures the robustness of each alternative that met the goal and puts the most robust first (the
        smaller change first among equals)."""
        from ._goals import as_goal  # noqa: PLC0415

        met = [a for a in self.alternatives if a.met]
        for a in met:
            a.robustness = share_of_twins(self._start, self._space, a.u, as_goal(goal), duration, twins, size, 0)
        met.sort(key=lambda a: (-(a.robustness or 0.0), a.change))
        self.alternatives = met + [a for a in self.alternatives if not a.met]

    def contact_sheet(self, path: str | Path, width: int = 320, columns: int = 4) -> Path:
        """One image (PNG) of the alternatives' last frames, best first, each labelled with its cost and change."""
        from PIL import Image  # noqa: PLC0415

        from ..export._preview import Renderer  # noqa: PLC0415

        pictures = []
        for k, a in enumerate(self.alternatives):
            r = Renderer(a.run, width)
            last = a.run.frames - 1
            image = r.scene(last, r.background())
            label = f"{'met' if a.met else f'cost {a.cost:.2g} m'}, change {a.change:.2f}"
            pictures.append(r.caption(image, f"#{k + 1}", label).convert("RGB"))
        rows = -(-len(pictures) // columns)
        w, h = pictures[0].size
        sheet = Image.new("RGB", (w * min(columns, len(pictures)), h * rows), "white")
        for k, p in enumerate(pictures):
            sheet.paste(p, ((k % columns) * w, (k // columns) * h))
        out = Path(path)
        sheet.save(out)
        return out


def share_of_twins(start: Any, space: Any, u: np.ndarray, goal: Any, duration: float, twins: int, size: float,
                   seed: int) -> float:
    """The share of ``twins`` starts within ``size`` (of each bound) of point ``u`` whose runs meet ``goal``."""
    rows = {b: start.bodies.row(b) for b in goal.bodies()}
    rng = np.random.default_rng(seed)
    held = 0
    for _ in range(twins):
        w = copy.copy(start)
        space.apply(np.clip(u + rng.uniform(-size, size, u.shape), -1.0, 1.0), w)
        held += goal.cost(w.run(duration), rows) == 0.0
    return held / twins


def sensitivity(world: Any, duration: float, twins: int = 8, size: float = 1e-6, seed: int = 0) -> dict[str, float]:
    """How sensitive a run's outcome is to its start: ``twins`` copies of ``world`` with every moving body moved
    by ``size`` metres in a random direction, run for ``duration``; gives ``size``, ``spread`` (the largest distance
    a body of a twin ends from where it ends in the run itself, m) and ``ratio`` (spread / size). A ratio near 1:
    the outcome holds to the start's accuracy; thousands and more: a chaotic shot, where a tolerance's worth of
    error (the method's, or a change of settings) may change what happens. ``world`` is not changed."""
    if isinstance(twins, bool) or not isinstance(twins, int) or twins < 1:
        raise ValueError(f"invalid argument `twins`: expected a whole number >= 1, got {twins!r}")
    if not (isinstance(size, (int, float)) and np.isfinite(size) and size > 0):
        raise ValueError(f"invalid argument `size`: expected a finite number > 0, got {size!r}")
    reference = copy.copy(world).run(duration).body_positions[-1]
    moving = [h for h, k in zip(world.bodies.handles, world.bodies.kinematic) if not k]
    rng = np.random.default_rng(seed)
    spread = 0.0
    for _ in range(twins):
        twin = copy.copy(world)
        for h in moving:
            row = twin.bodies.row(h)
            if twin.bodies.masses[row] == np.inf:
                continue
            d = rng.normal(size=3)
            twin.set_body_state(h, position=twin.bodies.positions[row] + size * d / np.linalg.norm(d))
        ends = twin.run(duration).body_positions[-1]
        spread = max(spread, float(np.linalg.norm(ends - reference, axis=1).max()))
    return {"size": float(size), "spread": spread, "ratio": spread / size}
