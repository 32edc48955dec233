#!/bin/bash
# Thread scaling of `analyze` (a 4096² fBm) and DLA (10⁶ particles, point seed) on a
# many-core machine, whole process. Usage: many_cores.sh PATH/TO/asperity [MAX_THREADS]
# Figures measured with it: BENCHMARKS.md, "16 cores".
set -u
A=${1:?usage: many_cores.sh PATH/TO/asperity [MAX_THREADS]}
MAX=${2:-$(nproc)}
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
TIMEFORMAT=%R
counts=""; n=1; while [ "$n" -lt "$MAX" ]; do counts="$counts $n"; n=$((n * 2)); done; counts="$counts $MAX"
"$A" -q generate fbm --size 4096 --hurst 0.8 --seed 1 -o "$T/f4096.npy"
for rep in 1 2; do
  for n in $counts; do
    w=$( { time "$A" -q --threads "$n" analyze "$T/f4096.npy" > "$T/r$n.txt"; } 2>&1 ); echo "analyze $n threads (run $rep): $w s"
    w=$( { time "$A" -q --threads "$n" analyze --hurst psd "$T/f4096.npy" > /dev/null; } 2>&1 ); echo "analyze --hurst psd $n threads (run $rep): $w s"
  done
done
cmp "$T/r1.txt" "$T/r$MAX.txt" && echo "analyze: the report at $MAX threads is identical to one thread's"
for n in $counts; do
  w=$( { time "$A" -q --json --threads "$n" growth dla --walkers "$n" --particles 1000000 --seed 3 -o "$T/c$n.xyz" > "$T/d$n.json"; } 2>&1 )
  echo "dla 1e6, $n walkers: $w s; $(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['measurements']['walkers'])" "$T/d$n.json" 2>/dev/null)"
  cmp "$T/c1.xyz" "$T/c$n.xyz" || echo "dla: $n walkers differ from one"
done
