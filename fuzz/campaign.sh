#!/usr/bin/env bash
# A fuzz campaign: each target given (default: all) for RUNS executions (default 10^7), from
# and into its corpus, then the corpus minimised (`cargo fuzz cmin`). Prints the executions
# and the run time of each target. A crash stops the campaign and is left in artifacts/TARGET.
# The targets' own stderr is closed (-close_fd_mask=2; libFuzzer still reports on its own):
# the tiff crate prints a debug line for every oversized image, which cut the GeoTIFF target
# to a fraction of its speed.
set -euo pipefail
cd "$(dirname "$0")"
runs="${RUNS:-10000000}"
jobs="${JOBS:-1}"
targets=("$@")
[ "${#targets[@]}" -gt 0 ] || mapfile -t targets < <(cargo +nightly fuzz list)
cargo +nightly fuzz build -O
for t in "${targets[@]}"; do
  mkdir -p "corpus/$t"
  start=$(date +%s)
  if [ "$jobs" -gt 1 ]; then
    # parallel workers share the corpus; each runs runs/jobs executions
    cargo +nightly fuzz run -O "$t" "corpus/$t" -- -runs=$((runs / jobs)) -jobs="$jobs" \
      -workers="$jobs" -timeout=10 -print_final_stats=1 -close_fd_mask=2 >"/tmp/fuzz-$t.log" 2>&1
    cat fuzz-*.log >>"/tmp/fuzz-$t.log" 2>/dev/null || true
    rm -f fuzz-*.log
  else
    cargo +nightly fuzz run -O "$t" "corpus/$t" -- -runs="$runs" -timeout=10 -print_final_stats=1 -close_fd_mask=2 \
      >"/tmp/fuzz-$t.log" 2>&1
  fi
  executed=$(grep -h "stat::number_of_executed_units" "/tmp/fuzz-$t.log" | awk '{s += $2} END {print s}')
  echo "$t: $executed executions in $(($(date +%s) - start)) s, no crash"
  cargo +nightly fuzz cmin -O "$t" "corpus/$t" >/dev/null 2>&1
  echo "$t: corpus $(ls "corpus/$t" | wc -l) files after cmin"
done
