#!/usr/bin/env python3
"""#56: ISO filtering and parameters, asperity beside surfalize, on one surface.

A 4096² non-periodic fBm (asperity's `generate fbm`, cropped from 4097²) is
filtered with an S-filter (λs = 5 samples) and an L-filter (λc = 250 samples),
and every parameter both programs compute is taken from the S-L surface:
Sa, Sq, Sp, Sv, Sz, Ssk, Sku, Sdq, Sdr, Sal, Str, Sk, Spk, Svk, Smr1, Smr2,
Sxp, Vmp, Vmc, Vvc, Vvv and the feature parameters Spd, Svd, Spc, Svc, S5p,
S5v, S10z (watershed and Wolf pruning at 5 % of Sz). asperity's time is the whole process
(`analyze --hurst psd`, which also computes the PSD, its Hurst fit, the
profiles and the scale-dependent statistics); surfalize's is its load from
.npy, `filter('bandpass', λs, λc)` and the parameters, in one Python process.

    python3 crates/benches/scripts/iso_peer.py [ASPERITY] [SIZE]

needs surfalize (python/tests/reference/requirements.txt). Not a test:
figures go to BENCHMARKS.md with the machine.
"""
import pathlib
import subprocess
import sys
import tempfile
import time

import numpy as np

REPO = pathlib.Path(__file__).resolve().parents[3]
BIN = sys.argv[1] if len(sys.argv) > 1 else str(REPO / "target/release/asperity")
N = int(sys.argv[2]) if len(sys.argv) > 2 else 4096
LAMBDA_S, LAMBDA_C = 5.0, 250.0
PARAMETERS = ("Sa", "Sq", "Sp", "Sv", "Sz", "Ssk", "Sku", "Sdq", "Sdr", "Sal", "Str", "Sk", "Spk",
              "Svk", "Smr1", "Smr2", "Sxp", "Vmp", "Vmc", "Vvc", "Vvv",
              "Spd", "Svd", "Spc", "Svc", "S5p", "S5v", "S10z")


def main():
    from surfalize import Surface

    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        subprocess.run([BIN, "--quiet", "generate", "fbm", "--size", str(N + 1), "--hurst", "0.8",
                        "-o", tmp / "big.npy"], check=True)
        np.save(tmp / "f.npy", np.load(tmp / "big.npy")[:N, :N])
        t = time.perf_counter()
        subprocess.run([BIN, "--quiet", "--json", "analyze", tmp / "f.npy", "--periodic", "no",
                        "--level", "mean", "--hurst", "psd", "--lambda-s", str(LAMBDA_S),
                        "--lambda-c", str(LAMBDA_C)], check=True, capture_output=True)
        ours = time.perf_counter() - t
        t = time.perf_counter()
        s = Surface(np.load(tmp / "f.npy"), 1.0, 1.0)
        s = s.filter("bandpass", LAMBDA_S, cutoff2=LAMBDA_C)
        for p in PARAMETERS:
            getattr(s, p)()
        theirs = time.perf_counter() - t
    print(f"{N}² S-L surface and {len(PARAMETERS)} parameters")
    print(f"  asperity analyze (whole process): {ours:8.2f} s")
    print(f"  surfalize 0.19.2:                 {theirs:8.2f} s")
    print(f"  asperity is {theirs / ours:.1f}× faster")


main()
