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

# module: files, then the test modules of tests/spec (and the allocation
# binary) that state its equations.
declare -A FILES=(
  [spline]="src/spline/*.rs"
  [quadrature]="src/quadrature.rs"
  [lagrange]="src/lagrange.rs"
  [mass]="src/mass.rs"
  [solve]="src/solve/*.rs"
  [reconstruct]="src/reconstruct/*.rs"
  [mpm]="src/mpm/*.rs src/mpm/mapping/*.rs"
  [mpm2d]="src/mpm2d/*.rs"
  [oracle]="src/oracle/*.rs"
)
declare -A TESTS=(
  [spline]="properties::properties_bspline book::golden_basis"
  [quadrature]="properties::properties_quadrature"
  [lagrange]="properties::properties_lagrange tls::spec_ddmpm"
  [mass]="properties::properties_mass book::golden_book meta::golden_tables book::spec_musl_step"
  [solve]="properties::properties_mass thesis::spec_richardson book::spec_pmultigrid book::golden_book cli::oracle::"
  [reconstruct]="properties::properties_reconstruct tls::golden_tls_example mls::spec_mpm2d allocations"
  [mpm]="book::spec_musl_step tls::spec_ddmpm properties::properties_mpm thesis::golden_thesis tls::golden_tls_conservation properties::stability allocations cli::oracle::"
  [mpm2d]="mls::spec_mpm2d allocations cli::oracle::"
  [oracle]="cli::check_strict cli::oracle cli::cli_fuzz cli::oracle_doc cli::check_claims"
)
# Extra cargo-mutants options, e.g. EXTRA="--shard 1/4" or EXTRA="--re fit";
# OUT names the output directory under target/mutants (default: the module).
read -r -a EXTRA <<< "${EXTRA:-}"
modules=("$@")
[ ${#modules[@]} -eq 0 ] && modules=(spline quadrature lagrange mass solve reconstruct mpm mpm2d oracle)
for m in "${modules[@]}"; do
  args=()
  for f in ${FILES[$m]}; do args+=(--file "$f"); done
  # --cargo-arg applies to the build as well as to the test run: only the
  # spec binary (and the allocation binary) is built for every mutant; the
  # module paths after `-- --` filter the tests it runs ("allocat" selects
  # the allocation binary's tests, whose names all contain it).
  tests=("--cargo-arg=--test=spec")
  filters=()
  for t in ${TESTS[$m]}; do
    if [ "$t" = allocations ]; then tests+=("--cargo-arg=--test=allocations"); filters+=(allocat)
    else filters+=("$t"); fi
  done
  echo "== $m: ${FILES[$m]} against ${TESTS[$m]}"
  dir="target/mutants/${OUT:-$m}"
  mkdir -p "$dir"
  # No debuginfo in the per-mutant test builds: linking is most of their cost.
  PROPTEST_CASES=64 CARGO_PROFILE_TEST_DEBUG=false cargo mutants "${args[@]}" --output "$dir" \
    --timeout 120 --no-shuffle "${tests[@]}" "${EXTRA[@]}" -- -- "${filters[@]}" || true
  out="$dir/mutants.out"
  for k in caught missed unviable timeout; do
    printf '%s %s: %s\n' "$m" "$k" "$(wc -l < "$out/$k.txt" 2>/dev/null || echo 0)"
  done
done
