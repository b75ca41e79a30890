#!/usr/bin/env python3
"""Independent MUSL (book Eqs. 4.5-4.18) in numpy/scipy, compared particle by
particle with `hompm run --json` on cases that are not in the papers.
Direct mapping, lumped mass, P1 or B-spline bases. Run by hand:
`pip install scipy numpy && python3 scripts/check_run_oracle.py [path/to/hompm]`."""
import json, subprocess, sys
import numpy as np
from scipy.interpolate import BSpline

HOMPM = sys.argv[1] if len(sys.argv) > 1 else "target/release/hompm"

def basis(knots, p, x):
    n = len(knots) - p - 1
    vals, ders = np.zeros(n), np.zeros(n)
    xx = min(x, knots[-1] * (1 - 1e-15)) if x >= knots[-1] else x  # right end: last span (left limit)
    for i in range(n):
        c = np.zeros(n); c[i] = 1.0
        s = BSpline(np.array(knots), c, p, extrapolate=True)
        vals[i] = s(xx); ders[i] = s(xx, nu=1)
    return vals, ders

def musl(L, rho, E, v0, g, top_load, large, cells, ppc, p, dt, steps, scene):
    knots = [0.0] * (p + 1) + [L * k / cells for k in range(1, cells)] + [L] * (p + 1)
    n = len(knots) - p - 1
    npart = cells * ppc
    x = np.array([(k + 0.5) * L / npart for k in range(npart)])
    V = np.full(npart, L / npart); dens = np.full(npart, rho); m = V * dens
    v = v0 * np.sin(np.pi * x / L) if scene == "vibrating-bar" else np.zeros(npart)
    u = np.zeros(npart); s = np.zeros(npart)
    trac = np.zeros(npart)
    if scene != "vibrating-bar": trac[-1] = top_load
    fixed = [0, n - 1] if scene == "vibrating-bar" else [0]
    for _ in range(steps):
        B = [basis(knots, p, xp) for xp in x]
        mi = sum(mp * b[0] for mp, b in zip(m, B))
        fint = sum(sp * Vp * b[1] for sp, Vp, b in zip(s, V, B))
        fext = sum(mp * g * b[0] + tp * b[0] for mp, tp, b in zip(m, trac, B))
        a = np.where(mi != 0, (fext - fint) / np.where(mi != 0, mi, 1), 0.0)
        a[fixed] = 0.0
        v = v + dt * np.array([b[0] @ a for b in B])
        P = sum(mp * vp * b[0] for mp, vp, b in zip(m, v, B))
        vn = np.where(mi != 0, P / np.where(mi != 0, mi, 1), 0.0)
        vn[fixed] = 0.0
        du = dt * vn
        dup = np.array([b[0] @ du for b in B]); de = np.array([b[1] @ du for b in B])
        u += dup; x = x + dup
        s = s + ((E - s) if large else E) * de
        V = V * (1 + de); dens = dens / (1 + de)
    return x, u, v, s

cases = [
    ("vibrating-bar", "tls-table-4", "mpm", 1, 5, 3, 1e-4, 150),
    ("vibrating-bar", "thesis-table-4.1", "bsmpm", 3, 7, 2, 1e-3, 120),
    ("column-top-load", "thesis-table-8.1", "bsmpm", 2, 9, 3, 1e-4, 200),
]
params = {
    "tls-table-4": (1.0, 2e3, 4e4, 0.8, 0.0, 0.0, True),
    "thesis-table-4.1": (25.0, 1.0, 100.0, 0.1, 0.0, 0.0, False),
    "thesis-table-8.1": (1.0, 1e3, 1e5, 0.0, 0.0, -1e4, True),
}
worst = 0.0
for scene, pset, method, p, cells, ppc, dt, steps in cases:
    args = [HOMPM, "run", scene, "--params", pset, "--method", method, "--degree", str(p), "--cells", str(cells),
            "--ppc", str(ppc), "--dt", repr(dt), "--steps", str(steps), "--json"]
    out = subprocess.run(args, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)["particles"]
    L, rho, E, v0, g, tl, large = params[pset]
    x, u, v, s = musl(L, rho, E, v0, g, tl, large, cells, ppc, p if method == "bsmpm" else 1, dt, steps, scene)
    for name, ref in [("x", x), ("u", u), ("v", v), ("stress", s)]:
        got = np.array(doc[name]); scale = max(np.abs(ref).max(), 1e-300)
        worst = max(worst, np.abs(got - ref).max() / scale)
    print(f"{scene} {pset} {method} p={p}: worst relative difference so far {worst:.2e}")
assert worst < 1e-10
print("run oracle agrees with the independent MUSL to 1e-10")
