"""Parameter sweeps on Dask: a grid of parameters × seeds of any asperity
method, measured into a pandas DataFrame.

Tasks are keyed by their parameters (a hash of the method, parameters and
seed), so a run gives the same table as a serial one, a lost worker's tasks
are recomputed by the scheduler and each appears exactly once. Small tasks
are batched so that scheduling overhead stays small next to the work.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import os
from pathlib import Path
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Sequence, Union

_DEFAULT_KEYS = ("beta", "alpha", "radius_of_gyration")


def _flatten(prefix: str, value: Any, row: Dict[str, Any]) -> None:
    if isinstance(value, bool) or value is None or isinstance(value, (int, float, str)):
        row[prefix] = value
    elif isinstance(value, Mapping):
        for k, v in value.items():
            _flatten(f"{prefix}.{k}" if prefix else str(k), v, row)
    # lists (series, spectra) are left out of the table


def default_measure(result) -> Dict[str, Any]:
    """Every scalar of a result's ``measurements`` (nested keys joined by
    dots) plus ``beta``, ``alpha`` and ``radius_of_gyration`` where present."""
    row: Dict[str, Any] = {}
    m = result.get("measurements") if isinstance(result, dict) else None
    if isinstance(m, Mapping):
        _flatten("", m, row)
    elif isinstance(result, Mapping):
        _flatten("", {k: v for k, v in result.items() if not hasattr(v, "shape")}, row)
    for k in _DEFAULT_KEYS:
        if isinstance(result, Mapping) and k in result and not isinstance(result[k], Mapping):
            row[k] = result[k]
    return row


def _method(method: Union[str, Callable]) -> Callable:
    if callable(method):
        return method
    from . import api

    fn = getattr(api, method, None)
    if fn is None or method.startswith("_") or not callable(fn):
        raise ValueError(f"unknown asperity method {method!r}")
    return fn


def _grid(params: Union[None, Mapping[str, Sequence], Sequence[Mapping[str, Any]]]) -> List[Dict[str, Any]]:
    if params is None:
        return [{}]
    if isinstance(params, Mapping):
        names = list(params)
        values = []
        for n in names:
            v = params[n]
            values.append(list(v) if isinstance(v, (list, tuple, range)) else [v])
        return [dict(zip(names, combo)) for combo in itertools.product(*values)]
    return [dict(p) for p in params]


def _task_key(name: str, params: Dict[str, Any], seed: int) -> str:
    text = json.dumps([name, params, seed], sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:24]


def _output_name(name: str, params: Dict[str, Any], seed: int) -> str:
    parts = [name] + [f"{k}={v}" for k, v in sorted(params.items())] + [f"seed={seed}"]
    safe = "_".join(parts)
    return "".join(c if c.isalnum() or c in "=.-_" else "-" for c in safe)


def _primary(result):
    for k in ("mesh", "surface", "points"):
        if isinstance(result, Mapping) and k in result:
            return result[k]
    return result if hasattr(result, "save") else None


def run_task(method, params: Dict[str, Any], seed: int, measure: Optional[Callable],
             out: Optional[str], fmt: str, threads: Optional[int]) -> Dict[str, Any]:
    """One task: runs the method, measures it, writes its output if asked."""
    fn = _method(method)
    kwargs = dict(params)
    kwargs["seed"] = seed
    if threads is not None:
        kwargs["threads"] = threads
    result = fn(**kwargs)
    row = dict(params)
    row["seed"] = seed
    row.update((measure or default_measure)(result))
    if out is not None:
        surface = _primary(result)
        if surface is not None:
            ext = fmt or (".ply" if not hasattr(surface, "heights") else ".npy")
            path = Path(out) / (_output_name(method if isinstance(method, str) else fn.__name__,
                                             params, seed) + ext)
            surface.save(path)
            row["output"] = str(path)
    return row


def _run_batch(method, tasks, measure, out, fmt, threads):
    return [(i, run_task(method, p, s, measure, out, fmt, threads)) for i, p, s in tasks]


def _client(client):
    from distributed import Client, LocalCluster

    if isinstance(client, Client):
        return client, None
    if isinstance(client, str):
        c = Client(client)
        return c, c
    cluster = LocalCluster(n_workers=max(1, min(os.cpu_count() or 1, 4)), threads_per_worker=1,
                           processes=True, dashboard_address=None)
    c = Client(cluster)
    return c, (c, cluster)


def sweep(method: Union[str, Callable], params=None, seeds: Iterable[int] = (0,), *,
          measure: Optional[Callable] = None, client=None, out: Optional[Union[str, Path]] = None,
          format: Optional[str] = None, threads: Optional[int] = 1, batch: Optional[int] = None,
          serial: bool = False):
    """Runs ``method`` over every combination of ``params`` and every seed and
    returns a pandas DataFrame, one row per task, in grid-then-seed order.

    method: an asperity function or its name ("rdsr", "dla", "ca_run"…).
    params: {name: [values]} (the Cartesian product) or a list of keyword dicts.
    seeds: the seeds of each combination.
    measure: result → dict of columns (default: every scalar measurement,
        with beta, alpha, R_g).
    client: None starts an embedded ``distributed.LocalCluster`` (closed
        afterwards); a ``distributed.Client`` or a scheduler address
        ("tcp://host:8786") runs on that cluster — dask-jobqueue's
        SLURMCluster/PBSCluster, Kubernetes… (docs/python.md has a Slurm
        example).
    serial: run in this process, one task after another (the reference).
    out: a folder to write each task's surface into, named by its parameters
        (``format`` chooses the extension: ".ply", ".npy", ".glb"…).
    threads: threads per task (default 1: the cluster's processes give the
        parallelism); None uses every core of the worker.
    batch: tasks per Dask task (default: about eight batches per worker).
    """
    import pandas as pd

    if measure is not None and not callable(measure):
        raise TypeError("measure must be a callable(result) -> dict")
    if isinstance(method, str):
        _method(method)
    grid = _grid(params)
    seeds = list(seeds)
    if not seeds:
        raise ValueError("seeds: give at least one seed")
    tasks = [(i, p, s) for i, (p, s) in enumerate((p, s) for p in grid for s in seeds)]
    if out is not None:
        Path(out).mkdir(parents=True, exist_ok=True)
        out = str(out)
    name = method if isinstance(method, str) else method
    if serial:
        rows = [r for _, r in _run_batch(name, tasks, measure, out, format, threads)]
        return pd.DataFrame(rows)
    c, owned = _client(client)
    try:
        workers = max(1, len(c.scheduler_info().get("workers", {})) or 1)
        size = batch or max(1, math.ceil(len(tasks) / (workers * 8)))
        batches = [tasks[k:k + size] for k in range(0, len(tasks), size)]
        label = method if isinstance(method, str) else getattr(method, "__name__", "method")
        futures = [
            c.submit(_run_batch, name, b, measure, out, format, threads, pure=False,
                     key=f"asperity-{label}-" + _task_key(label, {"batch": [(p, s) for _, p, s in b]}, 0),
                     retries=3)
            for b in batches
        ]
        done = {}
        for part in c.gather(futures):
            for i, row in part:
                done[i] = row
    finally:
        if owned is not None:
            for o in (owned if isinstance(owned, tuple) else (owned,)):
                o.close()
    return pd.DataFrame([done[i] for i in range(len(tasks))])
