#!/usr/bin/env bash
# Runs the thesis author's 1D B-spline MPM code (Tielen 2016, Matlab) under
# GNU Octave on the thesis bar (Table 4.1) and checks its particles with
# `hompm check` (issue #24; docs/oracle.md). Outside CI: it needs Octave
# (Debian's octave-cli) and a checkout of the author's repository, whose
# path is the first argument. It fetches nothing and copies nothing of that
# code: a driver written here calls its MPM_1D_B_spline function and writes
# the particles as CSV into a temporary directory.
#
#   scripts/author_code_check.sh /path/to/BSpline_MPM_1D [cells] [ppc] [steps]
#
# Cases: P1 (degree 1) and quadratic B-splines with the direct mapping and a
# lumped mass, and spline-based MPM (cubic splines, Richardson); each with
# the small- and the large-strain update (the code's flag.deformation).
set -euo pipefail
repo=$(cd "${1:?usage: author_code_check.sh CHECKOUT [cells] [ppc] [steps]}" && pwd)
cells=${2:-16}
ppc=${3:-4}
steps=${4:-1999}
root=$(cd "$(dirname "$0")/.." && pwd)
hompm="$root/target/release/hompm"
[ -x "$hompm" ] || (cd "$root" && cargo build --release --quiet)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$(dirname "$0")/author_code_grid.m" "$work/"

# The Octave driver: parameters come from the environment.
cat > "$work/driver.m" <<'OCTAVE'
addpath(getenv('REPO'));
num = @(name) str2double(getenv(name));
constant = struct('density',num('RHO'),'E',num('E'),'g',0,'load',0,'height',num('L'),'alpha',0,'v_0',num('V0'));
flag = struct('both_ends_fixed',1,'volume_update',1,'lumped',1,'change_glob_pos',1, ...
  'change_loc_pos',1,'lagranian',0,'momentum',1,'deformation',num('DEFORMATION'),'num_int',0, ...
  'dynamic',0,'splines',num('SPLINES'),'ULFEM',0);
deg = num('DEG'); n_e = num('CELLS'); ppc = num('PPC'); n_steps = num('STEPS'); dt = num('DT');
author_code_grid;  % scripts/author_code_grid.m
[u_n, v_p, v_n, m_p, u_p, a1, a2, a3, a4, s_p] = MPM_1D_B_spline(constant, flag, pos, pos_loc, ...
  n_e, h, ppc, dt, nt, nt*dt, z, z, z, z, weight, Xi, deg, @(x) 0*x, ...
  @(x) constant.v_0*sin(pi*x/constant.height), @(x) 0*x, n_p);
f = fopen(getenv('OUT'), 'w');
fprintf(f, 'x0,u,v,stress\n');
fprintf(f, '%.17g,%.17g,%.17g,%.17g\n', [pos, u_p(:, end), v_p(:, end), s_p(:, end)].');
fclose(f);
OCTAVE

run_case() { # degree splines deformation label hompm-options…
  local deg=$1 splines=$2 deformation=$3 label=$4
  shift 4
  local start=$(date +%s.%N)
  (cd "$work" && REPO="$repo" DEG=$deg SPLINES=$splines DEFORMATION=$deformation \
    CELLS=$cells PPC=$ppc STEPS=$steps OUT="$work/theirs.csv" \
    RHO=1 E=100 L=25 V0=0.1 DT=1e-5 \
    octave-cli --no-gui --quiet driver.m > octave.log 2>&1)
  local octave_s=$(echo "$(date +%s.%N) - $start" | bc)
  echo "== $label (Octave ${octave_s}s)"
  local args=(vibrating-bar --params thesis-table-4.1 --cells "$cells" --ppc "$ppc" --dt 1e-5 --steps "$steps" "$@")
  start=$(date +%s.%N)
  "$hompm" check "${args[@]}" --input "$work/theirs.csv" || true
  echo "(check $(echo "$(date +%s.%N) - $start" | bc)s)"
}

for deformation in 0 1; do
  if [ "$deformation" = 1 ]; then c=large; else c=small; fi
  run_case 1 0 $deformation "P1 (B-spline degree 1), direct, lumped, $c strain" \
    --method mpm --constitutive $c
  run_case 2 0 $deformation "quadratic B-splines, direct, lumped, $c strain" \
    --method bsmpm --degree 2 --constitutive $c
  run_case 2 1 $deformation "spline-based MPM (Richardson, residual over ‖v‖), $c strain" \
    --method bsmpm --degree 2 --mapping cubic-spline --mass richardson --residual solution --constitutive $c
  run_case 2 1 $deformation "spline-based MPM against hompm's default rule (residual over ‖P‖), $c strain" \
    --method bsmpm --degree 2 --mapping cubic-spline --mass richardson --constitutive $c
done

# Book §4.5's "more than 450" grid crossings: the author's code prints a
# line for every element border a particle crosses. Its count on the
# book's large-deformation bar as stated (book Table 4.1 with v0 = 0.8,
# large strain, 20 elements × 8 PPC, Δt = 1e-5 s, 0.1 s), P1 = degree 1:
(cd "$work" && REPO="$repo" DEG=1 SPLINES=0 DEFORMATION=1 CELLS=20 PPC=8 STEPS=10000 \
  OUT="$work/large.csv" RHO=2000 E=7e6 L=1 V0=0.8 DT=1e-5 \
  octave-cli --no-gui --quiet driver.m > crossings.log 2>&1) || true
echo "== book §4.5 large-deformation bar, P1, 20 × 8, 10000 steps: the author's code counts" \
  "$(grep -o 'crossed lower border\|crossed upper border' "$work/crossings.log" | wc -l) grid crossings;" \
  "hompm: $("$hompm" run vibrating-bar --params book-table-4.1-large --method mpm --cells 20 --ppc 8 \
    --dt 1e-5 --steps 10000 --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["diagnostics"]["grid_crossings"])')"
