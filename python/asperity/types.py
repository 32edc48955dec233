"""The three kinds of surface asperity makes and reads, holding numpy arrays.

Arrays returned by asperity own the engine's buffers (no copy was made to
hand them over). Passing a surface back into asperity copies its arrays once
into the engine's own types (see docs/python.md, "Copies").
"""

from __future__ import annotations

import json
from typing import Dict, Optional, Sequence, Tuple

import numpy as np

from . import _asperity


def params_json(params: Optional[dict]) -> Optional[str]:
    """A record as the JSON text the engine writes into files (None: none)."""
    return None if params is None else json.dumps(params)


def _f64(a, shape_tail, what):
    a = np.ascontiguousarray(a, dtype=np.float64)
    if a.ndim != 1 + len(shape_tail) or tuple(a.shape[1:]) != tuple(shape_tail):
        raise ValueError(f"{what} must have shape (n, {', '.join(map(str, shape_tail))}), got {a.shape}")
    return a


class _Surface:
    title: Optional[str]
    #: The record of the job that made it (job, schema version, seed, every
    #: value); ``asperity.fbm(**h.params)`` makes it again. A surface read
    #: from a file has the record the file keeps (None where it keeps none);
    #: None for surfaces built by hand.
    params: Optional[dict] = None
    #: A job's result sets ``params`` on the values that carry it (``_jobs``).
    carries_params = True

    def save(self, path, title: Optional[str] = None, up: Optional[str] = None) -> None:
        """Writes the surface to ``path``; the format follows the extension
        (``asperity formats`` lists them). The write is atomic. ``up``: "y" or
        "z", the CLI's ``--up`` for mesh and point files. The surface's
        ``params`` go where the format keeps metadata, as the CLI writes them."""
        _asperity.save(str(path), self, title if title is not None else self.title, up,
                       params_json(self.params))

    def info(self) -> dict:
        """The CLI's ``info`` facts: counts, bounds, topology, height range."""
        return json.loads(_asperity.info(self))

    def render(self, size=(800, 600), **options) -> np.ndarray:
        """A picture as an (H, W, 4) uint8 array; see :func:`asperity.render`."""
        from ._pictures import render

        return render(self, size=size, **options)

    def _repr_png_(self) -> bytes:
        return _asperity.encode_png(self.render((480, 360)))


class Mesh(_Surface):
    """A triangle mesh: ``vertices`` (N, 3) float64 and ``faces`` (M, 3) uint32,
    optionally ``normals`` (N, 3), ``colors`` (N, 4) uint8 sRGB, ``uvs`` (N, 2),
    ``scalars`` (name → (N,) float64 per vertex) and ``texture`` (H, W, 4) uint8."""

    def __init__(self, vertices, faces, normals=None, colors=None, uvs=None,
                 scalars: Optional[Dict[str, np.ndarray]] = None, texture=None,
                 title: Optional[str] = None):
        self.vertices = _f64(vertices, (3,), "vertices")
        faces = np.asarray(faces)
        if faces.ndim != 2 or faces.shape[1] != 3:
            raise ValueError(f"faces must have shape (m, 3), got {faces.shape}")
        if faces.size and (faces.min() < 0 or faces.max() >= 2**32):
            raise ValueError("faces must hold vertex indices in 0 ≤ i < 2³²")
        self.faces = np.ascontiguousarray(faces, dtype=np.uint32)
        self.normals = None if normals is None else _f64(normals, (3,), "normals")
        self.colors = None if colors is None else np.ascontiguousarray(colors, dtype=np.uint8)
        self.uvs = None if uvs is None else _f64(uvs, (2,), "uvs")
        self.scalars = {k: np.ascontiguousarray(v, dtype=np.float64) for k, v in (scalars or {}).items()}
        self.texture = None if texture is None else np.ascontiguousarray(texture, dtype=np.uint8)
        self.title = title

    @classmethod
    def _from(cls, d: dict, title: Optional[str] = None) -> "Mesh":
        m = cls.__new__(cls)
        m.vertices, m.faces = d["vertices"], d["faces"]
        m.normals, m.colors = d.get("normals"), d.get("colors")
        m.uvs, m.texture = d.get("uvs"), d.get("texture")
        m.scalars = dict(d.get("scalars", {}))
        m.title = title
        return m

    @property
    def n_vertices(self) -> int:
        return len(self.vertices)

    @property
    def n_faces(self) -> int:
        return len(self.faces)

    def to_trimesh(self, process: bool = False):
        """A ``trimesh.Trimesh`` with the same vertices, faces, normals and colours."""
        import trimesh

        kw = {}
        if self.colors is not None:
            kw["vertex_colors"] = self.colors
        if self.normals is not None:
            kw["vertex_normals"] = self.normals
        return trimesh.Trimesh(vertices=self.vertices, faces=self.faces, process=process, **kw)

    def __repr__(self) -> str:
        extra = [k for k in ("normals", "colors", "uvs", "texture") if getattr(self, k) is not None]
        extra += [f"scalar {k!r}" for k in self.scalars]
        more = f" with {', '.join(extra)}" if extra else ""
        return f"<asperity.Mesh {self.n_vertices} vertices, {self.n_faces} triangles{more}>"


class HeightField(_Surface):
    """Heights on a regular grid: ``heights`` (ny, nx) float64, row j at
    y = origin[1] + j·spacing[1], column i at x = origin[0] + i·spacing[0].
    ``units`` = (xy, z), each "m", "mm", "µm", "nm" or "none" (the default):
    the unit of the spacing and origin, and of the heights. Unmeasured points
    are NaN. A field :func:`load` read from an instrument file also has
    ``instrument`` (the instrument's header as a dict) and, for a
    multi-channel file, ``channels`` (dicts with ``index``, ``name`` and
    ``height``); both are None otherwise."""

    instrument: Optional[dict] = None
    channels: Optional[list] = None

    def __init__(self, heights, spacing: Sequence[float] = (1.0, 1.0),
                 origin: Sequence[float] = (0.0, 0.0), title: Optional[str] = None,
                 units: Tuple[str, str] = ("none", "none")):
        h = np.ascontiguousarray(heights, dtype=np.float64)
        if h.ndim != 2:
            raise ValueError(f"heights must be a 2-D array (ny, nx), got shape {h.shape}")
        self.heights = h
        self.spacing = (float(spacing[0]), float(spacing[1]))
        self.origin = (float(origin[0]), float(origin[1]))
        self.title = title
        self.units = (str(units[0]), str(units[1]))

    @classmethod
    def _from(cls, d: dict, title: Optional[str] = None) -> "HeightField":
        h = cls.__new__(cls)
        h.heights = d["heights"]
        h.spacing = tuple(d["spacing"])
        h.origin = tuple(d["origin"])
        h.units = tuple(d.get("units", ("none", "none")))
        h.title = title
        return h

    @property
    def shape(self):
        return self.heights.shape

    @property
    def x(self) -> np.ndarray:
        return self.origin[0] + self.spacing[0] * np.arange(self.heights.shape[1])

    @property
    def y(self) -> np.ndarray:
        return self.origin[1] + self.spacing[1] * np.arange(self.heights.shape[0])

    def __repr__(self) -> str:
        ny, nx = self.heights.shape
        units = "" if self.units == ("none", "none") else f", units {self.units[0]} / {self.units[1]}"
        return f"<asperity.HeightField {nx}×{ny}, spacing {self.spacing}{units}>"


class PointSet(_Surface):
    """Points ``points`` (N, 3) float64 with optional ``normals`` (N, 3),
    ``colors`` (N, 4) uint8 and per-point ``scalars``."""

    def __init__(self, points, scalars: Optional[Dict[str, np.ndarray]] = None,
                 normals=None, colors=None, title: Optional[str] = None):
        self.points = _f64(points, (3,), "points")
        self.normals = None if normals is None else _f64(normals, (3,), "normals")
        self.colors = None if colors is None else np.ascontiguousarray(colors, dtype=np.uint8)
        self.scalars = {k: np.ascontiguousarray(v, dtype=np.float64) for k, v in (scalars or {}).items()}
        self.title = title

    @classmethod
    def _from(cls, d: dict, title: Optional[str] = None) -> "PointSet":
        p = cls.__new__(cls)
        p.points = d["points"]
        p.normals, p.colors = d.get("normals"), d.get("colors")
        p.scalars = dict(d.get("scalars", {}))
        p.title = title
        return p

    def __len__(self) -> int:
        return len(self.points)

    def __repr__(self) -> str:
        return f"<asperity.PointSet {len(self.points)} points>"


def _wrap(d: dict, title: Optional[str] = None):
    kind = d.get("kind")
    if kind == "mesh":
        s = Mesh._from(d, title)
    elif kind == "height":
        s = HeightField._from(d, title)
    else:
        s = PointSet._from(d, title)
    if "params" in d:  # the record a file keeps
        s.params = json.loads(d["params"])
    if "instrument" in d:  # the instrument's own header
        s.instrument = dict(d["instrument"])
    if "channels" in d:
        s.channels = [dict(c) for c in d["channels"]]
    return s
