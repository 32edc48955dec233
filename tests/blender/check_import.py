"""Blender imports the demo's meshes as asperity means them (issue #24).

Run by crates/cli/tests/real_programs.rs:
    blender -b --factory-startup --python-exit-code 1 --python check_import.py -- DEMO_DIR BOUNDS_JSON PLANET_OBJ

BOUNDS_JSON holds `asperity info` of sample_mesh.ply ({"min": [...], "max": [...]});
PLANET_OBJ is the demo's subdiv_planet.ply converted to OBJ by asperity.
With Blender's own importers and their default settings:
- sample_mesh .glb, .obj, .ply and .stl stand upright: the world bounding box
  equals asperity's (so z is up in Blender as in asperity, whatever the file's
  convention);
- the planet's vertex colours from .glb (linear COLOR_0) and from .obj (sRGB
  floats after `v x y z`) equal those from .ply (sRGB bytes) within 1/255 once
  all are in sRGB, vertex by vertex (matched by position);
- the textured Voronoi cup (.glb) has a material with an image texture.

Blender 3.4's glTF importer uses `numpy.bool`, which numpy 1.24 removed
(Debian 12 ships numpy 1.24.2), so importing any .glb fails with an
AttributeError; the alias is restored here before importing. Later Blenders do
not need it.
"""
import json
import sys
from pathlib import Path

import bpy
import numpy as np
from mathutils.kdtree import KDTree

if not hasattr(np, "bool"):
    np.bool = bool  # Blender 3.4 glTF importer on numpy >= 1.24 (see above)

DEMO, BOUNDS, PLANET_OBJ = Path(sys.argv[-3]), json.loads(Path(sys.argv[-2]).read_text()), Path(sys.argv[-1])
failures = []


def check(what, ok, detail=""):
    print(f"{'ok  ' if ok else 'FAIL'} {what} {detail}", flush=True)
    if not ok:
        failures.append(what)


def fresh():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def imported(path):
    """Imports `path` with Blender's default importer for its extension; returns the new mesh objects."""
    before = set(bpy.data.objects)
    ext = path.suffix.lower()
    if ext == ".glb":
        bpy.ops.import_scene.gltf(filepath=str(path))
    elif ext == ".obj":
        bpy.ops.wm.obj_import(filepath=str(path))  # File > Import > Wavefront (.obj) in 3.4
    elif ext == ".ply":
        bpy.ops.import_mesh.ply(filepath=str(path))
    elif ext == ".stl":
        bpy.ops.import_mesh.stl(filepath=str(path))
    return [o for o in bpy.data.objects if o not in before and o.type == "MESH"]


def world_vertices(obj):
    m = obj.data
    co = np.empty(len(m.vertices) * 3)
    m.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    mw = np.array(obj.matrix_world)
    return co @ mw[:3, :3].T + mw[:3, 3]


def linear_to_srgb(c):
    c = np.clip(c, 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1 / 2.4) - 0.055)


def vertex_colours(obj):
    """Per-vertex linear RGB of the mesh's first colour attribute (point or corner domain)."""
    m = obj.data
    attrs = [a for a in m.color_attributes]
    if not attrs:
        return None
    a = attrs[0]
    rgba = np.empty(len(a.data) * 4)
    a.data.foreach_get("color", rgba)  # linear floats for byte and float colours alike
    rgba = rgba.reshape(-1, 4)
    if a.domain == "CORNER":
        per_vertex = np.zeros((len(m.vertices), 4))
        vi = np.empty(len(m.loops), dtype=np.int64)
        m.loops.foreach_get("vertex_index", vi)
        per_vertex[vi] = rgba
        rgba = per_vertex
    return rgba[:, :3]


# 1. Upright in every mesh format.
want_min, want_max = np.array(BOUNDS["min"]), np.array(BOUNDS["max"])
span = np.max(want_max - want_min)
for ext in ["glb", "obj", "ply", "stl"]:
    fresh()
    objs = imported(DEMO / f"sample_mesh.{ext}")
    check(f"sample_mesh.{ext}: imported", len(objs) == 1, str([o.name for o in objs]))
    if not objs:
        continue
    v = world_vertices(objs[0])
    lo, hi = v.min(axis=0), v.max(axis=0)
    tol = 1e-5 * span + (2e-7 * span if ext == "stl" else 0.0)  # STL holds f32 corners
    check(f"sample_mesh.{ext}: upright, bounds as asperity's",
          np.all(np.abs(lo - want_min) <= tol) and np.all(np.abs(hi - want_max) <= tol),
          f"min {lo.round(5)} max {hi.round(5)} (asperity: {want_min.round(5)} {want_max.round(5)})")

# 2. The planet's colours: .glb (linear COLOR_0) and .obj against .ply (sRGB bytes).
fresh()
(ply,) = imported(DEMO / "subdiv_planet.ply")
ply_v, ply_c = world_vertices(ply), linear_to_srgb(vertex_colours(ply))
spread = np.ptp(ply_c, axis=0)
check("planet: the colours vary (not one flat colour)", np.all(spread > 0.2), str(spread.round(3)))
for path in (DEMO / "subdiv_planet.glb", PLANET_OBJ):
    (other,) = imported(path)
    v, c = world_vertices(other), linear_to_srgb(vertex_colours(other))
    tree = KDTree(len(v))
    for i, p in enumerate(v):
        tree.insert(p, i)
    tree.balance()
    nearest = [tree.find(p) for p in ply_v]
    far = max(d for _, _, d in nearest)
    check(f"planet {path.suffix}: every .ply vertex is there", far <= 1e-5, f"farthest {far:.2e}")
    diff = max(float(np.max(np.abs(ply_c[k] - c[i]))) for k, (_, i, _) in enumerate(nearest))
    check(f"planet {path.suffix}: colours = .ply colours within 1/255 (sRGB)", diff <= 1 / 255,
          f"max difference {diff * 255:.3f}/255")

# 3. The cup's image texture.
fresh()
(cup,) = imported(DEMO / "surfca_voronoi_cup.glb")
images = [n.image for slot in cup.material_slots if slot.material and slot.material.use_nodes
          for n in slot.material.node_tree.nodes if n.type == "TEX_IMAGE" and n.image]
check("cup: an image texture", len(images) >= 1 and all(i.size[0] > 0 and i.size[1] > 0 for i in images),
      str([(i.name, tuple(i.size)) for i in images]))
check("cup: UVs", len(cup.data.uv_layers) >= 1)

print(f"{len(failures)} failures", flush=True)
sys.exit(1 if failures else 0)
