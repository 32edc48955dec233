#!/usr/bin/env bash
# Runs the fuzz targets (cargo-fuzz + libFuzzer, on the stable toolchain through
# RUSTC_BOOTSTRAP).   Usage: fuzz/run.sh SECONDS_PER_TARGET [TARGET…]
# Every target runs from fuzz/seeds/TARGET (committed) into fuzz/corpus/TARGET
# (kept between runs, not committed), FUZZ_JOBS targets at a time (default: one
# per core; each libFuzzer process is single-threaded). A crash, an abort, a
# hang (> 10 s for one input), an allocation over 1 GiB or more than 2 GiB
# resident fails the run: no further target starts, the running ones finish,
# and libFuzzer leaves the input in fuzz/artifacts/TARGET/. Turn it into a
# regression test in crates/io/tests/it/malformed.rs (see fuzz/README.md).
set -euo pipefail
cd "$(dirname "$0")"
export RUSTC_BOOTSTRAP=1
seconds=${1:?seconds per target}
shift
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  mapfile -t targets < <(cargo fuzz list)
fi
jobs=${FUZZ_JOBS:-$(nproc)}
cargo fuzz build -O --debug-assertions

# One target; its summary is printed in one piece when it ends, so parallel
# runs do not interleave their lines.
fuzz_one() {
  local t=$1 status=0 summary
  mkdir -p "corpus/$t" "artifacts/$t"
  cargo fuzz run -O --debug-assertions "$t" "corpus/$t" "seeds/$t" -- \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 \
    -max_len=65536 -print_final_stats=1 >"artifacts/$t.log" 2>&1 || status=$?
  summary=$(grep -E "^(Done|stat::peak_rss_mb)|ERROR|SUMMARY|panicked|Test unit written" "artifacts/$t.log" || true)
  if [ "$status" -ne 0 ] || [ -n "$(ls -A "artifacts/$t")" ]; then
    printf '==> fuzz %s for %ss: FAILED\n%s\n' "$t" "$seconds" "$(tail -n 30 "artifacts/$t.log")" >&2
    echo "fuzz $t: failing inputs in fuzz/artifacts/$t" >&2
    return 1
  fi
  printf '==> fuzz %s for %ss\n%s\n' "$t" "$seconds" "$summary"
}

echo "fuzz: ${#targets[@]} targets, ${seconds}s each, $jobs at a time"
failed=0
running=0
for t in "${targets[@]}"; do
  if [ "$running" -ge "$jobs" ]; then
    wait -n || failed=1
    running=$((running - 1))
  fi
  [ "$failed" -eq 0 ] || break
  fuzz_one "$t" &
  running=$((running + 1))
done
while [ "$running" -gt 0 ]; do
  wait -n || failed=1
  running=$((running - 1))
done
if [ "$failed" -ne 0 ]; then
  echo "fuzz: a target failed (see above)" >&2
  exit 1
fi
echo "fuzz: ${#targets[@]} targets, ${seconds}s each, no failure"
