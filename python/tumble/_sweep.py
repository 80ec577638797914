"""Parameter sweeps: ``tumble.sweep(build, params, duration)`` builds a world from each parameter set and runs it,
on this machine's cores (the default, nothing to install) or on a Ray or Dask cluster (``pip install
"./python[ray]"`` or ``"./python[dask]"``). The results are the same bit for bit wherever they run: each world is
built by the same function and stepped by the same deterministic code; worlds and runs travel between processes as
tumble's saved format and arrays."""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor
from typing import TYPE_CHECKING, Any, Callable, Literal, Sequence, TypeVar

from ._install import install_hint
from ._run import Run

if TYPE_CHECKING:
    from ._world import World

BACKENDS = ("local", "ray", "dask")
BackendName = Literal["local", "ray", "dask"]

P = TypeVar("P")


def _one(build: Callable[[P], World], param: P, duration: float, frame_interval: float | None) -> Run:
    """Builds one world and runs it (on whichever machine the backend chose)."""
    world = build(param)
    if not hasattr(world, "run") or not hasattr(world, "_to_bytes"):
        raise ValueError(f"invalid argument `build`: it returned {type(world).__name__}, not a tumble.World")
    return world.run(duration, frame_interval)


def _current_dask_client(distributed: Any) -> Any:
    """The Dask client in use (the current or global one), or None when there is none."""
    try:
        return distributed.get_client()
    except ValueError:  # "No global client found and no address provided"
        return None


def _dask_map(client: Any, build: Callable[[P], World], params: list[P], duration: float,
              frame_interval: float | None) -> list[Run]:
    """The runs of ``params`` as tasks on the Dask cluster of ``client``, in order."""
    futures = client.map(_one, [build] * len(params), params, duration=duration, frame_interval=frame_interval,
                         pure=False)
    runs: list[Run] = client.gather(futures)
    return runs


def _dask_local(distributed: Any, build: Callable[[P], World], params: list[P], duration: float,
                frame_interval: float | None) -> list[Run]:
    """The runs on a Dask cluster of this machine's cores started for them, threads of this process (each run
    releases the interpreter lock), closed when they are done."""
    with distributed.LocalCluster(n_workers=1, threads_per_worker=os.cpu_count() or 1, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        return _dask_map(client, build, params, duration, frame_interval)


def sweep(
    build: Callable[[P], World],
    params: Sequence[P],
    duration: float,
    frame_interval: float | None = None,
    backend: BackendName = "local",
    client: Any = None,
    workers: int | None = None,
) -> list[Run]:
    """Runs ``build(p)`` for ``duration`` seconds for each ``p`` of ``params`` and returns the runs in order.

    ``backend="local"`` runs the worlds on ``workers`` threads (default: one per core; each run releases the
    interpreter lock). ``backend="dask"`` submits each to a Dask cluster: ``client`` (a ``distributed.Client``),
    else the current one (``distributed.get_client()``), else a local cluster started for the sweep (threads of this
    process, one per core) and closed when it ends; a client the user started is left running. ``backend="ray"``
    runs each as a Ray task on the cluster ``ray.init`` connected to (started locally if none). ``build`` and the
    parameters must pickle and ``build`` must be importable where it runs: a function of an installed module (or a
    ``functools.partial`` of one), or one defined in ``__main__`` or a notebook (pickled by value); with Ray it is
    put in the object store once.
    The runs equal the local sweep bit for bit. An exception in any build or run is raised here."""
    if backend not in BACKENDS:
        raise ValueError(f"invalid argument `backend`: expected one of {BACKENDS}, got {backend!r}")
    if not callable(build):
        raise ValueError(f"invalid argument `build`: expected a function of one parameter set, got {build!r}")
    if client is not None and backend != "dask":
        raise ValueError("invalid argument `client`: only the dask backend takes a client")
    if workers is not None and backend != "local":
        raise ValueError("invalid argument `workers`: only the local backend takes a worker count")
    try:
        params = list(params)
    except TypeError:
        raise TypeError(f"invalid argument `params`: expected a sequence of parameter sets, got {params!r}") from None
    if backend == "local":
        count = workers if workers is not None else (os.cpu_count() or 1)
        if not isinstance(count, int) or count < 1:
            raise ValueError(f"invalid argument `workers`: expected a whole number >= 1, got {workers!r}")
        with ThreadPoolExecutor(max_workers=count) as pool:
            return list(pool.map(lambda p: _one(build, p, duration, frame_interval), params))
    if backend == "dask":
        try:
            import distributed  # noqa: PLC0415 - optional extra
        except ImportError as error:
            raise ImportError(f"backend='dask' needs Dask: {install_hint('dask')}") from error
        if client is None:
            client = _current_dask_client(distributed)
        if client is not None:
            return _dask_map(client, build, params, duration, frame_interval)
        return _dask_local(distributed, build, params, duration, frame_interval)
    try:
        import ray  # noqa: PLC0415 - optional extra
    except ImportError as error:
        raise ImportError(f"backend='ray' needs Ray: {install_hint('ray')}") from error
    if not ray.is_initialized():
        ray.init()
    task: Any = ray.remote(_one)  # a RemoteFunction of _one (its parameter type left open)
    shipped = ray.put(build)  # the build function goes to the object store once, not with every task
    runs: list[Run] = ray.get([task.remote(shipped, p, duration, frame_interval) for p in params])
    return runs
