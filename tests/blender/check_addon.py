"""The Blender add-on, installed from its zip and run headless (issues #25, #39).

Run by crates/python/tests/pytest.rs, in Debian's Blender 3.4 with the legacy zip:
    blender -b --factory-startup --python-exit-code 1 --python check_addon.py -- ZIP ASPERITY OUT
and in Blender 4.2 LTS and 5.0 as Python modules (``bpy`` from PyPI) with the extension zip:
    python check_addon.py ZIP ASPERITY OUT

- installs and enables the add-on from the zip blender/build.py made (an
  extension, with asperity's wheel, when the zip has a blender_manifest.toml:
  Blender installs the wheel itself);
- runs every operator with small parameters: the generators' objects have the
  vertex and face counts of the CLI's files for the same parameters and seed;
  Weather gives a material with an image texture, Regions a material per
  region on the faces, Roughen the CLI's subdivision of the same base (edge
  creases included), Analyze the CLI's Sa, Sq, Sk, Spk, Svk, Spd, S10z and Hurst;
- a run stopped half-way (time_limit, the same path as Esc) leaves no object
  and no mesh behind;
- renders each result with Cycles at a few samples: not blank. Pictures go to
  OUT (a test artefact), with addon_screenshot.png for the README.
Prints "ok   what" / "FAIL what".
"""
import importlib
import json
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

import bpy
import numpy as np
from mathutils import Vector

ZIP, ASPERITY, OUT = Path(sys.argv[-3]), sys.argv[-2], Path(sys.argv[-1])
OUT.mkdir(parents=True, exist_ok=True)
TMP = Path(tempfile.mkdtemp())
failures = []


def check(what, ok, detail=""):
    print(f"{'ok  ' if ok else 'FAIL'} {what} {detail}", flush=True)
    if not ok:
        failures.append(what)


def cli(*args):
    p = subprocess.run([ASPERITY, "--quiet", *map(str, args)], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"asperity {' '.join(map(str, args))}: {p.stderr}")
    return p.stdout


def cli_counts(path):
    m = json.loads(cli("info", "--json", path))["measurements"]
    return m["vertices"], m["triangles"]


def counts(obj):
    return len(obj.data.vertices), len(obj.data.polygons)


def positions(obj):
    v = np.empty(len(obj.data.vertices) * 3, dtype=np.float32)
    obj.data.vertices.foreach_get("co", v)
    return v.reshape(-1, 3)


def same_positions(obj, path):
    """The object's vertices are the CLI file's, in order (float32 in Blender)."""
    theirs = asp.load(path).vertices
    ours = positions(obj)
    return ours.shape == theirs.shape and np.allclose(ours, theirs, rtol=0, atol=1e-5 * np.abs(theirs).max())


bpy.ops.wm.read_factory_settings(use_empty=True)
EXTENSION = "blender_manifest.toml" in zipfile.ZipFile(ZIP).namelist()
if EXTENSION:
    # Blender 4.2+: an extension in the user repository, its wheel installed by Blender
    bpy.ops.extensions.package_install_files(filepath=str(ZIP), repo="user_default", enable_on_install=True)
    MODULE = "bl_ext.user_default.asperity"
else:
    bpy.ops.preferences.addon_install(filepath=str(ZIP), overwrite=True)
    bpy.ops.preferences.addon_enable(module="asperity_addon")
    MODULE = "asperity_addon"
engine = importlib.import_module(f"{MODULE}.engine")  # installed just now
scenes = importlib.import_module(f"{MODULE}.scenes")

asp = engine.package()  # the engine the add-on's zip carries (or the wheel Blender installed)

check(f"add-on installed from the zip and enabled (Blender {bpy.app.version_string})",
      MODULE in bpy.context.preferences.addons)
if EXTENSION:
    check("asperity from the extension's wheel", "extensions" in Path(asp.__file__).parts, asp.__file__)
check("Add > Mesh > Rough Surface registered", hasattr(bpy.types, "VIEW3D_MT_asperity_add"))

# ---- every property that follows an engine parameter has the engine's default (#36)
defaults = importlib.import_module(f"{MODULE}.defaults")

wrong = []
for (op, prop), (job, field) in sorted(defaults.FIELDS.items()):
    category, name = op.split(".")
    have = getattr(getattr(bpy.ops, category), name).get_rna_type().properties[prop].default
    desc = {f["name"]: f for f in json.loads(asp._asperity.describe(job))["fields"]}
    want = asp._asperity.DEFAULT_SEED if field == "seed" else desc[field]["default"]
    want = want[0] if isinstance(want, list) else want
    if abs(float(have) - float(want)) > 1e-6 * max(1.0, abs(float(want))):
        wrong.append(f"{op}.{prop} = {have}, the engine's {job} {field} = {want}")
check("the add-on's properties default to the engine's", len(defaults.FIELDS) >= 18 and not wrong,
      f"{len(defaults.FIELDS)} properties; {wrong}")
roughen = bpy.ops.object.asperity_roughen.get_rna_type().properties
want_rock = json.loads(asp._asperity.subdiv_rock_defaults())
check("Roughen's rock defaults are the engine's",
      all(abs(roughen[k].default - want_rock[k]) < 1e-6 for k in ("amplitude", "decay")),
      f"{[roughen[k].default for k in ('amplitude', 'decay')]} vs {want_rock}")
terrain = bpy.ops.mesh.asperity_ca_terrain.get_rna_type().properties
ex = json.loads(asp._asperity.ca_terrain_example())
have = (terrain["rule"].default, terrain["steps"].default, terrain["size"].default,
        terrain["init"].default, round(terrain["density"].default, 6))
want = (int(ex["rule"]), ex["steps"], ex["size"][0], "random", float(ex["init"].split(":")[1]))
check("CA terrain's defaults are the engine's example run", have == want, f"{have} vs {want}")
presets = [i.identifier for i in
           bpy.ops.mesh.asperity_ifs_surface.get_rna_type().properties["preset"].enum_items]
check("the IFS presets are the engine's", bool(presets) and presets == [p["name"] for p in asp.ifs_presets()],
      f"{presets}")
scene = bpy.context.scene
made = {}


def run(name, op, **params):
    before = set(bpy.data.objects)
    result = op(**params)
    new = [o for o in bpy.data.objects if o not in before]
    check(f"{name}: runs", result == {"FINISHED"} and len(new) == 1, f"{result} {len(new)} new")
    if new:
        made[name] = new[0]
        return new[0]
    return None


# ---- generators against the CLI
kinds = [k for k, _, _ in scenes.kinds()]
check("the subdivision kinds are the engine's example scenes",
      kinds == [e["name"] for e in asp.subdiv_examples()] and len(kinds) >= 5, str(kinds))
for kind in kinds:
    obj = run(f"subdivision {kind}", bpy.ops.mesh.asperity_subdivision, kind=kind, levels=3, seed=3)
    (TMP / f"{kind}.toml").write_text(scenes.scene(asp, kind, 3, 3))
    cli("--seed", 3, "subdiv", TMP / f"{kind}.toml", "--triangles", "-o", TMP / f"{kind}.ply")
    if obj:
        check(f"subdivision {kind}: the CLI's counts", counts(obj) == cli_counts(TMP / f"{kind}.ply"),
              f"{counts(obj)} vs {cli_counts(TMP / f'{kind}.ply')}")
        check(f"subdivision {kind}: the CLI's vertices", same_positions(obj, TMP / f"{kind}.ply"))

# the same values give the same mesh (what the Adjust Last Operation panel relies on)
again = [bpy.ops.mesh.asperity_subdivision(kind="rock", levels=3, seed=3) and bpy.context.active_object
         for _ in range(2)]
check("the same values give the same mesh", np.array_equal(positions(again[0]), positions(again[1]))
      and np.array_equal(positions(again[0]), positions(made["subdivision rock"])))
for o in again:
    bpy.data.objects.remove(o)

obj = run("CA terrain", bpy.ops.mesh.asperity_ca_terrain, rule=450, steps=12, size=32, density=0.3, seed=4)
cli("--seed", 4, "ca", "run", "--rule", 450, "--steps", 12, "--init", "random:0.3", "--size", "32x32", "-o",
    TMP / "ca.npy")
cli("facet", TMP / "ca.npy", "--shared", "-o", TMP / "ca.ply")
if obj:
    check("CA terrain: the CLI's counts", counts(obj) == cli_counts(TMP / "ca.ply"))

obj = run("DLA terrain", bpy.ops.mesh.asperity_dla_terrain, size=32, seed=5)
cli("--seed", 5, "generate", "dla-terrain", "--size", "32x32x32", "-o", TMP / "dla.ply")
if obj:
    check("DLA terrain: the CLI's counts", counts(obj) == cli_counts(TMP / "dla.ply"))

obj = run("RDSR sphere", bpy.ops.mesh.asperity_rdsr_sphere, radius=8.0, layers=3.0, seed=6)
cli("--seed", 6, "generate", "rdsr-sphere", "--radius", 8, "--layers", 3, "-o", TMP / "rdsr.ply")
if obj:
    check("RDSR sphere: the CLI's counts", counts(obj) == cli_counts(TMP / "rdsr.ply"))

obj = run("IFS surface", bpy.ops.mesh.asperity_ifs_surface, preset="bezier-takagi", depth=5)
cli("ifs", "surface", "--preset", "bezier-takagi", "--depth", 5, "-o", TMP / "ifs.ply")
if obj:
    check("IFS surface: the CLI's counts", counts(obj) == cli_counts(TMP / "ifs.ply"))
    check("IFS surface: the CLI's vertices", same_positions(obj, TMP / "ifs.ply"))
    check("IFS surface: curvature attributes", len(obj.data.attributes.keys()) > 2, str(obj.data.attributes.keys()))

# the add-on's RMS height is in sample spacings, as the engine's (spacing 1/48: 0.05)
fbm = run("fBm", bpy.ops.mesh.asperity_fbm, size=48, hurst=0.7, rms=2.4, seed=8)
# .gsf keeps the spacing (.npy would not)
cli("--seed", 8, "generate", "fbm", "--size", 48, "--hurst", 0.7, "--rms", 0.05, "--spacing", 1 / 48, "-o",
    TMP / "fbm.gsf")
cli("facet", TMP / "fbm.gsf", "--shared", "-o", TMP / "fbm.ply")
if fbm:
    check("fBm: the CLI's counts", counts(fbm) == cli_counts(TMP / "fbm.ply"))
    check("fBm: the CLI's vertices", same_positions(fbm, TMP / "fbm.ply"))

# ---- object operators
bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16)
sphere = bpy.context.active_object
check("Weather", bpy.ops.object.asperity_weather(cells=4000, steps=80, sites=6, seed=2) == {"FINISHED"})
images = [n.image for m in sphere.data.materials if m and m.use_nodes for n in m.node_tree.nodes
          if n.type == "TEX_IMAGE" and n.image]
check("Weather: a material with the cell atlas image", len(images) == 1 and images[0].size[0] > 0,
      str([tuple(i.size) for i in images]))
made["weathered sphere"] = sphere

bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3, location=(3, 0, 0))
ico = bpy.context.active_object
check("Regions", bpy.ops.object.asperity_regions(sites=6, cells=4000, seed=3) == {"FINISHED"})
index = np.empty(len(ico.data.polygons), dtype=np.int32)
ico.data.polygons.foreach_get("material_index", index)
check("Regions: a material per region on the faces", len(ico.data.materials) == 6 and len(set(index)) == 6,
      f"{len(ico.data.materials)} materials, {len(set(index))} used")
made["regions"] = ico

bpy.ops.mesh.primitive_cube_add(location=(-3, 0, 0))
cube = bpy.context.active_object
if bpy.app.version >= (4, 0, 0):  # creases are an edge attribute since Blender 4.0
    crease = cube.data.attributes.new("crease_edge", "FLOAT", "EDGE")
    for i in range(4):
        crease.data[i].value = 1.0
else:
    for e in cube.data.edges[:4]:
        e.crease = 1.0
build = importlib.import_module(f"{MODULE}.build")

v, polys, creases = build.object_arrays(cube)
build.write_ply(TMP / "cube.ply", v, polys)
check("Roughen", bpy.ops.object.asperity_roughen(levels=3, amplitude=0.1, seed=4) == {"FINISHED"})
args = ["subdiv", "--base", TMP / "cube.ply", "--levels", 3, "--detail", "rock:amplitude=0.1,decay=0.5", "--triangles"]
for (a, b), c in creases.items():
    args += ["--crease", f"{a}-{b}:inf"]
cli("--seed", 4, *args, "-o", TMP / "rough.ply")
check("Roughen: the CLI's subdivision of the same base and creases", same_positions(cube, TMP / "rough.ply"),
      f"{counts(cube)} vs {cli_counts(TMP / 'rough.ply')}, {len(creases)} creases")
cli("--seed", 4, *args[:args.index("--crease")], "-o", TMP / "smooth.ply")
check("Roughen: the creases matter (without them the surface differs)", not same_positions(cube, TMP / "smooth.ply"))
made["roughened cube"] = cube

if fbm:
    bpy.context.view_layer.objects.active = fbm
    check("Analyze", bpy.ops.object.asperity_analyze() == {"FINISHED"})
    ours = json.loads(fbm.get("asperity_analysis", "{}"))
    theirs = json.loads(cli("analyze", "--json", TMP / "fbm.gsf"))["measurements"]
    hurst = theirs["hurst"]["H"] if isinstance(theirs["hurst"], dict) else theirs["hurst"]
    for key, want in (("Sa", theirs["Sa"]), ("Sq", theirs["Sq"]), ("Sk", theirs["Sk"]), ("Spk", theirs["Spk"]),
                      ("Svk", theirs["Svk"]), ("Spd", theirs["Spd"]), ("S10z", theirs["S10z"]),
                      ("Hurst", hurst)):
        got = ours.get(key)
        check(f"Analyze: {key} as the CLI's", got is not None and abs(got - want) <= 1e-5 * abs(want),
              f"{got} vs {want}")

# ---- a stopped run leaves nothing
objects, meshes = len(bpy.data.objects), len(bpy.data.meshes)
result = bpy.ops.mesh.asperity_dla_terrain(size=160, particles=4_000_000, seed=1, time_limit=0.5)
check("a stopped run: cancelled", result == {"CANCELLED"}, str(result))
check("a stopped run: no half-built object or mesh",
      (len(bpy.data.objects), len(bpy.data.meshes)) == (objects, meshes))

# ---- Cycles renders
scene.render.engine = "CYCLES"
scene.cycles.samples = 4
scene.cycles.use_denoising = False  # Debian builds Blender without OpenImageDenoise
scene.cycles.device = "CPU"
scene.render.resolution_x, scene.render.resolution_y = 200, 150
world = bpy.data.worlds.new("asperity") if scene.world is None else scene.world
scene.world = world
world.color = (0.05, 0.05, 0.06)
sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
sun.rotation_euler = (0.7, 0.3, 0.5)
sun.data.energy = 4.0
scene.collection.objects.link(sun)
camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(camera)
scene.camera = camera


def frame(objs):
    pts = np.concatenate([np.array([o.matrix_world @ c.co for c in o.data.vertices]) for o in objs])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    centre, size = (lo + hi) / 2, float(np.max(hi - lo))
    camera.location = centre + np.array([1.2, -1.6, 1.0]) * size
    direction = Vector((centre - np.array(camera.location)).tolist())
    camera.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()


for name, obj in made.items():
    for o in made.values():
        o.hide_render = o is not obj
    frame([obj])
    path = OUT / f"{name.replace(' ', '_')}.png"
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(str(path))
    px = np.empty(img.size[0] * img.size[1] * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    rgb = px.reshape(-1, 4)[:, :3]
    lit = float(np.mean(np.abs(rgb - rgb[0]).sum(axis=1) > 0.05))  # pixels unlike the corner
    check(f"render {name}: not blank", lit > 0.02, f"{lit:.0%} of the pixels")

# the README's picture: a few of the results together
show = [made[k] for k in ("subdivision rock", "subdivision berry", "weathered sphere", "regions",
                          "roughened cube") if k in made]
for i, o in enumerate(show):
    o.hide_render = False
    o.location = (2.6 * i, 0, 0)
    o.scale = [1.0 / max(o.dimensions) * 2.0] * 3 if max(o.dimensions) > 0 else o.scale
for o in made.values():
    o.hide_render = o not in show
bpy.context.view_layer.update()
scene.render.resolution_x, scene.render.resolution_y = 960, 300
scene.cycles.samples = 16
frame(show)
scene.render.filepath = str(OUT / "addon_screenshot.png")
bpy.ops.render.render(write_still=True)
check("README picture written", (OUT / "addon_screenshot.png").exists())
print(f"{len(failures)} failures", flush=True)
sys.exit(1 if failures else 0)
