#!/usr/bin/env bash
# Lumped throughput of two binaries side by side on vaujany-site2 with its forest:
#   bench/throughput.sh OLD_BINARY NEW_BINARY [REPS] [THREADS]
# runs `rockfall run site2/scenario.toml --rocks-per-cell 200000 --threads THREADS`
# alternately with each binary REPS times (default 3, 2 threads) and prints trajectories/s
# and events/s of every run, then compares the two last run folders with bench/compare.sh
# (every output byte for byte, timing keys aside). With IR=1 it also counts the
# instructions each binary executes inside the engine for 5 000 rocks on one thread
# (valgrind's callgrind, from the rayon workers on: noise-free, unlike the wall time).
# Work files go to $WORK (default /tmp/rockfall-throughput).
set -eu
old=$(realpath "$1") new=$(realpath "$2") reps=${3:-3} threads=${4:-2}
here=$(cd "$(dirname "$0")" && pwd)
work=${WORK:-/tmp/rockfall-throughput}
mkdir -p "$work" && cd "$work"
[ -f site2/scenario.toml ] || "$new" site vaujany-site2 --out site2 > /dev/null
for k in $(seq 1 "$reps"); do
  for b in old new; do
    bin=$old; [ $b = new ] && bin=$new
    line=$("$bin" run site2/scenario.toml --rocks-per-cell 200000 --threads "$threads" --out "run_$b" | grep "trajectories/s")
    echo "$k $b:$line"
  done
done
"$here/compare.sh" run_old run_new && echo "outputs identical"
if [ "${IR:-0}" = 1 ]; then
  for b in old new; do
    bin=$old; [ $b = new ] && bin=$new
    valgrind --tool=callgrind --toggle-collect='rayon_core::registry::WorkerThread::wait_until_cold' \
      --callgrind-out-file="cg_$b.out" "$bin" run site2/scenario.toml --rocks-per-cell 5000 \
      --threads 1 --out "ir_$b" 2>&1 | awk -v b=$b '/refs/ {gsub(",", "", $4); printf "%s: %.0f M instructions in the workers\n", b, $4 / 1e6}'
  done
fi
