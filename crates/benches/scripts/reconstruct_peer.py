#!/usr/bin/env python3
"""asperity reconstruct beside Open3D's screened Poisson reconstruction (#52).

The same clouds for both — random samples of the unit sphere and of a torus
(R = 1, r = 0.35, area-uniform), with noise and outliers, and optionally a
real scan (the Stanford bunny's bun_zipper.ply) — and per cloud and tool:
pieces, genus, watertight, the area against the analytic one, the distance
from the vertices to the input points (mean, 95th percentile, max) and the
whole-process time (each run is its own process: the CLI, or a Python process
that imports Open3D, reads the file and writes the mesh).

Open3D as its users run it: normals estimated from 30 neighbours and oriented
by the tangent-plane propagation, Poisson at depth 9, the mesh as it comes
(no density trimming). Not a CI test; results go in BENCHMARKS.md.

    python3 -m venv /tmp/o3d && /tmp/o3d/bin/pip install open3d numpy scipy plyfile
    /tmp/o3d/bin/python crates/benches/scripts/reconstruct_peer.py \\
        --asperity target/release/asperity [--bunny bun_zipper.ply] > peer.md

(Open3D's wheel needs libusb-1.0 and libgomp1 from Debian.)
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from plyfile import PlyData
from scipy.spatial import cKDTree

O3D = r"""
import sys, open3d as o3d
pc = o3d.io.read_point_cloud(sys.argv[1])
pc.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(30))
pc.orient_normals_consistent_tangent_plane(15)
mesh, _ = o3d.geometry.TriangleMesh.create_from_point_cloud_poisson(pc, depth=9)
o3d.io.write_triangle_mesh(sys.argv[2], mesh)
"""


def sphere(n, rng):
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1)[:, None]


def torus(n, rng, big=1.0, small=0.35):
    out = []
    while sum(len(o) for o in out) < n:
        u, w, s = rng.uniform(0, 2 * np.pi, n), rng.uniform(0, 2 * np.pi, n), rng.uniform(0, 1, n)
        keep = s * (big + small) <= big + small * np.cos(w)
        u, w = u[keep], w[keep]
        q = big + small * np.cos(w)
        out.append(np.stack([q * np.cos(u), q * np.sin(u), small * np.sin(w)], 1))
    return np.concatenate(out)[:n]


def write_ply(path, p):
    with open(path, "w") as f:
        f.write(f"ply\nformat ascii 1.0\nelement vertex {len(p)}\n"
                "property float x\nproperty float y\nproperty float z\nend_header\n")
        np.savetxt(f, p, fmt="%.8g")


def topology(path):
    ply = PlyData.read(path)
    v = ply["vertex"]
    V = np.stack([v["x"], v["y"], v["z"]], 1).astype(float)
    F = np.stack(ply["face"]["vertex_indices"]).astype(np.int64)
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    edges, counts = np.unique(e, axis=0, return_counts=True)
    used = np.unique(F)
    # Pieces: union–find over the edges.
    parent = np.arange(len(V))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for a, b in edges:
        ra, rb = find(a), find(b)
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    pieces = len({find(x) for x in used})
    chi = len(used) - len(edges) + len(F)
    watertight = bool(np.all(counts == 2))
    genus = (2 * pieces - chi) // 2 if watertight else None
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum()
    return V[used], pieces, genus, watertight, area


def run(cmd):
    t = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode:
        raise RuntimeError(r.stderr[-2000:])
    return time.perf_counter() - t


def row(tool, name, out, pts, area, seconds):
    V, pieces, genus, watertight, a = topology(out)
    d, _ = cKDTree(pts).query(V)
    rel = f"{100 * (a / area - 1):+.2f} %" if area else f"{a:.5g}"
    return (f"| {name} | {tool} | {pieces} | {genus} | {'yes' if watertight else 'no'} | {rel} | "
            f"{d.mean():.2e} / {np.percentile(d, 95):.2e} / {d.max():.2e} | {seconds:.2f} |")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--asperity", default="target/release/asperity")
    ap.add_argument("--bunny", help="bun_zipper.ply (35,947 points)")
    args = ap.parse_args()
    rng = np.random.default_rng(1)
    clouds = [
        ("sphere 20,000", sphere(20_000, rng), 4 * np.pi),
        ("sphere 100,000", sphere(100_000, rng), 4 * np.pi),
        ("torus 50,000", torus(50_000, rng), 4 * np.pi ** 2 * 0.35),
        ("torus 200,000", torus(200_000, rng), 4 * np.pi ** 2 * 0.35),
    ]
    s = sphere(20_000, rng)
    spacing = np.median(cKDTree(s).query(s, k=2)[0][:, 1])
    clouds.append(("sphere 20,000, noise σ = 1 spacing", s + rng.normal(scale=spacing, size=s.shape), 4 * np.pi))
    clouds.append(("sphere 20,000 + 2 % outliers", np.concatenate([s, rng.uniform(-1, 1, (400, 3))]), 4 * np.pi))
    if args.bunny:
        v = PlyData.read(args.bunny)["vertex"]
        clouds.append(("bunny scan (bun_zipper)", np.stack([v["x"], v["y"], v["z"]], 1).astype(float), None))
    print("| cloud | tool | pieces | genus | watertight | area | distance to points mean / p95 / max | whole process, s |")
    print("|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as d:
        for name, pts, area in clouds:
            src = os.path.join(d, "in.ply")
            write_ply(src, pts)
            out = os.path.join(d, "a.ply")
            t = run([args.asperity, "-q", "reconstruct", src, "-o", out])
            print(row("asperity", name, out, pts, area, t), flush=True)
            out = os.path.join(d, "o.ply")
            t = run([sys.executable, "-c", O3D, src, out])
            print(row("Open3D Poisson", name, out, pts, area, t), flush=True)


if __name__ == "__main__":
    main()
