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

        goal = as_goal(goal)
        rows = {b: self._start.bodies.row(b) for b in goal.bodies()}
        rng = np.random.default_rng(seed)
        held = 0
        for _ in range(twins):
            w = copy.copy(self._start)
            self._space.apply(np.clip(self.best.u + rng.uniform(-size, size, self.best.u.shape), -1, 1), w)
            held += goal.cost(w.run(duration), rows) == 0.0
        return held / twins

    def contact_sheet(self, path: str | Path, width: int = 320, columns: int = 4) -> Path:
        """One image (PNG) of the alternatives' last frames, best first, each labelled with its cost and change."""
        from PIL import Image  # noqa: PLC0415

        from .._preview import Renderer  # noqa: PLC0415

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
