#!/usr/bin/env bash
# Runs every command of the user guide, so that the guide cannot drift from the code.
#
#   bash docs/guide/run-commands.sh [CHAPTER.md ...]
#
# Each chapter runs in a fresh folder of its own, its blocks in order in one bash session
# (a `cd` carries over to the next block), with `rockfall` on PATH and `docs` linked in:
# - ```sh blocks run as written (set -euo pipefail: any failing command fails the chapter);
# - ```python blocks run with $PYTHON (a Python with the `rockfall` package installed); without
#   it they are skipped with a notice, and with CI set that is a failure;
# - text, toml, rust, json and csv blocks are shown only; any other kind is an error (so that a
#   command block cannot go unrun by being tagged `bash`);
# - ```sh,norun blocks are not run here: each line's program must be one that another CI step
#   runs (cargo builds and tests, pip and the wheel, mpirun, a batch scheduler), listed below.
# First it checks the relative links of every Markdown page (check-links.py).
# Environment: ROCKFALL_BIN (default target/release/rockfall), PYTHON, KEEP=1 keeps the folders.
set -euo pipefail
repo="$(cd "$(dirname "$0")/../.." && pwd)"
guide="$repo/docs/guide"
bin="${ROCKFALL_BIN:-$repo/target/release/rockfall}"
[ -x "$bin" ] || { echo "no rockfall binary at $bin (cargo build --release -p rockfall-cli)" >&2; exit 2; }
bin="$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")"

# The programs a `sh,norun` block may use: each is run by another step of .ci/run.
norun_ok='^(cargo|pip|python3 -m venv|\.venv/bin/|build-venv/bin/|maturin|mpirun|sbatch|#|$)'

work="$(mktemp -d)"
trap '[ "${KEEP:-}" = 1 ] || rm -rf "$work"' EXIT
mkdir -p "$work/bin"
ln -s "$bin" "$work/bin/rockfall"

if [ "$#" -gt 0 ]; then
  chapters=("$@")
else
  chapters=()
  for f in "$guide"/*.md; do chapters+=("$(basename "$f")"); done
fi

# Turns a chapter into a bash script on stdout; norun blocks are checked on the way.
extract() {
  awk -v chapter="$1" -v norun_ok="$norun_ok" '
    /^```/ && !inblock {
      info = substr($0, 4); inblock = 1; kind = ""
      if (info == "sh") kind = "sh"
      else if (info == "python") { kind = "py"; print "run_python <<'"'"'PYGUIDE'"'"'" }
      else if (info == "sh,norun") kind = "norun"
      else if (info !~ /^(text|toml|rust|json|csv|)$/) {
        printf "%s:%d: a block of kind `%s`: use sh (run), sh,norun, python, text or toml\n", chapter, NR, info > "/dev/stderr"
        bad = 1
      }
      next
    }
    /^```/ && inblock {
      if (kind == "py") print "PYGUIDE"
      inblock = 0; kind = ""; next
    }
    inblock && kind == "sh" { print; next }
    inblock && kind == "py" { print; next }
    inblock && kind == "norun" {
      line = $0; sub(/^ +/, "", line)
      if (line !~ norun_ok) {
        printf "%s: a sh,norun line runs a program no CI step runs: %s\n", chapter, $0 > "/dev/stderr"
        bad = 1
      }
      next
    }
    END { if (bad) exit 3 }
  ' "$guide/$1"
}

failed=()
python3 "$guide/check-links.py" "$repo" || failed+=("links")
for chapter in "${chapters[@]}"; do
  dir="$work/${chapter%.md}"
  mkdir -p "$dir"
  ln -s "$repo/docs" "$dir/docs"
  if ! extract "$chapter" > "$work/${chapter%.md}.sh"; then
    failed+=("$chapter (a norun line or a block kind)")
    continue
  fi
  if ! grep -qv '^\s*$' "$work/${chapter%.md}.sh"; then
    echo "== $chapter: no commands"
    continue
  fi
  start=$(date +%s)
  echo "== $chapter"
  if (
    cd "$dir"
    export PATH="$work/bin:$PATH"
    run_python() {
      if [ -n "${PYTHON:-}" ]; then
        "$PYTHON" -
      elif [ -n "${CI:-}" ]; then
        echo "a python block and no PYTHON set (CI)" >&2
        return 1
      else
        cat > /dev/null
        echo "notice: python block skipped (set PYTHON to a Python with rockfall installed)"
      fi
    }
    export -f run_python
    bash -euo pipefail "$work/${chapter%.md}.sh"
  ) > "$work/${chapter%.md}.log" 2>&1; then
    echo "   ok in $(( $(date +%s) - start )) s"
  else
    echo "   FAILED after $(( $(date +%s) - start )) s; the last lines of its output:"
    tail -25 "$work/${chapter%.md}.log" | sed 's/^/   | /'
    failed+=("$chapter")
  fi
done

if [ "${#failed[@]}" -gt 0 ]; then
  echo "guide commands failed in: ${failed[*]}" >&2
  exit 1
fi
echo "every command of the guide ran"
