#!/usr/bin/env python3
"""Cross-check hompm's oracle commands against an independent implementation
(scipy.interpolate.BSpline and numpy). Not part of `cargo test` (CI has no
scipy); run by hand: `pip install scipy numpy && python3 scripts/check_oracles.py`.

- `hompm basis`: random knot vectors with repeated interior knots, degrees 0-5,
  points including both ends; values and derivatives to 1e-10.
- `hompm mass --condition`: 1D consistent mass matrices of degrees and sizes
  outside the book's tables, eigenvalues by numpy, kappa to 1e-8 relative.
- malformed knots must exit non-zero with one stderr line.
"""
import json, random, subprocess, sys
import numpy as np
from scipy.interpolate import BSpline

HOMPM = sys.argv[1] if len(sys.argv) > 1 else "target/release/hompm"
rng = random.Random(20261121)

def run(args):
    out = subprocess.run([HOMPM] + args, capture_output=True, text=True)
    return out.returncode, out.stdout, out.stderr

def scipy_basis(knots, p, x, nu):
    n = len(knots) - p - 1
    vals = []
    for i in range(n):
        c = np.zeros(n); c[i] = 1.0
        s = BSpline(np.array(knots), c, p, extrapolate=False)
        v = s(x, nu=nu) if nu <= p else 0.0
        vals.append(0.0 if np.isnan(v) else float(v))
    return vals

worst = 0.0
cases = 0
for trial in range(300):
    p = rng.randint(0, 5)
    interior = sorted(rng.sample(range(1, 20), rng.randint(0, 6)))
    knots = [0.0] * (p + 1)
    for t in interior:
        knots += [t / 20.0] * rng.randint(1, max(1, p))  # multiplicity <= p keeps scipy's derivative continuous
    knots += [1.0] * (p + 1)
    pts = [0.0, 1.0] + [rng.random() for _ in range(5)]
    pts = [x for x in pts if all(abs(x - k) > 1e-9 for k in interior)] + [0.0, 1.0]
    code, out, err = run(["basis", "--degree", str(p), "--knots", ",".join(repr(k) for k in knots),
                          "--at", ",".join(repr(x) for x in pts), "--derivatives", "--json"])
    assert code == 0, err
    doc = json.loads(out)
    for k, x in enumerate(pts):
        ref_v = scipy_basis(knots, p, x, 0)
        ref_d = scipy_basis(knots, p, x, 1)
        # scipy leaves the right end point to the last span only with extrapolate=True semantics;
        # evaluate just left of 1.0 for the reference at x = 1 (continuity from the left).
        if x == 1.0:
            c = lambda i: np.eye(len(knots) - p - 1)[i]
            ref_v = [float(BSpline(np.array(knots), c(i), p, extrapolate=True)(1.0)) for i in range(len(knots) - p - 1)]
            ref_d = [float(BSpline(np.array(knots), c(i), p, extrapolate=True)(1.0, nu=1)) if p > 0 else 0.0 for i in range(len(knots) - p - 1)]
        for a, b in zip(doc["values"][k], ref_v):
            worst = max(worst, abs(a - b)); cases += 1
        for a, b in zip(doc["derivatives"][k], ref_d):
            worst = max(worst, abs(a - b) / (1 + abs(b))); cases += 1
print(f"basis: {cases} values/derivatives compared, worst difference {worst:.2e}")
assert worst < 1e-10

# mass: kappa of 1D consistent mass, numpy Gauss-Legendre + scipy basis.
worst = 0.0
for p, n in [(6, 10), (7, 12), (2, 40), (3, 9), (8, 5)]:
    knots = [0.0] * (p + 1) + [k / n for k in range(1, n)] + [1.0] * (p + 1)
    nb = len(knots) - p - 1
    gx, gw = np.polynomial.legendre.leggauss(p + 1)
    M = np.zeros((nb, nb))
    for e in range(n):
        a, b = e / n, (e + 1) / n
        for t, w in zip(gx, gw):
            x = 0.5 * (b - a) * t + 0.5 * (a + b)
            phi = np.array(scipy_basis(knots, p, x, 0))
            M += 0.5 * (b - a) * w * np.outer(phi, phi)
    for dirichlet in [False, True]:
        A = M[1:-1, 1:-1] if dirichlet else M
        ev = np.linalg.eigvalsh(A)
        kappa = ev[-1] / ev[0]
        args = ["mass", "--degree", str(p), "--spans", str(n), "--condition", "--json"] + (["--dirichlet"] if dirichlet else [])
        code, out, err = run(args)
        assert code == 0, err
        got = json.loads(out)["condition_number"]
        worst = max(worst, abs(got - kappa) / kappa)
print(f"mass: kappa against numpy, worst relative difference {worst:.2e}")
assert worst < 1e-8

for bad in [["0", "1", "0.5"], ["0", "nan", "1"], ["0", "0", "0", "0", "1"]]:
    code, out, err = run(["basis", "--degree", "1", "--knots", ",".join(bad), "--at", "0.5"])
    assert code != 0 and len(err.strip().splitlines()) == 1 and "panicked" not in err, (bad, err)
print("malformed knots rejected cleanly")

# reconstruct: TLS by numpy least squares, cubic splines by scipy, MLS by numpy.
from scipy.interpolate import CubicSpline
from math import factorial
def taylor(a, b, nb, x):
    xc, dx = 0.5 * (a + b), 0.5 * (b - a)
    out = [1.0]
    for k in range(1, nb):
        avg = 0.0 if k % 2 else dx**k / (k + 1)
        out.append(((x - xc)**k - avg) / (factorial(k) * dx**k))
    return np.array(out)
worst = 0.0
for trial in range(60):
    ncell = rng.randint(1, 4)
    edges = [float(v) for v in np.cumsum([rng.uniform(-1, 1)] + [rng.uniform(0.3, 2.0) for _ in range(ncell)])]
    nb = rng.randint(1, 4)
    pts, vals = [], []
    for e in range(ncell):
        a, b = edges[e], edges[e + 1]
        for k in range(nb + 2):
            pts.append(a + (b - a) * (k + 0.5 + 0.3 * rng.uniform(-1, 1)) / (nb + 2))
            vals.append(rng.uniform(-2, 2))
    ints = [rng.uniform(-3, 3) for _ in range(ncell)]
    at = [edges[0] + (edges[-1] - edges[0]) * rng.random() for _ in range(5)]
    args = ["reconstruct", "--cells", ",".join(map(repr, edges)), "--points", ",".join(map(repr, pts)),
            "--values", ",".join(map(repr, vals)), "--order", str(nb), "--at", ",".join(map(repr, at)), "--json"]
    for method in ["tls", "tls-conservative"]:
        extra = ["--method", method] + (["--integrals", ",".join(map(repr, ints))] if method == "tls-conservative" else [])
        code, out, err = run(args + extra)
        assert code == 0, err
        doc = json.loads(out)
        for z, got in zip(at, doc["values"]):
            e = min(np.searchsorted(edges, z, side="right") - 1, ncell - 1)
            a, b = edges[e], edges[e + 1]
            sel = [(p, v) for p, v in zip(pts, vals) if a <= p <= b]
            P = np.array([taylor(a, b, nb, p) for p, _ in sel]); V = np.array([v for _, v in sel])
            if method == "tls":
                coef = np.linalg.lstsq(P, V, rcond=None)[0]
            else:
                a1 = ints[e] / (b - a)
                rest = np.linalg.lstsq(P[:, 1:], V - a1, rcond=None)[0] if nb > 1 else np.array([])
                coef = np.concatenate([[a1], rest])
            ref = float(taylor(a, b, nb, z) @ coef)
            worst = max(worst, abs(got - ref) / (1 + abs(ref)))
    order = np.argsort(pts)
    for method, bc in [("cubic-spline", "not-a-knot"), ("cubic-spline-natural", "natural")]:
        code, out, err = run(args + ["--method", method])
        assert code == 0, err
        cs = CubicSpline(np.array(pts)[order], np.array(vals)[order], bc_type=bc)
        for z, got in zip(at, json.loads(out)["values"]):
            worst = max(worst, abs(got - float(cs(z))) / (1 + abs(float(cs(z)))))
print(f"reconstruct: TLS and cubic splines against numpy/scipy, worst relative difference {worst:.2e}")
assert worst < 1e-10

# MLS (MLS paper Eqs. 10-17) by numpy.
def w(r):
    r = abs(r)
    return 0.75 - r * r if r <= 0.5 else (0.5 * (1.5 - r) ** 2 if r <= 1.5 else 0.0)
worst = 0.0
for trial in range(40):
    edges = [0.0, 1.0, 2.0, 3.0]
    pts = sorted(rng.uniform(0, 3) for _ in range(12))
    vals = [rng.uniform(-1, 1) for _ in pts]
    at = [rng.uniform(0, 3) for _ in range(4)]
    code, out, err = run(["reconstruct", "--method", "mls", "--cells", "0,1,2,3", "--points", ",".join(map(repr, pts)),
                          "--values", ",".join(map(repr, vals)), "--at", ",".join(map(repr, at)), "--json"])
    if code != 0:
        continue  # a singular moment matrix is reported as an error, by design
    for z, got in zip(at, json.loads(out)["values"]):
        W = np.array([w((z - p) / 2.0) for p in pts]); P = np.array([[1.0, p] for p in pts])
        A = (P.T * W) @ P
        ref = float(np.array([1.0, z]) @ np.linalg.solve(A, (P.T * W) @ np.array(vals)))
        worst = max(worst, abs(got - ref) / (1 + abs(ref)))
print(f"reconstruct: MLS against numpy, worst relative difference {worst:.2e}")
assert worst < 1e-10
