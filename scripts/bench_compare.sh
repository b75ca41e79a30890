#!/usr/bin/env bash
# Benchmarks BASE and HEAD back to back on this machine and prints, per
# case, ns per particle-step (divan's median throughput) and HEAD/BASE.
#
#   scripts/bench_compare.sh BASE [BENCH] [FILTER]
#
# BASE is any commit (e.g. main~3, bae3944); BENCH a divan bench target
# (mpm, mpm2d; default mpm); FILTER divan's substring filter (default: all
# cases of BENCH). BASE is checked out in a worktree under target/, built
# and run first, then HEAD (the work tree as it is); the same machine, one
# after the other, so the ratio is what the change did, not the day. A
# ratio above 1.10 is marked: runs on a shared 2-core machine vary by about
# ±10 % (README, "Speed").
set -euo pipefail
base=${1:?usage: scripts/bench_compare.sh BASE [BENCH] [FILTER]}
bench=${2:-mpm}
filter=${3:-}
root=$(cd "$(dirname "$0")/.." && pwd)
tree="$root/target/bench-base"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

run_bench() { # dir target-dir output
  (cd "$1" && CARGO_TARGET_DIR="$2" cargo bench --quiet --bench "$bench" -- $filter 2>/dev/null) > "$3"
}

# case → ns per particle-step, from divan's tree: a case line, then its
# throughput line whose third column is the median.
parse() {
  # Fields are split at '│'; the throughput fields are fastest, slowest,
  # median, mean, so the median is the third field that holds "item/s"
  # (nested groups prefix their lines with more '│' columns).
  awk -F'│' '
    /item\/s/ && name != "" {
      seen = 0
      for (i = 1; i <= NF; i++) if ($i ~ /item\/s/ && ++seen == 3) {
        split($i, m, " "); v = m[1]; u = m[2]
      }
      f = (u ~ /^G/) ? 1e9 : (u ~ /^M/) ? 1e6 : (u ~ /^K/) ? 1e3 : 1;
      printf "%s %.1f\n", name, 1e9 / (v * f); name = ""; next
    }
    /[├╰]─ / {
      # A case line carries its times; a line without them opens a group
      # (a bench function whose cases are its arguments, as in lean_p1:
      # hompm_step/1024), and a case named without a slash is prefixed
      # with its group.
      line = $0; sub(/.*─ /, "", line); split(line, w, " ");
      if (line ~ /[0-9.]+ (ns|µs|ms|s) /) name = (w[1] ~ /\//) ? w[1] : group "/" w[1];
      else group = w[1]
    }' "$1"
}

git -C "$root" worktree remove --force "$tree" 2>/dev/null || true
git -C "$root" worktree add --detach "$tree" "$base" >/dev/null
echo "benchmarking $base ($(git -C "$tree" rev-parse --short HEAD)) …" >&2
run_bench "$tree" "$root/target/bench-base-target" "$out/base.txt"
echo "benchmarking HEAD ($(git -C "$root" rev-parse --short HEAD), work tree) …" >&2
run_bench "$root" "$root/target" "$out/head.txt"
git -C "$root" worktree remove --force "$tree"

parse "$out/base.txt" | sort > "$out/base.tsv"
parse "$out/head.txt" | sort > "$out/head.tsv"
printf '%-36s %10s %10s %7s\n' "case (ns per particle-step)" "$base" "HEAD" "ratio"
join "$out/base.tsv" "$out/head.tsv" | while read -r name b h; do
  ratio=$(awk -v b="$b" -v h="$h" 'BEGIN { printf "%.2f", h / b }')
  mark=$(awk -v r="$ratio" 'BEGIN { if (r > 1.10) print "  slower"; else if (r < 0.90) print "  faster" }')
  printf '%-36s %10s %10s %7s%s\n' "$name" "$b" "$h" "$ratio" "$mark"
done
