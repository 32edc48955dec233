"""Parity property test (issue #36): for every job that both front ends run,
parameter sets drawn from the engine's own description of the job (its fields,
choices and ranges, ``_asperity.describe``) within CI-sized bounds give the same
outcome from the CLI (``--params FILE``) and from Python (``**params``): the
same file, byte for byte, and the same ``params`` record — or the same error,
each naming the parameter its own way (``--flag`` / ``flag=``). At least
``ASPERITY_PARITY_SETS`` (50) sets of each job must succeed.

The bounds below only keep the runs small (a lattice of 32, 300 particles);
the values themselves come from the engine's description, so a new field or
choice is drawn as soon as the engine has it. Inputs that are files on one
side and objects on the other (meshes, images) are made once per session.
"""

import json
import os
import re
import subprocess
import zlib
from pathlib import Path

import numpy as np
import pytest

import asperity
from asperity import _asperity
from asperity._jobs import describe

SETS = int(os.environ.get("ASPERITY_PARITY_SETS", "50"))

# Fields whose values are files or texts of files: the parity of reading
# them is checked elsewhere (test_cli_parity); here they keep their defaults.
FILE_FIELDS = {"scene", "scene_text", "ifs", "model", "control", "apply_details", "analyze",
               "save_every"}


def _between(lo, hi):
    return lambda rng, _: float(rng.uniform(lo, hi))


def _ints(lo, hi):
    return lambda rng, _: int(rng.integers(lo, hi + 1))


def _one_of(*values):
    return lambda rng, _: values[int(rng.integers(len(values)))]


def _maybe(p, draw):
    return lambda rng, d: None if rng.random() < p else draw(rng, d)


DEPOSIT = {"size": _ints(4, 32), "layers": _between(0.5, 20), "runs": _ints(1, 3),
           "bin": lambda rng, d: None, "samples_per_decade": _ints(1, 20),
           "fit_window": _maybe(0.7, lambda rng, d: [1.0, float(rng.uniform(2, 20))]),
           "alpha_sizes": lambda rng, d: None, "substrate": _one_of("flat", "flat", "sphere"),
           "radius": _between(2, 6), "resolution": _ints(8, 16), "relax": _ints(1, 3)}
LEVEL_SET = {"resolution": _ints(8, 16), "spacing": lambda rng, d: None,
             "offset": _maybe(0.4, _one_of("2h", "3h", "4h", 1.5)),
             "iterations": _ints(0, 8), "tolerance": _maybe(0.8, _between(0.01, 0.5)),
             "point_radius": _maybe(0.7, _between(0.0, 0.3)), "curvature_weight": _between(0, 2),
             "tube": _between(3, 4), "beta": _between(1, 2.5), "cfl": _between(0.3, 0.9),
             "redistance": _ints(0, 3), "min_shell": _ints(0, 32)}
CURVES = ("bezier-quadratic", "bezier-cubic", "bezier", "takagi-landsberg", "takagi-landsberg-4pt")
SURFACES = ("bezier-bicubic", "takagi-landsberg-surface", "bezier-takagi", "takagi-square")
IFS_MODEL = {"w": _maybe(0.6, _between(0.3, 0.9)), "degree": _maybe(0.7, _ints(2, 5)),
             "height": _maybe(0.6, _between(0.1, 1.0)), "move": lambda rng, d: [],
             "family_depth": _ints(2, 8), "family_period": _ints(0, 6)}

# job: (CLI words, Python function, leading inputs, output, bounds)
#   output: a file extension, or "report" (the measurements of --json)
JOBS = {
    "growth rd": (["growth", "rd"], "rd", [], "gsf", DEPOSIT),
    "growth rdsr": (["growth", "rdsr"], "rdsr", [], "gsf", DEPOSIT),
    "growth bd": (["growth", "bd"], "bd", [], "gsf", DEPOSIT),
    "growth dla": (["growth", "dla"], "dla", [], "ply", {
        "seed_shape": _one_of("point", "plane", "sphere"),
        "size": _maybe(0.3, _one_of(16, 24, 32, [16, 24], [32, 16, 24])), "particles": _ints(1, 300),
        "stick": _between(0.05, 1.0), "seed_radius": _between(0.5, 4), "resolution": _ints(8, 16),
        "seed_density": _between(0.01, 1.0), "launch_gap": _between(1, 4)}),
    "generate fbm": (["generate", "fbm"], "fbm", [], "npy", {
        "size": _ints(2, 64), "hurst": _between(0.05, 1.0), "rms": _between(0, 2),
        "spacing": _between(0.1, 2)}),
    "reconstruct": (["reconstruct"], "reconstruct", ["points"], "ply", LEVEL_SET),
    "generate dla-terrain": (["generate", "dla-terrain"], "dla_terrain", [], "ply", {
        **LEVEL_SET, "size": _one_of(16, 24, [16, 16, 24]),
        "particles": _maybe(0.2, _ints(20, 300)), "stick": _between(0.2, 1.0)}),
    "generate rdsr-sphere": (["generate", "rdsr-sphere"], "rdsr_sphere", [], "ply", {
        **LEVEL_SET, "radius": _between(2, 5),
        "layers": _between(0.5, 3), "relax": _ints(1, 2)}),
    "ca run": (["ca", "run"], "ca_run", [], "npy", {
        "rule": _one_of(450, 8, 480, 1018, 0, "B3/S23", 10 ** 12), "steps": _ints(0, 12),
        "states": _ints(2, 3), "init": _one_of("seed", "random:0.3", "random:0.5@3"),
        "size": _maybe(0.4, lambda rng, d: [int(rng.integers(4, 33)), int(rng.integers(4, 33))]),
        "decay": _maybe(0.7, _between(0.3, 1.0)), "weights": lambda rng, d: None,
        "values": lambda rng, d: None}),
    "ca gallery": (["ca", "gallery"], "ca_gallery", [], "png", {
        "rules": _one_of(["8"], ["450", "8"], ["B3/S23"]), "states": _ints(2, 3),
        "inits": _one_of(["seed"], ["seed", "random:0.3"], ["random:0.5@3"]), "steps": _ints(0, 6),
        "size": lambda rng, d: [int(rng.integers(4, 17)), int(rng.integers(4, 17))],
        "tile": lambda rng, d: [int(rng.integers(8, 48)), int(rng.integers(8, 48))]}),
    "ca rule": (["ca", "rule"], "ca_rule", [], "report", {
        "rule": _one_of(450, 8, 480, "B3/S23", 70000), "states": _ints(2, 4)}),
    # the draped curves go into the CLI's PLY beside the mesh, not into Python's
    # mesh (test_cli_parity compares them): no circle here
    "facet": (["facet"], "facet", ["heights"], "ply", {"circle": lambda rng, d: None}),
    "subdiv": (["subdiv", "--triangles"], "subdiv", [], "ply", {
        "base": _one_of("cube", "sphere", "torus", "cylinder", "plane", "fuse"), "levels": _ints(0, 2),
        "detail": _one_of([], ["rock"], ["fbm:amplitude=0.05"], ["berry:radius=0.2"]),
        "crease": lambda rng, d: [], "time": _between(0, 1)}),
    "ifs preset": (["ifs", "preset"], "ifs_model", [], "json",
                   {**IFS_MODEL, "preset": _one_of(*CURVES, *SURFACES)}),
    "ifs curve": (["ifs", "curve"], "ifs_curve", [], "csv",
                  {**IFS_MODEL, "preset": _one_of(*CURVES), "depth": _ints(0, 9)}),
    "ifs surface": (["ifs", "surface"], "ifs_surface", [], "ply",
                    {**IFS_MODEL, "preset": _one_of(*SURFACES, "takagi-landsberg"),
                     "depth": _ints(1, 5)}),
    "ifs dcf": (["ifs", "dcf"], "ifs_dcf", [], "csv", {
        **IFS_MODEL, "preset": _one_of(*CURVES), "operator": _ints(0, 1),
        "start": _maybe(0.5, _between(0, 1)), "samples": _ints(1, 64), "family": _ints(1, 12)}),
    "ifs sdcf": (["ifs", "sdcf"], "ifs_sdcf", [], "ply", {
        **IFS_MODEL, "preset": _one_of(*SURFACES),
        "operator": lambda rng, d: [int(rng.integers(2)), int(rng.integers(2))],
        "start": _maybe(0.5, lambda rng, d: [float(rng.uniform(0, 1)), float(rng.uniform(0, 1))]),
        "resolution": _ints(1, 12), "with_attractor": _maybe(0.7, _ints(1, 3))}),
    "ifs curvature": (["ifs", "curvature"], "ifs_curvature", [], "report", {
        **IFS_MODEL, "preset": _one_of(*CURVES, *SURFACES),
        "at": _one_of([], ["0.5"], ["0.25", "0.75"], ["0.5,0.25"])}),
    "surface-ca": (["surface-ca"], "surface_ca", ["mesh"], "ply", {
        "cells": _ints(100, 1500), "cell_size": lambda rng, d: None, "sites": _ints(1, 8),
        "max_steps": _ints(1, 150), "steps": _ints(1, 25), "patches": _ints(1, 6),
        "feed": _between(0.02, 0.06), "kill": _between(0.05, 0.07), "max_seeds": _ints(1, 50),
        "seed_rate": _between(0, 0.01), "strong_noise": _maybe(0.7, _between(0.2, 1.0)),
        "maturity": _ints(1, 60), "displace": _maybe(0.7, _between(-0.05, 0.05))}),
    "analyze": (["analyze"], "analyze", ["heights_file"], "report", {
        "bins": _ints(2, 60), "fit_window": _maybe(0.6, lambda rng, d: [0.2, float(rng.uniform(0.5, 3))]),
        "lambda_s": _maybe(0.6, _between(1, 5)), "lambda_c": _maybe(0.5, _between(4, 20))}),
    "filter": (["filter"], "filter_surface", ["heights_file"], "npy", {
        "lambda_s": _maybe(0.5, _between(1, 5)), "lambda_c": _maybe(0.3, _between(4, 20))}),
    "render": (["render"], "render", ["mesh_file"], "png", {
        "size": lambda rng, d: [int(rng.integers(8, 65)), int(rng.integers(8, 49))],
        "eye": _maybe(0.8, lambda rng, d: [float(v) for v in rng.uniform(-3, 3, 3)]),
        "target": lambda rng, d: None, "fov": _between(10, 90), "scalar": lambda rng, d: None,
        "light": _maybe(0.6, lambda rng, d: [float(rng.uniform(0, 360)), float(rng.uniform(5, 85))]),
        "ao": _between(0, 1), "supersample": _ints(1, 2), "z_scale": _between(0.5, 3),
        "background": _one_of("gradient", "white", "black", "#336699")}),
}


def draw_field(f, rng, bounds, drawn):
    name = f["name"]
    if name in bounds:
        return bounds[name](rng, drawn)
    if f.get("nullable") and rng.random() < 0.4:
        return None
    if "choices" in f:
        return f["choices"][int(rng.integers(len(f["choices"])))]["value"]
    t = f.get("type")
    if t == "boolean":
        return bool(rng.random() < 0.5)
    d = f["default"]
    if t == "integer":
        lo = f.get("minimum", 0)
        hi = f.get("maximum", max(lo, d if isinstance(d, int) else lo) + 8)
        return int(rng.integers(lo, hi + 1))
    if t == "number":
        lo = f.get("minimum", f.get("exclusiveMinimum", 0.0))
        hi = f.get("maximum", f.get("exclusiveMaximum", (d or 1.0) * 2 if isinstance(d, (int, float)) else lo + 1))
        return float(rng.uniform(lo, hi))
    return d


def draw(job, rng):
    """A parameter set: the fields the bounds name always drawn (their defaults
    can be large), every other one kept at its default or drawn, half and half."""
    desc = describe(job)
    bounds = JOBS[job][4]
    drawn = {}
    for f in desc["fields"]:
        if f["name"] in FILE_FIELDS:
            continue
        if f.get("required") or f["name"] in bounds or rng.random() < 0.5:
            drawn[f["name"]] = draw_field(f, rng, bounds, drawn)
    if desc["seeded"]:
        drawn["seed"] = int(rng.integers(0, 1000))
    return drawn


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    d = tmp_path_factory.mktemp("parity-inputs")
    heights = asperity.fbm(size=16, hurst=0.7, seed=1)
    heights.save(d / "heights.npy")
    pts = asperity.dla(particles=200, size=24, seed=2).points
    pts.save(d / "points.ply")
    mesh = asperity.subdiv(base="sphere", levels=1, detail=["rock"]).mesh
    mesh.save(d / "mesh.ply")
    files = {"points": d / "points.ply", "heights": d / "heights.npy", "mesh": "builtin:cube",
             "heights_file": d / "heights.npy", "mesh_file": d / "mesh.ply"}
    objects = {"points": asperity.load(d / "points.ply"), "heights": asperity.load(d / "heights.npy"),
               "mesh": "builtin:cube", "heights_file": asperity.load(d / "heights.npy"),
               "mesh_file": asperity.load(d / "mesh.ply")}
    return files, objects


def cli_run(words, lead, params_file, out):
    exe = os.environ["ASPERITY_CLI"]
    cmd = [exe, "--json", *words, *map(str, lead), "--params", str(params_file)]
    if out is not None:
        cmd += ["-o", str(out)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        err = [l for l in p.stderr.splitlines() if l.startswith("error: ")]
        assert err and "panicked" not in p.stderr, p.stderr
        # the CLI says which file the parameters came from
        return None, re.sub(r"^reading \S+: ", "", err[0][len("error: "):])
    return (json.loads(p.stdout) if p.stdout.strip() else None), None


# keywords beside the parameters: surface-ca writes cells to .ply, as the CLI does
PYTHON_EXTRA = {"surface_ca": {"textured": False}}


def output_kind(kind, params):
    """Curved deposits are point sets."""
    if kind == "gsf" and params.get("substrate", "flat") != "flat":
        return "ply"
    return kind


def python_run(name, lead, params, out, kind):
    try:
        r = getattr(asperity, name)(*lead, **params, **PYTHON_EXTRA.get(name, {}))
    except (ValueError, TypeError, OSError) as e:
        return None, str(e)
    if kind in ("npy", "gsf"):
        (r["surface"] if isinstance(r, dict) else r).save(out)
    elif kind == "ply":
        obj = r
        for attr in ("mesh", "points"):
            if isinstance(r, dict) and attr in r:
                obj = r[attr]
                break
        obj.save(out)
    elif kind == "png":
        out.write_bytes(_asperity.encode_png(r, json.dumps(r.params)))
    return r, None


def as_cli(message):
    """A Python message in the CLI's words: ``flag=`` is ``--flag``."""
    message = re.sub(r'([a-z_0-9]+)="([^"]*)"', lambda m: f"--{m[1].replace('_', '-')} {m[2]}", message)
    message = re.sub(r"\b([a-z_0-9]+)=(-?[0-9.]+)\b", lambda m: f"--{m[1].replace('_', '-')} {m[2]}", message)
    return re.sub(r"\b([a-z_0-9]+)=", lambda m: "--" + m[1].replace("_", "-"), message)


def strip(m):
    drop = {"elapsed_s", "seconds", "timings_s", "build_s", "write_s", "cells_s", "file",
            "cell_updates_per_second", "build_and_write_s", "run_s", "cell_updates_per_s"}
    if isinstance(m, dict):
        return {k: strip(v) for k, v in m.items() if k not in drop}
    if isinstance(m, list):
        return [strip(v) for v in m]
    return m


def compare(job, tmp, rep, r, kind):
    cli_out, py_out = tmp / f"c.{kind}", tmp / f"p.{kind}"
    if kind in ("npy", "gsf", "ply", "png"):
        assert cli_out.read_bytes() == py_out.read_bytes(), f"{job}: the files differ"
    elif kind == "csv":
        a = np.loadtxt(cli_out, delimiter=",", skiprows=1)[:, 1:]
        pts = r if isinstance(r, np.ndarray) else r["points"]
        b = np.asarray(pts)[:, : a.shape[1]]
        assert np.array_equal(a, b), f"{job}: the points differ"
    elif kind == "json":
        assert json.loads(cli_out.read_text()) == r, f"{job}: the models differ"
    if kind == "report":
        mine = dict(r)
        mine.pop("warnings", None)
        theirs = rep if job == "ifs curvature" else rep["measurements"]
        if job == "ca rule":
            mine = r["measurements"]
        assert strip({k: v for k, v in mine.items() if k != "params"}) == \
            strip({k: v for k, v in theirs.items() if k != "params"}), f"{job}: the reports differ"
    record = r["params"] if isinstance(r, dict) and "params" in r else getattr(r, "params", None)
    if job == "ifs preset":
        return
    cli_record = rep["params"] if rep is not None else None
    assert record == cli_record, f"{job}: params differ:\n{record}\n{cli_record}"


@pytest.mark.parametrize("job", sorted(JOBS))
def test_cli_and_python_agree(job, tmp_path, inputs):
    words, name, lead, job_kind, _ = JOBS[job]
    files, objects = inputs
    # A seed of the job's name that is the same in every process (Python's
    # str hash is salted per process, which made the draws differ run to run).
    rng = np.random.default_rng(zlib.crc32(job.encode()))
    ok = failed = 0
    for attempt in range(4 * SETS):
        if ok >= SETS:
            break
        params = draw(job, rng)
        kind = output_kind(job_kind, params)
        tmp = tmp_path / str(attempt)
        tmp.mkdir()
        (tmp / "p.json").write_text(json.dumps(params))
        out = None if kind == "report" else tmp / f"c.{kind}"
        rep, cli_err = cli_run(words, [files[i] for i in lead], tmp / "p.json", out)
        r, py_err = python_run(name, [objects[i] for i in lead], params, tmp / f"p.{kind}", kind)
        where = f"{job} with {json.dumps(params)}"
        assert (cli_err is None) == (py_err is None), f"{where}: CLI {cli_err!r}, Python {py_err!r}"
        if cli_err is not None:
            assert "--" not in py_err, f"{where}: Python names a flag: {py_err}"
            assert as_cli(py_err) == cli_err, f"{where}: CLI {cli_err!r}, Python {py_err!r}"
            failed += 1
            continue
        compare(job, tmp, rep, r, kind)
        ok += 1
    assert ok >= SETS, f"{job}: only {ok} of {ok + failed} parameter sets ran"


def test_a_2d_dla_lattice_is_the_same_from_both(cli, tmp):
    """The rule that once diverged: ``--dim 2 --size 64`` and ``dim=2,
    size=(64,)`` are both a 64 × 1 × 64 lattice (the CLI's reading of N)."""
    rep = cli("--seed", 5, "growth", "dla", "--dim", 2, "--size", 64, "--particles", 300,
              "-o", tmp / "c.ply")
    r = asperity.dla(dim=2, size=(64,), particles=300, seed=5)
    r.points.save(tmp / "p.ply")
    assert (tmp / "c.ply").read_bytes() == (tmp / "p.ply").read_bytes()
    assert rep["measurements"]["lattice"] == r.measurements["lattice"] == [64, 1, 64]
    assert rep["params"] == r.params and r.params["size"] == [64, 1, 64]


def test_every_job_with_parameters_is_drawn():
    """Every engine job is in JOBS, but those without parameters to draw:
    ``interpolate`` and ``info`` (none), ``convert`` (file options, compared
    byte for byte in test_cli_parity.test_render_and_load_save)."""
    untested = set(_asperity.jobs()) - set(JOBS)
    assert untested == {"interpolate", "info", "convert"}, untested
