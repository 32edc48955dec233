#!/usr/bin/env python3
"""#54's slow corners, whole process: `analyze` of one 20,000-corner polygon (a
star, non-convex, and an arc, convex: a fan of slivers) and of SurfaceTopography's
`sur-3.sur` (512², 89 % of the points not measured).

    python3 crates/benches/scripts/slow_corners.py target/release/asperity [OTHER_BINARY ...]

Prints wall seconds and peak RSS per binary and input (GNU time). Not a test: figures go
to BENCHMARKS.md with the machine.
"""
import math
import pathlib
import subprocess
import sys
import tempfile

REPO = pathlib.Path(__file__).resolve().parents[3]


def polygon(path, n, radius):
    with open(path, "w") as f:
        for k in range(n):
            x, y = radius(k)
            f.write(f"v {x!r} {y!r} 0\n")
        f.write("f " + " ".join(str(k + 1) for k in range(n)) + "\n")


def main():
    binaries = sys.argv[1:] or [str(REPO / "target/release/asperity")]
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        n = 20_000

        def star(k):
            t, r = 2 * math.pi * k / n, (1.0 if k % 2 == 0 else 0.6)
            return r * math.cos(t), r * math.sin(t)

        def arc(k):
            t = math.pi * k / (n - 1)
            return math.cos(t), math.sin(t)

        polygon(tmp / "star.obj", n, star)
        polygon(tmp / "arc.obj", n, arc)
        inputs = [tmp / "star.obj", tmp / "arc.obj", REPO / "tests/data/surfacetopography/sur-3.sur"]
        for b in binaries:
            for i in inputs:
                r = subprocess.run(
                    ["/usr/bin/time", "-f", "%e %M", b, "analyze", str(i)],
                    capture_output=True, text=True,
                )
                wall, rss = r.stderr.strip().splitlines()[-1].split()
                print(f"{b}\t{i.name}\t{float(wall):.2f} s\t{int(rss) / 1024:.0f} MiB")


if __name__ == "__main__":
    main()
