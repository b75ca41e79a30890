#!/usr/bin/env bash
# The experiment behind docs/reproduction-notes.md, "2D TLS": BSMPM with
# conservative TLS, BSMPM with MLS and BSMPM on the aligned vibration
# (E = 1e7 Pa, 16 x 16 cells, 9 PPC, 20 000 steps of 1e-5 s) at growing
# amplitudes A. With 9 PPC the outermost particles sit h/6 = 0.0104 m from
# their cell's edge, so below that amplitude the exact motion crosses no
# cell boundary. Prints, per run, where it stopped (or its RMS errors).
# Outside CI: about 10 minutes on two cores.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
bin=./target/release/hompm
cells=${1:-16}
for a in 0.001 0.003 0.005 0.01 0.02 0.05 0.1; do
  for m in bsmpm-tls bsmpm-mls bsmpm; do
    out=$($bin run aligned-vibration --method "$m" --degree 2 --cells "$cells" --ppc 9 \
      --steps 20000 --amplitude "$a" 2>&1 | tail -1 || true)
    case "$out" in
      error:*) echo "A = $a, $m: $(echo "$out" | sed -E 's/.*particle ([0-9]+) at step ([0-9]+).*/stopped at step \2 (particle \1)/')" ;;
      *) echo "A = $a, $m: $(echo "$out" | sed -E 's/.*"rms_displacement":([^,]+).*/reached T, RMS u = \1 m/')" ;;
    esac
  done
done
