#!/usr/bin/env bash
# Runs the TLS paper's first author's public TLS reconstruction (E. Wobbes,
# repository ewob/TLS, TLS1D.py, Python, 2020) and compares its values at
# the Gauss points with `hompm reconstruct --method tls-conservative`, under
# both of hompm's cell averages of (x - x_c)^2 (issue #25; docs/conventions.md,
# "The TLS author's cell average"). Outside CI: it needs Python 3 with
# NumPy and a checkout of that repository, whose path is the first
# argument. It fetches nothing and copies nothing of that code: a driver
# written here imports the checkout's module (with a stand-in for
# matplotlib, whose plots are not needed) and calls its TLS class.
#
#   scripts/author_tls_check.sh /path/to/TLS
#
# Cases: the module's own example (three points on [-1, 1], sin(x) + 2),
# and the same layout shifted to cells far from the origin, where the two
# averages round differently.
set -euo pipefail
repo=$(cd "${1:?usage: author_tls_check.sh CHECKOUT}" && pwd)
root=$(cd "$(dirname "$0")/.." && pwd)
hompm="$root/target/release/hompm"
[ -x "$hompm" ] || (cd "$root" && cargo build --release --quiet)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/matplotlib"
# A stand-in for matplotlib: every pyplot call does nothing.
printf '' > "$work/matplotlib/__init__.py"
printf 'def __getattr__(name):\n    return lambda *a, **k: None\n' > "$work/matplotlib/pyplot.py"

REPO="$repo" HOMPM="$hompm" PYTHONPATH="$work:$repo" python3 - <<'PYTHON'
import io, json, contextlib, os, subprocess
import numpy as np
from numpy.polynomial.legendre import leggauss

with contextlib.redirect_stdout(io.StringIO()):
    import TLS1D as author  # runs the module's example, prints its integral

hompm = os.environ["HOMPM"]
xi, _ = leggauss(2)

def hompm_values(a, b, points, values, integral, gauss, average):
    args = [hompm, "reconstruct", "--method", "tls-conservative", "--json",
            "--cells=%r,%r" % (a, b),
            "--points=" + ",".join(repr(float(p)) for p in points),
            "--values=" + ",".join(repr(float(v)) for v in values),
            "--integrals=%r" % integral,
            "--at=" + ",".join(repr(float(g)) for g in gauss),
            "--taylor-average", average]
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    return np.array(json.loads(out)["values"])

averages = ["exact", "antiderivative-difference", "antiderivative-six-terms"]
print("largest |hompm - TLS1D.py| / |TLS1D.py| at the two Gauss points, by --taylor-average")
print("cell                " + "  ".join("%-25s" % a for a in averages))
for shift in [0.0, 10.0, 48.0, 1000.0]:
    a, b = -1.0 + shift, 1.0 + shift
    points = np.array((-0.9, 0.0, 0.5)) + shift
    values = np.sin(points - shift) + 2.0
    mean = 2.0
    gauss = 0.5 * (a + b) + 0.5 * (b - a) * xi
    data = author.data_per_interval(a, b, points, values)
    theirs = author.TLS(data, gauss, True, mean).compute()[:, 0]
    row = []
    for average in averages:
        ours = hompm_values(a, b, points, values, mean * (b - a), gauss, average)
        row.append(np.max(np.abs(ours - theirs) / np.abs(theirs)))
    print("[%7.1f, %7.1f]    " % (a, b) + "  ".join("%-25.3e" % r for r in row))
PYTHON
