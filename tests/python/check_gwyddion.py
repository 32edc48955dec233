"""Gwyddion (the real program) reads asperity's height fields (issue #24).

A field with a non-unit spacing and a non-zero origin is written by
`asperity convert` as .gsf and 16-bit .png; `gwyddion --convert-to-gwy` turns
each into a .gwy, which the `gwyfile` package reads. Checks: sizes, physical
extents, offsets (Gwyddion's pixel-edge convention: x0 − dx/2), units (none for
unitless data; for a field in µm and nm, metres with the numbers scaled, as
Gwyddion keeps base units), the title, and the heights against what asperity reads back
from the same file (1e-6 of the range) and against the original (GSF: float32;
PNG: 16-bit, half a step of the range).

Usage: python check_gwyddion.py ASPERITY_BINARY WORKDIR
"""
import subprocess
import sys
from pathlib import Path

import gwyfile
import numpy as np

BIN, WORK = sys.argv[1], Path(sys.argv[2])
WORK.mkdir(parents=True, exist_ok=True)
nx, ny, dx, dy, x0, y0 = 40, 30, 0.25, 0.5, 10.0, -3.0
rng = np.random.default_rng(5)
z = np.cumsum(rng.normal(size=(ny, nx)), axis=1) * 1e-3 + 2.0
with open(WORK / "field.csv", "w") as f:
    f.write(f"# asperity height field: nx={nx} ny={ny} dx={dx} dy={dy} x0={x0} y0={y0}\n")
    for row in z:
        f.write(",".join(repr(float(v)) for v in row) + "\n")

failures = []


def check(what, ok, detail=""):
    print(f"{'ok  ' if ok else 'FAIL'} {what} {detail}")
    if not ok:
        failures.append(what)


def run(*args):
    p = subprocess.run([str(a) for a in args], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"{' '.join(map(str, args))} failed: {p.stderr}")


# (units flags, metres per xy unit, metres per z unit, Gwyddion's unit strings)
CASES = [([], 1.0, 1.0, ""), (["--xy-unit", "µm", "--z-unit", "nm"], 1e-6, 1e-9, "m")]
for flags, fx, fz, unit in CASES:
    for ext in ["gsf", "png"]:
        tag = f"{ext}{' ' + ' '.join(flags) if flags else ''}"
        src = WORK / f"field{len(flags)}.{ext}"
        run(BIN, "--quiet", *flags, "convert", WORK / "field.csv", src)
        run(BIN, "--quiet", "convert", src, WORK / f"back_{ext}.npy")
        gwy = WORK / f"field{len(flags)}_{ext}.gwy"
        run("gwyddion", f"--convert-to-gwy={gwy}", src)
        fields = gwyfile.util.get_datafields(gwyfile.load(str(gwy)))
        check(f"{tag}: one channel", len(fields) == 1, str(list(fields)))
        (title, d), = fields.items()
        data = np.asarray(d.data)
        check(f"{tag}: size", data.shape == (ny, nx), str(data.shape))
        # Gwyddion holds base units: metres when the field has units
        check(f"{tag}: extent", abs(d.xreal - nx * dx * fx) <= 1e-9 * nx * dx * fx
              and abs(d.yreal - ny * dy * fx) <= 1e-9 * ny * dy * fx, f"{d.xreal} × {d.yreal}")
        check(f"{tag}: offset", abs(d.get("xoff", 0.0) - (x0 - dx / 2) * fx) <= 1e-9 * abs(x0 * fx)
              and abs(d.get("yoff", 0.0) - (y0 - dy / 2) * fx) <= 1e-9 * abs(y0 * fx),
              f"{d.get('xoff')}, {d.get('yoff')}")
        units = {k: v.get("unitstr", "") for k, v in d.items() if k.startswith("si_unit")}
        check(f"{tag}: units {unit or 'none'}", all(units.get(k, "") == unit for k in ("si_unit_xy", "si_unit_z")),
              str(units))
        back = np.load(WORK / f"back_{ext}.npy")  # asperity's reading, in the file's units
        span = np.ptp(z) * fz
        check(f"{tag}: heights = asperity's reading", np.max(np.abs(data - back * (1.0 if ext == "gsf" else fz)))
              <= 1e-6 * span, f"{np.max(np.abs(data - back * (1.0 if ext == 'gsf' else fz))) / span:.2e} of the range")
        # GSF holds float32 (1e-6 relative to the heights); PNG 16-bit steps of the range
        scale = np.max(np.abs(z * fz)) * 1e-6 if ext == "gsf" else span * 0.5 / 65535 * 1.001
        check(f"{tag}: heights = the original", np.max(np.abs(data - z * fz)) <= scale,
              f"{np.max(np.abs(data - z * fz)):.2e} (allowed {scale:.2e})")
        if ext == "png":
            check(f"{tag}: title", title == "field", repr(title))  # convert titles by the input

sys.exit(1 if failures else 0)
