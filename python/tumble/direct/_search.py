"""The search: the user's start and a space-filling first batch (scrambled Sobol points, scipy's), then CMA-ES
(pycma's) from the best, started again from another good try when it closes in on a miss, each batch run as copies of the world on this machine's threads, Ray or Dask; it stops at the end of the batch where a
try met the goal, or when the tries or the seconds run out. Among the tries that met it, the smallest change from
the user's start wins; else the lowest cost."""

from __future__ import annotations

import copy
import importlib
import math
import os
import pickle
import time
from concurrent.futures import ThreadPoolExecutor
from functools import partial
from typing import Any, Callable

import numpy as np

from .._install import install_hint
from .._progress import Progress
from .._progress import progress as _progress
from ._found import Found, Try
from ._goals import Goal, as_goal
from ._vary import Space, Vary

BACKENDS = ("threads", "ray", "dask")
METHODS = ("cma-es", "random")
# CMA-ES's first step, in the bounds' cube [-1, 1]: a tenth of a bound. Chosen by measurement on eight seeds of
# two goals, batches of eight: a ball's pose 0.8 s into free flight (met on all eight by 0.05 and by 0.1, in 161 and
# 166 tries a seed) and the box thrown to rest within 1 cm 2 m away (python/examples/direct.py; met on all eight, in
# 334 and 281 tries a seed). The cross-entropy method it replaced, with batches of 32 and a first batch of 512,
# met the box's goal on seven of eight in 10,944 tries in all.
FIRST_STEP = 0.1
# The step below which CMA-ES has closed in on a start that does not meet the goal, and starts again elsewhere.
SMALLEST_STEP = 1e-4
# Batches of CMA-ES without a better try after which it starts again from another good try: measured on the ball
# thrown into the cup (six seeds, 512 tries; python/examples/direct.py's scene), 5 met the goal on one seed, 10 on
# three, never on two; on the 1 cm target 10 still met it on all eight seeds.
STALL = 10
# A try's outcome: its cost and its run.
Outcome = tuple[float, Any]


def _tried(world_bytes: bytes, space: Space, goal: Goal, rows: dict[Any, int], duration: float,
           frame_interval: float | None, u: np.ndarray) -> tuple[float, Any]:
    """One try where the backend put it: the world rebuilt from its bytes, changed to ``u``, run and judged."""
    world = pickle.loads(world_bytes)
    return _judge(world, space, goal, rows, duration, frame_interval, u)


def _judge(world: Any, space: Space, goal: Goal, rows: dict[Any, int], duration: float, frame_interval: float | None,
           u: np.ndarray) -> tuple[float, Any]:
    space.apply(u, world)
    run = world.run(duration, frame_interval, progress=False)
    return goal.cost(run, rows), run


def _extra(name: str) -> Any:
    """The optional extra's module (``ray``, or Dask's ``distributed``), or an ImportError saying how to install it."""
    try:
        return importlib.import_module("ray" if name == "ray" else "distributed")
    except ImportError as error:
        raise ImportError(f"backend={name!r} needs {name.capitalize()}: {install_hint(name)}") from error


def _evaluator(world: Any, space: Space, goal: Goal, rows: dict[Any, int], duration: float,
               frame_interval: float | None, backend: str,
               threads: int | None) -> Callable[[list[np.ndarray]], list[Outcome]]:
    """A function from a batch of points to their (cost, run), in order, on ``backend``."""
    if backend == "threads":
        count = threads or os.cpu_count() or 1

        def local(points: list[np.ndarray]) -> list[Outcome]:
            with ThreadPoolExecutor(max_workers=count) as pool:
                return list(pool.map(lambda u: _judge(copy.copy(world), space, goal, rows, duration,
                                                      frame_interval, u), points))
        return local
    task = partial(_tried, pickle.dumps(world), space, goal, rows, duration, frame_interval)
    if backend == "ray":
        ray: Any = _extra("ray")

        if not ray.is_initialized():
            ray.init()
        remote: Any = ray.remote(_tried)
        shared = [ray.put(x) for x in task.args]  # the world's bytes, the space and the goal go to the store once
        return lambda points: list(ray.get([remote.remote(*shared, u) for u in points]))
    distributed: Any = _extra("dask")

    from .._sweep import _current_dask_client  # noqa: PLC0415

    client = _current_dask_client(distributed)

    def dask(points: list[np.ndarray]) -> list[Outcome]:
        if client is not None:
            return list(client.gather(client.map(task, points, pure=False)))
        with distributed.LocalCluster(n_workers=1, threads_per_worker=os.cpu_count() or 1, processes=False,
                                      dashboard_address=None) as cluster, distributed.Client(cluster) as c:
            return list(c.gather(c.map(task, points, pure=False)))
    return dask


def search(world: Any, vary: dict[Any, Vary], goal: Any, duration: float, tries: int = 256,
           seconds: float | None = None, backend: str = "threads", seed: int = 0, frame_interval: float | None = None,
           keep: int = 8, batch: int | None = None, threads: int | None = None,
           progress: bool | Callable[[float], None] | None = None, method: str = "cma-es",
           robust: int = 0) -> Found:
    """Searches the starts of ``world`` within ``vary`` (each body's :class:`Vary`) for a run of ``duration``
    seconds that meets ``goal`` (a goal of this module, ``a & b``, or a function ``cost(run) -> float``, zero when
    met), trying at most ``tries`` starts (and for at most ``seconds``), on ``backend`` ("threads": this machine's
    cores, ``threads`` of them; "ray"; "dask"). ``method="random"`` tries uniform random starts within the bounds
    instead, batch after batch (the animator's re-throws, to compare with). ``robust=K`` measures each kept answer
    that met the goal on ``K`` twins started a thousandth of the bounds away and puts the most robust first. ``world`` is not changed. The same ``seed`` gives the same answer
    on any backend and thread count. Returns a :class:`Found`: ``met``, the best ``world`` (built, ready to run or
    bake), its ``run`` and ``cost``, the ``keep`` best ``alternatives``, ``tries`` and ``seconds``."""
    from .._world import World  # noqa: PLC0415

    if not isinstance(world, World):
        raise ValueError(f"invalid argument `world`: expected a tumble.World, got {type(world).__name__}")
    if not isinstance(vary, dict) or not vary:
        raise ValueError(f"invalid argument `vary`: expected a dict of body handle -> tumble.direct.Vary, got {vary!r}")
    for body, v in vary.items():
        if not isinstance(v, Vary):
            raise ValueError(f"invalid argument `vary`: {body!r} maps to {v!r}, not a tumble.direct.Vary")
    goal = as_goal(goal)
    if method not in METHODS:
        raise ValueError(f"invalid argument `method`: expected one of {METHODS}, got {method!r}")
    if backend not in BACKENDS:
        raise ValueError(f"invalid argument `backend`: expected one of {BACKENDS}, got {backend!r}")
    for name, value, low in (("tries", tries, 1), ("keep", keep, 1), ("batch", batch, 1), ("seed", seed, 0),
                             ("robust", robust, 0)):
        if value is not None and (isinstance(value, bool) or not isinstance(value, int) or value < low):
            raise ValueError(f"invalid argument `{name}`: expected a whole number >= {low}, got {value!r}")
    if seconds is not None and not (isinstance(seconds, (int, float)) and math.isfinite(seconds) and seconds > 0):
        raise ValueError(f"invalid argument `seconds`: expected a finite number > 0, got {seconds!r}")
    if isinstance(duration, bool) or not isinstance(duration, (int, float)) or not duration > 0:
        raise ValueError(f"invalid argument `duration`: expected a number > 0, got {duration!r}")
    handles = list(world.bodies.handles)
    rows = {}
    for body in [*vary, *goal.bodies()]:
        if body not in handles:
            raise ValueError(f"invalid argument `vary` or `goal`: {body!r} is not a body of the world")
        rows[body] = world.bodies.row(body)
    space = Space([(rows[body], v) for body, v in vary.items()])
    probe = copy.copy(world)
    space.apply(np.ones(space.dims), probe)  # a bound the world cannot take (a static body's velocity) fails here
    evaluate = _evaluator(world, space, goal, rows, float(duration), frame_interval, backend, threads)
    found = _loop(world, space, evaluate, tries, seconds, seed, keep, batch, progress, method == "random")
    if robust:
        found.prefer_robust(goal, float(duration), robust)
    return found


def _loop(world: Any, space: Space, evaluate: Callable[[list[np.ndarray]], list[Outcome]], tries: int,
          seconds: float | None, seed: int, keep: int, batch: int | None, progress: Any, random: bool) -> Found:
    qmc: Any = importlib.import_module("scipy.stats.qmc")

    clock = time.perf_counter()
    d = space.dims
    size = batch or max(8, min(32, tries // 8))
    # the first batch: eight points a dimension (a power of two, as Sobol's balance asks), at most a quarter of
    # the tries, at least a batch
    first = min(tries, max(size, min(2 ** math.ceil(math.log2(8 * d)), 2 ** math.floor(math.log2(max(1, tries // 4))))))
    # CMA-ES's batch: its own default for d dimensions (4 + 3 ln d), at least eight (a batch for each core of most
    # machines); more a batch takes more tries to close in (sixteen met the ball's pose on 7 of 8 seeds in 220 tries
    # a seed, eight on 8 in 166)
    population = batch or max(8, 4 + int(3 * math.log(d)))
    rng = np.random.default_rng(seed)
    if random:
        points = [rng.uniform(-1.0, 1.0, d) for _ in range(min(size, tries))]
    else:
        sobol = qmc.Sobol(d, scramble=True, seed=seed).random(2 ** math.ceil(math.log2(max(2, first - 1))))
        points = [np.zeros(d)] + [2.0 * p - 1.0 for p in sobol[:first - 1]]
    done: list[Try] = []
    strategy: Any = None
    stalled, run_best = 0, math.inf
    shown = _progress(progress)
    try:
        while points:
            outcomes = evaluate(points)
            for u, (cost, run) in zip(points, outcomes):
                done.append(Try(u, cost, run, space.size(u)))
            if shown is not None:
                shown(min(1.0, len(done) / tries))
            left = tries - len(done)
            out_of_time = seconds is not None and time.perf_counter() - clock > seconds
            if any(t.cost == 0.0 for t in done) or left <= 0 or out_of_time:
                break
            if random:
                points = [rng.uniform(-1.0, 1.0, d) for _ in range(min(size, left))]
                continue
            if strategy is not None:
                strategy.tell(points, [cost for cost, _ in outcomes])
                gained = min(cost for cost, _ in outcomes) < run_best
                run_best = min([run_best] + [cost for cost, _ in outcomes])
                stalled = 0 if gained else stalled + 1
            if strategy is None or strategy.stop() or strategy.sigma < SMALLEST_STEP or stalled >= STALL:
                stalled, run_best = 0, math.inf
                # CMA-ES from the best try (the first time) or, once it has closed in, from another good one
                ranked = sorted(done, key=lambda t: (t.cost, t.change))
                pick = 0 if strategy is None else int(rng.integers(0, max(1, len(ranked) // 16)))
                strategy = _strategy(ranked[pick].u, population, rng)
            points = [np.asarray(u, dtype=float) for u in strategy.ask(population)][:left]
    finally:
        if isinstance(shown, Progress):
            shown.close()
    return Found.of(world, space, done, keep, time.perf_counter() - clock)


def _strategy(centre: np.ndarray, size: int, rng: np.random.Generator) -> Any:
    """pycma's CMA-ES over the bounds' cube from ``centre``, ``size`` points a batch, drawing its normals from
    ``rng`` (so that the search's seed alone decides it, and numpy's global generator is left alone)."""
    cma: Any = importlib.import_module("cma")

    def normals(*shape: int) -> np.ndarray:
        return rng.standard_normal(shape)

    return cma.CMAEvolutionStrategy(list(centre), FIRST_STEP, {
        "popsize": size, "bounds": [-1.0, 1.0], "verbose": -9, "randn": normals, "seed": 1})
