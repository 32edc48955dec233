"""asperity: rough surfaces from numpy.

Growth (:func:`rd`, :func:`rdsr`, :func:`bd`, :func:`dla`), level-set
reconstruction (:func:`reconstruct`, :func:`dla_terrain`, :func:`rdsr_sphere`),
cellular-automaton height fields (:func:`ca_run`, :func:`ca_gallery`, :func:`facet`,
:func:`interpolate`), subdivision surfaces (:func:`subdiv`), projected IFS
(:func:`ifs_surface`, :func:`ifs_dcf`, :func:`ifs_sdcf`, :func:`ifs_curvature`…),
cellular automata on meshes (:func:`surface_ca`), analysis (:func:`analyze`, :func:`filter_surface`,
:func:`psd`, :func:`hurst`, :func:`fbm`), files (:func:`load`, :func:`save`,
:func:`save_image`),
pictures (:func:`render`) and parameter sweeps on Dask (:func:`sweep`).

Every function runs the same Rust engine as the ``asperity`` CLI.
"""

from . import _asperity
from .api import (Result, analyze, bd, ca_gallery, ca_rule, ca_run, dla, dla_terrain, facet,
                  fbm, filter_surface,
                  fractal_dimensions, hurst, ifs_curvature, ifs_curve, ifs_dcf, ifs_model,
                  ifs_presets, ifs_sdcf, ifs_surface, interpolate, load, memory_budget, psd, rd,
                  rdsr, rdsr_sphere,
                  reconstruct, render, save, save_image, set_limits, subdiv, subdiv_examples,
                  surface_ca)
from .errors import MemoryLimitError, TimeLimitError
from .sweep import sweep
from .types import HeightField, Mesh, PointSet

__version__ = _asperity.__version__

__all__ = [
    "HeightField", "Mesh", "PointSet", "Result", "MemoryLimitError", "TimeLimitError",
    "analyze", "bd", "ca_gallery", "ca_rule", "ca_run", "dla", "dla_terrain", "facet", "fbm",
    "filter_surface", "fractal_dimensions", "hurst", "ifs_curvature", "ifs_curve", "ifs_dcf", "ifs_model",
    "ifs_presets", "ifs_sdcf", "ifs_surface", "interpolate", "load", "memory_budget", "psd", "rd", "rdsr",
    "rdsr_sphere", "reconstruct", "render", "save", "save_image", "set_limits", "subdiv", "subdiv_examples", "surface_ca", "sweep",
]
