#!/usr/bin/env bash
# Mutation testing of the modules that state equations (issue #12), outside
# CI: cargo-mutants changes one operator, constant or return value at a time
# and runs the test targets that state that module's equations; a mutant the
# tests do not catch is "missed". Needs `cargo install cargo-mutants`.
#
#   scripts/mutants.sh [MODULE ...]     # default: every module below
#
# Results go to target/mutants/<module>/mutants.out (caught.txt, missed.txt,
# unviable.txt, timeout.txt); docs/mutation-testing.md records the counts.
set -euo pipefail
cd "$(dirname "$0")/.."

# module: files, then the test targets that state its equations.
declare -A FILES=(
  [spline]="src/spline/*.rs"
  [quadrature]="src/quadrature.rs"
  [lagrange]="src/lagrange.rs"
  [mass]="src/mass.rs"
  [solve]="src/solve/*.rs"
  [reconstruct]="src/reconstruct/*.rs"
  [mpm]="src/mpm/*.rs"
  [mpm2d]="src/mpm2d/*.rs"
)
declare -A TESTS=(
  [spline]="properties_bspline golden_basis"
  [quadrature]="properties_quadrature"
  [lagrange]="properties_lagrange spec_ddmpm"
  [mass]="properties_mass golden_book golden_tables spec_musl_step"
  [solve]="properties_mass spec_richardson spec_pmultigrid golden_book oracle"
  [reconstruct]="properties_reconstruct golden_tls_example spec_mpm2d allocations"
  [mpm]="spec_musl_step spec_ddmpm properties_mpm golden_thesis golden_tls_conservation stability allocations oracle"
  [mpm2d]="spec_mpm2d allocations oracle"
)
# Extra cargo-mutants options, e.g. EXTRA="--shard 1/4" or EXTRA="--re fit";
# OUT names the output directory under target/mutants (default: the module).
read -r -a EXTRA <<< "${EXTRA:-}"
modules=("$@")
[ ${#modules[@]} -eq 0 ] && modules=(spline quadrature lagrange mass solve reconstruct mpm mpm2d)
for m in "${modules[@]}"; do
  args=()
  for f in ${FILES[$m]}; do args+=(--file "$f"); done
  # --cargo-arg applies to the build as well as to the test run: without it,
  # cargo-mutants builds all 33 test targets for every mutant.
  tests=()
  for t in ${TESTS[$m]}; do tests+=("--cargo-arg=--test=$t"); done
  echo "== $m: ${FILES[$m]} against ${TESTS[$m]}"
  dir="target/mutants/${OUT:-$m}"
  mkdir -p "$dir"
  # No debuginfo in the per-mutant test builds: linking is most of their cost.
  PROPTEST_CASES=64 CARGO_PROFILE_TEST_DEBUG=false cargo mutants "${args[@]}" --output "$dir" \
    --timeout 120 --no-shuffle "${tests[@]}" "${EXTRA[@]}" || true
  out="$dir/mutants.out"
  for k in caught missed unviable timeout; do
    printf '%s %s: %s\n' "$m" "$k" "$(wc -l < "$out/$k.txt" 2>/dev/null || echo 0)"
  done
done
