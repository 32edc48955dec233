"""asperity's methods with the CLI's flag names and defaults as keywords.

Each function calls one job of the Rust engine (the same code the ``asperity``
CLI runs), so the same ``seed`` gives the same bytes as the CLI. Long jobs
release the GIL, stop on Ctrl-C within about a second, and take
``progress=True`` (a tqdm bar) or a callable ``(done, total, message)``.
``threads=None`` uses every core; results do not depend on the count.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Dict, Optional, Sequence, Tuple, Union

import numpy as np

from . import _asperity
from ._jobs import Job
from ._pictures import render
from ._run import call
from .types import HeightField, Mesh, PointSet, _wrap, params_json

Surface = Union[Mesh, HeightField, PointSet]


class Result(dict):
    """A job's result: a dict whose keys are also attributes
    (``r.points``, ``r.measurements``)."""

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    def __repr__(self) -> str:
        parts = []
        for k, v in self.items():
            if isinstance(v, np.ndarray):
                parts.append(f"{k}=<array {v.shape} {v.dtype}>")
            elif isinstance(v, dict):
                parts.append(f"{k}={{{len(v)} keys}}")
            else:
                parts.append(f"{k}={v!r}")
        return f"Result({', '.join(parts)})"


def _parse(text: str) -> dict:
    return json.loads(text)


def set_limits(max_memory: Optional[int] = None, max_time: Optional[float] = None) -> None:
    """Sets the memory budget (bytes; default the least of half of RAM and the
    headroom under the process's memory cgroup and ``ulimit -v``/``-d``) and the time limit
    (seconds; default one day; ``float('inf')`` for none) every job checks its
    estimate against before it starts, as the CLI's ``--max-memory`` and
    ``--max-time``."""
    mt = 0 if max_time is None else (2**64 - 1 if max_time == float("inf") else max(1, int(max_time)))
    _asperity.set_limits(int(max_memory or 0), mt)


def memory_budget() -> dict:
    """The memory budget every job checks its estimate against, as the CLI's
    ``--json`` reports it: ``{"bytes": N, "from": WHERE}``, where WHERE names
    the limit that applied: ``"given"`` (``set_limits(max_memory=...)``),
    ``"half_of_ram"``, ``"cgroup"`` (the process's memory cgroup, less what it
    uses), ``"rlimit_as"`` or ``"rlimit_data"`` (``ulimit -v``/``-d``, less the
    process's size)."""
    limit, source = _asperity.memory_budget()
    return {"bytes": limit, "from": source}


# ---------------------------------------------------------------- growth


def _deposit_result(d: dict) -> Result:
    m = _parse(d["measurements"])
    r = Result(measurements=m, beta=m.get("beta"))
    series = m.get("width_series") or []
    r["width"] = {k: np.array([row[k] for row in series]) for k in (series[0] if series else {})}
    r["alpha"] = (m.get("alpha") or {}).get("exponent")
    if "heights" in d:
        surface = HeightField._from(d["heights"], d["title"])
        r["surface"] = surface
        r["heights"] = surface.heights[0] if json.loads(d["params"])["dim"] == 1 else surface.heights
    if "points" in d:
        r["points"] = PointSet._from(d["points"], d["title"])
    return r


def _deposition(model: str, name: str, summary: str) -> Any:
    return Job(
        f"growth {model}", _asperity.deposit, _deposit_result, name=model, summary=summary,
        inputs=[("mesh", None, "a closed :class:`Mesh` substrate for ``substrate='mesh'``, "
                               "voxelised at ``resolution`` cells."),
                ("points", False, "also return every particle as ``points`` (lattice units; "
                                  "curved substrates always do).")],
        returns="Returns a :class:`Result` with ``heights`` (``(L,)`` or ``(L, L)``), ``surface`` "
                "(a :class:`HeightField`), ``width`` (arrays ``t`` and ``w``: W(t)), ``beta``, "
                "``alpha``, ``points`` when asked (curved substrates: always) and ``measurements`` "
                "(the CLI's JSON keys).",
    ).function()


rd = _deposition("rd", "rd", "Random deposition (RD, kim-machiraju-thompson §4.1) on a flat or "
                             "curved substrate: the CLI's ``growth rd``.")
rdsr = _deposition("rdsr", "rdsr", "Random deposition with surface relaxation (RDSR, "
                                   "kim-machiraju-thompson §4.1): the CLI's ``growth rdsr``.")
bd = _deposition("bd", "bd", "Ballistic deposition (BD, kim-machiraju-thompson §4.1): the CLI's "
                             "``growth bd``.")


def _dla_result(d: dict) -> Result:
    m = _parse(d["measurements"])
    return Result(points=PointSet._from(d["points"], d["title"]), warnings=d["warnings"],
                  measurements=m, radius_of_gyration=m.get("radius_of_gyration"),
                  dimension=m.get("fractal_dimension"))


dla = Job(
    "growth dla", _asperity.dla, _dla_result, name="dla",
    summary="Diffusion-limited aggregation (kim-machiraju-thompson §4.2): the CLI's ``growth dla``.",
    inputs=[("mesh", None, "a closed :class:`Mesh` seed for ``seed_shape='mesh'``, voxelised at "
                           "``resolution`` cells along its longest axis."),
            ("image", None, "a :class:`HeightField` whose bright columns seed a plane deposit "
                            "(``seed_shape='image'``), with probability up to ``seed_density``."),
            ("walkers", None, "concurrent walks (default: one a core, at most 4; more measure what a bigger "
                              "machine would see, in ``measurements['walkers']``); the cluster is the "
                              "same for any number.")],
    returns="Returns a :class:`Result` with ``points`` (a :class:`PointSet`, seeds first, in "
            "deposition order), ``warnings``, ``measurements`` (R_g, D, ρ(z) as the CLI's JSON), "
            "``radius_of_gyration`` and ``dimension``.",
).function()


# ---------------------------------------------------------------- level sets

def _reconstructed(d: dict) -> Result:
    r = Result(mesh=Mesh._from(d["mesh"]), measurements=_parse(d["measurements"]))
    if "points" in d:
        r["points"] = PointSet._from(d["points"])
        r["warnings"] = d["warnings"]
        r["grown"] = _parse(d["grown"])
    return r


def _points(points) -> np.ndarray:
    return points.points if isinstance(points, PointSet) else np.ascontiguousarray(points, dtype=np.float64)


_RECONSTRUCTED = ("Returns a :class:`Result` with ``mesh`` (with normals, and ``mean_curvature`` "
                  "and ``gaussian_curvature`` scalars with ``curvature=True``) and ``measurements`` "
                  "(the cloud, voids, grid, timings, topology, distance to the points, holes closed "
                  "as the CLI's JSON)")


def _normals(normals) -> Optional[np.ndarray]:
    return None if normals is None else np.ascontiguousarray(normals, dtype=np.float64)

reconstruct = Job(
    "reconstruct", _asperity.reconstruct, _reconstructed, name="reconstruct",
    summary="A watertight surface around (N, 3) points by the level-set flow "
            "(kim-machiraju-thompson §5): the CLI's ``reconstruct``.",
    leading=[("points", "a :class:`PointSet` or an (N, 3) array.", _points)],
    inputs=[("normals", None, "(N, 3) normals of the points, used to denoise a sampled "
                              "surface (e.g. a :class:`PointSet`'s ``normals``).")],
    convert={"normals": _normals},
    returns=_RECONSTRUCTED + ".",
).function()

dla_terrain = Job(
    "generate dla-terrain", _asperity.dla_terrain, _reconstructed, name="dla_terrain",
    summary="A plane DLA deposit reconstructed as a terrain (kim-machiraju-thompson Figs. 9–11): "
            "the CLI's ``generate dla-terrain``.",
    returns=_RECONSTRUCTED + ", ``points`` (the deposit), ``grown`` (the growth facts) and "
            "``warnings``.",
).function()

rdsr_sphere = Job(
    "generate rdsr-sphere", _asperity.rdsr_sphere, _reconstructed, name="rdsr_sphere",
    summary="RDSR layers grown on a sphere and reconstructed (kim-machiraju-thompson Fig. 8): the "
            "CLI's ``generate rdsr-sphere``.",
    returns=_RECONSTRUCTED + ", ``points`` (the deposit), ``grown`` (the growth facts) and "
            "``warnings``.",
).function()


# ---------------------------------------------------------------- cellular automata


def _ca_result(d: dict) -> Result:
    surface = HeightField._from(d["heights"], d["title"])
    r = Result(surface=surface, heights=surface.heights, measurements=_parse(d["measurements"]))
    if "states" in d:
        r["states"] = d["states"]
    return r


ca_run = Job(
    "ca run", _asperity.ca_run, _ca_result, name="ca_run",
    summary="A height field accumulated from a 2-D totalistic cellular automaton (peridier §2–3): "
            "the CLI's ``ca run --rule RULE --steps T``.",
    inputs=[("keep_states", False, "also return every step as ``states`` (T+1, ny, nx) uint8.")],
    returns="Returns a :class:`Result` with ``surface`` (a :class:`HeightField`), ``heights``, "
            "``measurements`` and, with ``keep_states``, ``states``.",
).function()

ca_rule = Job(
    "ca rule", _asperity.ca_rule,
    lambda d: Result(describe=d["describe"], measurements=_parse(d["measurements"])),
    name="ca_rule",
    summary="A rule's look-up table (peridier Figure 2): the CLI's ``ca rule``.",
    returns="Returns a :class:`Result` with ``describe`` (the table as text) and ``measurements``.",
    threads=False, progress=False,
).function()


ca_gallery = Job(
    "ca gallery", _asperity.ca_gallery, lambda d: d["image"], name="ca_gallery", result="np.ndarray",
    summary="A picture of CA height fields, one row per rule and one column per initial "
            "condition (peridier Figures 3–5): the CLI's ``ca gallery``.",
    returns="Returns the picture as an (H, W, 4) uint8 array (with ``params``; "
            ":func:`save_image` writes it with them).",
    progress=False,
).function()


def _polyline(p):
    return None if p is None else np.ascontiguousarray(p, dtype=np.float64)


facet = Job(
    "facet", _asperity.facet,
    lambda d: Result(mesh=Mesh._from(d["mesh"]), curves=d["curves"]),
    name="facet",
    summary="The alternating-diagonal facet mesh of a height field with curves draped on it "
            "(peridier §3): the CLI's ``facet``.",
    leading=[("heights", "a :class:`HeightField`.")],
    inputs=[("polyline", None, "(n, 2) x, y points of a curve to drape on the facets.")],
    returns="Returns a :class:`Result` with ``mesh`` and ``curves`` (a list of (n, 3) arrays).",
    threads=False, progress=False, convert={"polyline": _polyline},
).function()


def interpolate(heights: HeightField, points) -> np.ndarray:
    """Heights on the facets at (N, 2) x, y points (peridier's consistent
    interpolation; the CLI's ``interpolate``); NaN outside the field."""
    return _asperity.interpolate(heights, np.ascontiguousarray(points, dtype=np.float64))


# ---------------------------------------------------------------- subdivision


def _scene(fields: dict) -> dict:
    """``scene`` may be a scene file (a path, or a string ending in .toml), a
    built-in example (``"example:rock"``, see :func:`subdiv_examples`) or its
    TOML text: the text goes to the engine as ``scene_text``."""
    scene = fields.get("scene")
    if scene is None or isinstance(scene, Path):
        return fields
    text = str(scene)
    one_line = "\n" not in text and len(text) < 4096
    if one_line and (Path(text).suffix == ".toml" or text.startswith("example:")):
        return fields
    fields = dict(fields, scene_text=text)
    del fields["scene"]
    return fields


subdiv = Job(
    "subdiv", _asperity.subdiv,
    lambda d: Result(mesh=Mesh._from(d["mesh"]), levels=[tuple(c) for c in d["levels"]],
                     euler_characteristic=d["euler_characteristic"], details=d["details"]),
    name="subdiv",
    summary="A multiresolution Catmull–Clark surface with procedural detail (velho-perlin): the "
            "CLI's ``subdiv … --triangles``. ``scene`` may also be a built-in example "
            "(``\"example:rock\"``, :func:`subdiv_examples`) or a scene's TOML text.",
    inputs=[("export_details", False, "also return the detail file's text as ``details``.")],
    returns="Returns a :class:`Result` with ``mesh`` (triangles), ``levels`` ((vertices, faces) "
            "per level), ``euler_characteristic`` and ``details``.",
    prepare=_scene,
).function()


# ---------------------------------------------------------------- projected IFS


def subdiv_examples() -> list:
    """The built-in example scenes (velho-perlin Figs. 3–5, 7, 9), which
    ``subdiv("example:NAME")`` runs: a list of dicts with ``name``,
    ``description``, ``levels``, ``seed``, the main detail's ``size`` (its
    ``field`` and ``value``) and ``spacing``."""
    return json.loads(_asperity.subdiv_examples())


def _ifs_fields(fields: dict) -> dict:
    """A model given as a dict (e.g. built from numpy arrays of control points
    and operator matrices) goes to the engine as its JSON text; ``at`` points
    as "s" or "s,t" strings."""
    fields = dict(fields)
    model = fields.get("model")
    if isinstance(model, dict):
        fields["model"] = json.dumps(model, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o))
    if "at" in fields:
        fields["at"] = [",".join(map(str, a)) if isinstance(a, (tuple, list)) else str(a)
                        for a in fields["at"]]
    return fields


_IFS = dict(prepare=_ifs_fields, threads=False, progress=False)


def ifs_presets() -> list:
    """Every IFS preset: dicts with name, kind ("curve"/"surface") and description."""
    return _parse(_asperity.ifs_presets())


ifs_model = Job(
    "ifs preset", _asperity.ifs_model, _parse, name="ifs_model", record=False, result="dict",
    summary="The model as a model-file dict (what ``asperity ifs preset`` writes); edit it and "
            "pass it back as ``model=``.",
    returns="Returns the model file as a dict.", **_IFS,
).function()

ifs_curve = Job(
    "ifs curve", _asperity.ifs_curve, lambda d: d["points"], name="ifs_curve", result="np.ndarray",
    summary="A projected-IFS curve's attractor (poull-gentil §2): the CLI's ``ifs curve``.",
    returns="Returns the (2^depth + 1, 3) attractor points (an array with ``params``).", **_IFS,
).function()

ifs_surface = Job(
    "ifs surface", _asperity.ifs_surface, lambda d: Mesh._from(d["mesh"], d["name"]),
    name="ifs_surface", result="Mesh",
    summary="A tensor-product IFS surface's attractor mesh, with pseudo-curvature scalars unless "
            "``curvature=False`` (poull-gentil §2, §4): the CLI's ``ifs surface``.",
    returns="Returns a :class:`Mesh`.", prepare=_ifs_fields, progress=False,
).function()

ifs_dcf = Job(
    "ifs dcf", _asperity.ifs_dcf,
    lambda d: Result(points=d["points"], **{"class": d["class"]}, alpha=d["alpha"]),
    name="ifs_dcf",
    summary="The DCF of operator T_i of a curve (poull-gentil §3): the CLI's ``ifs dcf``.",
    returns="Returns a :class:`Result` with ``points`` (samples + 1, 3), ``class`` and ``alpha``.",
    **_IFS,
).function()

ifs_sdcf = Job(
    "ifs sdcf", _asperity.ifs_sdcf, lambda d: Mesh._from(d["mesh"]), name="ifs_sdcf", result="Mesh",
    summary="The SDCF of T_i ⊗ T'_j of a surface as a mesh (poull-gentil §4, Fig. 4): the CLI's "
            "``ifs sdcf``.",
    returns="Returns a :class:`Mesh`.", **_IFS,
).function()

ifs_curvature = Job(
    "ifs curvature", _asperity.ifs_curvature, _parse, name="ifs_curvature", result="dict",
    summary="Pseudo-curvature ranges per operator and at points (poull-gentil §5): the CLI's "
            "``ifs curvature --json`` document. ``at``: parameters s (curves), or (s, t) pairs "
            "or \"s,t\" strings (surfaces).",
    returns="Returns the report as a dict (with ``params``).", **_IFS,
).function()


# ---------------------------------------------------------------- surface CA

def _site_points(p):
    if p is None:
        return None
    return np.ascontiguousarray(p.points if isinstance(p, PointSet) else p, dtype=np.float64)


surface_ca = Job(
    "surface-ca", _asperity.surface_ca,
    lambda d: Result(mesh=Mesh._from(d["mesh"]),
                     labels=None if d["labels"] is None else PointSet._from(d["labels"]),
                     field=d["field"], warnings=d["warnings"],
                     measurements=_parse(d["measurements"])),
    name="surface_ca",
    summary="A cellular automaton on a triangle mesh (gobron-chiba): the CLI's ``surface-ca``.",
    leading=[("mesh", "a :class:`Mesh`, or \"builtin:sphere|cube|cylinder|cup\" or a path.")],
    inputs=[("site_points", None, "(n, 3) points or a :class:`PointSet`: the Voronoi sites, or "
                                  "the cells corroded from the start."),
            ("textured", True, "the original mesh with the cell atlas as ``mesh.texture`` (as "
                               "the CLI writes .glb/.obj); otherwise coloured cells.")],
    convert={"site_points": _site_points},
    returns="Returns a :class:`Result` with ``mesh``, ``labels`` (Voronoi: a :class:`PointSet` "
            "of cell centres with their region label; None otherwise), ``field`` (per-cell "
            "oxide or activator, or None), ``warnings`` and ``measurements``.",
).function()


# ---------------------------------------------------------------- analysis


def _surface(surface):
    """A numpy 2-D array is taken as heights with unit spacing."""
    return HeightField(surface) if isinstance(surface, np.ndarray) else surface


def _analysis(d: dict) -> dict:
    m = _parse(d["measurements"])
    m["warnings"] = d["warnings"]
    return m


analyze = Job(
    "analyze", _asperity.analyze, _analysis, name="analyze", result="dict",
    summary="Roughness numbers of a height field (ISO 25178 parameters, profiles, PSD, five Hurst "
            "estimators, fractal dimensions), of a mesh (topology, curvature) or of a point set: "
            "the CLI's ``analyze --json`` measurements, same keys, plus ``warnings``.",
    leading=[("surface", "a :class:`HeightField` (or a 2-D array: heights with unit spacing), "
                         "a :class:`Mesh` or a :class:`PointSet`.", _surface)],
    inputs=[("name", "array", "the name the report gives the surface (the CLI: the file).")],
    returns="Returns the measurements as a dict, with ``warnings`` and ``params``.",
    progress=False,
).function()


def _filtered(d: dict) -> Result:
    def part(name):
        return HeightField._from(d[name], name) if d[name] is not None else None

    return Result(surface=part("surface"), form=part("form"), waviness=part("waviness"),
                  noise=part("noise"), measurements=_parse(d["measurements"]),
                  warnings=d["warnings"])


filter_surface = Job(
    "filter", _asperity.filter_surface, _filtered, name="filter_surface",
    summary="The scale-limited surface of a height field or profile by the Gaussian filters of "
            "ISO 16610 (S-filter λs, L-filter λc, robust or linear), after the F-operator: the "
            "CLI's ``filter``.",
    leading=[("surface", "a :class:`HeightField` (or a 2-D array: heights with unit spacing).",
              _surface)],
    returns="Returns a :class:`Result` with ``surface`` (the scale-limited surface), ``form``, "
            "``waviness`` and ``noise`` (what the F-operator, L-filter and S-filter removed; "
            "None without that filter; the four add up to the input), ``measurements`` and "
            "``warnings``.",
    progress=False,
).function()


def psd(surface: Union[HeightField, np.ndarray], **options) -> Tuple[np.ndarray, np.ndarray]:
    """The radially averaged power spectral density of a height field as
    (q, C(q)) arrays (the ``psd`` of :func:`analyze`)."""
    p = analyze(surface, **options)["psd"]
    return np.asarray(p["q"]), np.asarray(p["C"])


def hurst(surface: Union[HeightField, np.ndarray], **options) -> Tuple[float, dict]:
    """The Hurst exponent H of a height field and every estimator's result."""
    m = analyze(surface, **options)
    return m["hurst"], m["hurst_estimates"]


def fractal_dimensions(surface: Union[HeightField, np.ndarray], **options) -> dict:
    """Fractal dimension estimates (D = 3 − H from the PSD, partitioning…)."""
    return analyze(surface, **options)["fractal_dimension"]


fbm = Job(
    "generate fbm", _asperity.fbm, lambda d: HeightField._from(d, d["title"]), name="fbm",
    result="HeightField",
    summary="A periodic self-affine (fBm) test surface by Fourier synthesis: the CLI's "
            "``generate fbm``.",
    returns="Returns a :class:`HeightField` (N × N samples); its ``params`` record the run.",
    progress=False,
).function()


# ---------------------------------------------------------------- io and render


def load(path: Union[str, Path], up: Optional[str] = None,
         channel: Optional[Union[int, str]] = None) -> Surface:
    """Reads any file asperity reads (by content and extension): a
    :class:`Mesh`, :class:`HeightField` or :class:`PointSet`. Its ``title``
    is the file's stem, as ``asperity convert`` titles what it writes.
    ``up="y"`` reads a mesh or point file as y-up, ``up="z"`` as it is (the
    CLI's ``--up``; by default asperity's own OBJ is turned back from y-up).
    ``channel`` picks a channel of a multi-channel file (Nanoscope images,
    Sensofar layers) by number or name, as the CLI's ``--channel``; by
    default the first height channel. Unmeasured points are NaN."""
    ch = None if channel is None else str(channel)
    return _wrap(_asperity.load(str(path), up, ch), Path(path).stem)


def save(path: Union[str, Path], surface: Surface, title: Optional[str] = None,
         up: Optional[str] = None) -> None:
    """Writes a surface by the path's extension (atomically); ``up`` as the
    CLI's ``--up`` (by default OBJ is written y-up, the others z-up)."""
    surface.save(path, title, up)


def save_image(path: Union[str, Path], image: np.ndarray) -> None:
    """Writes an (H, W, 4) uint8 picture (a :func:`render`, a colour map) as
    PNG, atomically; a picture a job returned keeps its ``params`` in the
    file, as the CLI's ``render -o FILE.png`` does."""
    _asperity.save_png(str(path), image, params_json(getattr(image, "params", None)))


