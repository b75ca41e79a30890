#!/usr/bin/env bash
# scripts/karamelo_check.sh CHECKOUT [OUTDIR]
#
# Runs Karamelo (github.com/adevaucorbeil/karamelo, the C++ MPM code; GPL,
# not vendored here) on hompm's setups and leaves its particle dumps in
# OUTDIR (default /tmp/karamelo-out), then checks each final dump with one
# `hompm check` line under the conventions that match the case (issue #36;
# docs/oracle.md, "Recipes by code"). Set NO_CHECK=1 to only run Karamelo.
#
#   CHECKOUT  a Karamelo source tree (tested at commit 08e444db1da9, 2025-04-01)
#   OUTDIR    one folder per case, each with final/ (input.mpm, the dump of
#             the last step, stdout) and first3/ (a run of 3 steps with a
#             dump after every step); OUTDIR/timings.tsv has the wall times
#             (a rerun appends), OUTDIR/edits.diff the edits as a git diff.
#             The patched, built copy is kept; its path is printed.
#
# The checkout is copied to a temporary folder, which gets five small edits
# (idempotent sed one-liners, each checked), then built with cmake and
# `make -j1` (about 2.5 minutes on one core). Build deps (Debian): cmake,
# g++, make, libeigen3-dev, libopenmpi-dev, openmpi-bin, zlib1g-dev.
#
# The edits:
#  (a) src/universe.cpp: 1D refuses to start on any number of ranks ("New
#      partitioning not supported for dimensions 1 yet!"); raise it only
#      when nprocs > 1 (one rank needs no send/receive pattern).
#  (b) src/solid.cpp, Solid::populate: in 1D the N particles of a cell all
#      get the same x (the sub-cell offsets along x come from the loop index
#      i, which is 0 for the first N of the N^3 offsets) and a y of
#      (j + 0.5)h/N, which no 1D region contains (y must be 0), so no
#      particle is created at all. In 1D take the x offset from j and set
#      y = 0: particle k of a cell is then at cell_start + (k + 0.5) h/N,
#      hompm's layout. (Only the N >= 4 branch is changed: N = 2 and N = 3 in 1D keep
#      Karamelo's coincident particles.)
#  (c) src/dump_particle.cpp: dumps are written with the stream's default 6
#      significant digits; set precision(17).
#  (d) src/input.cpp, Input::parsev: every number of an input expression is
#      read by std::stof (float32: 0.1 -> 0.100000001490116); use std::stod.
#  (e) src/var.cpp, to_string_with_precision: a constant inside an
#      expression that depends on x, y, x0, y0 or time is kept as text
#      printed with "%.15f" and re-read at each evaluation, so a constant
#      below 1 loses digits (0.6283185307179586 -> 0.628318530717959) and
#      one of 1e15 or more overflows the 30-character buffer; print "%.17g",
#      which round-trips every double between 1e-5 and 1e17.
#
# Cases (all on one rank, ulmpm, set_dt; P1 "linear" shape functions
# unless the name says bspline):
#   bar16-musl-flip1, bar16-usl-flip1, bar16-usf-flip1, bar16-musl-flip0.99:
#       the thesis bar (Table 4.1: L = 25, E = 100, rho = 1, v0 = 0.1,
#       v(x,0) = v0 sin(pi x/L), both end nodes fixed), 16 cells, 4 particles
#       per cell, dt = 1e-5, 1999 steps, linear elastic with nu = 0
#       (sigma += E d_eps in 1D since 2G = E and lambda = 0).
#   bar4096-musl-flip1, bar4096-usl-flip1, bar4096-usf-flip1,
#   bar4096-musl-flip0.99: the same four on 4096 cells (BAR4096_STEPS
#       steps, default 1999).
#   bar16-bspline2, bar16-bspline3: the MUSL, FLIP 1 bar with Karamelo's
#       quadratic-spline and cubic-spline shape functions (its
#       boundary-modified uniform B-splines), checked with
#       --method bsmpm --degree 2|3 --knots natural.
#   bar4096-bspline2, bar4096-bspline3 (only when CASES names them): the
#       same on 4096 cells. The cubic one differs in stress by 1.1e-12
#       absolute, Karamelo's rounding (docs/oracle.md, "Recipes by code"),
#       so the script then exits 1.
#   av8-musl-flip1: hompm's aligned vibration (neo-Hookean, E = 1e7,
#       nu = 0.3, rho0 = 1000, A = 0.1, L = 1), 8 x 8 cells, 2 x 2 particles
#       per cell, dt = 1e-5, 1000 steps, the manufactured body force applied
#       the Karamelo way (fix body_force: m_i b(X_i, t) at the nodes, X_i the node's coordinate,
#       t the time at the start of the step),
#       normal velocity 0 on the walls.
#
# Environment: KARAMELO_WORKDIR=DIR reuses (or creates) DIR as the patched
# copy instead of a fresh temporary folder (the edits are idempotent and make
# rebuilds only what changed); CASES="name ..." runs only those cases;
# HOMPM=PATH checks with that hompm binary (default: this tree's
# target/release/hompm, built with cargo if missing).
set -euo pipefail

if [ $# -lt 1 ] || [ ! -d "$1/src" ]; then
    echo "usage: $0 KARAMELO_CHECKOUT [OUTDIR]" >&2
    exit 2
fi
checkout=$(cd "$1" && pwd)
out=${2:-/tmp/karamelo-out}
mkdir -p "$out"
out=$(cd "$out" && pwd)

if [ -n "${KARAMELO_WORKDIR:-}" ]; then
    work=$KARAMELO_WORKDIR
    mkdir -p "$work"
else
    work=$(mktemp -d /tmp/karamelo-work.XXXXXX)
fi
if [ ! -f "$work/src/solid.cpp" ]; then
    cp -a "$checkout/." "$work/"
    rm -rf "$work/build"
fi
echo "work tree: $work" >&2

# ---- the edits ----------------------------------------------------------
src=$work/src
# (a)
sed -i 's/^\(\s*if (domain->dimension == 1\)) {$/\1 \&\& nprocs > 1) {/' "$src/universe.cpp"
# (b)
sed -i 's/intpoints\.push_back((i + 0\.5) \* d - 0\.5);/intpoints.push_back(((domain->dimension == 1 ? j : i) + 0.5) * d - 0.5);/' "$src/solid.cpp"
sed -i 's/^\(\s*\)\(boundlo\[1\] + delta\*(noffsetlo\[1\] + j + 0\.5 + intpoints\[3\*ip+1\]);\)$/\1(dim == 1) ? 0.0 : \2/' "$src/solid.cpp"
# (c)
sed -i 's/^\(\s*ofstream dumpstream(fdump, ios_base::out);\)$/\1 dumpstream.precision(17);/' "$src/dump_particle.cpp"
# (d)
sed -i 's/stof(number)/stod(number)/g' "$src/input.cpp"
# (e)
sed -i 's/"%\.15f", a_value/"%.17g", a_value/' "$src/var.cpp"

check() { # file, fixed string that must now be there
    grep -qF -- "$2" "$src/$1" || { echo "edit not applied in src/$1: $2" >&2; exit 1; }
}
check universe.cpp 'if (domain->dimension == 1 && nprocs > 1) {'
check solid.cpp 'intpoints.push_back(((domain->dimension == 1 ? j : i) + 0.5) * d - 0.5);'
check solid.cpp '(dim == 1) ? 0.0 : boundlo[1] + delta*(noffsetlo[1] + j + 0.5 + intpoints[3*ip+1]);'
check dump_particle.cpp 'ofstream dumpstream(fdump, ios_base::out); dumpstream.precision(17);'
check input.cpp 'values.push(Var (stod(number)));'
check input.cpp 'Var result((-1)*stod(number));'
check var.cpp '"%.17g", a_value'
if grep -q 'stof(number)' "$src/input.cpp"; then echo "stof left in src/input.cpp" >&2; exit 1; fi
git -C "$work" diff -- src > "$out/edits.diff" 2>/dev/null || true

# ---- build --------------------------------------------------------------
mkdir -p "$work/build"
(
    cd "$work/build"
    [ -f Makefile ] || cmake -DCMAKE_BUILD_TYPE=release .. > cmake.log 2>&1 || { cat cmake.log >&2; exit 1; }
    make -j1 > make.log 2>&1 || { tail -50 make.log >&2; exit 1; }
)
bin=$work/build/karamelo
grep -E '^CXX_FLAGS' "$work/build/CMakeFiles/karamelo.dir/flags.make" > "$out/build-flags.txt" || true
git -C "$checkout" rev-parse HEAD > "$out/karamelo-commit.txt" 2>/dev/null || echo unknown > "$out/karamelo-commit.txt"

# ---- input files --------------------------------------------------------
# Numbers are written so that the parser reads them exactly: no "1e-5"
# (Karamelo reads "aeb" as a*pow(10,b)); dt = 1/100000 is one correctly
# rounded division.

# bar_input SCHEME FLIP CELLS STEPS DUMP_EVERY [SHAPE, default linear]
bar_input() {
    cat <<EOF
# Thesis Table 4.1 vibrating bar, hompm's layout (written by scripts/karamelo_check.sh)
E = 100
nu = 0
rho = 1
L = 25
v0 = 1/10
N = $3
h = L/N
alpha = $2
method(ulmpm, FLIP, ${6:-linear}, alpha)
scheme($1)
dimension(1, 0, L, h)
region(box, block, 0, L)
material(mat1, linear, rho, E, nu)
solid(solid1, region, box, 4, mat1, h, 0)
region(rL, block, INF, h/4)
region(rR, block, L-h/4, INF)
group(gL, nodes, region, rL, solid, solid1)
group(gR, nodes, region, rR, solid, solid1)
fix(fL, velocity_nodes, gL, 0)
fix(fR, velocity_nodes, gR, 0)
fix(vinit, initial_velocity_particles, all, v0*sin(PI*x/L), NULL, NULL)
dump(dp, all, particle, $5, dump_p.*.LAMMPS, x0, x, vx, s11, e11, volume, mass)
set_dt(1/100000)
set_output($5)
run($4)
EOF
}

# av_input STEPS DUMP_EVERY
av_input() {
    cat <<EOF
# hompm's aligned vibration (MLS paper Eqs. 38-42, body force with pi^2),
# Karamelo's nodal body force (written by scripts/karamelo_check.sh)
E = 10000000
nu = 3/10
rho = 1000
A = 1/10
L = 1
N = 8
h = L/N
mu = E/(2*(1+nu))
lambda = E*nu/((1+nu)*(1-2*nu))
c = sqrt(E/rho)
k = 2*PI/L
method(ulmpm, FLIP, linear, 1)
scheme(musl)
dimension(2, 0, L, 0, L, h)
region(box, block, 0, L, 0, L)
material(mat1, neo-hookean, rho, E, nu)
solid(solid1, region, box, 2, mat1, h, 0)
region(rX0, block, INF, h/4, INF, INF)
region(rX1, block, L-h/4, INF, INF, INF)
region(rY0, block, INF, INF, INF, h/4)
region(rY1, block, INF, INF, L-h/4, INF)
group(gX0, nodes, region, rX0, solid, solid1)
group(gX1, nodes, region, rX1, solid, solid1)
group(gY0, nodes, region, rY0, solid, solid1)
group(gY1, nodes, region, rY1, solid, solid1)
fix(fX0, velocity_nodes, gX0, 0, NULL)
fix(fX1, velocity_nodes, gX1, 0, NULL)
fix(fY0, velocity_nodes, gY0, NULL, 0)
fix(fY1, velocity_nodes, gY1, NULL, 0)
va = A*c*PI/L
fix(vinit, initial_velocity_particles, all, va*sin(k*x), va*sin(k*y)*cos(PI), NULL)
s0 = sin(c*PI*time/L)
s1 = sin(c*PI*time/L+PI)
Fxx = 1+A*k*cos(k*x0)*s0
Fyy = 1+A*k*cos(k*y0)*s1
lnJ = log(Fxx*Fyy)
bx = PI*PI/(L*L)*A*sin(k*x0)*s0*(4*mu/rho-c*c-4*(lambda*(lnJ-1)-mu)/(rho*Fxx*Fxx))
by = PI*PI/(L*L)*A*sin(k*y0)*s1*(4*mu/rho-c*c-4*(lambda*(lnJ-1)-mu)/(rho*Fyy*Fyy))
fix(fbody, body_force, all, bx, by)
dump(dp, all, particle, $2, dump_p.*.LAMMPS, x0, y0, x, y, vx, vy, s11, s22, s33, s12, volume, mass)
set_dt(1/100000)
set_output($2)
run($1)
EOF
}

# ---- cases ----------------------------------------------------------------
steps4096=${BAR4096_STEPS:-1999}
all_cases="bar16-musl-flip1 bar16-usl-flip1 bar16-usf-flip1 bar16-musl-flip0.99 bar4096-musl-flip1 bar4096-usl-flip1 bar4096-usf-flip1 bar4096-musl-flip0.99 av8-musl-flip1 bar16-bspline2 bar16-bspline3"
cases=${CASES:-$all_cases}

input_of() { # case, steps, dump_every
    case $1 in
        bar16-musl-flip1) bar_input musl 1 16 "$2" "$3" ;;
        bar16-usl-flip1) bar_input usl 1 16 "$2" "$3" ;;
        bar16-usf-flip1) bar_input usf 1 16 "$2" "$3" ;;
        bar16-musl-flip0.99) bar_input musl 99/100 16 "$2" "$3" ;;
        bar4096-musl-flip1) bar_input musl 1 4096 "$2" "$3" ;;
        bar4096-usl-flip1) bar_input usl 1 4096 "$2" "$3" ;;
        bar4096-usf-flip1) bar_input usf 1 4096 "$2" "$3" ;;
        bar4096-musl-flip0.99) bar_input musl 99/100 4096 "$2" "$3" ;;
        bar16-bspline2) bar_input musl 1 16 "$2" "$3" quadratic-spline ;;
        bar16-bspline3) bar_input musl 1 16 "$2" "$3" cubic-spline ;;
        bar4096-bspline2) bar_input musl 1 4096 "$2" "$3" quadratic-spline ;;
        bar4096-bspline3) bar_input musl 1 4096 "$2" "$3" cubic-spline ;;
        av8-musl-flip1) av_input "$2" "$3" ;;
        *) echo "unknown case $1" >&2; exit 2 ;;
    esac
}
steps_of() {
    case $1 in
        bar4096-*) echo "$steps4096" ;;
        av8-*) echo 1000 ;;
        *) echo 1999 ;;
    esac
}

run_one() { # dir, label
    local dir=$1 t0 t1
    cd "$dir"
    rm -f dump_p.*.LAMMPS log.mpm
    t0=$(date +%s.%N)
    "$bin" -i input.mpm > stdout.txt 2>&1 || { tail -20 stdout.txt >&2; echo "Karamelo failed in $dir" >&2; exit 1; }
    t1=$(date +%s.%N)
    awk -v a="$t0" -v b="$t1" -v c="$2" -v r="$(basename "$dir")" 'BEGIN { printf "%s\t%s\t%.3f\n", c, r, b - a }' >> "$out/timings.tsv"
    cd - > /dev/null
}

[ -f "$out/timings.tsv" ] || printf 'case\trun\tseconds\n' > "$out/timings.tsv"
for c in $cases; do
    n=$(steps_of "$c")
    mkdir -p "$out/$c/final" "$out/$c/first3"
    input_of "$c" "$n" "$n" > "$out/$c/final/input.mpm"
    input_of "$c" 3 1 > "$out/$c/first3/input.mpm"
    echo "$c: $n steps" >&2
    run_one "$out/$c/final" "$c"
    run_one "$out/$c/first3" "$c"
    ls "$out/$c/final/dump_p.$n.LAMMPS" > /dev/null
done
echo "dumps in $out" >&2

# ---- hompm check, one line per case -----------------------------------------
[ -n "${NO_CHECK:-}" ] && exit 0
root=$(cd "$(dirname "$0")/.." && pwd)
if [ -n "${HOMPM:-}" ]; then
    hompm=$HOMPM
    [ -x "$hompm" ] || { echo "HOMPM=$hompm is not an executable" >&2; exit 2; }
else
    hompm="$root/target/release/hompm"
    [ -x "$hompm" ] || (cd "$root" && cargo build --release --quiet)
fi
bar_columns="v=vx,stress=s11"
av_columns="x0_x=x0,x0_y=y0,x_x=x,x_y=y,v_x=vx,v_y=vy,stress_xx=s11,stress_yy=s22,stress_xy=s12"
conventions_of() {
    case $1 in
        bar16-musl-flip1|bar4096-musl-flip1) echo "--positions grid" ;;
        bar16-usl-flip1|bar4096-usl-flip1) echo "--scheme usl" ;;
        bar16-usf-flip1|bar4096-usf-flip1) echo "--scheme usf" ;;
        bar16-musl-flip0.99|bar4096-musl-flip0.99) echo "--positions grid --transfer flip:0.99" ;;
        bar16-bspline2|bar4096-bspline2) echo "--method bsmpm --degree 2 --knots natural --positions grid" ;;
        bar16-bspline3|bar4096-bspline3) echo "--method bsmpm --degree 3 --knots natural --positions grid" ;;
        av8-musl-flip1) echo "--body-force nodes" ;;
    esac
}
status=0
for c in $cases; do
    n=$(steps_of "$c")
    dump="$out/$c/final/dump_p.$n.LAMMPS"
    case $c in
        bar16-*) args="vibrating-bar --cells 16 --steps $n --columns $bar_columns" ;;
        bar4096-*) args="vibrating-bar --cells 4096 --steps $n --columns $bar_columns" ;;
        av8-*) args="aligned-vibration --method mpm --cells 8 --ppc 4 --steps $n --match x0 --columns $av_columns" ;;
    esac
    echo "== $c: hompm check $args $(conventions_of "$c")"
    # shellcheck disable=SC2086,SC2046
    "$hompm" check $args $(conventions_of "$c") --input "$dump" 2>/dev/null | head -2 || status=1
done
exit $status
