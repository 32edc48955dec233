"""asperity.sweep on a real Dask LocalCluster with two worker processes."""

import os
import threading
import time

import numpy as np
import pandas as pd
import pytest
from distributed import Client, LocalCluster

import asperity

GRID = dict(dim=1, size=[256, 512], layers=[50, 100])


@pytest.fixture(scope="module")
def client():
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                           dashboard_address=None)
    c = Client(cluster)
    yield c
    c.close()
    cluster.close()


def test_cluster_equals_serial(client, tmp):
    serial = asperity.sweep("rdsr", GRID, seeds=range(3), serial=True)
    parallel = asperity.sweep("rdsr", GRID, seeds=range(3), client=client, out=tmp, format=".npy")
    assert len(serial) == 12
    pd.testing.assert_frame_equal(serial, parallel.drop(columns=["output"]))
    # each output is the method's surface for that task
    row = parallel.iloc[5]
    h = asperity.load(row["output"])
    again = asperity.rdsr(dim=1, size=int(row["size"]), layers=float(row["layers"]), seed=int(row["seed"]))
    np.testing.assert_array_equal(h.heights, again.surface.heights)


def test_a_killed_worker_still_gives_every_row_once(client):
    grid = dict(dim=2, size=[128], layers=[200, 201, 202, 203])
    serial = asperity.sweep("rdsr", grid, seeds=range(4), serial=True)
    result = {}

    def run():
        result["df"] = asperity.sweep("rdsr", grid, seeds=range(4), client=client, batch=1)

    t = threading.Thread(target=run)
    t.start()
    # wait until tasks are running, then kill one worker process outright
    deadline = time.time() + 30
    while time.time() < deadline and not any(client.processing().values()):
        time.sleep(0.05)
    victim = sorted(client.scheduler_info()["workers"])[0]
    try:
        client.run(os._exit, 1, workers=[victim])
    except Exception:
        pass  # the worker died before it could answer
    t.join(120)
    assert not t.is_alive()
    assert victim not in client.scheduler_info()["workers"], "the worker was killed"
    df = result["df"]
    assert len(df) == len(serial) == 16
    assert not df.duplicated(subset=["layers", "seed"]).any()
    pd.testing.assert_frame_equal(serial, df)


def test_rdsr_beta_over_sixteen_seeds(client):
    df = asperity.sweep("rdsr", dict(dim=1, size=4096, layers=1000), seeds=range(16), client=client)
    assert len(df) == 16
    assert df["beta"].mean() == pytest.approx(0.25, abs=0.02)


def test_custom_measure_and_callable_method(client):
    df = asperity.sweep(asperity.fbm, dict(size=32, hurst=[0.3, 0.8]), seeds=[1, 2], client=client,
                        measure=lambda h: {"rms": float(h.heights.std())})
    assert list(df.columns) == ["size", "hurst", "seed", "rms"]
    assert np.allclose(df["rms"], 1.0, rtol=1e-6)


def test_bad_sweeps_raise():
    with pytest.raises(ValueError):
        asperity.sweep("no_such_method", {}, serial=True)
    with pytest.raises(ValueError):
        asperity.sweep("rd", dict(size=16, layers=2), seeds=[], serial=True)
    with pytest.raises(ValueError):
        asperity.sweep("rd", dict(size=0), serial=True)
