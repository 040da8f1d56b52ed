#!/usr/bin/env bash
# Writing one large synthetic raster through the GeoTIFF writer alone: a dense f32 field, the
# same as f64, dense i32 counts, and sparse f32 and i32 maps like a regional run's results
# (crates/raster/examples/write_raster.rs; cells computed row by row, so the process's peak
# memory is the writer's). Prints the writing time, the file size and the maximum resident
# set size that /usr/bin/time -v reports.
#
# Usage: bench/geotiff.sh [WORK_DIR] [SIZE ...]    (sizes as NCOLSxNROWS; default 4000x4000)
# WRITE_RASTER names the example binary (default: this workspace's, built first).
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
work=${1:-${TMPDIR:-/tmp}/rockfall-geotiff}
shift || true
sizes=${*:-4000x4000}
target=${CARGO_TARGET_DIR:-$here/target}
(cd "$here" && cargo build --release -q -p rockfall-raster --example write_raster)
bin=${WRITE_RASTER:-$target/release/examples/write_raster}
mkdir -p "$work"
printf '%-12s %-12s %10s %14s %10s\n' size raster seconds bytes "peak RSS"
for size in $sizes; do
  ncols=${size%x*} nrows=${size#*x}
  for kind in "f32" "f64" "i32" "f32 sparse" "i32 sparse"; do
    out=$work/$size-${kind// /-}.tif
    # shellcheck disable=SC2086 # kind is two words
    line=$(/usr/bin/time -v "$bin" "$out" "$ncols" "$nrows" $kind 2> "$work/time.txt")
    kb=$(awk -F': ' '/Maximum resident/ {print $2}' "$work/time.txt")
    seconds=$(echo "$line" | sed -E 's/.* in ([0-9.]+) s.*/\1/')
    bytes=$(echo "$line" | sed -E 's/.*, ([0-9]+) bytes/\1/')
    printf '%-12s %-12s %10s %14s %7.1f MB\n' "$size" "$kind" "$seconds" "$bytes" "$(echo "$kb / 1024" | bc -l)"
    rm -f "$out"
  done
done
