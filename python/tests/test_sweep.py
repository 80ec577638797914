"""Parameter sweeps (issue 15): the local sweep equals the same worlds run one by one, and the sweeps on a real
local Dask cluster and a local Ray instance equal the local sweep bit for bit. The Dask and Ray tests run when their
extras are installed (``pip install "./python[dask,ray]"``; CI installs both)."""

import functools

import numpy as np
import pytest

import tumble

# Rows of six dominoes (the built-in scene, which every worker process imports), spacing varied. A function of the
# test module itself would not import in Ray's workers.
PARAMS = [0.35, 0.4, 0.45, 0.5]
build = functools.partial(tumble.scenes.dominoes, 6)


def same(a: list, b: list) -> bool:
    fields = ("times", "body_positions", "body_orientations", "energy", "penetration")
    return len(a) == len(b) and all(
        getattr(x, f).tobytes() == getattr(y, f).tobytes() for x, y in zip(a, b) for f in fields)


def one_by_one() -> list:
    return [build(p).run(1.0) for p in PARAMS]


def test_the_local_sweep_equals_the_worlds_run_one_by_one():
    expected = one_by_one()
    assert same(tumble.sweep(build, PARAMS, 1.0), expected)
    assert same(tumble.sweep(build, PARAMS, 1.0, workers=1), expected)
    # the dominoes fall differently at each spacing: the sweep really varies the world
    assert not np.array_equal(expected[0].body_positions, expected[-1].body_positions)


def test_bad_sweeps_are_refused():
    with pytest.raises(ValueError, match="backend"):
        tumble.sweep(build, PARAMS, 1.0, backend="spark")
    with pytest.raises(ValueError, match="build"):
        tumble.sweep(lambda p: p, PARAMS, 1.0)
    with pytest.raises(ValueError, match="workers"):
        tumble.sweep(build, PARAMS, 1.0, workers=0)
    with pytest.raises(ValueError, match="client"):
        tumble.sweep(build, PARAMS, 1.0, client=object())


def test_a_dask_cluster_gives_the_local_sweep():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            runs = tumble.sweep(build, PARAMS, 1.0, backend="dask", client=client)
    assert same(runs, one_by_one())


def no_dask_client(distributed) -> bool:
    try:
        distributed.get_client()
    except ValueError:  # "No global client found"
        return True
    return False


def test_dask_without_a_client_starts_a_local_one_and_closes_it():
    distributed = pytest.importorskip("distributed")
    assert no_dask_client(distributed)
    runs = tumble.sweep(build, PARAMS, 1.0, backend="dask")
    assert same(runs, one_by_one())
    assert no_dask_client(distributed)  # the client it started is closed
    # a client the user started is the one used, and is left running
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=2, dashboard_address=None) as client:
        with distributed.get_task_stream(client=client) as tasks:
            assert same(tumble.sweep(build, PARAMS[:2], 1.0, backend="dask"), one_by_one()[:2])
        assert len(tasks.data) == 2  # both runs were tasks on the user's cluster
        assert client.status == "running" and distributed.get_client() is client


def test_a_ray_instance_gives_the_local_sweep():
    ray = pytest.importorskip("ray")
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        runs = tumble.sweep(build, PARAMS, 1.0, backend="ray")
    finally:
        ray.shutdown()
    assert same(runs, one_by_one())
