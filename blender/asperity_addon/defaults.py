"""The engine's defaults for the add-on's properties (issue #36): the add-on
types none of its own. ``blender/build.py`` writes ``engine_defaults.json``
into the zip from the asperity package it bundles (every job's fields with
their defaults, the IFS presets, the subdivision example scenes); without that file (the add-on run from the
source folder) they come from the package itself.

``default(job, field)`` is a property's default; ``FIELDS`` records which
engine field each property follows, so the add-on's test checks every one
against the engine.
"""
from __future__ import annotations

import json
from pathlib import Path

_FILE = Path(__file__).with_name("engine_defaults.json")


def snapshot(asp) -> dict:
    """What ``engine_defaults.json`` holds, from the package ``asp``."""
    jobs = {}
    for job in asp._asperity.jobs():
        desc = json.loads(asp._asperity.describe(job))
        jobs[job] = {f["name"]: f["default"] for f in desc["fields"]}
    return {"seed": asp._asperity.DEFAULT_SEED, "jobs": jobs,
            "ifs_presets": [p["name"] for p in asp.ifs_presets()],
            "subdiv_examples": json.loads(asp._asperity.subdiv_examples()),
            "rock": json.loads(asp._asperity.subdiv_rock_defaults()),
            "ca_terrain": json.loads(asp._asperity.ca_terrain_example())}


def _load() -> dict:
    if _FILE.exists():
        return json.loads(_FILE.read_text())
    from . import engine

    return snapshot(engine.package())


_DATA: dict = {}


def _data() -> dict:
    if not _DATA:
        _DATA.update(_load())
    return _DATA

#: (operator id name, property) -> (job, field): the properties that follow the engine
FIELDS: dict = {}


def default(job: str, field: str):
    """The engine's default of ``field`` of ``job`` (``seed``: the default seed)."""
    if field == "seed":
        return _data()["seed"]
    return _data()["jobs"][job][field]


def follow(op: str, prop: str, job: str, field: str):
    """``default(job, field)``, recorded as property ``prop`` of operator ``op``."""
    FIELDS[(op, prop)] = (job, field)
    return default(job, field)


def rock(key: str) -> float:
    """The engine's default of the rock detail's ``key`` (amplitude, decay)."""
    return _data()["rock"][key]


def ca_terrain() -> dict:
    """The engine's example CA terrain run (``CaRunParams::terrain_example``):
    rule, steps, density of its random start, cells a side."""
    ex = _data()["ca_terrain"]
    init = ex["init"]
    return {"rule": int(ex["rule"]), "steps": ex["steps"],
            "init": "random" if init.startswith("random") else "seed",
            "density": float(init.split(":")[1].split("@")[0]) if init.startswith("random:") else 0.5,
            "size": ex["size"][0]}


def subdiv_examples() -> list:
    """The engine's example scenes: name, description, levels, seed, size, spacing."""
    return list(_data()["subdiv_examples"])


def ifs_presets() -> list:
    """The engine's IFS presets, in its order."""
    return list(_data()["ifs_presets"])
