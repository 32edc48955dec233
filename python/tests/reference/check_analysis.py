"""`asperity analyze` against SurfaceTopography (issue #21).

Surfaces of known Hurst exponent made by SurfaceTopography's own
`fourier_synthesis` (Ramisetti et al. 2011; Jacobs, Junge & Pastewka 2017),
periodic and cropped out of a larger periodic surface (non-periodic, the case of
measured data), with a tilt added (all crops, two periodic surfaces in three),
are analysed by the asperity binary with
its default settings. Checks:

* H from the 2-D PSD within 0.05 of the truth; every other estimator within 0.1;
* every fractal dimension within 0.1 of 3 - H, or null with a warning;
* the radial PSD within 2 % of SurfaceTopography's (same window and detrending)
  in every bin holding at least 50 modes;
* Sq, Sdq, Sdr equal to SurfaceTopography's to 1e-6 relative, Ssk and Sku to its
  detrended heights' moments;
* line scans (1-D .npy): the profile PSD against `power_spectrum_from_profile`,
  Rq, Rdq and the scale-dependent rms slope and curvature against
  SurfaceTopography, H within 0.05 and the other estimators within 0.1.

Usage: python check_analysis.py ASPERITY_BINARY WORKDIR [quick]
Prints one line per surface and a summary of the worst errors; exits 1 on the
first failed check (after printing every failure of that surface).
"""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
from SurfaceTopography import Topography, UniformLineScan
from SurfaceTopography.Generation import fourier_synthesis

from checks import binned

BIN = sys.argv[1]
WORK = Path(sys.argv[2])
QUICK = len(sys.argv) > 3 and sys.argv[3] == "quick"
WORK.mkdir(parents=True, exist_ok=True)

H_TOL = 0.05
OTHER_TOL = 0.1
PSD_TOL = 0.02
PSD_MIN_MODES = 50
AREAL_TOL = 1e-6

worst = {}
failures = []


def note(name, err):
    worst[name] = max(worst.get(name, 0.0), err)


def check(case, what, ok, detail):
    if not ok:
        failures.append(f"{case}: {what}: {detail}")


def surface(n, hurst, seed, periodic):
    """Heights indexed [x, y] (SurfaceTopography's layout), pixel size 1."""
    rng = np.random.default_rng(seed)
    if periodic:
        h = fourier_synthesis((n, n), (n, n), hurst=hurst, rms_height=1.0, rng=rng).heights()
    else:
        big = fourier_synthesis((2 * n, 2 * n), (2 * n, 2 * n), hurst=hurst, rms_height=1.0, rng=rng).heights()
        ox, oy = rng.integers(0, n, size=2)
        h = big[ox:ox + n, oy:oy + n]
    if periodic and seed % 3 == 0:
        # Some periodic surfaces stay untilted, as asperity's own generators
        # write them: periodicity is then detected on the raw heights.
        return np.ascontiguousarray(h + 3.0)
    x, y = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    # A tilt of a few percent of the rms height per pixel: larger than the
    # surface's own long-wavelength slope, as on a sample mounted askew.
    return np.ascontiguousarray(h + 0.02 * x - 0.015 * y + 3.0)


def analyze(path):
    out = subprocess.run([BIN, "--quiet", "analyze", str(path), "--json"], capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit(f"asperity analyze {path} failed: {out.stderr}")
    return json.loads(out.stdout)


def check_psd(case, m, topo, window):
    p = m["psd"]
    _, _, c_map = topo.power_spectrum_from_area(window=window, return_map=True)
    nx, ny = topo.nb_grid_pts
    sx, sy = topo.physical_sizes
    qx = 2 * np.pi * np.fft.fftfreq(nx, sx / nx)
    qy = 2 * np.pi * np.fft.fftfreq(ny, sy / ny)
    q_map = np.hypot(qx[:, None], qy[None, :])
    ref, counts = binned(q_map, c_map, p["q_edges"])
    ours = np.array(p["C"])
    modes = np.array(p["modes"])
    check(case, "PSD mode counts", np.array_equal(counts, modes), f"{counts} vs {modes}")
    big = modes >= PSD_MIN_MODES
    err = np.max(np.abs(ours[big] / ref[big] - 1))
    note("PSD vs SurfaceTopography (rel.)", err)
    check(case, "PSD", err <= PSD_TOL, f"worst bin off by {err:.2%}")


def detrended(m, topo):
    """SurfaceTopography's detrending matching asperity's levelling."""
    mode = {"plane": "height", "mean": "center", "slope": "slope"}[m["levelling"]]
    t = topo.detrend(detrend_mode=mode)
    # SurfaceTopography marks every detrended field but a centred one
    # non-periodic; removing the mean slope keeps a periodic surface periodic
    # (it is how asperity levels one), so rebuild it with the original flag.
    return Topography(t.heights(), t.physical_sizes, periodic=topo.is_periodic)


def check_areal(case, m, topo):
    t = detrended(m, topo)
    h = t.heights()
    gx, gy = t.derivative(1)
    ref = {
        "Sq": t.rms_height_from_area(),
        "Sdq": t.rms_gradient(),
        "Sdr": np.mean(np.sqrt(1 + gx ** 2 + gy ** 2)) - 1,
        "Ssk": np.mean((h - h.mean()) ** 3) / np.std(h) ** 3,
        "Sku": np.mean((h - h.mean()) ** 4) / np.std(h) ** 4,
    }
    for k, v in ref.items():
        err = abs(m[k] / v - 1) if k not in ("Ssk",) else abs(m[k] - v) / max(1.0, abs(v))
        note(f"{k} vs SurfaceTopography", err)
        check(case, k, err <= AREAL_TOL, f"{m[k]!r} vs {v!r}")


def check_estimates(case, d, hurst, top=3):
    """H from every estimator; dimensions against top - H (3 for a map, 2 for a profile)."""
    m = d["measurements"]
    warnings = " ".join(d.get("warnings", []))
    err = abs(m["hurst"] - hurst)
    note("H psd_2d (default)", err)
    check(case, "H", err <= H_TOL, f"{m['hurst']:.3f} vs {hurst}")
    for name, e in m["hurst_estimates"].items():
        check(case, f"estimator {name}", e is not None, "missing")
        if e is None:
            continue
        err = abs(e["H"] - hurst)
        note(f"H {name}", err)
        check(case, f"H {name}", err <= OTHER_TOL, f"{e['H']:.3f} vs {hurst}")
    for name, f in m["fractal_dimension"].items():
        if f is None:
            check(case, f"D {name} null", name in warnings, "null without a warning")
            worst[f"D {name} null"] = worst.get(f"D {name} null", 0) + 1
            continue
        err = abs(f["D"] - (top - hurst))
        note(f"D {name}", err)
        check(case, f"D {name}", err <= OTHER_TOL, f"{f['D']:.3f} vs {top - hurst}")


def areal_case(n, hurst, seed, periodic):
    kind = "periodic" if periodic else "crop"
    case = f"{n}² H={hurst} seed={seed} {kind}"
    h = surface(n, hurst, seed, periodic)
    path = WORK / f"s{n}_{hurst}_{seed}_{kind}.npy"
    # asperity's .npy layout is rows = y: the transpose of SurfaceTopography's [x, y].
    np.save(path, np.ascontiguousarray(h.T))
    d = analyze(path)
    m = d["measurements"]
    check(case, "periodic detected", m["periodic"]["value"] == periodic, json.dumps(m["periodic"]))
    check_estimates(case, d, hurst)
    topo = Topography(h, (n, n), periodic=periodic)
    check_areal(case, m, topo)
    check(case, "window", m["window"] == ("none" if periodic else "hann"), m["window"])
    check_psd(case, m, detrended(m, topo), None if periodic else "hann")
    path.unlink()
    est = " ".join(f"{k}={v['H']:.3f}" for k, v in m["hurst_estimates"].items() if v)
    dims = " ".join(f"{k}={'null' if v is None else format(v['D'], '.3f')}" for k, v in m["fractal_dimension"].items())
    print(f"{case}: H={m['hurst']:.3f} | {est} | D {dims}", flush=True)


def profile_case(n, hurst, seed):
    case = f"profile {n} H={hurst} seed={seed}"
    rng = np.random.default_rng(seed)
    big = fourier_synthesis((4 * n,), (4 * n,), hurst=hurst, rms_height=1.0, rng=rng).heights()
    off = int(rng.integers(0, 3 * n))
    h = big[off:off + n] + 0.01 * np.arange(n)
    path = WORK / f"p{n}_{hurst}_{seed}.npy"
    np.save(path, h)
    d = analyze(path)
    m = d["measurements"]
    check(case, "periodic detected", m["periodic"]["value"] is False, json.dumps(m["periodic"]))
    check(case, "kind", m["kind"] == "profile", m["kind"])
    check_estimates(case, d, hurst, top=2)
    line = UniformLineScan(h, (n,), periodic=False).detrend(detrend_mode="height")
    for k, v in {"Rq": line.rms_height_from_profile(), "Rdq": line.rms_slope_from_profile()}.items():
        err = abs(m["profile_x"][k] / v - 1)
        note(f"{k} vs SurfaceTopography", err)
        check(case, k, err <= AREAL_TOL, f"{m['profile_x'][k]!r} vs {v!r}")
    # Scale-dependent slope and curvature (Sanner et al. 2022), at asperity's distances.
    sd = m["scale_dependent"]
    for key, fn in (("rms_slope", line.scale_dependent_slope_from_profile),
                    ("rms_curvature", line.scale_dependent_curvature_from_profile)):
        r, v = fn(resampling_method=None)
        ours = np.array([np.nan if x is None else x for x in sd[key]])
        at = np.array([np.argmin(np.abs(r - x)) for x in sd["distance"]])
        ok = ~np.isnan(ours)
        check(case, f"{key} distances", np.allclose(r[at], sd["distance"]), "not on SurfaceTopography's grid")
        err = np.max(np.abs(ours[ok] / v[at][ok] - 1))
        note(f"profile scale-dependent {key} (rel.)", err)
        check(case, f"scale-dependent {key}", err <= AREAL_TOL, f"off by {err:.2e}")
    p = m["psd"]
    # SurfaceTopography returns q = 0 … (n/2 - 1)·2π/L; asperity counts +q and
    # -q and the Nyquist mode: compare on both signs, counts up to the Nyquist mode.
    q, c = line.power_spectrum_from_profile(window="hann", resampling_method=None)
    q, c = np.concatenate([q[1:], q[1:]]), np.concatenate([c[1:], c[1:]])
    ours = np.array(p["C"])
    ref, counts = binned(q, c, p["q_edges"])
    extra = np.array(p["modes"]) - counts
    check(case, "profile PSD mode counts", np.all((extra == 0) | ((extra == 1) & (np.arange(len(extra)) == len(extra) - 1))),
          f"{counts} vs {p['modes']}")
    big = counts >= PSD_MIN_MODES
    err = np.max(np.abs(ours[big] / ref[big] - 1)) if big.any() else 0.0
    note("profile PSD vs SurfaceTopography (rel.)", err)
    check(case, "profile PSD", err <= PSD_TOL, f"worst bin off by {err:.2%}")
    path.unlink()
    est = " ".join(f"{k}={v['H']:.3f}" for k, v in m["hurst_estimates"].items() if v)
    print(f"{case}: H={m['hurst']:.3f} | {est}", flush=True)


def battery():
    hursts = [0.2, 0.35, 0.5, 0.65, 0.8, 0.9]
    if QUICK:
        yield from ((256, hu, s, p) for hu in (0.3, 0.8) for s in (1,) for p in (True, False))
        return
    # Every H, both kinds, on several seeds at 256² and 512²; fewer at the
    # sizes that take seconds each.
    for n, seeds in ((256, (1, 2, 3)), (512, (4, 5))):
        for hu in hursts:
            for s in seeds:
                for p in (True, False):
                    yield n, hu, s, p
    for i, hu in enumerate(hursts):
        yield 1024, hu, 10 + i, i % 2 == 0
        yield 1024, hu, 20 + i, i % 2 == 1
    for i, hu in enumerate((0.2, 0.5, 0.8, 0.9)):
        yield 2048, hu, 30 + i, i % 2 == 0


for n, hu, s, p in battery():
    areal_case(n, hu, s, p)
for n, hu, s in ((4096, 0.3, 1), (4096, 0.8, 2), (16384, 0.5, 3)) if not QUICK else ((4096, 0.5, 1),):
    profile_case(n, hu, s)

print("\nworst errors:")
for k in sorted(worst):
    print(f"  {k:40s} {worst[k]:.3g}")
if failures:
    print(f"\n{len(failures)} failed checks:")
    for f in failures:
        print("FAIL", f)
    sys.exit(1)
print("OK: every check passed")
