#!/usr/bin/env bash
# Time-step convergence of the rigid engine on seed 001's forest slope (docs/guide/engines.md, "Time step").
#
# Runs the shape study of `forest-slope-40` (cubic1.2, flat2.2, long2.2) at dt = 0.5, 1 and
# 2 ms with the same seed and rocks, then compares each shape's per-rock run-out, lateral
# end offset and largest recorded kinetic energy between the time steps: means with their
# 95 % intervals and the two-sample Kolmogorov–Smirnov statistic with its 5 % critical value.
#
#   bench/dt-study.sh [OUT] [ROCKS]      (default OUT=dt-study, ROCKS=500)
#
# ROCKFALL=path/to/rockfall runs that binary instead of building this checkout.
set -euo pipefail
out=${1:-dt-study}
rocks=${2:-500}
here=$(cd "$(dirname "$0")/.." && pwd)
if [ -z "${ROCKFALL:-}" ]; then
  cargo build --release -q --manifest-path "$here/Cargo.toml" -p rockfall-cli
fi
bin=${ROCKFALL:-${CARGO_TARGET_DIR:-$here/target}/release/rockfall}
mkdir -p "$out"
"$bin" site forest-slope-40 --out "$out/site" >/dev/null
for dt in 0.0005 0.001 0.002; do
  sed "s/^dt_s = .*/dt_s = $dt/" "$out/site/scenario.toml" >"$out/site/scenario_$dt.toml"
  start=$(date +%s.%N)
  "$bin" shape-study "$out/site/scenario_$dt.toml" --rocks "$rocks" --out "$out/dt_$dt" >/dev/null
  echo "dt $dt s: $(echo "$(date +%s.%N) - $start" | bc) s wall"
done
python3 "$here/bench/dt_compare.py" "$out" 0.0005 0.001 0.002
