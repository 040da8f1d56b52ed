#!/usr/bin/env bash
# Compares two run folders file by file: every file byte for byte with cmp, except
# summary.json (and any other *.json), compared with jq after deleting the timing keys
# (threads, wall_time_s, trajectories_per_s, at any depth), and report.html without the
# rows of those keys and of the command line and the time written. Prints each difference; exits 1
# when there is one.
set -u
a=$1 b=$2 status=0
timing='del(.. | objects | .threads?, .wall_time_s?, .trajectories_per_s?)'
# report.html with the cell after a timing or command header blanked
html() { tr '>' '\n' < "$1" | awk '/^(Threads|threads|Wall time|wall_time_s|Trajectories per second|trajectories_per_s|Command|Written)<\/th$/ {skip=3} {if (skip && --skip == 0 && /<\/td$/) next; print}'; }
while IFS= read -r f; do
  if [ ! -f "$b/$f" ]; then echo "only in $a: $f"; status=1; continue; fi
  case $f in
    *report.html) cmp -s <(html "$a/$f") <(html "$b/$f") || { echo "differs: $f"; status=1; } ;;
    *.json) cmp -s <(jq -S "$timing" "$a/$f") <(jq -S "$timing" "$b/$f") || { echo "differs: $f"; status=1; } ;;
    *) cmp -s "$a/$f" "$b/$f" || { echo "differs: $f"; status=1; } ;;
  esac
done < <(cd "$a" && find . -type f | sort)
while IFS= read -r f; do
  [ -f "$a/$f" ] || { echo "only in $b: $f"; status=1; }
done < <(cd "$b" && find . -type f | sort)
exit $status
