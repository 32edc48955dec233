"""Blender data from asperity's arrays: meshes built directly with ``bpy``
(no importer), with the vertex colours, UVs, per-vertex attributes, texture and
shading asperity computed.

asperity is z-up like Blender, so coordinates go in as they are. asperity's
colours are sRGB bytes; Blender's colour attributes take linear floats (and
store bytes back in sRGB), so they are converted once here. Textures are sRGB
images, stored as they are.
"""
from __future__ import annotations

import bpy
import numpy as np


def srgb_to_linear(c: np.ndarray) -> np.ndarray:
    """sRGB values in [0, 1] to linear light (the sRGB transfer function)."""
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def mesh_data(name: str, mesh) -> bpy.types.Mesh:
    """A ``bpy.types.Mesh`` from an ``asperity.Mesh`` (triangles)."""
    v = np.ascontiguousarray(mesh.vertices, dtype=np.float32)
    f = np.ascontiguousarray(mesh.faces, dtype=np.int32)
    me = bpy.data.meshes.new(name)
    me.vertices.add(len(v))
    me.vertices.foreach_set("co", v.ravel())
    me.loops.add(f.size)
    me.loops.foreach_set("vertex_index", f.ravel())
    me.polygons.add(len(f))
    me.polygons.foreach_set("loop_start", np.arange(0, f.size, 3, dtype=np.int32))
    if bpy.app.version < (4, 0, 0):  # read-only from 4.0 (derived from loop_start)
        me.polygons.foreach_set("loop_total", np.full(len(f), 3, dtype=np.int32))
    me.update(calc_edges=True)
    me.polygons.foreach_set("use_smooth", np.ones(len(f), dtype=bool))
    if mesh.colors is not None:
        rgba = np.asarray(mesh.colors, dtype=np.float32) / 255.0
        rgba[:, :3] = srgb_to_linear(rgba[:, :3])
        col = me.color_attributes.new("Col", "BYTE_COLOR", "POINT")
        col.data.foreach_set("color", rgba.ravel())
    if mesh.uvs is not None:
        uv = me.uv_layers.new(name="UVMap")
        uv.data.foreach_set("uv", np.asarray(mesh.uvs, dtype=np.float32)[f.ravel()].ravel())
    for key, values in (mesh.scalars or {}).items():
        attr = me.attributes.new(key, "FLOAT", "POINT")
        attr.data.foreach_set("value", np.asarray(values, dtype=np.float32))
    if mesh.normals is not None and hasattr(me, "use_auto_smooth"):
        me.use_auto_smooth = True  # Blender < 4.1: custom normals need it
        me.normals_split_custom_set_from_vertices(np.asarray(mesh.normals, dtype=np.float32))
    me.validate()
    return me


def image(name: str, rgba: np.ndarray) -> bpy.types.Image:
    """A packed sRGB image from (H, W, 4) uint8 (row 0 at the top, as asperity stores it)."""
    h, w = rgba.shape[:2]
    img = bpy.data.images.new(name, width=w, height=h, alpha=True)
    img.pixels.foreach_set((np.flipud(rgba).astype(np.float32) / 255.0).ravel())
    img.pack()
    return img


def material(name: str, *, colors: bool = False, texture=None, base=(0.8, 0.8, 0.8)) -> bpy.types.Material:
    """A Principled material: its base colour from the vertex colours, the
    texture image, or ``base``."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    bsdf = next(n for n in nodes if n.type == "BSDF_PRINCIPLED")
    bsdf.inputs["Roughness"].default_value = 0.7
    if texture is not None:
        tex = nodes.new("ShaderNodeTexImage")
        tex.image = texture
        links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    elif colors:
        attr = nodes.new("ShaderNodeVertexColor")
        attr.layer_name = "Col"
        links.new(attr.outputs["Color"], bsdf.inputs["Base Color"])
    else:
        bsdf.inputs["Base Color"].default_value = (*base, 1.0)
    return mat


def add_object(context, name: str, mesh, *, location=None) -> bpy.types.Object:
    """A new object of ``mesh`` (an ``asperity.Mesh``) in the active
    collection, selected and active, with a material for its colours or texture."""
    me = mesh_data(name, mesh)
    tex = image(f"{name} texture", mesh.texture) if mesh.texture is not None else None
    me.materials.append(material(name, colors=mesh.colors is not None, texture=tex))
    obj = bpy.data.objects.new(name, me)
    obj.location = location if location is not None else context.scene.cursor.location
    context.collection.objects.link(obj)
    for o in context.selected_objects:
        o.select_set(False)
    obj.select_set(True)
    context.view_layer.objects.active = obj
    return obj


def replace_mesh(obj, mesh, name: str) -> None:
    """Gives ``obj`` the geometry (and colour/texture material) of ``mesh``."""
    old = obj.data
    me = mesh_data(name, mesh)
    tex = image(f"{name} texture", mesh.texture) if mesh.texture is not None else None
    me.materials.append(material(name, colors=mesh.colors is not None, texture=tex))
    obj.data = me
    if old.users == 0:
        bpy.data.meshes.remove(old)


def object_arrays(obj):
    """(vertices (N, 3) in object space, polygons as lists, edge creases {(a, b): c})."""
    me = obj.data
    v = np.empty(len(me.vertices) * 3, dtype=np.float64)
    me.vertices.foreach_get("co", v)
    polys = [list(p.vertices) for p in me.polygons]
    creases = {}
    attr = me.attributes.get("crease_edge")  # Blender 4
    for i, e in enumerate(me.edges):
        c = attr.data[i].value if attr is not None else getattr(e, "crease", 0.0)
        if c > 0:
            creases[tuple(e.vertices)] = c
    return v.reshape(-1, 3), polys, creases


def write_ply(path, vertices, polygons) -> None:
    """A binary PLY of ``polygons`` over ``vertices`` (vertex order kept, so
    crease indices stay valid)."""
    with open(path, "wb") as f:
        f.write((
            "ply\nformat binary_little_endian 1.0\n"
            f"element vertex {len(vertices)}\nproperty double x\nproperty double y\nproperty double z\n"
            f"element face {len(polygons)}\nproperty list uchar int vertex_indices\nend_header\n"
        ).encode())
        f.write(np.ascontiguousarray(vertices, dtype="<f8").tobytes())
        for p in polygons:
            f.write(np.uint8(len(p)).tobytes() + np.asarray(p, dtype="<i4").tobytes())
