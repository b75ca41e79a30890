#!/usr/bin/env bash
# Checks that the work tree computes bit for bit what BASE computed: builds
# BASE in a worktree under target/, then runs both binaries on a fixed list
# of `hompm run … --json` cases (every 2D method, the 1D bases, a run that
# stops) and compares their JSON with the wall-clock fields removed.
#
#   scripts/same_output.sh BASE
#   BASE_BINARY=/path/to/hompm scripts/same_output.sh BASE   # BASE built already
#
# Use it with scripts/bench_compare.sh for a change meant to be faster and
# otherwise identical (a speed change that moves a number is a different
# change, and says so). Exit status 1 if any case differs.
set -euo pipefail
base=${1:?usage: scripts/same_output.sh BASE}
root=$(cd "$(dirname "$0")/.." && pwd)
tree="$root/target/same-output-base"
old="$root/target/same-output-target/release/hompm"
if [ -n "${BASE_BINARY:-}" ]; then
  # A release binary of BASE built before (e.g. by a fuzz campaign).
  old=$BASE_BINARY
else
  git -C "$root" worktree remove --force "$tree" 2>/dev/null || true
  git -C "$root" worktree add --detach "$tree" "$base" >/dev/null
  trap 'git -C "$root" worktree remove --force "$tree"' EXIT
  echo "building $base …" >&2
  (cd "$tree" && CARGO_TARGET_DIR="$root/target/same-output-target" cargo build --quiet --release --bin hompm)
fi
echo "building the work tree …" >&2
(cd "$root" && cargo build --quiet --release --bin hompm)
# The work tree's binary is where cargo put it: CARGO_TARGET_DIR if set
# (else a stale binary under target/ would be compared).
target_dir=${CARGO_TARGET_DIR:-$root/target}
case $target_dir in /*) ;; *) target_dir=$root/$target_dir ;; esac
new="$target_dir/release/hompm"

# The JSON of one run without its timing fields (errors compare as text).
digest() {
  "$@" --json 2>&1 | python3 -c '
import json, sys
text = sys.stdin.read()
try:
    d = json.loads(text)
except ValueError:
    print(text); sys.exit()
def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if "seconds" not in k and "elapsed" not in k}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v
print(json.dumps(strip(d), sort_keys=True))' | sha256sum
}

status=0
while read -r args; do
  [ -z "$args" ] && continue
  # shellcheck disable=SC2086
  if [ "$(digest "$old" run $args)" == "$(digest "$new" run $args)" ]; then
    echo "same    $args"
  else
    echo "DIFFERS $args"
    status=1
  fi
done <<'CASES'
aligned-vibration --method mpm --cells 8 --steps 400
aligned-vibration --method bsmpm --cells 16 --steps 1500
aligned-vibration --method bsmpm --degree 3 --cells 8 --steps 200
aligned-vibration --method bsmpm-mls --cells 16 --steps 600
aligned-vibration --method bsmpm-tls --cells 8 --steps 1400
aligned-vibration --method tl-fe --cells 8 --steps 200
vibrating-bar --method mpm --cells 16 --steps 500
vibrating-bar --method bsmpm --cells 16 --steps 500
vibrating-bar --method bsmpm --degree 3 --cells 16 --steps 500
vibrating-bar --method mpm-p2 --cells 16 --steps 500
vibrating-bar --method ddmpm --cells 16 --steps 500
vibrating-bar --method bsmpm --mapping tls --cells 16 --steps 500
vibrating-bar --method bsmpm --mapping cubic-spline --cells 16 --steps 500
column-self-weight --method bsmpm --cells 16 --steps 500
CASES
exit $status
