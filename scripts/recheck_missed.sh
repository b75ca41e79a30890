#!/usr/bin/env bash
# Re-runs the mutants that a scripts/mutants.sh run MISSED, against today's
# tests: each diff is applied to a scratch copy of the tree (patch finds the
# hunk even when lines have moved), the module's test targets run, and the
# mutant is reported as now caught, still missed, or no longer applicable.
#
#   scripts/recheck_missed.sh MODULE TEST_MODULE...   (e.g. mls::spec_mpm2d, or allocations)
set -euo pipefail
cd "$(dirname "$0")/.."
module=$1; shift
out="target/mutants/$module/mutants.out"
work=$(mktemp -d /tmp/recheck-XXXX)
git ls-files -z | xargs -0 -I{} cp --parents {} "$work"/
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-/tmp/recheck-target}
export PROPTEST_CASES=64 CARGO_PROFILE_TEST_DEBUG=false
tests=(--test spec); filters=()
for t in "$@"; do
  if [ "$t" = allocations ]; then tests+=(--test allocations); filters+=(allocat); else filters+=("$t"); fi
done
(cd "$work" && cargo test --no-run "${tests[@]}" >/dev/null 2>&1)
python3 - "$out/outcomes.json" <<'PY' > "$work/missed.tsv"
import json, sys
for o in json.load(open(sys.argv[1]))["outcomes"]:
    if o["summary"] == "MissedMutant":
        print(o["diff_path"] + "\t" + o["scenario"]["Mutant"]["name"])
PY
caught=0; missed=0; stale=0
while IFS=$'\t' read -r diff name; do
  if ! (cd "$work" && patch -s -p0 --dry-run < "$OLDPWD/$out/$diff" >/dev/null 2>&1); then
    echo "STALE   $name"; stale=$((stale+1)); continue
  fi
  (cd "$work" && patch -s -p0 < "$OLDPWD/$out/$diff")
  if (cd "$work" && timeout 300 cargo test -q "${tests[@]}" -- "${filters[@]}" >/dev/null 2>&1); then
    echo "MISSED  $name"; missed=$((missed+1))
  else
    echo "CAUGHT  $name"; caught=$((caught+1))
  fi
  (cd "$work" && patch -s -R -p0 < "$OLDPWD/$out/$diff")
done < "$work/missed.tsv"
echo "$module: previously missed, now caught $caught, still missed $missed, no longer applicable $stale"
rm -rf "$work"
