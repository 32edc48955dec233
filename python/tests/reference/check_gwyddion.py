"""Gwyddion (the real program) reads asperity's height fields, and asperity
reads the .gwy files Gwyddion writes (issue #24).

A field with a non-unit spacing and a non-zero origin is written by
`asperity convert` as .gsf, 16-bit .png, .x3p and .gwy; `gwyddion
--convert-to-gwy` turns each into a .gwy, which the `gwyfile` package reads.
Checks: sizes, physical extents, offsets (Gwyddion's pixel-edge convention:
x0 − dx/2; Gwyddion 2.62 ignores an x3p file's offsets, so 0 there), units (none
for unitless data; for a field in µm and nm, metres with the numbers scaled, as
Gwyddion keeps base units; x3p is always metres), the title, and the heights
against what asperity reads back from the same file (1e-6 of the range) and
against the original (GSF: float32; PNG: 16-bit, half a step of the range;
x3p and .gwy: float64).

Then asperity reads each .gwy that Gwyddion wrote: the heights equal gwyfile's
reading exactly, and size, spacing, origin and units match the DataField.

Missing points (issue #38): a field with a hole, written as .gsf and .x3p
(NaN) and .gwy (a mask), is opened by Gwyddion with those points and only
those in the channel's mask, and its measured heights unchanged.

With a demo gallery folder as a third argument, Gwyddion also converts the
demo's sample height field as .gsf, 16-bit .png and .x3p: size, extent, units
and heights as asperity reads the same file.

Usage: python check_gwyddion.py ASPERITY_BINARY WORKDIR [DEMO_DIR]
"""
import sys
from pathlib import Path

import gwyfile
import numpy as np

from checks import check, finish, info, run, write_csv_field

BIN, WORK = sys.argv[1], Path(sys.argv[2])
WORK.mkdir(parents=True, exist_ok=True)
nx, ny, dx, dy, x0, y0 = 40, 30, 0.25, 0.5, 10.0, -3.0
rng = np.random.default_rng(5)
z = np.cumsum(rng.normal(size=(ny, nx)), axis=1) * 1e-3 + 2.0
write_csv_field(WORK / "field.csv", z, dx, dy, x0, y0)


def read_back_gwyddions_file(tag, gwy, d):
    """asperity reads the .gwy Gwyddion wrote: gwyfile's heights, size, geometry and units."""
    npy = gwy.with_suffix(".back.npy")
    run(BIN, "--quiet", "convert", gwy, npy)
    ours = np.load(npy)
    check(f"{tag}: asperity reads Gwyddion's .gwy heights exactly", np.array_equal(ours, np.asarray(d.data)))
    facts = info(BIN, gwy)
    px, py = d.xreal / d["xres"], d.yreal / d["yres"]
    expect = [px, py, d.get("xoff", 0.0) + px / 2, d.get("yoff", 0.0) + py / 2]
    got = facts["spacing"] + facts["origin"]
    units = {k: v.get("unitstr", "") for k, v in d.items() if k.startswith("si_unit")}
    check(f"{tag}: asperity reads Gwyddion's .gwy geometry and units",
          np.allclose(got, expect, rtol=1e-12, atol=0)
          and facts["units"]["xy"] == (units.get("si_unit_xy") or "none")
          and facts["units"]["z"] == (units.get("si_unit_z") or "none"), f"{got} vs {expect}, {facts['units']}")


# (units flags, metres per xy unit, metres per z unit, Gwyddion's unit strings)
CASES = [([], 1.0, 1.0, ""), (["--xy-unit", "µm", "--z-unit", "nm"], 1e-6, 1e-9, "m")]
for flags, fx, fz, unit in CASES:
    for ext in ["gsf", "png", "x3p", "gwy"]:
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
        # Gwyddion 2.62's x3p import drops CX/CY Offset (the field starts at 0); the x3p
        # offsets are checked against SurfaceTopography and x3pio in check_x3p.py instead
        x_off, y_off = (0.0, 0.0) if ext == "x3p" else ((x0 - dx / 2) * fx, (y0 - dy / 2) * fx)
        check(f"{tag}: offset", abs(d.get("xoff", 0.0) - x_off) <= 1e-9 * abs(x0 * fx)
              and abs(d.get("yoff", 0.0) - y_off) <= 1e-9 * abs(y0 * fx),
              f"{d.get('xoff')}, {d.get('yoff')}")
        units = {k: v.get("unitstr", "") for k, v in d.items() if k.startswith("si_unit")}
        want = "m" if ext == "x3p" else unit  # x3p lengths are always metres
        check(f"{tag}: units {want or 'none'}", all(units.get(k, "") == want for k in ("si_unit_xy", "si_unit_z")),
              str(units))
        back = np.load(WORK / f"back_{ext}.npy")  # asperity's reading, in the file's units
        span = np.ptp(z) * fz
        # asperity reads .png in the file's own units, the others in metres when they have units
        factor = fz if ext == "png" else 1.0
        check(f"{tag}: heights = asperity's reading", np.max(np.abs(data - back * factor))
              <= 1e-6 * span, f"{np.max(np.abs(data - back * factor)) / span:.2e} of the range")
        # GSF holds float32 (1e-6 relative to the heights); PNG 16-bit steps of the range;
        # x3p and .gwy float64
        scale = {"gsf": np.max(np.abs(z * fz)) * 1e-6, "png": span * 0.5 / 65535 * 1.001}.get(
            ext, np.max(np.abs(z * fz)) * 1e-14)
        check(f"{tag}: heights = the original", np.max(np.abs(data - z * fz)) <= scale,
              f"{np.max(np.abs(data - z * fz)):.2e} (allowed {scale:.2e})")
        if ext in ("png", "gwy"):
            check(f"{tag}: title", title == "field", repr(title))  # convert titles by the input
        read_back_gwyddions_file(tag, gwy, d)



def check_demo(demo):
    """Gwyddion opens the demo's sample height field as asperity reads it."""
    for ext, unit in [("gsf", ""), ("png", ""), ("x3p", "m")]:
        src = demo / f"sample_height.{ext}"
        gwy, npy = WORK / f"demo_{ext}.gwy", WORK / f"demo_{ext}.npy"
        run("gwyddion", f"--convert-to-gwy={gwy}", src)
        run(BIN, "--quiet", "convert", src, npy)
        facts = info(BIN, src)
        (_, d), = gwyfile.util.get_datafields(gwyfile.load(str(gwy))).items()
        data, ours = np.asarray(d.data), np.load(npy)
        check(f"demo .{ext}: size", data.shape == ours.shape == (facts["ny"], facts["nx"]), str(data.shape))
        check(f"demo .{ext}: extent", np.allclose([d.xreal, d.yreal], [facts["nx"] * facts["spacing"][0],
              facts["ny"] * facts["spacing"][1]], rtol=1e-9, atol=0), f"{d.xreal} × {d.yreal}")
        # pixel edges half a spacing before the first sample (Gwyddion 2.62 drops x3p offsets)
        want = [0.0, 0.0] if ext == "x3p" else [o - sp / 2 for o, sp in zip(facts["origin"], facts["spacing"])]
        check(f"demo .{ext}: offsets", np.allclose([d.get("xoff", 0.0), d.get("yoff", 0.0)], want,
              rtol=1e-9, atol=1e-12 * max(facts["spacing"])), f"{d.get('xoff')}, {d.get('yoff')} vs {want}")
        units = {k: v.get("unitstr", "") for k, v in d.items() if k.startswith("si_unit")}
        check(f"demo .{ext}: units {unit or 'none'}", all(units.get(k, "") == unit
              for k in ("si_unit_xy", "si_unit_z")), str(units))
        span = np.ptp(ours)
        check(f"demo .{ext}: heights", np.max(np.abs(data - ours)) <= 1e-6 * span,
              f"{np.max(np.abs(data - ours)) / span:.2e} of the range")


def check_missing_points():
    """Gwyddion masks the points asperity writes as missing."""
    nx, ny = 9, 7
    z = np.add.outer(np.arange(ny) * 0.5, np.arange(nx) * 0.25)
    hole = np.zeros((ny, nx), bool)
    hole[2:4, 3:6] = True
    hole[6, 0] = True
    src = WORK / "holed.npy"
    np.save(src, np.where(hole, np.nan, z))
    for ext in ("gsf", "x3p", "gwy"):
        out, gwy = WORK / f"holed.{ext}", WORK / f"holed_{ext}.gwy"
        run(BIN, "--quiet", "convert", src, out)
        run("gwyddion", f"--convert-to-gwy={gwy}", out)
        g = gwyfile.load(str(gwy))
        mask = g.get("/0/mask")
        masked = np.zeros((ny, nx), bool) if mask is None else np.asarray(mask.data) > 0.5
        check(f"missing points in .{ext}: Gwyddion masks those {hole.sum()} points", np.array_equal(masked, hole),
              f"{int(masked.sum())} masked")
        data = np.asarray(g["/0/data"].data)
        check(f"missing points in .{ext}: the measured heights", np.allclose(data[~hole], z[~hole], rtol=0, atol=1e-6),
              f"{np.max(np.abs(data[~hole] - z[~hole])):.2e}")


check_missing_points()
if len(sys.argv) > 3:
    check_demo(Path(sys.argv[3]))
finish()
