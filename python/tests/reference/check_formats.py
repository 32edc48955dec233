"""Reads every file asperity wrote with independent reference readers and compares
the contents with manifest.json. Exits non-zero on the first disagreement.

Usage: python check_formats.py DIR   (DIR holds the files and manifest.json)
"""
import json
import struct
import sys
from pathlib import Path

import numpy as np
import OpenEXR
import plyfile
import trimesh
from PIL import Image

d = Path(sys.argv[1])
m = json.loads((d / "manifest.json").read_text())
H = m["height"]
ny, nx = H["ny"], H["nx"]
Z = np.array(H["data"]).reshape(ny, nx)


def ok(name, cond, detail=""):
    if not cond:
        print(f"FAIL {name} {detail}")
        sys.exit(1)
    print(f"OK {name}")


# --- height fields -----------------------------------------------------------
a = np.load(d / "h.npy")
ok("h.npy", a.dtype == np.float64 and a.shape == (ny, nx) and np.array_equal(a, Z), f"{a.dtype} {a.shape}")
a = np.load(d / "h32.npy")
ok("h32.npy", a.dtype == np.float32 and np.allclose(a, Z, atol=1e-6))

a = np.loadtxt(d / "h.csv", delimiter=",")
ok("h.csv", a.shape == (ny, nx) and np.array_equal(a, Z))

im = Image.open(d / "h.png")
px = np.array(im, dtype=np.float64)
lo, hi = float(im.text["asperity:z_min"]), float(im.text["asperity:z_max"])
z = lo + px / 65535.0 * (hi - lo)
ok("h.png", im.mode.startswith("I") and px.shape == (ny, nx) and px.max() == 65535 and px.min() == 0
   and np.allclose(z, Z, atol=(hi - lo) / 65535.0), f"mode {im.mode}")

with OpenEXR.File(str(d / "h.exr")) as f:
    ch = f.channels()
    y = ch["Y"].pixels
ok("h.exr", y.dtype == np.float32 and y.shape == (ny, nx) and np.allclose(y, Z, atol=1e-6), f"{y.dtype} {y.shape}")

# Gwyddion Simple Field, parsed by the rules of Gwyddion's gsf.c: data start 4-aligned after the first NUL.
raw = (d / "h.gsf").read_bytes()
assert raw.startswith(b"Gwyddion Simple Field 1.0\n")
nul = raw.index(b"\0")
start = nul + 4 - nul % 4
hdr = dict(l.split("=", 1) for l in raw[26:nul].decode().splitlines() if "=" in l)
hdr = {k.strip(): v.strip() for k, v in hdr.items()}
xres, yres = int(hdr["XRes"]), int(hdr["YRes"])
g = np.frombuffer(raw[start:], dtype="<f4").reshape(yres, xres)
dx = float(hdr["XReal"]) / xres
x0 = float(hdr["XOffset"]) + dx / 2
ok("h.gsf", (xres, yres) == (nx, ny) and len(raw) - start == 4 * nx * ny and np.allclose(g, Z, atol=1e-6)
   and abs(dx - H["spacing"][0]) < 1e-12 and abs(x0 - H["origin"][0]) < 1e-12)

# --- meshes ------------------------------------------------------------------
M = m["mesh"]
P = np.array(M["positions"]).reshape(-1, 3)
T = np.array(M["triangles"])
C = np.array(M["colors"], dtype=np.uint8)
for name in ["m.ply", "m_ascii.ply"]:
    ply = plyfile.PlyData.read(str(d / name))
    v = ply["vertex"]
    pos = np.stack([v["x"], v["y"], v["z"]], axis=1)
    faces = np.stack(ply["face"]["vertex_indices"])
    col = np.stack([v["red"], v["green"], v["blue"], v["alpha"]], axis=1)
    ok(name, np.array_equal(pos, P) and np.array_equal(faces, T) and np.array_equal(col, C)
       and np.array_equal(v["curvature"], np.array(M["curvature"])) and np.allclose(v["s"], np.array(M["uvs"])[:, 0], atol=1e-7))

# OBJ and glTF are y-up: asperity's (x, y, z) is written (x, z, -y)
yup = np.stack([P[:, 0], P[:, 2], -P[:, 1]], axis=1)
obj = trimesh.load(d / "m.obj", process=False, maintain_order=True)
ok("m.obj", np.allclose(obj.vertices, yup) and np.array_equal(obj.faces, T) and abs(obj.area - M["area"]) < 1e-9,
   f"{obj.vertices.shape} {obj.faces.shape}")

glb = trimesh.load(d / "m.glb", force="mesh", process=False)
ok("m.glb", np.allclose(glb.vertices, yup, atol=1e-6) and np.array_equal(glb.faces, T)
   and abs(glb.area - M["area"]) < 1e-5, f"{glb.vertices.shape}")

K = m["closed"]
stl = trimesh.load(d / "c.stl")  # trimesh merges the STL corners itself
ok("c.stl", len(stl.faces) == K["n_faces"] and len(stl.vertices) == 6 and stl.is_watertight
   and abs(stl.volume - K["volume"]) < 1e-6, f"{len(stl.vertices)} {stl.volume}")

# --- polygons (quads and n-gons kept) -------------------------------------------
PP = np.array(m["poly"]["positions"]).reshape(-1, 3)
PF = m["poly"]["faces"]
ply = plyfile.PlyData.read(str(d / "q.ply"))
v = ply["vertex"]
ok("q.ply", np.array_equal(np.stack([v["x"], v["y"], v["z"]], axis=1), PP)
   and [list(f) for f in ply["face"]["vertex_indices"]] == PF)
text = (d / "q.obj").read_text().splitlines()
faces = [[int(t.split("/")[0]) - 1 for t in l.split()[1:]] for l in text if l.startswith("f ")]
verts = np.array([[float(x) for x in l.split()[1:4]] for l in text if l.startswith("v ")])
ok("q.obj", faces == PF and np.array_equal(verts, np.stack([PP[:, 0], PP[:, 2], -PP[:, 1]], axis=1)))

# --- point sets --------------------------------------------------------------
Q = np.array(m["points"]["positions"]).reshape(-1, 3)
a = np.load(d / "p.npy")
ok("p.npy", a.shape == Q.shape and np.array_equal(a, Q))
a = np.loadtxt(d / "p.xyz")
ok("p.xyz", np.array_equal(a, Q))
v = plyfile.PlyData.read(str(d / "p.ply"))["vertex"]
ok("p.ply", np.array_equal(np.stack([v["x"], v["y"], v["z"]], axis=1), Q) and np.array_equal(v["age"], m["points"]["age"]))

# --- CA states and polylines -----------------------------------------------
a = np.load(d / "s.npy")
ok("s.npy", a.dtype == np.uint8 and a.shape == (2, 3, 4) and np.array_equal(a.ravel(), np.arange(24) % 3))
ply = plyfile.PlyData.read(str(d / "l.ply"))
e = ply["edge"]
v = ply["vertex"]
ok("l.ply", len(e) == 2 and list(e["vertex1"]) == [6, 7] and list(e["vertex2"]) == [7, 8]
   and abs(v["z"][8] - 2.0) < 1e-12 and len(ply["face"]) == 8)
lines = [l.split() for l in (d / "l.obj").read_text().splitlines() if l.startswith("l ")]
verts = [l.split() for l in (d / "l.obj").read_text().splitlines() if l.startswith("v ")]
ok("l.obj", lines == [["l", "7", "8", "9"]] and [float(x) for x in verts[8][1:4]] == [1.0, 2.0, 0.0])  # y-up

# --- the recorded parameters (asperity_io::metadata), as other readers see them
PARAMS = m["params"]
hdr_exr = OpenEXR.File(str(d / "h.exr")).header()
exr_text = hdr_exr.get("comments")
exr_text = exr_text.decode() if isinstance(exr_text, bytes) else exr_text
ply_comments = plyfile.PlyData.read(str(d / "m.ply")).comments
ply_text = next(c[len("asperity-params "):] for c in ply_comments if c.startswith("asperity-params "))
seen = {
    "png": Image.open(d / "h.png").text["asperity:params"],
    "exr": exr_text,
    "gsf": hdr["AsperityParams"],
    "ply": ply_text,
}
ok("params", all(json.loads(t) == PARAMS for t in seen.values()), str(seen))
