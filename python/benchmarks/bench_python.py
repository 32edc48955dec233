"""Benchmarks of the Python package (issue #23), recorded in BENCHMARKS.md.

    python python/benchmarks/bench_python.py ASPERITY_CLI [WORKDIR]

with the package importable (``pip install ./python``, a release build) and
the release CLI of the same checkout. Prints:

1. ``analyze`` of a 4096² float64 array from numpy against the same work from
   Rust (the CLI on the same heights as .npy; its report's elapsed_s counts
   reading the file and the analysis), median of 3;
2. a sweep of 40 tasks of about 1 s on a 2-worker LocalCluster against the same
   tasks one after another (threads=1);
3. 1000 tiny tasks (RD, L = 64) on the cluster against the serial run.
"""

import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from distributed import Client, LocalCluster

import asperity

CLI = sys.argv[1]
WORK = Path(sys.argv[2] if len(sys.argv) > 2 else "target/bench-python")
WORK.mkdir(parents=True, exist_ok=True)


def median_time(fn, n=3):
    times = []
    for _ in range(n):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def analyze_bench():
    h = asperity.fbm(size=4096, hurst=0.8, seed=1)
    h.save(WORK / "f4096.npy")
    arr = np.load(WORK / "f4096.npy")
    # interleaved, so that both see the same machine state
    py, rust = [], []
    for _ in range(3):
        py.append(median_time(lambda: asperity.analyze(arr), 1))
        out = subprocess.run([CLI, "--json", "analyze", str(WORK / "f4096.npy")],
                             capture_output=True, text=True, check=True)
        rust.append(json.loads(out.stdout)["elapsed_s"])
    py, rust = statistics.median(py), statistics.median(rust)
    copy = median_time(lambda: asperity.HeightField(arr.copy()))
    print(f"analyze 4096² from numpy: {py:.3f} s; from Rust (CLI, read + analyse): {rust:.3f} s; "
          f"ratio {py / rust:.3f}; one 128 MiB copy ≈ {copy:.3f} s")


def one_second_task_size():
    # rdsr in 2-D with threads=1: grow layers until a task takes about 1 s
    layers = 200
    while True:
        t = median_time(lambda: asperity.rdsr(size=256, layers=layers, threads=1), 1)
        if t > 0.8:
            return layers, t
        layers = int(layers * 1.0 / max(t, 0.05) * 1.05)


def sweep_bench():
    layers, t1 = one_second_task_size()
    grid = dict(size=256, layers=layers)
    seeds = range(40)
    t = time.perf_counter()
    serial = asperity.sweep("rdsr", grid, seeds=seeds, serial=True, threads=1)
    t_serial = time.perf_counter() - t
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None)
    client = Client(cluster)
    asperity.sweep("rd", dict(size=16, layers=2), seeds=range(4), client=client)  # warm workers
    t = time.perf_counter()
    par = asperity.sweep("rdsr", grid, seeds=seeds, client=client, threads=1)
    t_par = time.perf_counter() - t
    assert par.equals(serial)
    print(f"40 tasks of {t1:.2f} s (rdsr L=256, T={layers}): serial {t_serial:.1f} s, "
          f"2-worker LocalCluster {t_par:.1f} s, ratio {t_par / t_serial:.2f}")
    tiny = dict(size=64, layers=100)
    t = time.perf_counter()
    s = asperity.sweep("rd", tiny, seeds=range(1000), serial=True, threads=1)
    t_s = time.perf_counter() - t
    t = time.perf_counter()
    p = asperity.sweep("rd", tiny, seeds=range(1000), client=client, threads=1)
    t_p = time.perf_counter() - t
    assert p.equals(s)
    print(f"1000 tiny tasks (rd L=64, T=100): serial {t_s:.2f} s, cluster {t_p:.2f} s, "
          f"ratio {t_p / t_s:.2f}")
    client.close()
    cluster.close()


if __name__ == "__main__":
    analyze_bench()
    sweep_bench()
