#!/usr/bin/env python3
"""An independent 2D MPM (bilinear, MUSL as MLS paper Eqs. 18-41 with the
direct mapping) for the MLS paper's manufactured neo-Hookean vibration,
written from the paper in numpy, and checked with one `hompm check` command
(issue #24, docs/oracle.md). It writes its particles with its own column
names and its own parameters, then asks hompm to run the same setup through
the overrides and compares the error hompm reports for it (rms_exact.yours)
with the error it computes itself (MLS paper Eq. 43).

    pip install numpy && python3 scripts/independent_2d_mpm.py [path/to/hompm]

Outside CI: it needs numpy and a release build of hompm."""
import json, math, os, subprocess, sys, tempfile
import numpy as np

HOMPM = sys.argv[1] if len(sys.argv) > 1 else "target/release/hompm"

# Its own parameters: not the paper's set.
A, E, NU, RHO, L = 0.05, 2.0e7, 0.25, 800.0, 1.0
CELLS, PER_SIDE, DT, STEPS = 8, 2, 1.0e-5, 300
MU = E / (2 * (1 + NU))
LAM = E * NU / ((1 + NU) * (1 - 2 * NU))
C = math.sqrt(E / RHO)


def exact(X, Y, t):
    """u, v, F diagonal and Cauchy stress of Eqs. (38)-(41) at (X, Y, t)."""
    k = 2 * math.pi / L
    s0, s1 = math.sin(C * math.pi * t / L), math.sin(C * math.pi * t / L + math.pi)
    c0, c1 = math.cos(C * math.pi * t / L), math.cos(C * math.pi * t / L + math.pi)
    u = np.stack([A * np.sin(k * X) * s0, A * np.sin(k * Y) * s1], axis=-1)
    w = A * C * math.pi / L
    v = np.stack([w * np.sin(k * X) * c0, w * np.sin(k * Y) * c1], axis=-1)
    fxx = 1 + A * k * np.cos(k * X) * s0
    fyy = 1 + A * k * np.cos(k * Y) * s1
    return u, v, fxx, fyy


def body_force(X, Y, t):
    """b = ü − ∇·P/ρ0 per unit mass, derived (π²; Eq. 42 prints π)."""
    u, _, fxx, fyy = exact(X, Y, t)
    lnj = np.log(fxx * fyy)
    def bracket(f):
        return 4 * MU / RHO - C**2 - 4 * (LAM * (lnj - 1) - MU) / (RHO * f * f)
    pre = math.pi**2 / L**2
    return np.stack([pre * u[:, 0] * bracket(fxx), pre * u[:, 1] * bracket(fyy)], axis=-1)


def hat(x, h, n):
    """Indices of the two 1D nodes of each point's cell, values and slopes."""
    cell = np.minimum((x / h).astype(int), n - 1)
    xi = x / h - cell
    return cell, np.stack([1 - xi, xi], -1), np.stack([-np.ones_like(xi), np.ones_like(xi)], -1) / h


def run():
    n = CELLS * PER_SIDE
    d = L / n
    g = (np.arange(n) + 0.5) * d
    X, Y = np.meshgrid(g, g)                   # row j, column i: particle j*n + i
    X, Y = X.ravel(), Y.ravel()
    npart = X.size
    h = L / CELLS
    nodes = CELLS + 1
    V0 = np.full(npart, d * d)
    m = RHO * V0
    x, y = X.copy(), Y.copy()
    _, v, _, _ = exact(X, Y, 0.0)
    F = np.tile(np.eye(2), (npart, 1, 1))
    sig = np.zeros((npart, 2, 2))
    V = V0.copy()
    for step in range(STEPS):
        t = step * DT
        cx, nx, gx = hat(x, h, CELLS)
        cy, ny, gy = hat(y, h, CELLS)
        b = body_force(X, Y, t)
        M = np.zeros((nodes, nodes)); P = np.zeros((nodes, nodes, 2)); Fo = np.zeros((nodes, nodes, 2))
        stencil = [(a, bb) for a in range(2) for bb in range(2)]
        for a, bb in stencil:
            N = nx[:, a] * ny[:, bb]
            dN = np.stack([gx[:, a] * ny[:, bb], nx[:, a] * gy[:, bb]], -1)
            ix, iy = cx + a, cy + bb
            np.add.at(M, (ix, iy), N * m)
            np.add.at(P, (ix, iy), (N * m)[:, None] * v)
            fint = -np.einsum("p,pij,pj->pi", V, sig, dN)
            np.add.at(Fo, (ix, iy), (N * m)[:, None] * b + fint)
        for arr in (Fo, P):                    # zero normal components on the walls
            arr[0, :, 0] = arr[-1, :, 0] = 0.0
            arr[:, 0, 1] = arr[:, -1, 1] = 0.0
        P = P + DT * Fo
        active = M > 0
        acc = np.where(active[..., None], Fo / np.where(active, M, 1)[..., None], 0.0)
        vel = np.where(active[..., None], P / np.where(active, M, 1)[..., None], 0.0)
        ap = np.zeros((npart, 2)); vp = np.zeros((npart, 2))
        for a, bb in stencil:
            N = nx[:, a] * ny[:, bb]
            ap += N[:, None] * acc[cx + a, cy + bb]
            vp += N[:, None] * vel[cx + a, cy + bb]
        v = v + DT * ap
        x = x + DT * vp[:, 0]; y = y + DT * vp[:, 1]
        PL = np.zeros((nodes, nodes, 2))
        for a, bb in stencil:
            N = nx[:, a] * ny[:, bb]
            np.add.at(PL, (cx + a, cy + bb), (N * m)[:, None] * v)
        vL = np.where(active[..., None], PL / np.where(active, M, 1)[..., None], 0.0)
        vL[0, :, 0] = vL[-1, :, 0] = 0.0
        vL[:, 0, 1] = vL[:, -1, 1] = 0.0
        Lg = np.zeros((npart, 2, 2))
        for a, bb in stencil:
            dN = np.stack([gx[:, a] * ny[:, bb], nx[:, a] * gy[:, bb]], -1)
            Lg += np.einsum("pi,pj->pij", vL[cx + a, cy + bb], dN)
        F = np.einsum("pij,pjk->pik", np.eye(2) + DT * Lg, F)
        J = np.linalg.det(F)
        V = J * V0
        Bm = np.einsum("pij,pkj->pik", F, F)
        sig = (LAM * np.log(J) / J)[:, None, None] * np.eye(2) + (MU / J)[:, None, None] * (Bm - np.eye(2))
    return X, Y, x, y, v, sig, F


def main():
    X, Y, x, y, v, sig, F = run()
    t = STEPS * DT
    u = np.stack([x - X, y - Y], -1)
    ue, _, _, _ = exact(X, Y, t)
    own_rms = math.sqrt(np.sum((u - ue) ** 2) / X.size)
    order = np.random.default_rng(24).permutation(X.size)   # as a GPU code sorts
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "mine.csv")
        with open(path, "w") as f:
            f.write("X0,Y0,ux,uy,vx,vy,sxx,syy,sxy,Fxx,Fxy,Fyx,Fyy\n")
            for p in order:
                row = [X[p], Y[p], u[p, 0], u[p, 1], v[p, 0], v[p, 1], sig[p, 0, 0], sig[p, 1, 1],
                       sig[p, 0, 1], F[p, 0, 0], F[p, 0, 1], F[p, 1, 0], F[p, 1, 1]]
                f.write(",".join("%.17g" % r for r in row) + "\n")
        cmd = [HOMPM, "check", "aligned-vibration", "--method", "mpm", "--cells", str(CELLS),
               "--ppc", str(PER_SIDE**2), "--dt", str(DT), "--steps", str(STEPS),
               "--amplitude", str(A), "--young", str(E), "--poisson", str(NU), "--density", str(RHO),
               "--columns", "x0_x=X0,x0_y=Y0,u_x=ux,u_y=uy,v_x=vx,v_y=vy,stress_xx=sxx,stress_yy=syy,"
               "stress_xy=sxy,F_xx=Fxx,F_xy=Fxy,F_yx=Fyx,F_yy=Fyy",
               "--input", path]
        print("$", " ".join(cmd[:1] + ["check"] + cmd[2:]).replace(path, "mine.csv"))
        text = subprocess.run(cmd, capture_output=True, text=True)
        print(text.stdout.strip())
        report = json.loads(subprocess.run(cmd + ["--json"], capture_output=True, text=True).stdout)
    yours = report["fields"]["u"]["rms_exact"]["yours"]
    print("RMS of u (Eq. 43): computed here %.15e, hompm's rms_exact.yours %.15e, relative difference %.1e"
          % (own_rms, yours, abs(yours - own_rms) / own_rms))
    print("exit code %d; verdict: %s" % (text.returncode, report["verdict"].splitlines()[0]))
    return 0 if abs(yours - own_rms) <= 1e-12 * own_rms else 1


if __name__ == "__main__":
    sys.exit(main())
