"""The add-on's operators: Add > Mesh > Rough surface (generators) and
Object > asperity (Weather, Regions, Roughen, Analyze).

Every operator is an :class:`AsperityOperator`: ``job`` returns the engine
call, ``finish`` turns its result into Blender data. ``execute`` runs the job
to the end (background mode, scripts, and the Adjust Last Operation panel,
which re-runs it); ``invoke`` runs it on a worker thread with progress in the
status bar and Esc to cancel. Nothing is created until the engine returns, so
a cancelled or failed run leaves the scene as it was; errors are reports.
"""

import json
import tempfile
import threading
from pathlib import Path

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty

from . import build, engine, scenes
from .defaults import ca_terrain, default, follow, ifs_presets, rock


def _prefs(context):
    addon = context.preferences.addons.get(__package__)
    return addon.preferences if addon is not None else None


def _package(context):
    prefs = _prefs(context)
    return engine.package(prefs.package_path if prefs is not None else "")


class AsperityOperator:
    """The job/finish protocol with synchronous and modal running."""

    bl_options = {"REGISTER", "UNDO"}
    time_limit: FloatProperty(
        name="Stop after (s)", description="Cancel the run after this many seconds (0: no limit)",
        default=0.0, min=0.0, options={"SKIP_SAVE"})

    def job(self, asp, context):  # -> callable(progress=...) -> result
        raise NotImplementedError

    def finish(self, context, result) -> None:
        raise NotImplementedError

    def _start(self, context):
        try:
            asp = _package(context)
            return engine.Job(self.job(asp, context)).start()
        except Exception as e:  # noqa: BLE001 - a report, never a crash
            self.report({"ERROR"}, f"asperity: {e}")
            return None

    def _end(self, context, job) -> set:
        if isinstance(job.error, engine.Cancelled):
            self.report({"WARNING"}, "asperity: cancelled; nothing was changed")
            return {"CANCELLED"}
        if job.error is not None:
            self.report({"ERROR"}, f"asperity: {job.error}")
            return {"CANCELLED"}
        try:
            self.finish(context, job.result)
        except Exception as e:  # noqa: BLE001
            self.report({"ERROR"}, f"asperity: {e}")
            return {"CANCELLED"}
        return {"FINISHED"}

    def execute(self, context):
        job = self._start(context)
        if job is None:
            return {"CANCELLED"}
        if self.time_limit > 0:
            timer = threading.Timer(self.time_limit, job.cancel)
            timer.start()
        try:
            job.wait()
        except BaseException:  # noqa: BLE001 - kept on the job, reported by _end
            pass
        finally:
            if self.time_limit > 0:
                timer.cancel()
        return self._end(context, job)

    def invoke(self, context, event):
        if bpy.app.background:
            return self.execute(context)
        self._job = self._start(context)
        if self._job is None:
            return {"CANCELLED"}
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.modal_handler_add(self)
        wm.progress_begin(0, 1000)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC":
            self._job.cancel()
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        done, total, message = self._job.progress
        wm = context.window_manager
        if total:
            wm.progress_update(int(1000 * done / total))
        context.workspace.status_text_set(
            f"asperity: {message or self.bl_label} {done}/{total or '?'} — Esc to cancel")
        if not self._job.done():
            return {"RUNNING_MODAL"}
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        context.workspace.status_text_set(None)
        return self._end(context, self._job)


# ---------------------------------------------------------------- Add > Mesh > Rough surface


class ASPERITY_OT_add_subdivision(AsperityOperator, bpy.types.Operator):
    """A multiresolution subdivision surface with procedural detail (velho-perlin)"""

    bl_idname = "mesh.asperity_subdivision"
    bl_label = "Rough Surface: Subdivision"

    kind: EnumProperty(name="Kind", items=scenes.kinds())
    levels: IntProperty(name="Levels", default=follow("mesh.asperity_subdivision", "levels", "subdiv", "levels"),
                        min=1, max=7)
    size: FloatProperty(name="Size", description="The detail's main size (amplitude, radius, length or height; "
                        "0: the example's)", default=0.0, min=0.0, soft_max=3.0)
    spacing: FloatProperty(name="Spacing", description="Distance between placed features, relative (0: the "
                           "example's)", default=0.0, min=0.0, soft_max=2.0)
    seed: IntProperty(name="Seed", default=follow("mesh.asperity_subdivision", "seed", "subdiv", "seed"), min=0)

    def job(self, asp, context):
        text = scenes.scene(asp, self.kind, self.levels, self.seed, self.size or None, self.spacing or None)
        return lambda progress: asp.subdiv(scene=text, seed=self.seed, progress=progress)

    def finish(self, context, result):
        build.add_object(context, f"asperity {self.kind}", result.mesh)


class ASPERITY_OT_add_ca_terrain(AsperityOperator, bpy.types.Operator):
    """A terrain accumulated from a 2-D totalistic cellular automaton, drawn with alternating-diagonal facets (peridier)"""

    bl_idname = "mesh.asperity_ca_terrain"
    bl_label = "Rough Surface: CA Terrain"

    # The engine's example terrain (CaRunParams::terrain_example); the height is
    # the add-on's own: the relief's scale in the scene, a quarter of its width.
    rule: IntProperty(name="Rule", description="Wolfram code (9-neighbour totalistic)",
                      default=ca_terrain()["rule"], min=0)
    steps: IntProperty(name="Steps", default=ca_terrain()["steps"], min=1, soft_max=500)
    init: EnumProperty(name="Start", items=[("seed", "One cell", ""), ("random", "Random", "")],
                       default=ca_terrain()["init"])
    density: FloatProperty(name="Density", default=ca_terrain()["density"], min=0.0, max=1.0)
    size: IntProperty(name="Cells", default=ca_terrain()["size"], min=4, soft_max=1024)
    height: FloatProperty(name="Height", description="Height of the whole run in the scene", default=0.25, min=0.0)
    seed: IntProperty(name="Seed", default=follow("mesh.asperity_ca_terrain", "seed", "ca run", "seed"), min=0)

    def job(self, asp, context):
        init = "seed" if self.init == "seed" else f"random:{self.density}"

        def run(progress):
            h = asp.ca_run(self.rule, self.steps, init=init, size=(self.size, self.size), seed=self.seed,
                           progress=progress).surface
            return asp.facet(h, shared=True).mesh, h

        return run

    def finish(self, context, result):
        mesh, h = result
        mesh = _fit(mesh, self.height)
        obj = build.add_object(context, "asperity CA terrain", mesh)
        _mark_grid(obj, h)


class ASPERITY_OT_add_dla_terrain(AsperityOperator, bpy.types.Operator):
    """A plane DLA deposit grown and reconstructed with level sets (kim-machiraju-thompson)"""

    bl_idname = "mesh.asperity_dla_terrain"
    bl_label = "Rough Surface: DLA Terrain"

    size: IntProperty(name="Lattice", description="Cells along each side of the lattice",
                      default=follow("mesh.asperity_dla_terrain", "size", "generate dla-terrain", "size")[0],
                      min=16, soft_max=256)
    particles: IntProperty(name="Particles", description="0: the engine's default for the lattice", default=0, min=0)
    seed: IntProperty(name="Seed", default=follow("mesh.asperity_dla_terrain", "seed", "generate dla-terrain", "seed"),
                      min=0)

    def job(self, asp, context):
        n = self.size
        return lambda progress: asp.dla_terrain(size=(n, n, n), particles=self.particles or None, seed=self.seed,
                                                progress=progress)

    def finish(self, context, result):
        build.add_object(context, "asperity DLA terrain", _fit(result.mesh, None))


class ASPERITY_OT_add_rdsr_sphere(AsperityOperator, bpy.types.Operator):
    """Random deposition with surface relaxation grown on a sphere and reconstructed (kim-machiraju-thompson Fig. 8)"""

    bl_idname = "mesh.asperity_rdsr_sphere"
    bl_label = "Rough Surface: RDSR Sphere"

    radius: FloatProperty(name="Radius (cells)",
                          default=follow("mesh.asperity_rdsr_sphere", "radius", "generate rdsr-sphere", "radius"),
                          min=3.0, soft_max=60.0)
    layers: FloatProperty(name="Layers",
                          default=follow("mesh.asperity_rdsr_sphere", "layers", "generate rdsr-sphere", "layers"),
                          min=0.5, soft_max=40.0)
    seed: IntProperty(name="Seed", default=follow("mesh.asperity_rdsr_sphere", "seed", "generate rdsr-sphere", "seed"),
                      min=0)

    def job(self, asp, context):
        return lambda progress: asp.rdsr_sphere(radius=self.radius, layers=self.layers, seed=self.seed,
                                                progress=progress)

    def finish(self, context, result):
        build.add_object(context, "asperity RDSR sphere", _fit(result.mesh, None))


class ASPERITY_OT_add_ifs_surface(AsperityOperator, bpy.types.Operator):
    """A tensor-product projected-IFS fractal surface with pseudo-curvature attributes (poull-gentil)"""

    bl_idname = "mesh.asperity_ifs_surface"
    bl_label = "Rough Surface: IFS Surface"

    # A static list, read from the engine when the add-on loads (a dynamic items callback
    # would hide the choices from RNA, and its strings are the ones Blender's docs warn
    # the Python GC may free while the menu shows them).
    preset: EnumProperty(name="Preset", items=[(p, p, "") for p in ifs_presets()])
    w: FloatProperty(name="w", description="The Takagi presets' roughness (0: the preset's)", default=0.0,
                     min=0.0, max=0.99)
    depth: IntProperty(name="Depth", default=follow("mesh.asperity_ifs_surface", "depth", "ifs surface", "depth"),
                       min=1, max=10)

    def job(self, asp, context):
        w = self.w if self.w > 0 and "takagi" in self.preset else None
        return lambda progress: asp.ifs_surface(self.preset, depth=self.depth, w=w)

    def finish(self, context, result):
        build.add_object(context, f"asperity {self.preset}", result)


class ASPERITY_OT_add_fbm(AsperityOperator, bpy.types.Operator):
    """A self-affine (fBm) height field by Fourier synthesis"""

    bl_idname = "mesh.asperity_fbm"
    bl_label = "Rough Surface: fBm Height Field"

    size: IntProperty(name="Samples", default=follow("mesh.asperity_fbm", "size", "generate fbm", "size"), min=4,
                      soft_max=2048)
    hurst: FloatProperty(name="Hurst", default=follow("mesh.asperity_fbm", "hurst", "generate fbm", "hurst"),
                         min=0.01, max=1.0)
    rms: FloatProperty(name="RMS height", description="In sample spacings",
                       default=follow("mesh.asperity_fbm", "rms", "generate fbm", "rms"), min=0.0)
    seed: IntProperty(name="Seed", default=follow("mesh.asperity_fbm", "seed", "generate fbm", "seed"), min=0)

    def job(self, asp, context):
        def run(progress):
            h = asp.fbm(size=self.size, hurst=self.hurst, rms=self.rms / self.size, spacing=1.0 / self.size,
                        seed=self.seed)
            return asp.facet(h, shared=True).mesh, h

        return run

    def finish(self, context, result):
        mesh, h = result
        obj = build.add_object(context, "asperity fBm", mesh)
        _mark_grid(obj, h)


def _fit(mesh, height):
    """``mesh`` scaled to about 2 units across (and its z to ``height``), as Blender's own primitives."""
    v = np.array(mesh.vertices, dtype=np.float64)
    lo, hi = v.min(axis=0), v.max(axis=0)
    centre, span = (lo + hi) / 2, max(float(np.max(hi[:2] - lo[:2])), 1e-12)
    v = (v - [centre[0], centre[1], lo[2] if height is not None else centre[2]]) * (2.0 / span)
    if height is not None and hi[2] > lo[2]:
        v[:, 2] = (v[:, 2] / (v[:, 2].max() or 1.0)) * height
    return type(mesh)(v, mesh.faces, colors=mesh.colors, uvs=mesh.uvs, scalars=mesh.scalars, texture=mesh.texture)


def _mark_grid(obj, h):
    """Remembers that the vertices are the height field's samples in row order (for Analyze)."""
    obj["asperity_grid"] = [int(h.heights.shape[1]), int(h.heights.shape[0])]


# ---------------------------------------------------------------- Object > asperity


def _object_mesh(asp, obj):
    """The selected object's mesh (object space, triangulated) as an ``asperity.Mesh``."""
    v, polys, _ = build.object_arrays(obj)
    tris = [(p[0], p[i], p[i + 1]) for p in polys for i in range(1, len(p) - 1)]
    if not tris:
        raise ValueError(f"{obj.name} has no faces")
    return asp.Mesh(v, np.asarray(tris, dtype=np.uint32))


class _OnMesh:
    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH" and context.mode == "OBJECT"


class ASPERITY_OT_weather(_OnMesh, AsperityOperator, bpy.types.Operator):
    """Copper corrosion and patina grown by a cellular automaton on the surface (gobron-chiba): a material with the cell atlas texture"""

    bl_idname = "object.asperity_weather"
    bl_label = "Weather (corrosion and patina)"

    cells: IntProperty(name="Cells", default=follow("object.asperity_weather", "cells", "surface-ca", "cells"),
                       min=1000, soft_max=1000000)
    steps: IntProperty(name="Steps", default=follow("object.asperity_weather", "steps", "surface-ca", "steps"), min=1,
                       soft_max=10000)
    sites: IntProperty(name="Corrosion sites", default=follow("object.asperity_weather", "sites", "surface-ca", "sites"),
                       min=1, soft_max=500)
    displace: FloatProperty(name="Displacement", description="Pits and crust along the normals (0: none)",
                            default=0.0, min=0.0, soft_max=0.1)
    seed: IntProperty(name="Seed", default=follow("object.asperity_weather", "seed", "surface-ca", "seed"), min=0)

    def job(self, asp, context):
        mesh = _object_mesh(asp, context.active_object)
        return lambda progress: asp.surface_ca(mesh, app="corrosion", cells=self.cells, steps=self.steps,
                                               sites=self.sites, displace=self.displace or None, seed=self.seed,
                                               textured=True, progress=progress)

    def finish(self, context, result):
        obj = context.active_object
        build.replace_mesh(obj, result.mesh, f"{obj.name} weathered")
        obj["asperity_weather"] = json.dumps(result.measurements)


class ASPERITY_OT_regions(_OnMesh, AsperityOperator, bpy.types.Operator):
    """A Voronoi diagram on the surface (gobron-chiba): a material per region, or the atlas as a texture"""

    bl_idname = "object.asperity_regions"
    bl_label = "Regions (surface Voronoi)"

    sites: IntProperty(name="Regions", default=follow("object.asperity_regions", "sites", "surface-ca", "sites"), min=2, soft_max=500)
    cells: IntProperty(name="Cells", default=follow("object.asperity_regions", "cells", "surface-ca", "cells"), min=1000, soft_max=1000000)
    result_as: EnumProperty(name="As", items=[("MATERIALS", "Materials", "A material per region (face material index)"),
                                               ("TEXTURE", "Texture", "The coloured cell atlas as an image texture")])
    seed: IntProperty(name="Seed", default=follow("object.asperity_regions", "seed", "surface-ca", "seed"), min=0)

    def job(self, asp, context):
        mesh = _object_mesh(asp, context.active_object)
        return lambda progress: asp.surface_ca(mesh, app="voronoi", cells=self.cells, sites=self.sites,
                                               seed=self.seed, textured=True, progress=progress)

    def finish(self, context, result):
        obj = context.active_object
        if self.result_as == "TEXTURE":
            build.replace_mesh(obj, result.mesh, f"{obj.name} regions")
            return
        import mathutils  # Blender's own KD-tree

        labels = result.labels
        tree = mathutils.kdtree.KDTree(len(labels))
        for i, p in enumerate(labels.points):
            tree.insert(p, i)
        tree.balance()
        region = np.asarray(labels.scalars["label"], dtype=np.int64)
        me = obj.data
        n = int(region.max()) + 1
        me.materials.clear()
        rng = np.random.default_rng(self.seed)
        for k in range(n):
            me.materials.append(build.material(f"{obj.name} region {k}", base=tuple(rng.uniform(0.15, 0.9, 3))))
        index = [int(region[tree.find(obj.data.polygons[f].center)[1]]) for f in range(len(me.polygons))]
        me.polygons.foreach_set("material_index", np.asarray(index, dtype=np.int32))
        me.update()


class ASPERITY_OT_roughen(_OnMesh, AsperityOperator, bpy.types.Operator):
    """Subdivide the mesh with procedural rock detail (velho-perlin); edge creases become subdivision creases"""

    bl_idname = "object.asperity_roughen"
    bl_label = "Roughen (subdivision detail)"

    levels: IntProperty(name="Levels", default=follow("object.asperity_roughen", "levels", "subdiv", "levels"), min=1, max=6)
    amplitude: FloatProperty(name="Amplitude", default=rock("amplitude"), min=0.0, soft_max=1.0)
    decay: FloatProperty(name="Decay", description="Amplitude ratio per level (1/f)", default=rock("decay"),
                         min=0.0, max=1.0)
    seed: IntProperty(name="Seed", default=follow("object.asperity_roughen", "seed", "subdiv", "seed"), min=0)

    def job(self, asp, context):
        v, polys, creases = build.object_arrays(context.active_object)
        tmp = tempfile.TemporaryDirectory()
        base = Path(tmp.name) / "base.ply"
        build.write_ply(base, v, polys)
        # Blender's crease 1 is sharp forever; below it the sharpness grows with the crease
        crease = [f"{a}-{b}:{'inf' if c >= 1.0 else round(4.0 * c, 3)}" for (a, b), c in creases.items()]
        detail = [f"rock:amplitude={self.amplitude},decay={self.decay}"]

        def run(progress):
            try:
                return asp.subdiv(base=str(base), levels=self.levels, detail=detail, crease=crease, seed=self.seed,
                                  progress=progress)
            finally:
                tmp.cleanup()

        return run

    def finish(self, context, result):
        obj = context.active_object
        build.replace_mesh(obj, result.mesh, f"{obj.name} rough")


class ASPERITY_OT_analyze(_OnMesh, AsperityOperator, bpy.types.Operator):
    """Roughness of the surface: Sa, Sq, the core height Sk with Spk and Svk, the peak density Spd and ten-point height S10z, and the Hurst exponent of a height-field object, curvature statistics of any mesh (shown in the sidebar's asperity tab)"""

    bl_idname = "object.asperity_analyze"
    bl_label = "Analyze"
    bl_options = {"REGISTER"}

    def job(self, asp, context):
        obj = context.active_object
        mesh = _object_mesh(asp, obj)
        grid = obj.get("asperity_grid")
        heights = None
        if grid is not None and len(obj.data.vertices) == grid[0] * grid[1]:
            v = np.asarray(mesh.vertices)
            dx = float(v[1, 0] - v[0, 0]) if grid[0] > 1 else 1.0
            heights = asp.HeightField(v[:, 2].reshape(grid[1], grid[0]), spacing=(dx, dx))

        def run(progress):
            out = {"mesh": asp.analyze(mesh)}
            if heights is not None:
                out["height"] = asp.analyze(heights)
            return out

        return run

    def finish(self, context, result):
        obj = context.active_object
        m, h = result["mesh"], result.get("height")
        facts = {}
        if h is not None:
            hurst = h.get("hurst") or {}
            facts.update(Sa=h.get("Sa"), Sq=h.get("Sq"), Sk=h.get("Sk"), Spk=h.get("Spk"), Svk=h.get("Svk"),
                         Spd=h.get("Spd"), S10z=h.get("S10z"),
                         Hurst=hurst.get("H") if isinstance(hurst, dict) else hurst)
        curv = m.get("curvature") or {}
        for kind in ("mean", "gaussian"):
            stats = curv.get(kind) or {}
            facts[f"{kind} curvature mean"] = stats.get("mean")
            facts[f"{kind} curvature std"] = stats.get("std")
        facts["rms vs smoothed"] = (m.get("roughness_vs_smoothed") or {}).get("rms")
        facts["box-counting D"] = ((m.get("fractal_dimension") or {}).get("box_counting") or {}).get("D")
        obj["asperity_analysis"] = json.dumps({k: v for k, v in facts.items() if v is not None})
        self.report({"INFO"}, "asperity: " + ", ".join(f"{k} {v:.4g}" for k, v in facts.items()
                                                        if isinstance(v, (int, float))))


class VIEW3D_PT_asperity(bpy.types.Panel):
    """The last Analyze of the active object."""

    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "asperity"
    bl_label = "asperity"

    def draw(self, context):
        col = self.layout.column()
        obj = context.active_object
        col.operator(ASPERITY_OT_analyze.bl_idname, icon="GRAPH")
        if obj is None or "asperity_analysis" not in obj:
            col.label(text="No analysis of this object yet")
            return
        for key, value in json.loads(obj["asperity_analysis"]).items():
            row = col.row()
            row.label(text=key)
            row.label(text=f"{value:.5g}" if isinstance(value, (int, float)) else str(value))


ADD_OPERATORS = (ASPERITY_OT_add_subdivision, ASPERITY_OT_add_ca_terrain, ASPERITY_OT_add_dla_terrain,
                 ASPERITY_OT_add_rdsr_sphere, ASPERITY_OT_add_ifs_surface, ASPERITY_OT_add_fbm)
OBJECT_OPERATORS = (ASPERITY_OT_weather, ASPERITY_OT_regions, ASPERITY_OT_roughen, ASPERITY_OT_analyze)
