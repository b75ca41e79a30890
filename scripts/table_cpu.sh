#!/usr/bin/env bash
# The processor time (user + system) of every registered table, each run
# alone by `hompm table ID`, longest first: where `hompm reproduce` spends
# its CPU (issue #39; tables::TABLE_CPU_SECONDS orders the tables by it).
# Processor time, not wall time, so that a shared machine still gives
# usable numbers (a loaded machine inflates them by a few per cent).
#
#   scripts/table_cpu.sh [path/to/hompm] [ID …]
#
# Default binary: target/release/hompm (CARGO_TARGET_DIR if set); default
# ids: all of `hompm table --list`. Needs GNU time (/usr/bin/time).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${1:-${CARGO_TARGET_DIR:-$root/target}/release/hompm}
shift || true
ids=("$@")
if [ ${#ids[@]} -eq 0 ]; then
  mapfile -t ids < <("$bin" table --list | awk '{print $1}')
fi
out=$(mktemp)
trap 'rm -f "$out"' EXIT
for id in "${ids[@]}"; do
  /usr/bin/time -f "%U %S %e" -o "$out" "$bin" table "$id" >/dev/null
  awk -v id="$id" '{printf "%-24s %8.2f s CPU %8.2f s wall\n", id, $1 + $2, $3}' "$out"
done | sort -k2 -n -r
