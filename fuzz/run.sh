#!/usr/bin/env bash
# Fuzzes asperity's readers (cargo-fuzz + libFuzzer, on the stable toolchain
# through RUSTC_BOOTSTRAP).   Usage: fuzz/run.sh SECONDS_PER_READER [READER…]
# One binary (fuzz_targets/readers.rs) holds every reader; an input is
# `NAME\0BYTES`. Each reader (default: every folder of fuzz/seeds) runs for
# SECONDS from its committed seeds in fuzz/seeds/NAME (prefixed with its name
# here) into fuzz/corpus/readers/NAME (kept between runs, not committed),
# FUZZ_JOBS readers at a time (default: one per core; each libFuzzer process is
# single-threaded). A crash, an abort, a hang (> 10 s for one input), an
# allocation over 1 GiB or more than 2 GiB resident fails the run: no further
# reader starts, the running ones finish, and libFuzzer leaves the input in
# fuzz/artifacts/NAME/. Turn it into a regression test (see fuzz/README.md).
set -euo pipefail
cd "$(dirname "$0")"
export RUSTC_BOOTSTRAP=1
seconds=${1:?seconds per reader}
shift
readers=("$@")
if [ ${#readers[@]} -eq 0 ]; then
  mapfile -t readers < <(ls seeds)
fi
for r in "${readers[@]}"; do
  if [ ! -d "seeds/$r" ]; then
    echo "fuzz: no reader named $r (the readers: $(ls seeds | tr '\n' ' '))" >&2
    exit 2
  fi
done
jobs=${FUZZ_JOBS:-$(nproc)}
cargo fuzz build -O --debug-assertions readers
binary="target/$(rustc -vV | sed -n 's/^host: //p')/release/readers"

# The committed seeds with their reader's name in front, as the binary reads them.
prefixed=$(mktemp -d)
trap 'rm -rf "$prefixed"' EXIT
for r in "${readers[@]}"; do
  mkdir -p "$prefixed/$r"
  for f in "seeds/$r"/*; do
    { printf '%s\0' "$r"; cat "$f"; } >"$prefixed/$r/$(basename "$f")"
  done
done

# One reader; its summary is printed in one piece when it ends, so parallel
# runs do not interleave their lines.
fuzz_one() {
  local r=$1 status=0 summary
  mkdir -p "corpus/readers/$r" "artifacts/$r"
  "$binary" "corpus/readers/$r" "$prefixed/$r" -artifact_prefix="artifacts/$r/" \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 \
    -max_len=65536 -print_final_stats=1 >"artifacts/$r.log" 2>&1 || status=$?
  summary=$(grep -E "^(Done|stat::peak_rss_mb)|ERROR|SUMMARY|panicked|Test unit written" "artifacts/$r.log" || true)
  if [ "$status" -ne 0 ] || [ -n "$(ls -A "artifacts/$r")" ]; then
    printf '==> fuzz %s for %ss: FAILED\n%s\n' "$r" "$seconds" "$(tail -n 30 "artifacts/$r.log")" >&2
    echo "fuzz $r: failing inputs in fuzz/artifacts/$r (reproduce: $binary fuzz/artifacts/$r/crash-…)" >&2
    return 1
  fi
  printf '==> fuzz %s for %ss\n%s\n' "$r" "$seconds" "$summary"
}

echo "fuzz: ${#readers[@]} readers, ${seconds}s each, $jobs at a time"
failed=0
running=0
for r in "${readers[@]}"; do
  if [ "$running" -ge "$jobs" ]; then
    wait -n || failed=1
    running=$((running - 1))
  fi
  [ "$failed" -eq 0 ] || break
  fuzz_one "$r" &
  running=$((running + 1))
done
while [ "$running" -gt 0 ]; do
  wait -n || failed=1
  running=$((running - 1))
done
if [ "$failed" -ne 0 ]; then
  echo "fuzz: a reader failed (see above)" >&2
  exit 1
fi
echo "fuzz: ${#readers[@]} readers, ${seconds}s each, no failure"
