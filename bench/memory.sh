#!/usr/bin/env bash
# Peak memory of `rockfall run` on the big synthetic sites of the memory issue: 4 000 × 4 000
# and 10 000 × 10 000 cells of 2 m (1.6·10⁷ and 10⁸ cells), a slope easing into a plain, two
# release points × 1 000 rocks that reach a small part of the grid, constant surface
# parameters (crates/raster/examples/big_site.rs). Prints the maximum resident set size that
# /usr/bin/time -v reports, and the DEM's own size in memory (f64 + validity byte per cell).
#
# Usage: bench/memory.sh [WORK_DIR] [SIZE ...]    (sizes as NCOLSxNROWS; default both)
# ROCKFALL names the binary (default: target/release/rockfall of this workspace, built first).
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
work=${1:-${TMPDIR:-/tmp}/rockfall-memory}
shift || true
sizes=${*:-4000x4000 10000x10000}
target=${CARGO_TARGET_DIR:-$here/target}
(cd "$here" && cargo build --release -q -p rockfall-cli --bin rockfall -p rockfall-raster --example big_site)
bin=${ROCKFALL:-$target/release/rockfall}
mkdir -p "$work"
printf '%-12s %12s %14s %12s %10s\n' cells grid "DEM (f64+mask)" "peak RSS" wall
for size in $sizes; do
  ncols=${size%x*} nrows=${size#*x}
  site=$work/site-$size
  [ -f "$site/scenario.toml" ] || "$target/release/examples/big_site" "$site" "$ncols" "$nrows" > /dev/null
  rm -rf "$work/run-$size"
  /usr/bin/time -v "$bin" run "$site/scenario.toml" --out "$work/run-$size" --threads 2 \
    > "$work/run-$size.log" 2> "$work/run-$size.time"
  kb=$(awk -F': ' '/Maximum resident/ {print $2}' "$work/run-$size.time")
  wall=$(awk -F': ' '/Elapsed/ {print $2}' "$work/run-$size.time")
  cells=$((ncols * nrows))
  printf '%-12s %12s %11.2f GB %9.2f GB %10s\n' "$cells" "$size" \
    "$(echo "$cells * 9 / 10^9" | bc -l)" "$(echo "$kb * 1024 / 10^9" | bc -l)" "$wall"
done
