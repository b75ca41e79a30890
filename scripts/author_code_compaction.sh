#!/usr/bin/env bash
# Runs the thesis author's 1D MPM code (MPM_1D_B_spline.m, Tielen 2016,
# "based on code of Lisa Wobbes") under GNU Octave on the column compaction
# of TLS paper §6.2 (Table 6: H = 50 m, ρ = 1, E = 1e6 Pa, body force
# ramped linearly to −200 over 0.5 s, Δt = 1e-4 s, 50 elements × 20 PPC,
# P1 = B-splines of degree 1, bottom fixed, top free) and prints how many
# grid crossings its own counting rule reports and the largest particle
# displacement: the instruments for the TLS paper's "180 times" and
# "0.27 m" (issue #25). Outside CI; needs octave-cli and a checkout of
# roeltielen24/BSpline_MPM_1D, whose path is the first argument.
#
# The code applies a constant gravity, so the driver runs a copy of
# MPM_1D_B_spline.m in a temporary directory in which the gravity of step s
# is multiplied by min(1, (s−1)Δt / 0.5), the ramp hompm uses (the body
# force at the start of the step). Nothing of that code enters the crate.
#
#   scripts/author_code_compaction.sh /path/to/BSpline_MPM_1D [deformation]
set -euo pipefail
repo=$(cd "${1:?usage: author_code_compaction.sh CHECKOUT [deformation 0|1]}" && pwd)
deformation=${2:-1}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$(dirname "$0")/author_code_grid.m" "$work/"
cp "$repo"/*.m "$work"/
# The ramp: only the nodal gravity force inside the time loop changes.
sed -i 's/F_grav(i,1) = sum(\(.*\)constant\.g);/F_grav(i,1) = sum(\1constant.g*min(1,(s-1)*t_step\/constant.ramp));/' \
  "$work/MPM_1D_B_spline.m"
grep -c "constant.ramp" "$work/MPM_1D_B_spline.m" | sed 's/^/ramped gravity lines: /'

cat > "$work/driver.m" <<'OCTAVE'
num = @(name) str2double(getenv(name));
constant = struct('density',1,'E',1e6,'g',-200,'load',0,'height',50,'alpha',0,'ramp',0.5);
flag = struct('both_ends_fixed',0,'volume_update',1,'lumped',1,'change_glob_pos',1, ...
  'change_loc_pos',1,'lagranian',0,'momentum',1,'deformation',num('DEFORMATION'),'num_int',0, ...
  'dynamic',0,'splines',0,'ULFEM',0);
deg = 1; n_e = 50; ppc = 20; dt = 1e-4; n_steps = 5000;
author_code_grid;  % scripts/author_code_grid.m
[u_n, v_p, v_n, m_p, u_p] = MPM_1D_B_spline(constant, flag, pos, pos_loc, ...
  n_e, h, ppc, dt, nt, nt*dt, z, z, z, z, weight, Xi, deg, @(x) 0*x, ...
  @(x) 0*x, @(x) 0*x, n_p, zeros(n_dof, nt));
printf('RESULT largest |u_p| at the end: %.6g m; over the run: %.6g m\n', ...
  max(abs(u_p(:, end))), max(max(abs(u_p))));
OCTAVE

start=$(date +%s)
(cd "$work" && DEFORMATION=$deformation octave-cli --no-gui --quiet driver.m > octave.log 2>&1) || {
  tail -20 "$work/octave.log"; exit 1; }
echo "Octave: $(( $(date +%s) - start )) s, flag.deformation = $deformation"
grep -o "Particle crossed \(lower\|upper\) border" "$work/octave.log" | sort | uniq -c
printf 'crossings (one message per element border crossed): %s\n' \
  "$(grep -o "Particle crossed \(lower\|upper\) border" "$work/octave.log" | wc -l)"
grep "^RESULT" "$work/octave.log"
