#!/bin/bash
# DLA beside DLAf-optimized (github.com/BrutPitt/DLAf-optimized, off-lattice,
# one thread, nanoflann k-d tree), #55. Usage:
#   dla_peer.sh DLAF_DIR FASTPRNG_DIR [ASPERITY] [PARTICLES] [THREADS...]
# DLAF_DIR holds dlaf.cpp and nanoflann.hpp, FASTPRNG_DIR fastPRNG.h
# (github.com/BrutPitt/fastPRNG; DLAf includes it but does not ship it).
# DLAf is built as its Makefile builds it (g++ -O3 -march=native -flto), in
# its benchmark mode (particles kept in memory, not printed) and with its
# particle count set to PARTICLES; asperity writes its cluster to a file.
# Prints each program's wall and CPU seconds, and asperity's speed-up.
set -euo pipefail
dlaf_dir=$1
prng_dir=$2
bin=${3:-target/release/asperity}
particles=${4:-1000000}
shift $(($# < 4 ? $# : 4))
threads=("${@:-1 2}")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

sed "s/i < 1000000; i++/i < $particles; i++/" "$dlaf_dir/dlaf.cpp" >"$work/dlaf.cpp"
cp "$dlaf_dir/nanoflann.hpp" "$prng_dir/fastPRNG.h" "$work/"
g++ -std=c++14 -O3 -flto -march=native -DDLAF_BENCHMARK -I"$work" -o "$work/dlaf" "$work/dlaf.cpp"

/usr/bin/time -f "%e %U %S" -o "$work/t" "$work/dlaf" >/dev/null 2>&1
read -r dlaf_wall user sys <"$work/t"
printf 'DLAf-optimized  %8s particles  wall %7ss  cpu %7.2fs\n' "$particles" "$dlaf_wall" \
    "$(echo "$user + $sys" | bc)"
for t in ${threads[*]}; do
    /usr/bin/time -f "%e %U %S" -o "$work/t" "$bin" -q --threads "$t" growth dla \
        --particles "$particles" -o "$work/c.xyz"
    read -r wall user sys <"$work/t"
    printf 'asperity -t %-3s %8s particles  wall %7ss  cpu %7.2fs  %.2fx DLAf\n' "$t" \
        "$particles" "$wall" "$(echo "$user + $sys" | bc)" "$(echo "$dlaf_wall / $wall" | bc -l)"
done
