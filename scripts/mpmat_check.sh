#!/usr/bin/env bash
# scripts/mpmat_check.sh CHECKOUT [OUTDIR]
#
# Runs mpmat's 2D manufactured-solution case (github.com/vinhphunguyen/mpmat,
# Matlab, by V. P. Nguyen; not vendored here) under GNU Octave, writes its
# final particles as CSV with hompm's column names, and has
# `hompm check aligned-vibration --solution axis-aligned` report that code's
# own RMS error (`fields.<f>.rms_exact.yours`) beside the error the driver
# computes from mpmat's own exact-solution functions (docs/oracle.md,
# "Recipes by code"). The verdict says "differs": mpmat's case is the
# improved MPM (MLS projections to nodes and cell centres), not hompm's
# bilinear MPM; what is checked is that hompm reproduces mpmat's own error.
#
#   CHECKOUT  an mpmat source tree (tested at commit 086bb39b03a7, 2023-04-18)
#   OUTDIR    default /tmp/mpmat-out; one folder cellsN per run with
#             particles.csv (mpmat's final particles), mpmat_errors.txt (the
#             driver's numbers), check.json (hompm's report), octave.log;
#             OUTDIR/summary.tsv has one line per run (a rerun appends).
#
# Environment:
#   CELLS="8 16"   grid sizes (cells per side); default: mpmat's own,
#                  noX0 = 2^m(4) = 64 (16384 particles, 640 steps: hours
#                  of one core under Octave; 8 cells takes seconds)
#   HOMPM=path     the hompm binary (default ROOT/target/release/hompm;
#                  this script never builds it)
#   HOMPM_FLAGS    extra flags of the check (default "--scheme usl", the
#                  step order of mpmat's loop: stress from the updated grid
#                  velocity, no second projection); rms_exact.yours does not
#                  depend on them, rms_exact.hompm and the verdict do
#   MLS=mfile      use mpmat's own mls/mlsLinearBasis2D.m (quartic weight)
#                  instead of the vectorised stand-in of its macOS MEX file
#                  (same numbers to rounding, much slower)
#
# What runs: a temporary copy of example2D/mpm/impmMMS2D.m with these edits
# (sed, each checked; nothing else of mpmat is copied or changed):
#  (a) `addpath ../../X/` -> `addpath CHECKOUT/X/` (the copy runs elsewhere);
#  (b) `clc` and `colordef white` removed (colordef does not exist in Octave);
#  (c) the plot of the mesh and particles (figure(1) .. axis off) removed;
#  (d) `noX0 = 2^m(4);` keeps mpmat's value unless MPMAT_CELLS is set;
#  (e) `ppc = 2;` -> `ppc = [2 2];`: generateMPForRectangle reads ppc(2),
#      which fails for a scalar in Octave and Matlab ("index (2): out of
#      bound 1"); [2 2] is the 2 x 2 particles per cell the script means;
#  (f) everything from `%% post processing` on removed (hard-coded error
#      tables of an earlier run and plots).
# Its per-step line `time step t` goes to OUTDIR/cellsN/octave.log (progress).
# The script calls mlsLinearBasis2D_mex, which mpmat ships only as a macOS
# binary (example2D/mpm/mlsLinearBasis2D_mex.mexmaci64). Its codegen C
# (example2D/mpm/codegen/mex/mlsLinearBasis2D/mlsLinearBasis2D.c) shows
# what it computes: linear-basis MLS with the weight 1 - 6r^2 + 8r^3 - 3r^4
# for r = |x - x_I|/d_I <= 1 (the 'form' argument is ignored) and
# c = inv(A) p. A stand-in written here computes that, vectorised.
# Octave's warning "colon arguments should be scalars" (from (e)) is
# switched off by its id.
set -euo pipefail

if [ $# -lt 1 ] || [ ! -f "$1/example2D/mpm/impmMMS2D.m" ]; then
    echo "usage: $0 MPMAT_CHECKOUT [OUTDIR]" >&2
    exit 2
fi
checkout=$(cd "$1" && pwd)
out=${2:-/tmp/mpmat-out}
mkdir -p "$out"
out=$(cd "$out" && pwd)
root=$(cd "$(dirname "$0")/.." && pwd)
hompm=${HOMPM:-$root/target/release/hompm}
[ -x "$hompm" ] || { echo "no hompm binary at $hompm (set HOMPM=...)" >&2; exit 2; }
command -v octave-cli > /dev/null || { echo "octave-cli not found (apt-get install octave)" >&2; exit 2; }
hompm_flags=${HOMPM_FLAGS-"--scheme usl"}
read -r -a cells_list <<< "${CELLS:-default}"

work=$(mktemp -d /tmp/mpmat-work.XXXXXX)
trap 'rm -rf "$work"' EXIT
trap 'exit 130' INT TERM

# ---- the edited copy of mpmat's script ---------------------------------
src="$checkout/example2D/mpm/impmMMS2D.m"
cp "$src" "$work/impm_run.m"
edit() { # sed-expression grep-pattern-that-must-match-after description
    sed -i -e "$1" "$work/impm_run.m"
    grep -q -e "$2" "$work/impm_run.m" || { echo "edit failed: $3" >&2; exit 2; }
}
gone() { # grep-pattern-that-must-not-match description
    if grep -q -e "$1" "$work/impm_run.m"; then echo "edit failed: $2" >&2; exit 2; fi
}
edit "s|^addpath \.\./\.\./|addpath $checkout/|" "^addpath $checkout/mls/" "(a) addpath"
gone '^addpath \.\./' "(a) addpath"
sed -i -e '/^clc$/d' -e '/^colordef white/d' "$work/impm_run.m"
gone '^colordef' "(b) colordef"
grep -q '^figure(1)$' "$work/impm_run.m" || { echo "edit failed: (c) no figure(1)" >&2; exit 2; }
sed -i -e '/^figure(1)$/,/^axis off$/d' "$work/impm_run.m"
gone '^plot_mesh' "(c) plot"
edit "s|^noX0    = 2^m(4);|if isempty(getenv('MPMAT_CELLS')), noX0 = 2^m(4); else, noX0 = str2double(getenv('MPMAT_CELLS')); end;|" \
    "noX0 = str2double(getenv('MPMAT_CELLS'))" "(d) noX0"
edit 's|^ppc           = 2;|ppc           = [2 2];|' '^ppc           = \[2 2\];' "(e) ppc"
grep -q '^%% post processing' "$work/impm_run.m" || { echo "edit failed: (f) no post processing" >&2; exit 2; }
sed -i -e '/^%% post processing/,$d' "$work/impm_run.m"
gone '^disp2=' "(f) post processing"
diff -u "$src" "$work/impm_run.m" > "$out/edits.diff" || true

# ---- the stand-in of the MEX file ---------------------------------------
cat > "$work/mlsLinearBasis2D_mex.m" <<'OCTAVE'
function phi = mlsLinearBasis2D_mex(pt, index, node, di, form)
  % What mpmat's example2D/mpm/mlsLinearBasis2D_mex.mexmaci64 computes
  % (its codegen C): linear-basis MLS shape functions at pt of the points
  % node(index,:), weight 1 - 6r^2 + 8r^3 - 3r^4 for r = |pt - x_I|/d_I <= 1
  % ('form' ignored), c = inv(A) p, phi_I = (p_I' c) w_I.
  if strcmp(getenv('MPMAT_MLS'), 'mfile')
    phi = mlsLinearBasis2D(pt, index, node, di, 'quartic_spline');  % mpmat's mls/
    return
  end
  xi = node(index, 1);
  yi = node(index, 2);
  r  = sqrt((pt(1) - xi).^2 + (pt(2) - yi).^2) ./ di(index);
  w  = zeros(size(r));
  in = r <= 1;
  w(in) = 1 - 6*r(in).^2 + 8*r(in).^3 - 3*r(in).^4;
  P  = [ones(size(xi)) xi yi];
  A  = P' * (P .* w);
  c  = inv(A) * [1; pt(1); pt(2)];
  phi = (P * c) .* w;
end
OCTAVE

# ---- the driver ----------------------------------------------------------
cat > "$work/mpmat_mms2d_driver.m" <<'OCTAVE'
% Runs the edited copy of impmMMS2D.m (its workspace stays here), then
% writes the final particles with hompm's column names and mpmat's error:
% its own norm sqrt(sum_p |e_p|^2 V_p) (V_p = J_p V0_p, as its loop stores
% it in err(istep)) and the RMS over particles sqrt(sum_p |e_p|^2 / N_p)
% (hompm's rms_exact, MLS paper Eq. 43), e_p = (x_p - X_p) - u(X_p, t)
% with mpmat's own mmsU1/mmsU2 (and mmsV1/2, mmsF11/22 for v, F, sigma).
warning('off', 'Octave:colon-nonscalar-argument');
page_output_immediately(true);   % octave.log shows the steps as they run
impm_run;
out = getenv('MPMAT_OUT');
K   = istep - 1;              % steps taken (istep starts at 1)
tK  = K * dtime;              % hompm's end time, steps x dt
Np  = pCount;
X0  = coords0;
u   = coords - coords0;
ue = zeros(Np,2); ueK = zeros(Np,2); ve = zeros(Np,2); veK = zeros(Np,2);
Fe = zeros(Np,4); FeK = zeros(Np,4); se = zeros(Np,3); seK = zeros(Np,3);
for p = 1:Np
  for k = 1:2
    if k == 1, tt = t; else, tt = tK; end
    U  = [mmsU1(X0(p,1),tt) mmsU2(X0(p,2),tt)];
    V  = [mmsV1(X0(p,1),tt) mmsV2(X0(p,2),tt)];
    Fp = [mmsF11(X0(p,1),tt) 0; 0 mmsF22(X0(p,2),tt)];
    Jp = det(Fp);
    sp = 1/Jp*( mu*(Fp*Fp'-identity) + lambda*log(Jp)*identity );  % mpmat's law
    if k == 1
      ue(p,:) = U; ve(p,:) = V; Fe(p,:) = [Fp(1,1) Fp(1,2) Fp(2,1) Fp(2,2)];
      se(p,:) = [sp(1,1) sp(2,2) sp(1,2)];
    else
      ueK(p,:) = U; veK(p,:) = V; FeK(p,:) = [Fp(1,1) Fp(1,2) Fp(2,1) Fp(2,2)];
      seK(p,:) = [sp(1,1) sp(2,2) sp(1,2)];
    end
  end
end
% deform(p,:) = reshape(F,1,4) = [F11 F21 F12 F22]
Fh = [deform(:,1) deform(:,3) deform(:,2) deform(:,4)];
rms2 = @(a) sqrt(sum(sum(a.^2, 2)) / Np);
rmss = @(d) sqrt(sum(d(:,1).^2 + d(:,2).^2 + 2*d(:,3).^2) / Np);
fid = fopen([out '/particles.csv'], 'w');
fprintf(fid, '# scene: aligned-vibration\n# cells: %d\n# ppc: 4\n# steps: %d\n# dt: %.17g\n', noX0, K, dtime);
fprintf(fid, 'x0_x,x0_y,u_x,u_y,v_x,v_y,stress_xx,stress_yy,stress_xy,F_xx,F_xy,F_yx,F_yy\n');
fprintf(fid, [repmat('%.17g,', 1, 12) '%.17g\n'], [X0 u velo stress Fh]');
fclose(fid);
fid = fopen([out '/mpmat_errors.txt'], 'w');
fprintf(fid, 'cells=%d\nparticles=%d\nsteps=%d\ndt=%.17g\nt_mpmat=%.17g\nt_steps_dt=%.17g\n', ...
        noX0, Np, K, dtime, t, tK);
fprintf(fid, 'sum_volume=%.17g\nown_err_stored=%.17g\nown_err_recomputed=%.17g\n', ...
        sum(volume), err(istep), sqrt(sum(sum((u - ue).^2, 2) .* volume)));
fprintf(fid, 'rms_u=%.17g\nrms_v=%.17g\nrms_stress=%.17g\nrms_F=%.17g\n', ...
        rms2(u - ue), rms2(velo - ve), rmss(stress - se), rms2(Fh - Fe));
fprintf(fid, 'rms_u_at_steps_dt=%.17g\nrms_v_at_steps_dt=%.17g\nrms_stress_at_steps_dt=%.17g\nrms_F_at_steps_dt=%.17g\n', ...
        rms2(u - ueK), rms2(velo - veK), rmss(stress - seK), rms2(Fh - FeK));
fclose(fid);
OCTAVE

# ---- the runs --------------------------------------------------------------
summary="$out/summary.tsv"
[ -f "$summary" ] || printf 'cells\tsteps\tdt\tfield\tmpmat_own_volume_weighted\tmpmat_own_rms_at_t_mpmat\tmpmat_own_rms_at_steps_dt\thompm_rms_exact_yours\trel_diff_vs_steps_dt\trel_diff_vs_t_mpmat\thompm_rms_exact_hompm\n' > "$summary"

for n in "${cells_list[@]}"; do
    if [ "$n" = default ]; then envn=; label=default; else envn=$n; label=$n; fi
    case_dir="$out/cells$label"
    mkdir -p "$case_dir"
    echo "== mpmat impmMMS2D, cells: $label"
    (cd "$work" && MPMAT_CELLS="$envn" MPMAT_OUT="$case_dir" MPMAT_MLS="${MLS:-}" OMP_NUM_THREADS=1 \
        octave-cli --quiet --no-history --no-window-system --norc mpmat_mms2d_driver.m > "$case_dir/octave.log" 2>&1) \
        || { echo "Octave failed; see $case_dir/octave.log" >&2; exit 1; }
    csv="$case_dir/particles.csv"
    ncells=$(sed -n 's/^# cells: //p' "$csv")
    steps=$(sed -n 's/^# steps: //p' "$csv")
    dt=$(sed -n 's/^# dt: //p' "$csv")
    if [ "$label" = default ] && [ ! -e "$out/cells$ncells" ]; then
        mv "$case_dir" "$out/cells$ncells"; case_dir="$out/cells$ncells"; csv="$case_dir/particles.csv"
    fi
    # shellcheck disable=SC2086
    cmd=("$hompm" check aligned-vibration --solution axis-aligned --method mpm --cells "$ncells" --ppc 4
         --steps "$steps" --dt "$dt" $hompm_flags --input "$csv" --json)
    echo "${cmd[*]}" > "$case_dir/check.cmd"
    rc=0
    "${cmd[@]}" > "$case_dir/check.json" 2> "$case_dir/check.stderr" || rc=$?
    if [ "$rc" -gt 1 ]; then echo "hompm check failed (exit $rc); see $case_dir/check.stderr" >&2; exit 1; fi
    python3 - "$case_dir" "$summary" <<'PY'
import json, sys
d, summary = sys.argv[1], sys.argv[2]
rep = json.load(open(f"{d}/check.json"))
mine = dict(l.strip().split("=", 1) for l in open(f"{d}/mpmat_errors.txt") if "=" in l)
print(f"   cells {mine['cells']}, {mine['particles']} particles, {mine['steps']} steps of dt {mine['dt']}, "
      f"t (mpmat, accumulated) {mine['t_mpmat']}, steps*dt {mine['t_steps_dt']}")
print(f"   mpmat's own error, its norm sqrt(sum |e|^2 V_p): {float(mine['own_err_stored']):.17g}")
print(f"   verdict: {rep['verdict'].splitlines()[0][:110]}...")
rows = []
for f in ("u", "v", "stress", "F"):
    r = rep["fields"][f]["rms_exact"]
    yours, own, own_k = r["yours"], float(mine[f"rms_{f}"]), float(mine[f"rms_{f}_at_steps_dt"])
    rel_k = abs(yours - own_k) / abs(own_k)
    rel = abs(yours - own) / abs(own)
    vw = mine["own_err_stored"] if f == "u" else ""
    print(f"   {f:6s} mpmat's own RMS {own_k:.17g} (at t_mpmat {own:.17g}); hompm rms_exact.yours {yours:.17g}; "
          f"relative difference {rel_k:.2e} ({rel:.2e} at t_mpmat); hompm's own {r['hompm']:.6g}")
    rows.append([mine["cells"], mine["steps"], mine["dt"], f, vw, f"{own:.17g}", f"{own_k:.17g}",
                 f"{yours:.17g}", f"{rel_k:.3e}", f"{rel:.3e}", f"{r['hompm']:.17g}"])
with open(summary, "a") as s:
    for row in rows:
        s.write("\t".join(row) + "\n")
PY
    echo "   check: $(cat "$case_dir/check.cmd")"
done
echo "summary: $summary"
