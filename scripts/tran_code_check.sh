#!/usr/bin/env bash
# Runs the MLS paper's own Matlab code (Tran et al., "Moving least squares
# reconstruction for B-spline MPM"; the first commit, f30bc24, 2019-12-19,
# of QuocAnh90/CPLS-least-squares-for-Material-Point-Method) under GNU Octave
# on its manufactured-solution vibration of a strip, writes what it
# computes as CSV, and checks each strip file with `hompm check
# manufactured-strip` (issue #40). Outside CI: it needs Octave (Debian's
# octave-cli) and a checkout of that repository, whose path is the first
# argument. It fetches nothing and copies none of that code into this
# repository: it copies the checkout into a temporary directory, applies two
# one-line sed edits there (Vibration.m and Vibration2D.m also return their
# final particle state, not only their RMS errors), writes an Octave driver
# beside it, and runs one Octave process per case.
#
#   scripts/tran_code_check.sh CHECKOUT [OUT]     (OUT defaults to /tmp/tran-out)
#
# Environment (optional): CELLS (default "8 16 32 64"), METHODS (default
# "MPM BSMPM MLS_BSMPM"), CELLS_2D (default 8; empty skips the 2D runs),
# METHODS_2D (default "MPM BSMPM MLS_BSMPM").
#
# Output in OUT:
#   strip-METHOD-N.csv   final particles of Vibration(METHOD, N), columns
#                        id,x0,x,u,v,stress,F,area (x components; stress is
#                        the code's Cauchy sigma_xx, F its F_xx, area its
#                        particle area V0*det F: not hompm's 1D volume, so
#                        not compared); '# ' comment lines carry
#                        cells, steps, dt, time and the code's RMS errors
#   square-METHOD-N.csv  the same for Vibration2D (x and y components)
#   errors.csv           one line per case: the code's own RMS errors (the
#                        vector Vibration returns, which Paper.m plots),
#                        the driver's recomputation of them, wall-clock time
#   METHOD-N.log         Octave's output (the code prints Version, resolution
#                        and t at each step: the count of 't = ' lines is the
#                        step count)
# The code's runs are not timed precisely: wall_s is rough wall-clock.
set -euo pipefail
src=$(cd "${1:?usage: tran_code_check.sh CHECKOUT [OUT]}" && pwd)
out=${2:-/tmp/tran-out}
cells_1d=${CELLS-8 16 32 64}
methods_1d=${METHODS-MPM BSMPM MLS_BSMPM}
cells_2d=${CELLS_2D-8}
methods_2d=${METHODS_2D-MPM BSMPM MLS_BSMPM}
octave=$(command -v octave-cli || command -v octave || true)
[ -n "$octave" ] || { echo "tran_code_check.sh: needs GNU Octave (apt-get install octave)" >&2; exit 2; }
mkdir -p "$out"
out=$(cd "$out" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The code, copied; which commit it is (the edits below expect f30bc24).
commit=unknown
if git -C "$src" rev-parse HEAD > /dev/null 2>&1; then
  commit=$(git -C "$src" rev-parse HEAD)
fi
case $commit in
  f30bc24*) ;;
  *) echo "warning: checkout is at $commit, not f30bc24 (the MLS paper's first commit)" >&2 ;;
esac
mkdir "$work/code"
tar -C "$src" --exclude=.git -cf - . | tar -C "$work/code" -xf -

# Headless edits: none needed for plotting (every figure/plot call in
# Vibration.m, Vibration2D.m and the solvers they call is commented out in
# this commit); only the two entry points are made to return their state.
edit_signature() { # file function-name
  local file=$work/code/$1 name=$2
  sed -i "1s/^function results = $name(Version,resolution)\r\?\$/function [results, x_sp, x_spo, d_sp, v_ssp, s_sp, F_sp, V_sp, dt, t] = $name(Version,resolution)/" "$file"
  head -n 1 "$file" | grep -q "^function \[results, x_sp," ||
    { echo "tran_code_check.sh: $1 line 1 is not the expected signature; not commit f30bc24?" >&2; exit 1; }
}
edit_signature Vibration.m Vibration
edit_signature Vibration2D.m Vibration2D

# The Octave driver: one case per process, parameters from the environment.
cat > "$work/driver.m" <<'OCTAVE'
set(0, 'defaultfigurevisible', 'off');
dim = str2double(getenv('DIM')); method = getenv('METHOD');
cells = str2double(getenv('CELLS')); out = getenv('OUT');
cd(getenv('CODE'));
if dim == 1, entry = 'Vibration'; else, entry = 'Vibration2D'; end
[results, x_sp, x_spo, d_sp, v_ssp, s_sp, F_sp, V_sp, dt, t] = feval(entry, method, cells);
n = rows(x_sp);
steps = round(t / dt);
F = zeros(n, 4);
for p = 1:n
  F(p, :) = [F_sp{p}(1,1), F_sp{p}(1,2), F_sp{p}(2,1), F_sp{p}(2,2)];
end
% Recompute the RMS errors from the returned state (a check of the
% extraction): the manufactured solution of Vibration.m / Vibration2D.m.
h = 1 / cells; E = 1e7; rho = 1000; c = sqrt(E / rho);
X = x_spo(:, 1) - 2*h;
if dim == 1
  A = 1e-4; nu = 0; te = t;   % Vibration.m evaluates it after t = t + dt
  ue = A*sin(pi*X)*sin(c*pi*te); ve = A*c*pi*sin(pi*X)*cos(c*pi*te);
  Fe = 1 + A*pi*cos(pi*X)*sin(c*pi*te);
  lam = E*nu/(1+nu)/(1-2*nu); mu = E/2/(1+nu);
  se = (lam*log(Fe) + mu*(Fe.^2 - 1)) ./ Fe;
  re = [sqrt(mean((ue - d_sp(:,1)).^2)), sqrt(mean((ve - v_ssp(:,1)).^2)), sqrt(mean((se - s_sp(:,1)).^2))];
else
  A = 0.1; nu = 0.3; te = t - dt;  % Vibration2D.m evaluates it before its last step
  Y = x_spo(:, 2) - 2*h;
  ue = [A*sin(pi*X)*sin(c*pi*te), A*sin(pi*Y)*sin(c*pi*te + pi)];
  ve = [A*c*pi*sin(pi*X)*cos(c*pi*te), A*c*pi*sin(pi*Y)*cos(c*pi*te + pi)];
  Fx = 1 + A*pi*cos(pi*X)*sin(c*pi*te); Fy = 1 + A*pi*cos(pi*Y)*sin(c*pi*te + pi);
  lam = E*nu/(1+nu)/(1-2*nu); mu = E/2/(1+nu); J = Fx .* Fy;
  se = [lam*log(J)./J + mu./J.*(Fx.^2 - 1), lam*log(J)./J + mu./J.*(Fy.^2 - 1), zeros(n, 1)];
  sq = @(d) sqrt(sum(sum(d.^2)) / n);
  re = [sq(ue - d_sp), sq(ve - v_ssp), sq(se - s_sp)];
end
f = fopen(out, 'w');
fprintf(f, '# code: Tran MLS paper, %s(''%s'', %d), commit %s\n', ...
  entry, method, cells, getenv('COMMIT'));
fprintf(f, '# cells: %d\n# steps: %d\n# dt: %.17g\n# time: %.17g\n', cells, steps, dt, t);
fprintf(f, '# exact solution evaluated at: %.17g\n', te);
fprintf(f, '# rms (code): u %.17g, v %.17g, stress %.17g\n', results);
fprintf(f, '# rms (driver): u %.17g, v %.17g, stress %.17g\n', re);
if dim == 1
  fprintf(f, 'id,x0,x,u,v,stress,F,area\n');
  fprintf(f, '%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n', ...
    [(1:n)', x_spo(:,1), x_sp(:,1), d_sp(:,1), v_ssp(:,1), s_sp(:,1), F(:,1), V_sp(:)].');
else
  fprintf(f, 'id,x0,y0,x,y,ux,uy,vx,vy,sxx,syy,sxy,Fxx,Fxy,Fyx,Fyy,volume\n');
  fprintf(f, ['%d' repmat(',%.17g', 1, 16) '\n'], ...
    [(1:n)', x_spo, x_sp, d_sp, v_ssp, s_sp, F, V_sp(:)].');
end
fclose(f);
printf('RESULT,%s,%d,%d,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n', ...
  method, dim, cells, steps, dt, t, results, re);
OCTAVE

summary=$out/errors.csv
echo "method,dim,cells,steps,dt,time,rms_u,rms_v,rms_stress,driver_rms_u,driver_rms_v,driver_rms_stress,wall_s,status" > "$summary"
run_case() { # dim method cells
  local dim=$1 method=$2 cells=$3 name
  if [ "$dim" = 1 ]; then name=strip-$method-$cells; else name=square-$method-$cells; fi
  local log=$out/$name.log start end status=ok
  start=$(date +%s)
  (cd "$work" && DIM=$dim METHOD=$method CELLS=$cells OUT="$out/$name.csv" CODE="$work/code" \
    COMMIT=$commit "$octave" --no-gui --quiet --norc --no-history driver.m > "$log" 2>&1) || status=failed
  end=$(date +%s)
  local line
  line=$(grep '^RESULT,' "$log" | tail -n 1 | cut -d, -f2-) || true
  if [ -z "$line" ]; then
    status=failed
    line="$method,$dim,$cells,,,,,,,,,"
    rm -f "$out/$name.csv"
  fi
  echo "$line,$((end - start)),$status" >> "$summary"
  local steps_printed
  steps_printed=$(grep -c '^t = ' "$log" || true)
  echo "== $name: $status, $((end - start)) s, $steps_printed steps printed"
  [ "$status" = ok ] || grep -m 3 -i 'error' "$log" | sed 's/^/   /'
}

for method in $methods_1d; do
  for cells in $cells_1d; do run_case 1 "$method" "$cells"; done
done
for method in $methods_2d; do
  for cells in $cells_2d; do run_case 2 "$method" "$cells"; done
done
echo "errors: $summary"

# Each strip file checked with one `hompm check` line (issue #40): the
# code's MPM is MUSL moving particles with the updated grid momentum
# (--positions grid), its BSMPM is USL (--scheme usl), its MLS_BSMPM is
# USL with cubic B-splines, the code's 1D MLS with the code's own weights
# and the consistent mass (--mapping mls-code-weights --mass consistent,
# src/mpm/mapping/mls.rs); Δt and steps are the file's own.
hompm=${HOMPM:-$(cd "$(dirname "$0")/.." && pwd)/target/release/hompm}
if [ -z "${HOMPM:-}" ] && [ ! -x "$hompm" ]; then
  (cd "$(dirname "$0")/.." && cargo build --release --quiet)
fi
[ -x "$hompm" ] || { echo "tran_code_check.sh: HOMPM=$hompm is not executable" >&2; exit 2; }
agreed=0 checked=0
for method in $methods_1d; do
  case $method in
    MPM) flags="--method mpm --positions grid" ;;
    BSMPM) flags="--method bsmpm --degree 2 --scheme usl" ;;
    MLS_BSMPM) flags="--method bsmpm --degree 3 --mapping mls-code-weights --mass consistent --scheme usl" ;;
    *) echo "== strip-$method: not checked (no hompm counterpart)"; continue ;;
  esac
  for cells in $cells_1d; do
    f=$out/strip-$method-$cells.csv
    [ -f "$f" ] || continue
    dt=$(sed -n 's/^# dt: //p' "$f"); steps=$(sed -n 's/^# steps: //p' "$f")
    # shellcheck disable=SC2086
    verdict=$("$hompm" check manufactured-strip --params mls-paper-code $flags --cells "$cells" --ppc 5 \
      --dt "$dt" --steps "$steps" --input "$f" 2> /dev/null | head -n 1) || true
    checked=$((checked + 1))
    case $verdict in agrees*) agreed=$((agreed + 1)) ;; esac
    echo "== check strip-$method-$cells ($flags): ${verdict:-error}"
  done
done
for cells in $cells_2d; do
  f=$out/square-MPM-$cells.csv
  [ -f "$f" ] || continue
  h=$(awk "BEGIN { printf \"%.17g\", 2 / $cells }")
  steps=$(sed -n 's/^# steps: //p' "$f")
  verdict=$("$hompm" check aligned-vibration --method mpm --cells "$cells" --ppc 9 --steps "$steps" \
    --solution axis-aligned --amplitude 0.1 --poisson 0.3 --origin "$h,$h" \
    --columns x0_x=x0,x0_y=y0,x_x=x,x_y=y,v_x=vx,v_y=vy,stress_xx=sxx,stress_yy=syy,stress_xy=sxy,F_xx=Fxx,F_xy=Fxy,F_yx=Fyx,F_yy=Fyy \
    --input "$f" 2> /dev/null | head -n 1) || true
  checked=$((checked + 1))
  case $verdict in agrees*) agreed=$((agreed + 1)) ;; esac
  echo "== check square-MPM-$cells (--origin $h,$h): ${verdict:-error}"
done
echo "checks: $agreed of $checked agree"
