#!/usr/bin/env bash
# Spatial tiles on the procedural region `alpine-region` (5 m cells, 1 rock per source cell):
# every tile run one after the other with its peak memory (/usr/bin/time -v) and wall time
# (the first writes the tile index, region.index, which the others read),
# and, where the single run fits (SINGLE=1), the single run and the merge of the tiles,
# compared file by file with bench/compare.sh.
#
# Usage: bench/tiles.sh CELLS TILES [WORK_DIR]
#   e.g. SINGLE=1 bench/tiles.sh 10000000 4     (10⁷ cells: the merge equals the single run)
#        bench/tiles.sh 100000000 100           (10⁸ cells: 100 tiles ≤ 1 GB each)
# ROCKFALL names the binary (default: target/release/rockfall of this workspace, built
# first). Each tile's tally is removed once measured unless KEEP=1 (they are large), and
# then no merge is made; with KEEP=1 the tiles are merged by `rockfall merge --stream` (in
# bounded memory, whatever the region's size), and with SINGLE=1 also in memory, and both
# merges compared with the single run.
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
cells=$1 tiles=$2
work=${3:-${TMPDIR:-/tmp}/rockfall-tiles-$cells}
target=${CARGO_TARGET_DIR:-$here/target}
[ -n "${ROCKFALL:-}" ] || (cd "$here" && cargo build --release -q -p rockfall-cli --bin rockfall)
bin=${ROCKFALL:-$target/release/rockfall}
mkdir -p "$work"
cd "$work"
[ -f region/scenario.toml ] || "$bin" site alpine-region --cells "$cells" --out region > /dev/null
peak() { sed -n 's/.*Maximum resident set size (kbytes): //p' "$1"; }
wall() { sed -n 's/.*Elapsed (wall clock) time (h:mm:ss or m:ss): //p' "$1"; }
printf '%-6s %10s %12s %8s %10s %8s\n' tile rocks "cells reached" passes "peak MB" wall
for i in $(seq 1 "$tiles"); do
  /usr/bin/time -v "$bin" run region/scenario.toml --rocks-per-cell 1 --threads 2 \
    --tile "$i/$tiles" --tile-index region.index --out "t$i" > "t$i.log" 2> "t$i.time"
  python3 - "t$i/tile.json" "$i" "$(peak "t$i.time")" "$(wall "t$i.time")" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print(f"{sys.argv[2]:<6} {d['rocks']:>10} {d['cells_reached']:>12} {len(d['passes']):>8} "
      f"{int(sys.argv[3]) / 1024:>10.0f} {sys.argv[4]:>8}")
PY
  [ "${KEEP:-0}" = 1 ] || rm -f "t$i/rockfall.tally"
done
if [ "${KEEP:-0}" = 1 ]; then
  echo "tally files: $(du -cb t*/rockfall.tally | tail -1 | cut -f1) bytes"
  dirs=$(for i in $(seq 1 "$tiles"); do printf 't%s ' "$i"; done)
  # shellcheck disable=SC2086
  /usr/bin/time -v "$bin" merge $dirs --stream --out streamed > streamed.log 2> streamed.time
  echo "streamed merge: peak $(( $(peak streamed.time) / 1024 )) MB, $(wall streamed.time)"
fi
if [ "${SINGLE:-0}" = 1 ] && [ "${KEEP:-0}" = 1 ]; then
  /usr/bin/time -v "$bin" run region/scenario.toml --rocks-per-cell 1 --threads 2 \
    --out single > single.log 2> single.time
  echo "single run: peak $(( $(peak single.time) / 1024 )) MB, $(wall single.time)"
  dirs=$(for i in $(seq 1 "$tiles"); do printf 't%s ' "$i"; done)
  # shellcheck disable=SC2086
  /usr/bin/time -v "$bin" merge $dirs --out merged > merged.log 2> merged.time
  echo "merge: peak $(( $(peak merged.time) / 1024 )) MB, $(wall merged.time)"
  # the tally files differ in their record (the tiles' fingerprint), not in their statistics,
  # and the report in how the input was named (absolute in a merge) and its speed
  if "$here/bench/compare.sh" single merged | grep -v -e 'rockfall.tally' -e 'report.html'; then
    echo "merged tiles differ from the single run"
  else
    echo "merged tiles: identical to the single run (every raster, table and summary.json)"
  fi
  # the streamed merge writes no tally, report, styles or QGIS project
  if "$here/bench/compare.sh" single streamed | grep -v -e 'rockfall.tally' -e 'report' \
    -e '\.qml' -e '\.qgs' -e '\.geojson'; then
    echo "streamed merge differs from the single run"
  else
    echo "streamed merge: identical to the single run (every raster, table and summary.json)"
  fi
fi
