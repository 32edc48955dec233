"""What the real-program check scripts share (check_gwyddion.py, check_x3p.py):
"ok   what" / "FAIL what" lines, running the asperity binary, and the CSV
height field they start from."""
import json
import subprocess
import sys

import numpy as np

failures = []


def check(what, ok, detail=""):
    print(f"{'ok  ' if ok else 'FAIL'} {what} {detail}")
    if not ok:
        failures.append(what)


def run(*args, check=True):
    """Runs a command; its stdout. A failure ends the script with its stderr
    (with ``check=False``: the finished process, whatever its status)."""
    p = subprocess.run([str(a) for a in args], capture_output=True, text=True)
    if not check:
        return p
    if p.returncode != 0:
        sys.exit(f"{' '.join(map(str, args))} failed: {p.stderr}")
    return p.stdout


def info(binary, path):
    """`asperity info --json PATH`'s measurements."""
    return json.loads(run(binary, "--quiet", "info", "--json", path))["measurements"]


def write_csv_field(path, z, dx, dy, x0, y0):
    """Heights z (ny, nx) as asperity's CSV grid, geometry in the comment line."""
    ny, nx = z.shape
    with open(path, "w") as f:
        f.write(f"# asperity height field: nx={nx} ny={ny} dx={dx} dy={dy} x0={x0} y0={y0}\n")
        for row in z:
            f.write(",".join(repr(float(v)) for v in row) + "\n")


def finish():
    sys.exit(1 if failures else 0)


def in_bin(q, lo, hi, last):
    """asperity's bins are [lo, hi), the last one closed; a wavevector within
    1e-9 (relative) below an edge counts as on it (psd::EDGE_TOLERANCE): log
    edges fall on lattice wavevectors, and rounding must not decide."""
    qt = q * (1 + 1e-9)
    return (qt >= lo) & ((q <= hi * (1 + 1e-12)) if last else (qt < hi))


def binned(q, c, edges):
    """Bin means and counts of PSD values `c` at wavevectors `q` over asperity's bins."""
    means, counts = [], []
    q, c = q.ravel(), c.ravel()
    for k, (lo, hi) in enumerate(edges):
        sel = in_bin(q, lo, hi, k == len(edges) - 1)
        counts.append(int(sel.sum()))
        means.append(c[sel].mean() if sel.any() else np.nan)
    return np.array(means), np.array(counts)
