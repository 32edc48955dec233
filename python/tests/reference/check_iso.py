"""`asperity analyze` against surfalize (issue #56): ISO 25178-2 parameters.

surfalize (PyPI, pinned in requirements.txt) is an independent implementation
of ISO 25178-2 in numpy and scipy. Both programs analyse the same heights:

* a generated battery, drawn afresh on each run (the seed is printed): an fBm
  surface (SurfaceTopography's `fourier_synthesis`), cropped so it is not
  periodic; a plateau-honed surface (a smooth random field whose tops are
  flattened, so its height distribution has a plateau and deep valleys); a
  two-dimensional sinusoid; a field of separated Gaussian bumps;
* every areal file of `tests/data/surfacetopography` that both read with the
  same grid and no missing points (surfalize's Abbott–Firestone curve refuses
  missing points).

asperity runs with `--level mean --periodic no` (surfalize levels nothing and
subtracts the mean in its height parameters). Checks, relative to surfalize:
height parameters (Sa, Sq, Sp, Sv, Sz, Ssk, Sku) to 1e-9; Sdq to 1e-4; the Sk
family (Sk, Spk, Svk, Smr1, Smr2), Sxp and the volume family (Vmp, Vmc, Vvc,
Vvv) to 1e-3 of the parameter or, for a parameter near zero, of Sq; Sal and
Str to 10 %; Std to 10 % of the half turn; the feature parameters (Spd, Svd,
Spc, Svc, S5p, S5v, S10z: watershed segmentation, Wolf pruning at 5 % of Sz,
motifs touching the edge left out, as both programs default) to 10 %, and Spd
and Svd exactly (the same number of significant motifs) on the bump field.

Documented exceptions:
1. Sdr is not compared. surfalize computes it from the area of a triangulated
   surface (in %), asperity from the gradient form of ISO 25178-2 §4.3.2 (a
   fraction), as SurfaceTopography does; the discretisations differ by the
   curvature within a pixel. The gradient form is checked against
   SurfaceTopography in check_analysis.py.
2. Sdq to 5e-3, not 1e-4: surfalize averages the squared x differences over
   their ny(nx − 1) pairs and the y differences over theirs; asperity (and
   SurfaceTopography, to 1e-6 in check_analysis.py) over the (nx − 1)(ny − 1)
   points that have both forward neighbours. The two agree on any plane and
   differ by O(1/n) on a rough field.
3. Smr1 (Smr2) where the equivalent line's top (bottom) lies beyond the
   highest (lowest) point: asperity gives 0 % (100 %), no material lies there;
   surfalize interpolates with its ends clamped and returns the ratio of a
   tied extreme. Not compared in that case.
4. The spatial parameters where they are undefined: Str where either program
   finds that the ACF does not decay to 0.2 within the field in some direction
   (asperity's `Str_capped`, surfalize's warning: the value is then a bound),
   and Std where the surface has no strong lay (Str ≥ 0.2): the angular
   spectrum's maximum is then a draw of the noise, and the axes' bins, which
   hold whole lines of the lowest modes, win (a crop of an fBm with Str 0.31:
   asperity 90°, surfalize 0°). Not compared in those cases. Std is
   compared as an angle to 10 % of the half turn, with the axes' convention
   flipped (surfalize's y runs up the rows).
5. The functional family (Sk, Spk, Svk, Smr1, Smr2, Sxp, Vmp, Vmc, Vvc, Vvv) is
   compared to 1e-6 with ISO's construction on surfalize's own curve evaluated
   exactly (numpy, `exact_functional`), and to surfalize's values to 1e-2 for
   Sk and Sxp (the others' distance printed: on a lay, whose arcsine height
   distribution leaves the secant's gradient flat over tens of %, surfalize's
   Smr1 moves by up to 0.3 % points). surfalize samples the curve in
   10,000 classes: its secant search moves along a flat gradient (nms-1.nms:
   its window starts at 30.47 %, the exact curve's at 30.75 %, gradients equal
   to 7e-6), and it stops each area at the class before the line, a bias that
   falls slowly as the classes grow (Spk of the sinusoid below: 0.39416 at 10⁴
   classes, 0.39553 at 10⁵, 0.39585 at 4·10⁵, the exact curve 0.39616) and that
   one spike makes large (metropro-1.dat: Spk 2.6× at 10⁴ classes).
   crates/analysis checks Sk, Spk and Svk against a bimodal distribution's
   exact curve.
Fields under 16 samples a side are skipped (too small for Sal and Str).

Usage: python check_iso.py ASPERITY_BINARY WORKDIR DATA_DIR
Prints one line per surface and the worst errors; exits 1 after the first
surface with a failed check.
"""
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
from surfalize import Surface
from surfalize.abbottfirestone import AbbottFirestoneCurve
from SurfaceTopography.Generation import fourier_synthesis

BIN = sys.argv[1]
WORK = Path(sys.argv[2])
DATA = Path(sys.argv[3])
WORK.mkdir(parents=True, exist_ok=True)

TOLERANCES = {
    **{k: 1e-9 for k in ("Sa", "Sq", "Sp", "Sv", "Sz", "Ssk", "Sku")},
    "Sdq": 5e-3,
    **{k: 1e-6 for k in ("Sk", "Spk", "Svk", "Smr1", "Smr2", "Sxp", "Vmp", "Vmc", "Vvc", "Vvv")},
    "Sal": 0.10,
    "Str": 0.10,
    "Std": 0.10,
    **{k: 0.10 for k in ("Spd", "Svd", "Spc", "Svc", "S5p", "S5v", "S10z")},
}
# the field of separated bumps: the same count of significant hills and dales
EXACT_ON = {"separated Gaussian bumps 256²": ("Spd", "Svd")}
worst = {}
UM_PER = {"m": 1e6, "mm": 1e3, "µm": 1.0, "um": 1.0, "nm": 1e-3, "": 1.0}


def analyze(path):
    out = subprocess.run(
        [BIN, "--quiet", "analyze", str(path), "--json", "--level", "mean", "--periodic", "no",
         "--hurst", "psd"],
        capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError(out.stderr.strip())
    return json.loads(out.stdout)["measurements"]


OWN_CHECKED = ("Sk", "Sxp")
OWN_TOL = 1e-2
FUNCTIONAL = ("Sk", "Spk", "Svk", "Smr1", "Smr2", "Sxp", "Vmp", "Vmc", "Vvc", "Vvv")


def exact_functional(h):
    """ISO 25178-2 Annex B's construction on the curve surfalize samples — numpy's
    (1 − mr/100) quantile, linear between order statistics — evaluated exactly rather
    than over surfalize's 10,000 classes (documented exception 5): the 40 % secant of
    least gradient searched at every 0.01 % (the first kept), the least-squares line
    over it, the areas beyond it, and the volumes, integrated by the trapezoid rule
    over every order statistic."""
    d = np.sort(h.ravel())[::-1]
    mr = 100 * np.arange(d.size) / (d.size - 1)

    def smc(q):
        return np.interp(q, mr, d)

    def ratio(c):
        return float(np.interp(-c, -d, mr))

    def above(c):
        m = ratio(c)
        keep = mr <= m
        return np.trapezoid(np.append(d[keep], c) - c, np.append(mr[keep], m))

    def below(c):
        m = ratio(c)
        keep = mr >= m
        return np.trapezoid(c - np.insert(d[keep], 0, c), np.insert(mr[keep], 0, m))

    starts = np.arange(6001) * 0.01
    gradient = (smc(starts + 40) - smc(starts)) / 40
    start = starts[np.argmax(gradient)]
    xs = start + np.arange(4001) * 0.01
    slope, top = np.polyfit(xs, smc(xs), 1)
    bottom = top + 100 * slope
    smr1, smr2 = ratio(top), ratio(bottom)
    a1, a2 = above(top), below(bottom)
    vm = {p: above(float(smc(p))) / 100 for p in (10, 80)}
    vv = {p: below(float(smc(p))) / 100 for p in (10, 80)}
    return {
        "Sk": top - bottom, "Smr1": smr1, "Smr2": smr2,
        "Spk": 2 * a1 / smr1 if a1 > 0 else 0.0,
        "Svk": 2 * a2 / (100 - smr2) if a2 > 0 else 0.0,
        "Sxp": float(smc(2.5) - smc(50)),
        "Vmp": vm[10], "Vmc": vm[80] - vm[10], "Vvc": vv[10] - vv[80], "Vvv": vv[80],
    }


def reference(surface):
    values = {k: float(getattr(surface, k)()) for k in TOLERANCES}
    surfalize_own = {k: values[k] for k in FUNCTIONAL}
    values.update(exact_functional(surface.data))
    return values, surfalize_own


def skipped(ours):
    """The documented exceptions 3 and 4 that apply to asperity's report `ours`."""
    skip = set()
    line = ours["material_ratio"]["equivalent_line"]
    heights = ours["material_ratio"]["height"]
    if line["at_0"] >= heights[0]:
        skip.add("Smr1")
    if line["at_100"] <= heights[-1]:
        skip.add("Smr2")
    if ours.get("Str_capped"):
        skip.add("Str")
    if ours.get("Str") is None or ours["Str"] >= 0.2:
        skip.add("Std")
    return skip


def compare(case, ours, reference_values, scale):
    theirs, own = reference_values
    failed = []
    skip = skipped(ours)
    for k, tol in TOLERANCES.items():
        if k in skip or (k == "Str" and not np.isfinite(theirs[k])):
            print(f"    {k} not compared (documented exception)")
            continue
        a, b = ours.get(k), theirs[k]
        if a is None and not np.isfinite(b):
            continue  # undefined in both (a feature parameter of no motif)
        if k in EXACT_ON.get(case, ()):
            if a != b and abs(a - b) > 1e-12 * abs(b):
                failed.append(f"{k}: {a!r} vs surfalize {b!r} (not the same count)")
            continue
        if k == "Std" and a is not None:
            # surfalize's y runs up the rows (row 0 on top), asperity's down them: the
            # same direction is θ in one and 180° − θ in the other. Compared to 10 % of
            # the half turn (18°), as an angle.
            flipped = (180.0 - b) % 180.0
            off = min((a - flipped) % 180.0, (flipped - a) % 180.0)
            if off / 180.0 >= worst.get(k, (0.0, ""))[0]:
                worst[k] = (off / 180.0, case)
            if off > tol * 180.0:
                failed.append(f"{k}: {a!r}° vs surfalize {b!r}° (180° − it: {flipped}°)")
            continue
        if a is None:
            failed.append(f"{k}: asperity gave none (surfalize {b!r})")
            continue
        # volumes and heights of a near-zero parameter against the surface's Sq
        denom = max(abs(b), 1e-3 * scale) if k not in ("Smr1", "Smr2") else max(abs(b), 1.0)
        err = abs(a - b) / denom
        if err >= worst.get(k, (0.0, ""))[0]:
            worst[k] = (err, case)
        if err > tol:
            failed.append(f"{k}: {a!r} vs surfalize {b!r} ({err:.2e} > {tol:g})")
        if k in own:
            err = abs(a - own[k]) / max(abs(own[k]), 1e-3 * scale)
            if err >= worst.get(k + " vs surfalize's classes", (0.0, ""))[0]:
                worst[k + " vs surfalize's classes"] = (err, case)
            if k in OWN_CHECKED:
                if err > OWN_TOL:
                    failed.append(f"{k}: {a!r} vs surfalize's own {own[k]!r} ({err:.2e} > {OWN_TOL:g})")
    print(f"{case}: {'ok' if not failed else 'FAILED'}")
    for f in failed:
        print(f"    {f}")
    return not failed


def battery(rng):
    n = 256
    x, y = np.meshgrid(np.arange(n), np.arange(n))
    big = fourier_synthesis((2 * n, 2 * n), (2 * n, 2 * n), hurst=0.8, rms_height=1.0, rng=rng).heights()
    ox, oy = rng.integers(0, n, size=2)
    yield "fBm 256² (H 0.8, a crop)", big[ox:ox + n, oy:oy + n]
    # a smooth random field, its tops flattened: a plateau over deep valleys
    noise = rng.normal(size=(n, n))
    k = np.hypot(*np.meshgrid(np.fft.fftfreq(n), np.fft.fftfreq(n)))
    smooth = np.real(np.fft.ifft2(np.fft.fft2(noise) * np.exp(-(k / 0.04) ** 2)))
    smooth /= smooth.std()
    top = np.quantile(smooth, 0.3)
    yield "plateau-honed 256²", np.where(smooth > top, top + 0.05 * (smooth - top), smooth)
    yield "sinusoid 256²", np.sin(2 * np.pi * x / 37.0) * np.cos(2 * np.pi * y / 53.0) + 0.3 * np.sin(2 * np.pi * x / 11.0)
    angle = rng.uniform(0, np.pi)
    ridges = np.sin(2 * np.pi * (x * np.cos(angle) + y * np.sin(angle)) / 23.0)
    yield f"a lay at {np.degrees(angle):.0f}° with noise 256²", ridges + 0.2 * smooth
    bumps = np.zeros((n, n))
    for cx in range(16, n, 32):
        for cy in range(16, n, 32):
            px, py = cx + rng.uniform(-4, 4), cy + rng.uniform(-4, 4)
            bumps += rng.uniform(0.5, 1.5) * np.exp(-((x - px) ** 2 + (y - py) ** 2) / (2 * 4.0 ** 2))
    yield "separated Gaussian bumps 256²", bumps


def main():
    # a fresh draw each run; ISO_SEED=N repeats one
    seed = int(os.environ.get("ISO_SEED", np.random.SeedSequence().entropy % 2**32))
    print(f"seed {seed}")
    rng = np.random.default_rng(seed)
    ok = True
    compared = 0
    for name, h in battery(rng):
        h = np.ascontiguousarray(h, dtype=np.float64)
        path = WORK / f"battery-{compared}.npy"
        np.save(path, h)
        ours = analyze(path)
        ok &= compare(name, ours, reference(Surface(h, 1.0, 1.0)), float(h.std()))
        compared += 1
    files = 0
    for path in sorted(DATA.iterdir()):
        if path.suffix in (".md", ".txt", ".csv", ".npy", ".xlsx"):
            continue
        try:
            theirs_read = Surface.load(path)
        except Exception:  # surfalize does not read it
            continue
        try:
            ours = analyze(path)
        except RuntimeError as e:
            print(f"{path.name}: skipped (asperity: {e})")
            continue
        if ours.get("kind") != "height field" or "missing" in ours:
            print(f"{path.name}: skipped ({ours.get('kind')}, missing points: {'missing' in ours})")
            continue
        if min(ours["size"]) < 16:
            print(f"{path.name}: skipped ({ours['size'][0]}×{ours['size'][1]} grid)")
            continue
        # The parameters are compared on the heights asperity read, in µm (surfalize's
        # unit): the readers are checked against SurfaceTopography and Gwyddion elsewhere;
        # here a difference in reading is printed, not failed.
        heights = WORK / f"{path.stem}.npy"
        subprocess.run([BIN, "--quiet", "convert", str(path), str(heights)], check=True,
                       capture_output=True)
        units = ours["units"]
        z_um, xy_um = (UM_PER.get(units.get(a), 1.0) for a in ("z", "xy"))
        h = np.load(heights) * z_um
        dx, dy = (d * xy_um for d in ours["spacing"])
        read = theirs_read.data
        if read.shape != h.shape:
            print(f"    {path.name}: surfalize reads a {read.shape} grid, asperity {h.shape}")
        else:
            diff = np.nanmax(np.abs(read - h)) / max(np.nanstd(h), 1e-300)
            if not diff < 1e-5:
                print(f"    {path.name}: surfalize reads other heights (max difference {diff:.3g} Sq)")
        mine = dict(ours)
        for k in ("Sa", "Sq", "Sp", "Sv", "Sz", "Sk", "Spk", "Svk", "Sxp", "Vmp", "Vmc", "Vvc", "Vvv"):
            mine[k] = ours[k] * z_um if ours.get(k) is not None else None
        mine["Sal"] = ours["Sal"] * xy_um if ours.get("Sal") is not None else None
        mine["Sdq"] = ours["Sdq"] * z_um / xy_um
        for k in ("S5p", "S5v", "S10z"):
            mine[k] = ours[k] * z_um if ours.get(k) is not None else None
        for k in ("Spd", "Svd"):
            mine[k] = ours[k] / xy_um**2
        for k in ("Spc", "Svc"):
            mine[k] = ours[k] * z_um / xy_um**2 if ours.get(k) is not None else None
        ok &= compare(path.name, mine, reference(Surface(h, dx, dy)), float(h.std()))
        files += 1
    print(f"{compared} generated surfaces and {files} files compared")
    for k, (err, case) in sorted(worst.items()):
        print(f"  worst {k}: {err:.2e} ({case})")
    if not ok:
        sys.exit(1)
    print("OK: every check passed")


main()
