#!/usr/bin/env bash
# Runs the reference runs with ROCKFALL (default: the release binary of the workspace) into
# OUT_PREFIX-{s2,demo,asc} and compares each with the folder of the same name under
# BASE_PREFIX (made the same way by an earlier binary) through bench/compare.sh.
# Usage: bench/same-outputs.sh BASE_PREFIX OUT_PREFIX   (e.g. /tmp/base /tmp/new)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
bin=${ROCKFALL:-$here/../target/release/rockfall}
base=$1 out=$2 site=${TMPDIR:-/tmp}/rockfall-same-outputs-site2 status=0
rm -rf "$site" "$out-s2" "$out-demo" "$out-asc"
"$bin" site vaujany-site2 --out "$site" > /dev/null
"$bin" run "$site/scenario.toml" --out "$out-s2" --rocks-per-cell 2000 --threads 2 > /dev/null
"$bin" demo --out "$out-demo" > /dev/null
"$bin" run "$site" --out "$out-asc" --rocks-per-cell 500 --ascii --threads 2 > /dev/null
for run in s2 demo asc; do
  "$here/compare.sh" "$base-$run" "$out-$run" && echo "$run: identical" || status=1
done
exit $status
