#!/usr/bin/env python3
"""A Taichi MLS-MPM run of hompm's 2D aligned vibration, written for `hompm check`.

An instrument outside the crate: an independent code in the style of Taichi's
mpm88/mpm99 examples (Hu et al. 2018, MLS-MPM with APIC), run on hompm's
manufactured solution (src/scenes/aligned_vibration.rs), that writes the
particles at the end in hompm's column names so that

    hompm check aligned-vibration --method bsmpm --degree 2 --cells N \
        --ppc S² --steps K --amplitude A --input FILE.csv

compares them with hompm's run and prints both codes' RMS errors against the
exact solution.

Needs `pip install taichi==1.7.4` (CPU backend). Float64 by default
(`ti.init(arch=ti.cpu, default_fp=ti.f64)`); `--f32` runs in float32.

The step, in order (t^n = n Δt, h = L / cells, D⁻¹ = 4/h²):

  grid   nodes x_i = (i_x h, i_y h) for i_x, i_y = -1 … cells+1: one padding
         node beyond each wall. Stored in Taichi fields of shape
         (cells+3, cells+3) with offset (-1, -1), so the field index *is* i.
  basis  uniform quadratic B-spline centred on each node,
         N_i(x_p) = w(x_p/h - i_x) w(y_p/h - i_y), w(r) = 3/4 - r² (|r| ≤ 1/2),
         (3/2 - |r|)²/2 (1/2 ≤ |r| ≤ 3/2), 0 beyond; the 3×3 stencil starts at
         base = floor(x_p/h - 1/2) (floor, not int(): particles lie within
         h/2 of the walls).
  P2G    τ_p = μ(F_p F_pᵀ - I) + λ ln J_p I  (Kirchhoff, = J σ_p; F_p from the
         end of the previous step: update-stress-last)
         A_p = -Δt D⁻¹ V_p⁰ τ_p + m_p C_p      (= -Δt D⁻¹ V_p σ_p + m_p C_p)
         m_i   = Σ_p N_i m_p
         (mv)_i = Σ_p N_i [m_p v_p + m_p Δt b(X_p, t^n) + A_p (x_i - x_p)]
         (the body force enters here, as particle momentum)
  grid   v_i = (mv)_i / m_i where m_i > 0 (else 0); then the walls:
         v_i,x = 0 on every node with i_x ≤ 0 or i_x ≥ cells,
         v_i,y = 0 on every node with i_y ≤ 0 or i_y ≥ cells.
         (`--walls mirror`, a diagnostic: then the padding nodes copy the
         first interior node with the normal component negated,
         v_{-1} = (-v_{1,x}, v_{1,y}), v_{cells+1} = (-v_{cells-1,x}, v_{cells-1,y}),
         and likewise in y, x walls first.)
  G2P    v_p = Σ_i N_i v_i,  C_p = D⁻¹ Σ_i N_i v_i ⊗ (x_i - x_p),
         x_p += Δt v_p,  F_p ← (I + Δt C_p) F_p,
         σ_p = (μ(F_p F_pᵀ - I) + λ ln J_p I) / J_p   (written out only).

Initial state: per_side² particles per cell at the sub-cell centres, in
hompm's order (x fastest), V_p⁰ = (L/(cells·per_side))², m_p = ρ₀ V_p⁰,
v_p = v(X_p, 0), F = I, σ = 0, C_p = 0 (`--initial-affine exact`: C_p = ∇v(X_p, 0)).
"""

import argparse
import math
import sys
import time

import numpy as np

SCENE = "aligned-vibration"
COLUMNS = [
    "id", "x0_x", "x0_y", "x_x", "x_y", "u_x", "u_y", "v_x", "v_y",
    "stress_xx", "stress_yy", "stress_xy", "F_xx", "F_xy", "F_yx", "F_yy",
]


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--cells", type=int, default=8, help="cells per side (default 8)")
    p.add_argument("--ppc-side", type=int, default=2,
                   help="particles per cell per side S; S² per cell (default 2)")
    p.add_argument("--dt", type=float, default=1e-5, help="time step (default 1e-5 s)")
    p.add_argument("--steps", type=int, default=1000, help="steps (default 1000)")
    p.add_argument("--amplitude", type=float, default=0.05, help="A (default 0.05 m)")
    p.add_argument("--young", type=float, default=1e7, help="E (default 1e7 Pa)")
    p.add_argument("--poisson", type=float, default=0.3, help="ν (default 0.3)")
    p.add_argument("--density", type=float, default=1000.0, help="ρ₀ (default 1000 kg/m³)")
    p.add_argument("--length", type=float, default=1.0, help="L (default 1 m)")
    p.add_argument("--solution", choices=["mls-paper", "axis-aligned"], default="mls-paper",
                   help="n = 2 (MLS paper Eq. 38, default) or n = 1 (Wallstedt & Guilkey)")
    p.add_argument("--f32", action="store_true", help="run in float32 (default float64)")
    p.add_argument("--initial-affine", choices=["zero", "exact"], default="zero",
                   help="C_p at t = 0: zero (Taichi's examples, default) or the exact "
                        "velocity gradient ∇v(X_p, 0)")
    p.add_argument("--walls", choices=["zero", "mirror"], default="zero",
                   help="zero: v_n = 0 on the wall and padding nodes (default); mirror "
                        "(diagnostic): v_n = 0 on the wall nodes, padding nodes mirror the "
                        "first interior node (v_n odd, v_t even)")
    p.add_argument("--threads", type=int, default=1,
                   help="CPU threads for Taichi (default 1)")
    p.add_argument("--out", required=True, help="output CSV")
    a = p.parse_args(argv)
    if a.cells < 1 or a.ppc_side < 1 or a.steps < 0 or not a.dt > 0:
        p.error("need --cells ≥ 1, --ppc-side ≥ 1, --steps ≥ 0, --dt > 0")
    return a


class Scene:
    """The manufactured solution of src/scenes/aligned_vibration.rs, in float64."""

    def __init__(self, a):
        self.A, self.L, self.rho = a.amplitude, a.length, a.density
        self.lam = a.young * a.poisson / ((1 + a.poisson) * (1 - 2 * a.poisson))
        self.mu = a.young / (2 * (1 + a.poisson))
        self.c = math.sqrt(a.young / a.density)
        self.n = 2.0 if a.solution == "mls-paper" else 1.0
        self.k = self.n * math.pi / self.L

    def time_factors(self, t):
        ph = self.c * math.pi * t / self.L
        return math.sin(ph), math.sin(ph + math.pi)

    def displacement(self, X, t):
        s0, s1 = self.time_factors(t)
        return np.stack([self.A * np.sin(self.k * X[:, 0]) * s0,
                         self.A * np.sin(self.k * X[:, 1]) * s1], axis=1)

    def velocity(self, X, t):
        ph = self.c * math.pi * t / self.L
        a = self.A * self.c * math.pi / self.L
        return np.stack([a * np.sin(self.k * X[:, 0]) * math.cos(ph),
                         a * np.sin(self.k * X[:, 1]) * math.cos(ph + math.pi)], axis=1)

    def velocity_gradient(self, X, t):
        """The diagonal of ∇_X v (= ∇_x v at t = 0)."""
        ph = self.c * math.pi * t / self.L
        a = self.A * self.c * math.pi / self.L * self.k
        return (a * np.cos(self.k * X[:, 0]) * math.cos(ph),
                a * np.cos(self.k * X[:, 1]) * math.cos(ph + math.pi))

    def stress(self, X, t):
        s0, s1 = self.time_factors(t)
        ak = self.A * self.k
        fxx = 1 + ak * np.cos(self.k * X[:, 0]) * s0
        fyy = 1 + ak * np.cos(self.k * X[:, 1]) * s1
        j = fxx * fyy
        sxx = (self.mu * (fxx * fxx - 1) + self.lam * np.log(j)) / j
        syy = (self.mu * (fyy * fyy - 1) + self.lam * np.log(j)) / j
        return sxx, syy


def particles(a):
    """Particles2d::cell_centred: sub-cell centres, x fastest, then y."""
    m = a.cells * a.ppc_side
    d = a.length / m
    i = np.arange(m, dtype=np.float64)
    xs, ys = np.meshgrid((i + 0.5) * d, (i + 0.5) * d, indexing="xy")
    X = np.stack([xs.ravel(), ys.ravel()], axis=1)  # row k = j*m + i
    return X, d * d


def run(a):
    import taichi as ti

    fp = ti.f32 if a.f32 else ti.f64
    ti.init(arch=ti.cpu, default_fp=fp, cpu_max_num_threads=a.threads,
            random_seed=0, log_level=ti.WARN)
    npfp = np.float32 if a.f32 else np.float64

    sc = Scene(a)
    X, vol0 = particles(a)
    n_p = X.shape[0]
    cells = a.cells
    h = a.length / cells
    inv_h = 1.0 / h
    dinv = 4.0 / (h * h)
    mass = a.density * vol0
    mu, lam = sc.mu, sc.lam
    dt = a.dt
    pre = math.pi ** 2 / a.length ** 2
    n2 = sc.n ** 2
    c2 = sc.c ** 2
    rho = a.density
    ak = sc.A * sc.k
    amp = sc.A
    mirror = a.walls == "mirror"

    x = ti.Vector.field(2, fp, n_p)
    v = ti.Vector.field(2, fp, n_p)
    C = ti.Matrix.field(2, 2, fp, n_p)
    F = ti.Matrix.field(2, 2, fp, n_p)
    sig = ti.Matrix.field(2, 2, fp, n_p)
    trig = ti.Vector.field(4, fp, n_p)  # sin kX, cos kX, sin kY, cos kY
    gm = ti.field(fp, (cells + 3, cells + 3), offset=(-1, -1))
    gv = ti.Vector.field(2, fp, (cells + 3, cells + 3), offset=(-1, -1))

    @ti.func
    def stencil(xp):
        r = xp * inv_h
        base = ti.floor(r - 0.5, ti.i32)
        fx = r - base  # in [0.5, 1.5)
        w = [0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1.0) ** 2, 0.5 * (fx - 0.5) ** 2]
        return base, fx, w

    @ti.func
    def kirchhoff(Fp):
        J = Fp.determinant()
        I = ti.Matrix.identity(fp, 2)
        return mu * (Fp @ Fp.transpose() - I) + lam * ti.log(J) * I, J

    @ti.kernel
    def substep(s0: fp, s1: fp):
        for I in ti.grouped(gm):
            gm[I] = 0.0
            gv[I] = ti.Vector.zero(fp, 2)
        # P2G
        for p in x:
            base, fx, w = stencil(x[p])
            tau, _ = kirchhoff(F[p])
            affine = -dt * dinv * vol0 * tau + mass * C[p]
            # manufactured body force per unit mass at (X_p, t^n), π²/L²
            t4 = trig[p]
            fxx = 1.0 + ak * t4[1] * s0
            fyy = 1.0 + ak * t4[3] * s1
            lnj = ti.log(fxx * fyy)
            bx = pre * amp * t4[0] * s0 * (
                n2 * mu / rho - c2 - n2 * (lam * (lnj - 1.0) - mu) / (rho * fxx * fxx))
            by = pre * amp * t4[2] * s1 * (
                n2 * mu / rho - c2 - n2 * (lam * (lnj - 1.0) - mu) / (rho * fyy * fyy))
            mom = mass * v[p] + mass * dt * ti.Vector([bx, by])
            for i, j in ti.static(ti.ndrange(3, 3)):
                off = ti.Vector([i, j])
                dpos = (off - fx) * h  # x_i - x_p
                wt = w[i][0] * w[j][1]
                gv[base + off] += wt * (mom + affine @ dpos)
                gm[base + off] += wt * mass
        # grid update and walls
        for i, j in gm:
            vi = ti.Vector.zero(fp, 2)
            if gm[i, j] > 0:
                vi = gv[i, j] / gm[i, j]
            if i <= 0 or i >= cells:
                vi[0] = 0.0
            if j <= 0 or j >= cells:
                vi[1] = 0.0
            gv[i, j] = vi
        if ti.static(mirror):
            for j in range(-1, cells + 2):
                gv[-1, j] = ti.Vector([-gv[1, j][0], gv[1, j][1]])
                gv[cells + 1, j] = ti.Vector([-gv[cells - 1, j][0], gv[cells - 1, j][1]])
            for i in range(-1, cells + 2):
                gv[i, -1] = ti.Vector([gv[i, 1][0], -gv[i, 1][1]])
                gv[i, cells + 1] = ti.Vector([gv[i, cells - 1][0], -gv[i, cells - 1][1]])
        # G2P
        for p in x:
            base, fx, w = stencil(x[p])
            nv = ti.Vector.zero(fp, 2)
            nC = ti.Matrix.zero(fp, 2, 2)
            for i, j in ti.static(ti.ndrange(3, 3)):
                off = ti.Vector([i, j])
                dpos = (off - fx) * h
                wt = w[i][0] * w[j][1]
                g = gv[base + off]
                nv += wt * g
                nC += dinv * wt * g.outer_product(dpos)
            v[p] = nv
            C[p] = nC
            x[p] += dt * nv
            F[p] = (ti.Matrix.identity(fp, 2) + dt * nC) @ F[p]

    @ti.kernel
    def cauchy():
        for p in F:
            tau, J = kirchhoff(F[p])
            sig[p] = tau / J

    @ti.kernel
    def outside() -> ti.i32:
        bad = 0
        for p in x:
            r = x[p] * inv_h
            if not (r[0] >= -0.5 and r[0] < cells + 0.5 and r[1] >= -0.5 and r[1] < cells + 0.5):
                bad += 1
        return bad

    x.from_numpy(X.astype(npfp))
    v.from_numpy(sc.velocity(X, 0.0).astype(npfp))
    eye = np.broadcast_to(np.eye(2), (n_p, 2, 2)).copy()
    F.from_numpy(eye.astype(npfp))
    C0 = np.zeros((n_p, 2, 2))
    if a.initial_affine == "exact":
        C0[:, 0, 0], C0[:, 1, 1] = sc.velocity_gradient(X, 0.0)
    C.from_numpy(C0.astype(npfp))
    kx, ky = sc.k * X[:, 0], sc.k * X[:, 1]
    trig.from_numpy(np.stack([np.sin(kx), np.cos(kx), np.sin(ky), np.cos(ky)], 1).astype(npfp))

    start = time.perf_counter()
    for step in range(a.steps):
        s0, s1 = sc.time_factors(step * dt)
        substep(s0, s1)
        if step % 100 == 99 and outside():
            sys.exit(f"a particle left the padded grid at step {step + 1}")
    cauchy()
    ti.sync()
    seconds = time.perf_counter() - start

    out = dict(x=x.to_numpy().astype(np.float64), v=v.to_numpy().astype(np.float64),
               F=F.to_numpy().astype(np.float64), sig=sig.to_numpy().astype(np.float64))
    return sc, X, out, seconds


def write_csv(a, X, o, path):
    fmt = lambda z: "%.17g" % z
    u = o["x"] - X
    with open(path, "w") as f:
        f.write(f"# scene: {SCENE}\n# cells: {a.cells}\n# ppc: {a.ppc_side ** 2}\n"
                f"# steps: {a.steps}\n# dt: {a.dt!r}\n")
        f.write(",".join(COLUMNS) + "\n")
        for k in range(X.shape[0]):
            s, F = o["sig"][k], o["F"][k]
            row = [X[k, 0], X[k, 1], o["x"][k, 0], o["x"][k, 1], u[k, 0], u[k, 1],
                   o["v"][k, 0], o["v"][k, 1], s[0, 0], s[1, 1], s[0, 1],
                   F[0, 0], F[0, 1], F[1, 0], F[1, 1]]
            f.write(str(k) + "," + ",".join(fmt(z) for z in row) + "\n")


def main(argv=None):
    a = parse_args(argv)
    sc, X, o, seconds = run(a)
    write_csv(a, X, o, a.out)
    t = a.steps * a.dt
    eu = np.sqrt(np.mean(np.sum((o["x"] - X - sc.displacement(X, t)) ** 2, 1)))
    ev = np.sqrt(np.mean(np.sum((o["v"] - sc.velocity(X, t)) ** 2, 1)))
    sxx, syy = sc.stress(X, t)
    s = o["sig"]
    es = np.sqrt(np.mean((s[:, 0, 0] - sxx) ** 2 + (s[:, 1, 1] - syy) ** 2
                         + s[:, 0, 1] ** 2 + s[:, 1, 0] ** 2))
    print(f"taichi {'f32' if a.f32 else 'f64'} cells={a.cells} ppc={a.ppc_side ** 2} "
          f"steps={a.steps} dt={a.dt!r} t={t!r}: RMS u {eu:.6e}, v {ev:.6e}, "
          f"stress {es:.6e}; stepping {seconds:.2f} s; wrote {a.out}")


if __name__ == "__main__":
    main()
