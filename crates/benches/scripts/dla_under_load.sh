#!/bin/bash
# DLA at 1 and 2 threads, quiet and with a CPU-bound loop at nice 10 on every
# core (#55). Usage: dla_under_load.sh [ASPERITY] [PARTICLES] [ROUNDS]
# Prints, per run: threads, load, the walk's seconds (from --progress lines),
# the whole process's wall and CPU seconds, and the walkers' figures.
set -euo pipefail
bin=${1:-target/release/asperity}
particles=${2:-1000000}
rounds=${3:-2}
out=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$out"' EXIT

run() { # threads label
    /usr/bin/time -f "%e %U %S" -o "$out/time" "$bin" -q --json --progress lines \
        --threads "$1" growth dla --particles "$particles" -o "$out/c$1.xyz" \
        >"$out/report.json" 2>"$out/progress"
    walk=$(grep -o 'DLA: done ([^,]*, [0-9.]* s)' "$out/progress" | grep -o '[0-9.]* s)' | tr -d ' s)')
    read -r wall user sys <"$out/time"
    walkers=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['measurements']['walkers'])" "$out/report.json")
    printf '%-6s threads=%s walk=%5ss wall=%6ss cpu=%6.2fs %s\n' "$2" "$1" "$walk" "$wall" \
        "$(echo "$user + $sys" | bc)" "$walkers"
}

for _ in $(seq "$rounds"); do run 1 quiet; run 2 quiet; done
cmp "$out/c1.xyz" "$out/c2.xyz" && echo "quiet: the same cluster at 1 and 2 threads"
for _ in $(seq "$(nproc)"); do nice -n 10 sh -c 'while :; do :; done' & done
for _ in $(seq "$rounds"); do run 1 loaded; run 2 loaded; done
cmp "$out/c1.xyz" "$out/c2.xyz" && echo "loaded: the same cluster at 1 and 2 threads"
