#!/usr/bin/env python3
"""#54: are the memory estimates honest? For each workload, the smallest
`--max-memory` the command accepts (its estimate, found by bisection: a refusal
comes before the work) against the peak RSS of a run (GNU time), less the
process's RSS at rest. A ratio above 3 means the estimate lets a job exceed its budget; far
below 1/3 means real jobs are refused needlessly.

    python3 crates/benches/scripts/estimate_honesty.py [BINARY]

Not a test (minutes): figures go to BENCHMARKS.md with the machine.
"""
import pathlib
import subprocess
import sys
import tempfile

REPO = pathlib.Path(__file__).resolve().parents[3]
BIN = sys.argv[1] if len(sys.argv) > 1 else str(REPO / "target/release/asperity")

WORKLOADS = [
    ("generate fbm 2048²", ["generate", "fbm", "--size", "2048", "-o", "f.npy"]),
    ("analyze 1024² fBm", ["analyze", "f1024.npy"]),
    ("analyze sur-3.sur", ["analyze", str(REPO / "tests/data/surfacetopography/sur-3.sur")]),
    ("ca run 2048² × 64 steps", ["ca", "run", "--rule", "450", "--steps", "64", "--init", "random:0.3",
                                 "--size", "2048x2048", "-o", "ca.npy"]),
    ("growth rdsr 512² × 500", ["growth", "rdsr", "--size", "512", "--layers", "500", "-o", "r.npy"]),
    ("growth dla 100,000", ["growth", "dla", "--particles", "100000", "-o", "c.ply"]),
    ("generate dla-terrain", ["generate", "dla-terrain", "-o", "t.ply"]),
    ("reconstruct 100,000-point sphere", ["reconstruct", "sphere.xyz", "-o", "s.ply"]),
    ("subdiv planet scene", ["subdiv", str(REPO / "crates/subdiv/scenes/planet.toml"), "-o", "p.glb"]),
    ("render 2048² height field", ["render", "f.npy", "-o", "f.png"]),
]


def run(args, cwd, budget=None):
    cmd = ["/usr/bin/time", "-f", "%M", BIN, "--quiet"]
    if budget:
        cmd += ["--max-memory", f"{budget}K"]
    r = subprocess.run(cmd + args, cwd=cwd, capture_output=True, text=True)
    rss = int(r.stderr.strip().splitlines()[-1])
    return r.returncode == 0, rss, r.stderr


def threshold(args, cwd, high_kib):
    """The smallest budget (KiB) accepted, to 5 %."""
    lo, hi = 256, high_kib
    while hi > lo * 1.05:
        mid = int((lo * hi) ** 0.5)
        ok, _, err = run(args, cwd, mid)
        if ok:
            hi = mid
        elif "memory" in err or "would need" in err:
            lo = mid
        else:
            raise SystemExit(f"{args}: failed otherwise:\n{err}")
    return hi


def main():
    with tempfile.TemporaryDirectory() as tmp:
        import math, random
        rng = random.Random(1)
        with open(pathlib.Path(tmp) / "sphere.xyz", "w") as f:
            for _ in range(100_000):
                v = [rng.gauss(0, 1) for _ in range(3)]
                n = math.sqrt(sum(c * c for c in v))
                f.write(" ".join(f"{c / n:.9f}" for c in v) + "\n")
        subprocess.run([BIN, "--quiet", "generate", "fbm", "--size", "1024", "-o", "f1024.npy"],
                       cwd=tmp, check=True)
        subprocess.run([BIN, "--quiet", "generate", "fbm", "--size", "2048", "-o", "f.npy"],
                       cwd=tmp, check=True)
        # The process at rest (the binary, the thread pool): not the job's.
        _, rest, _ = run(["generate", "fbm", "--size", "16", "-o", "tiny.npy"], tmp)
        print(f"at rest: {rest / 1024:.0f} MiB")
        print(f"{'workload':34} {'peak RSS':>10} {'estimate':>10} {'(RSS - rest)/estimate':>22}")
        for name, args in WORKLOADS:
            ok, rss, err = run(args, tmp)
            if not ok:
                raise SystemExit(f"{name}: {err}")
            est = threshold(args, tmp, max(8 * rss, 1 << 20))
            ratio = (rss - rest) / est
            print(f"{name:34} {rss / 1024:8.0f} M {est / 1024:8.0f} M {ratio:22.2f}")


if __name__ == "__main__":
    main()
