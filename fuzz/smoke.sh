#!/usr/bin/env bash
# Fuzz smoke: every target for SECONDS seconds (default 5) from its corpus, failing on the
# first crash. Needs a nightly toolchain and cargo-fuzz (`cargo install cargo-fuzz`).
# Long campaigns: `cargo +nightly fuzz run -O TARGET corpus/TARGET -- -runs=10000000`.
set -euo pipefail
cd "$(dirname "$0")"
seconds="${1:-5}"
targets=$(cargo +nightly fuzz list)
cargo +nightly fuzz build -O
for t in $targets; do
  mkdir -p "corpus/$t"
  # a copy of the corpus, so that a smoke run never grows the committed one
  work=$(mktemp -d)
  cp -r "corpus/$t/." "$work/"
  echo "== fuzz $t (${seconds} s)"
  log="$work.log"
  status=0
  cargo +nightly fuzz run -O "$t" "$work" -- -max_total_time="$seconds" -timeout=10 -print_final_stats=1 \
    >"$log" 2>&1 || status=$?
  grep -E "^(Done|stat::number_of_executed_units)" "$log" || true
  if [ "$status" -ne 0 ]; then tail -40 "$log"; fi
  rm -f "$log"
  rm -rf "$work"
  if [ "$status" -ne 0 ]; then
    echo "fuzz target $t failed: see the crash above and fuzz/artifacts/$t" >&2
    exit 1
  fi
done
