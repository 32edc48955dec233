#!/usr/bin/env python3
"""Byte-for-byte comparison of what two `asperity` binaries write.

A refactor that claims "outputs unchanged" runs this with the binary from before and the
binary from after:

    cargo build --release && cp target/release/asperity /tmp/asperity-before
    # ... change the code ...
    cargo build --release
    python3 scripts/compare_outputs.py /tmp/asperity-before target/release/asperity

It runs the full demo, the quick demo and every command of the README (with small inputs the
script makes itself with the same binary) in a fresh folder per binary, hashes every file each
command writes and its stdout, and reports every difference. Wall-clock measurements (JSON keys
ending in `_s`, `_seconds`, `per_s`, `per_second`; DLA's scheduling figures `mean_in_flight`,
`redone_fraction`) and the run folder's own path are masked
before hashing; nothing else is. `--manifest BIN` prints one binary's hashes instead.
Exit status 0 when the two agree, 1 when they differ. `--allow REGEX` (repeatable) names
outputs expected to differ (a deliberate change): they are listed but do not fail the run.

`--mask-params` also masks the parameter records of issue #36 (`asperity_io::metadata`), to
compare a binary from before it with one from after: the `params`, `params_overridden` and
`made_with` keys of JSON (and the `bytes` of the files a report lists); the PLY, OBJ and CSV comment lines; the GSF header field (the
header's padding recomputed); PNG's `asperity:params` chunk; glTF's `asset.extras`; x3p's
`Record2` (and the checksum of `main.xml`). EXR and `.gwy` hold theirs inside binary headers
whose offsets and sizes shift, so those files are compared as their heights and geometry:
converted to GSF by the second binary, then masked.
"""
import argparse
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import struct
import time
import zipfile

# (label, argv after the binary). Inputs first, then the README's commands in README order.
SETUP = [
    ("input rock.ply", "subdiv --base sphere --levels 3 --detail rock --triangles -o rock.ply"),
    ("input dem.gsf", "generate fbm --size 128 --hurst 0.7 -o dem.gsf"),
    ("input pattern.png", "generate fbm --size 64 --hurst 0.5 -o pattern.png"),
    ("input seeds.png", "generate fbm --size 256 --hurst 0.9 -o seeds.png"),
    ("input bunny.obj", "subdiv --base sphere --levels 2 --triangles -o bunny.obj"),
    ("input mesh.obj", "subdiv --base cube --levels 1 --triangles -o mesh.obj"),
    ("input quads.obj", "subdiv --base cube --levels 1 -o quads.obj"),
    ("input edited.obj", "subdiv --base cube --levels 0 -o edited.obj"),
]
README = [
    "convert rock.ply rock.glb",
    "convert dem.gsf dem.npy",
    "convert dem.npy dem.stl --diagonal alternating",
    "--json info rock.ply",
    "render rock.ply -o rock.png --size 1024x768 --view iso --shader phong",
    "render dem.gsf -o dem_map.png --view map",
    "render dem.gsf -o dem.png --z-scale 3 --shader height --turntable 6",
    "generate fbm --size 1024 --hurst 0.8 --rms 1 -o f.npy",
    "analyze f.npy --json",
    "analyze f.npy --plot plots",
    "ca rule 450",
    "ca run --rule 450 --steps 5 --init seed -o h.npy --states-out s.npy",
    "ca run --rule 450 --steps 64 --init random:0.3 --size 1024x1024 -o big.npy",
    "ca run --rule B3/S23 --family outer9 --steps 50 --init pattern.png -o life.gsf",
    "ca gallery --rules 8,480,450 --inits seed,random:0.3 --steps 10 -o grid.png",
    "facet h.npy -o h.ply --circle 5,5,3 --render h.png",
    "interpolate h.npy --points pts.csv",
    "growth rdsr --size 256 --layers 2000 --seed 7 -o h_rdsr.npy --json",
    "growth bd --dim 1 --size 8192 --layers 1000 --runs 8 --bin 4 --plot plots_bd -o h_bd.npy",
    "growth rdsr --dim 1 --size 1024 --layers 100 --alpha-sizes 16,32,64,128 --runs 8 -o h_a.npy",
    "growth dla --seed-shape plane --size 128x128x64 --particles 200000 --stick 0.5 -o pts.ply",
    "growth dla --particles 100000 -o cluster.ply --json",
    "growth rdsr --substrate sphere --radius 40 --layers 50 -o sphere_pts.ply",
    "growth bd --substrate mesh --mesh bunny.obj --resolution 96 --layers 5 -o crust.ply",
    "growth dla --seed-shape image --image seeds.png --size 256x256x128 -o terrain.ply",
    "reconstruct pts.ply --resolution 128 --offset 0.05 --iterations 30 -o mesh.ply --json",
    "reconstruct pts.ply --resolution 64 --save-every 10 --iterations 20 -o bunny_rec.ply",
    "reconstruct pts.ply --resolution 64 --flow regularized -o smooth.ply",
    "generate dla-terrain --size 64x64x64 --particles 8000 --seed 3 -o terrain.glb",
    "generate rdsr-sphere --radius 20 --layers 10 --seed 3 -o sphere.glb --points sphere_pts2.ply",
    "ifs presets",
    "ifs surface --preset takagi-landsberg --w 0.7071 --depth 8 -o t.ply",
    "ifs surface --preset bezier-takagi --depth 10 --control-net net.obj -o s.ply",
    "ifs curvature --preset bezier-bicubic --at 0.5,0.25 --json",
    "ifs curvature --preset takagi-landsberg --w 0.5",
    "ifs dcf --preset takagi-landsberg --bound upper -o fig2.svg",
    "ifs sdcf --preset takagi-landsberg-surface --with-attractor 6 -o fig4.ply",
    "ifs preset takagi-landsberg --w 0.6 -o mine.json",
    "ifs curvature --ifs mine.json --move 2=0.2,1.1 --json",
    "surface-ca builtin:cup --app voronoi --sites 16 --cells 200000 --seed 3 -o v.glb"
    " --labels-out labels.ply --stats-out steps.csv --plot steps.png --json",
    "surface-ca bunny.obj --app corrosion --cells 50000 --steps 300 -o patina.glb",
    "surface-ca builtin:sphere --app corrosion --strong-noise 0.2 --k1 0.001 -o spots.ply",
    "surface-ca builtin:sphere --app gray-scott --steps 400 --frames 200 -o rd.glb",
    "surface-ca mesh.obj --site-points sites.xyz -o regions.ply",
    "subdiv --base cube --levels 4 --limit -o cube.ply",
    "subdiv --base sphere --levels 5 --detail rock:amplitude=0.12,decay=0.5 --seed 4 -o rock5.ply",
    "subdiv --base sphere --levels 5 --detail berry:radius=0.3,spacing=0.7,levels=2 -o berry.glb",
    "subdiv --base quads.obj --levels 3 --boundary edge-and-corner --crease 0-1:2 -o smooth.obj",
    "subdiv {repo}/crates/subdiv/scenes/planet.toml -o planet.glb",
    "subdiv {repo}/crates/subdiv/scenes/tentacle.toml --frames 4 -o t.glb",
    "subdiv --base cube --detail rock --export-details d.json -o a.ply",
    "subdiv --base edited.obj --apply-details d.json -o b.ply",
    "demo --quick --out gallery_quick --quiet",
    "demo --out gallery --quiet",
]
REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# Wall-clock measurements, and what the speculative DLA's scheduling did (how many walks
# were in flight and redone depends on the threads' timing; the cluster does not).
TIMING_KEY = re.compile(r"(_s|_seconds|seconds|per_s|per_second|^mean_in_flight|^redone_fraction)$")


def strip_timings(value):
    """Removes wall-clock measurements from a JSON value."""
    if isinstance(value, dict):
        return {k: strip_timings(v) for k, v in value.items() if not TIMING_KEY.search(k)}
    if isinstance(value, list):
        return [strip_timings(v) for v in value]
    return value


# (and the sizes of the files a report lists, which the records lengthen)
PARAM_KEYS = {"params", "params_overridden", "made_with", "bytes"}
# Set by --mask-params: the binary that decodes EXR and .gwy files for masking.
MASK = {"decoder": None}


def strip_params(value):
    """Removes the parameter records from a JSON value."""
    if isinstance(value, dict):
        return {k: strip_params(v) for k, v in value.items() if k not in PARAM_KEYS}
    if isinstance(value, list):
        return [strip_params(v) for v in value]
    return value


def mask_gsf(data: bytes) -> bytes:
    """A GSF file without its `AsperityParams` field, its NUL padding redone."""
    nul = data.index(b"\0")
    head, body = data[:nul], data[nul + 4 - nul % 4:]
    head = re.sub(rb"AsperityParams = [^\n]*\n", b"", head)
    return head + b"\0" * (4 - len(head) % 4) + body


def mask_png(data: bytes) -> bytes:
    """A PNG without its `asperity:params` tEXt chunk."""
    out, at = [data[:8]], 8
    while at < len(data):
        (length,) = struct.unpack(">I", data[at:at + 4])
        chunk = data[at:at + 12 + length]
        if not (chunk[4:8] == b"tEXt" and chunk[8:].startswith(b"asperity:params\0")):
            out.append(chunk)
        at += 12 + length
    return b"".join(out)


def mask_glb(data: bytes) -> bytes:
    """A glTF binary as its JSON (without `asset.extras`, keys sorted) and binary chunk."""
    (length,) = struct.unpack("<I", data[12:16])
    doc = json.loads(data[20:20 + length])
    doc.get("asset", {}).pop("extras", None)
    return json.dumps(doc, sort_keys=True).encode() + data[20 + length:]


def mask_x3p(data: bytes) -> bytes:
    """An x3p archive as its main.xml without `Record2` and its data."""
    import io

    with zipfile.ZipFile(io.BytesIO(data)) as z:
        main = re.sub(rb"\s*<Record2>.*?</Record2>", b"", z.read("main.xml"), flags=re.S)
        return main + b"".join(z.read(n) for n in sorted(z.namelist())
                               if n not in ("main.xml", "md5checksum.hex"))


def mask_decoded(path: str) -> bytes:
    """An EXR or .gwy file as the GSF the decoding binary converts it to."""
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "decoded.gsf")
        subprocess.run([MASK["decoder"], "convert", path, out, "--quiet"], check=True,
                       capture_output=True)
        with open(out, "rb") as f:
            return mask_gsf(f.read())


def mask_params(data: bytes, path: str) -> bytes:
    """`data` (of file `path`, None for stdout) without its parameter records."""
    ext = os.path.splitext(path or "")[1].lower()
    try:
        if ext == ".gsf":
            return mask_gsf(data)
        if ext == ".png":
            return mask_png(data)
        if ext == ".glb":
            return mask_glb(data)
        if ext == ".x3p":
            return mask_x3p(data)
        if ext in (".exr", ".gwy"):
            return mask_decoded(path)
    except (ValueError, KeyError, struct.error, zipfile.BadZipFile, subprocess.CalledProcessError):
        return data
    return re.sub(rb"(comment asperity-params|# asperity-params|# asperity params:) [^\n]*\n", b"",
                  data)


def normalise(data: bytes, workdir: str, path: str = None) -> bytes:
    """Masks the run folder's path and, in JSON, every timing (and with
    --mask-params, the parameter records)."""
    if MASK["decoder"]:
        data = mask_params(data, path)
    data = data.replace(workdir.encode(), b"WORKDIR")
    try:
        doc = json.loads(data)
    except (ValueError, UnicodeDecodeError):
        return data
    if MASK["decoder"]:
        doc = strip_params(doc)
    return json.dumps(strip_timings(doc), sort_keys=True).encode()


def snapshot(workdir):
    out = {}
    for root, _, files in os.walk(workdir):
        for name in files:
            path = os.path.join(root, name)
            st = os.stat(path)
            out[os.path.relpath(path, workdir)] = (st.st_mtime_ns, st.st_size)
    return out


def manifest(binary, workdir):
    """Runs every command with `binary` in `workdir`; returns {label: hash}."""
    with open(os.path.join(workdir, "pts.csv"), "w") as f:
        f.write("0.5,0.5\n2.25,3.75\n5,5\n7.1,2.2\n")
    with open(os.path.join(workdir, "sites.xyz"), "w") as f:
        f.write("1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n")
    hashes = {}
    for label, cmd in SETUP + [(c, c) for c in README]:
        argv = [binary] + cmd.format(repo=REPO).split()
        before = snapshot(workdir)
        t = time.time()
        proc = subprocess.run(argv, cwd=workdir, capture_output=True)
        took = time.time() - t
        print(f"  {took:6.1f} s  {label}", file=sys.stderr)
        hashes[f"{label} | exit"] = str(proc.returncode)
        stdout = normalise(proc.stdout, workdir)
        hashes[f"{label} | stdout"] = hashlib.md5(stdout).hexdigest()
        if proc.returncode != 0:
            hashes[f"{label} | stderr"] = proc.stderr.decode(errors="replace").strip()
        after = snapshot(workdir)
        for rel, stamp in sorted(after.items()):
            if before.get(rel) != stamp:
                path = os.path.join(workdir, rel)
                with open(path, "rb") as f:
                    digest = hashlib.md5(normalise(f.read(), workdir, path)).hexdigest()
                hashes[f"{label} | {rel}"] = digest
    return hashes


def run(binary):
    binary = os.path.abspath(binary)
    workdir = tempfile.mkdtemp(prefix="asperity-compare-")
    try:
        return manifest(binary, workdir)
    finally:
        shutil.rmtree(workdir, ignore_errors=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("before", help="the asperity binary from before the change")
    ap.add_argument("after", nargs="?", help="the asperity binary from after the change")
    ap.add_argument("--manifest", action="store_true", help="print one binary's hashes as JSON")
    ap.add_argument("--allow", action="append", default=[], metavar="REGEX",
                    help="outputs expected to differ (listed, not failed)")
    ap.add_argument("--mask-params", action="store_true",
                    help="mask the parameter records files and reports hold (#36)")
    a = ap.parse_args()
    if a.mask_params:
        MASK["decoder"] = os.path.abspath(a.after or a.before)
    if a.manifest or a.after is None:
        json.dump(run(a.before), sys.stdout, indent=1, sort_keys=True)
        print()
        return 0
    print(f"before: {a.before}", file=sys.stderr)
    first = run(a.before)
    print(f"after: {a.after}", file=sys.stderr)
    second = run(a.after)
    differ = sorted(k for k in first.keys() | second.keys() if first.get(k) != second.get(k))
    allowed = [k for k in differ if any(re.search(pattern, k) for pattern in a.allow)]
    for k in differ:
        tag = "differs (allowed)" if k in allowed else "DIFFERS"
        print(f"{tag} {k}: {first.get(k)} -> {second.get(k)}")
    print(f"{len(first)} outputs compared, {len(differ)} differ, {len(allowed)} of them allowed")
    return 1 if len(differ) > len(allowed) else 0


if __name__ == "__main__":
    sys.exit(main())
