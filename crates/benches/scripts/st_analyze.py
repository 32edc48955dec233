"""SurfaceTopography's side of the analyze comparison of issue #37.

Times what `asperity analyze` reports from the PSD on the same array, the way a
SurfaceTopography user computes it: a periodic `Topography`, `detrend("center")`,
the rms height and gradient, `power_spectrum_from_area(nb_points=40,
collocation="log")` and a log-log fit of C(q) from 2 q_min to the Nyquist q.

    python crates/benches/scripts/st_analyze.py FILE.npy [--repeat 3]

Prints the median wall time in seconds and the Hurst exponent (asperity's side:
`asperity -q analyze FILE.npy --hurst psd`, timed the same way; BENCHMARKS.md).
"""
import argparse
import statistics
import time

import numpy as np
from SurfaceTopography import Topography


def analyse(h):
    nx, ny = h.shape
    t = Topography(h, physical_sizes=(float(nx), float(ny)), periodic=True).detrend("center")
    rms_height = t.rms_height_from_area()
    rms_gradient = t.rms_gradient()
    q, c = t.power_spectrum_from_area(nb_points=40, collocation="log")
    q_min, q_nyquist = 2 * np.pi / nx, np.pi
    keep = np.isfinite(c) & (c > 0) & (q >= 2 * q_min) & (q <= q_nyquist)
    slope = np.polyfit(np.log(q[keep]), np.log(c[keep]), 1)[0]
    return rms_height, rms_gradient, -slope / 2 - 1


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("file")
    parser.add_argument("--repeat", type=int, default=3)
    a = parser.parse_args()
    h = np.load(a.file)
    times = []
    for _ in range(a.repeat):
        start = time.perf_counter()
        result = analyse(h)
        times.append(time.perf_counter() - start)
    print(f"SurfaceTopography: median {statistics.median(times):.3f} s over {a.repeat}; "
          f"Sq = {result[0]:.6g}, rms gradient = {result[1]:.6g}, H = {result[2]:.4f}")


if __name__ == "__main__":
    main()
