#!/usr/bin/env bash
# Runs the fuzz targets (cargo-fuzz + libFuzzer, on the stable toolchain through
# RUSTC_BOOTSTRAP).   Usage: fuzz/run.sh SECONDS_PER_TARGET [TARGET…]
# Every target runs from fuzz/seeds/TARGET (committed) into fuzz/corpus/TARGET
# (kept between runs, not committed). A crash, an abort, a hang (> 10 s for one
# input), an allocation over 1 GiB or more than 2 GiB resident fails the run;
# libFuzzer leaves the input in fuzz/artifacts/TARGET/. Turn it into a
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
cargo fuzz build -O --debug-assertions
for t in "${targets[@]}"; do
  mkdir -p "corpus/$t" "artifacts/$t"
  echo "==> fuzz $t for ${seconds}s"
  status=0
  cargo fuzz run -O --debug-assertions "$t" "corpus/$t" "seeds/$t" -- \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 \
    -max_len=65536 -print_final_stats=1 >"artifacts/$t.log" 2>&1 || status=$?
  grep -E "^(Done|stat::peak_rss_mb)|ERROR|SUMMARY|panicked|Test unit written" "artifacts/$t.log" || true
  if [ "$status" -ne 0 ] || [ -n "$(ls -A "artifacts/$t")" ]; then
    tail -n 30 "artifacts/$t.log" >&2
    echo "fuzz $t: failing inputs in fuzz/artifacts/$t" >&2
    exit 1
  fi
done
echo "fuzz: ${#targets[@]} targets, ${seconds}s each, no failure"
