#!/usr/bin/env bash
# Runs the 2D Taylor least squares of QuocAnh90/MPM2D_basic (commit
# cc01c1b, 2018-03, "TLS-MPM": SubFunctions/Reconstruction.m, TLS2D.m and
# Conserve_Integral.m, the last "copied from the code written by Lisa
# Wobbes, 27 Feb 2018") under GNU Octave and compares its values at the
# Gauss points with hompm's 2D TLS (src/mpm2d/tls.rs) on the same
# particles, as scripts/author_tls_check.sh does for the TLS author's 1D
# code (issue #40, item 5; docs/reproduction-notes.md, "The 2D TLS of
# MPM2D_basic"). Outside CI: it needs octave-cli and a checkout of that
# repository at cc01c1b, whose path is the first argument. It fetches
# nothing and copies nothing of that code: Octave runs the checkout's
# functions from their folder.
#
#   scripts/tls2d_code_check.sh /path/to/MPM2D_basic
#
# What the code does (file:line at cc01c1b):
# - TLS2D.m:13-14  the Taylor basis is scaled by the half cell, dx = le(1)/2
#   and (for square cells only) dy = le(1)/2, as hompm's;
# - TLS2D.m:17-25  the cell averages of the quadratic terms come from their
#   antiderivatives at the absolute cell ends (hompm: 1/3 and 0 exactly);
# - TLS2D.m:78-82  D = sum_p psi(x_p) psi(x_p)^T: unweighted, as hompm's;
# - TLS2D.m:56-76  the basis by the particle count: with the constraint the
#   average alone below 3 particles, linear below 6, quadratic from 6;
#   without it linear below 6 (a singular D below 3), quadratic from 6;
# - Conserve_Integral.m:16-20  the constraint sum_p m_p / |Omega_e| (and
#   sum_p m_p v_p / |Omega_e|), hompm's sum_p V_p f_p / |Omega_e| with
#   f = rho;
# - Reconstruction.m:20-25  density and momentum are fitted with the
#   constraint, the three stress components without it (Conserve = -999).
#
# The driver feeds hompm (examples/tls2d_cells.rs) particles x y V f s on a
# 16 x 16 grid of the unit square, takes hompm's Gauss points, calls the
# code's Reconstruction with rho = f, m = V f and the stress's first
# component = s, and prints per cell the largest |hompm - code| over the
# four Gauss points, relative to the cell's largest |code value|, for hompm's
# engine rule ("conditioning") and its MPM2D_basic rule ("count"), with
# kappa_1 of the normal matrix of the conservative quadratic fit.
set -euo pipefail
repo=$(cd "${1:?usage: tls2d_code_check.sh CHECKOUT}" && pwd)
root=$(cd "$(dirname "$0")/.." && pwd)
for f in TLS2D.m Reconstruction.m Conserve_Integral.m; do
  [ -f "$repo/SubFunctions/$f" ] || { echo "no SubFunctions/$f in $repo" >&2; exit 2; }
done
if git -C "$repo" rev-parse HEAD >/dev/null 2>&1; then
  echo "MPM2D_basic at $(git -C "$repo" rev-parse --short HEAD) (expected cc01c1b)"
fi
target=${CARGO_TARGET_DIR:-$root/target}
(cd "$root" && cargo build --release --quiet --example tls2d_cells)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cat > "$work/driver.m" <<'OCTAVE'
addpath([getenv("REPO") "/SubFunctions"]);
work = getenv("WORK"); driver = getenv("DRIVER");
cells = 16; L = 1; h = L / cells; V = (h / 3)^2;
f = @(x, y) 1000 * (1 + 0.1 * sin(2 * pi * x) .* cos(2 * pi * y) + 0.05 * x .* y);
s = @(x, y) 1e4 * (cos(3 * x) + y.^2 - 0.3 * x .* y);
rand("twister", 40);
% Cases: cell (cx, cy), a name, local coordinates in [0, 1]^2.
[a, b] = meshgrid([1 3 5] / 6);
regular = [a(:) b(:)];
[a, b] = meshgrid([1 3 5 7] / 8);
sixteen = [a(:) b(:)];
[a, b] = meshgrid([1 3 5] / 6, [1 5] / 6);
two_rows = [a(:) b(:)];
jitter = @(p) p + (rand(size(p)) - 0.5) * 0.25;
cases = {
  [0 0],  "9, the engine's layout",       regular;
  [1 0],  "9, jittered",                  jitter(regular);
  [2 0],  "12, random",                   0.02 + 0.96 * rand(12, 2);
  [3 0],  "16, 4 x 4",                    sixteen;
  [15 15], "9, jittered, far corner",     jitter(regular);
  [4 0],  "6, random",                    0.02 + 0.96 * rand(6, 2);
  [5 0],  "6 on two rows",                two_rows;
  [6 0],  "5, random",                    0.02 + 0.96 * rand(5, 2);
  [7 0],  "4, random",                    0.02 + 0.96 * rand(4, 2);
  [8 0],  "3, random",                    0.02 + 0.96 * rand(3, 2);
  [9 0],  "2, random",                    0.02 + 0.96 * rand(2, 2);
  [10 0], "1",                            [0.3 0.6];
};
x = []; owner = [];
for c = 1:rows(cases)
  p = (cases{c, 1} + cases{c, 3}) * h;
  x = [x; p]; owner = [owner; c * ones(rows(p), 1)];
end
n = rows(x);
fp = f(x(:, 1), x(:, 2)); sp = s(x(:, 1), x(:, 2));
data = [x, V * ones(n, 1), fp, sp];
fid = fopen([work "/particles.txt"], "w");
fprintf(fid, "%.17g %.17g %.17g %.17g %.17g\n", data');
fclose(fid);
status = system(sprintf("'%s' %d %.17g < '%s/particles.txt' > '%s/hompm.txt'", driver, cells, L, work, work));
if status != 0, error("hompm's driver failed"); end
out = load([work "/hompm.txt"]);   % cx cy q xg yg n f_cond f_count s_cond s_count
printf("largest |hompm - MPM2D_basic| / max|MPM2D_basic| at the four Gauss points of a cell\n");
printf("%-8s %-28s %-9s %-18s %-18s %-18s %-18s %s\n", "cell", "particles", "kappa_1", "rho: conditioning", "rho: count", "s: conditioning", "s: count", "Octave's warning");
for c = 1:rows(cases)
  ce = cases{c, 1};
  rowsel = out(:, 1) == ce(1) & out(:, 2) == ce(2);
  o = out(rowsel, :);
  members = find(owner == c);
  k = ce(1) + cells * ce(2) + 1;   % the code's element number
  mspoints = {};
  mspoints{k} = members;
  m_sp = V * fp;
  v_ssp = zeros(n, 2);
  [cm, cp] = Conserve_Integral([h h], k, mspoints, m_sp, v_ssp);
  LOCC = zeros(k, 2);
  lower = ce * h;
  LOCC(k, :) = 0.5 * (lower + (lower + h));
  s_sp = [sp, zeros(n, 2)];
  lastwarn("");
  [rho, ~, ~, sx] = Reconstruction(k, mspoints, fp, v_ssp, s_sp, 4, o(:, 4)', o(:, 5)', x, [h h], LOCC, cm, cp);
  [msg, ~] = lastwarn();
  % kappa_1 of the conservative quadratic fit's D (hompm's psi_2..psi_6).
  xi = (x(members, 1) - LOCC(k, 1)) / (h / 2); eta = (x(members, 2) - LOCC(k, 2)) / (h / 2);
  P = [xi, eta, (xi.^2 - 1/3) / 2, xi .* eta, (eta.^2 - 1/3) / 2];
  kappa = cond(P' * P, 1);
  d = @(ours, theirs) max(abs(ours - theirs(:))) / max(abs(theirs(:)));
  cols = {d(o(:, 7), rho), d(o(:, 8), rho), d(o(:, 9), sx), d(o(:, 10), sx)};
  text = cellfun(@(v) sprintf("%.1e", v), cols, "UniformOutput", false);
  printf("(%2d,%2d)  %-28s %-9.1e %-18s %-18s %-18s %-18s %s\n", ce(1), ce(2), cases{c, 2}, kappa, text{:}, msg);
end
OCTAVE
# Octave's warnings (a singular D in the code) go to stderr; the table
# names them per cell.
(cd "$work" && WORK="$work" DRIVER="$target/release/examples/tls2d_cells" REPO="$repo" \
  octave-cli --no-gui --quiet --norc driver.m 2>/dev/null)
