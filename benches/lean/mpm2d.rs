//! # A lean 2D step of the MLS paper: the speed limit of hompm's 2D step
//!
//! Issue #39 measures hompm's 2D step against this one: the step of
//! `Simulation2d::step` on the aligned vibration with the direct mapping
//! and the lumped mass (MLS paper Eqs. 4–5, 22–37 and 41, the body force of
//! Eq. 42 with π²), bilinear (`LeanBilinear2d`) or with open-uniform
//! B-splines of degree W − 1 (`LeanBsmpm2d`), written as two particle loops
//! and two node loops, without diagnostics, checks or `Result`. It computes
//! **bit for bit** what hompm computes (tests/spec/speed/lean_2d.rs),
//! because every number is formed from the same operands in the same order:
//! - each axis' basis: P1 on element k = ⌊x/h⌋ at ξ = (x − kh)/h clamped to
//!   [0, 1], ∇ = (−1/h, 1/h) (`LagrangeBasis::evaluate_fixed`); B-splines by
//!   the Cox–de Boor triangle of `KnotVector::values_and_gradients_fixed`
//!   (NURBS Book A2.2, book Eq. 4.23 with 1/ndu[p][r] formed once) on the
//!   span `find_span` finds;
//! - N_i = N_a(x) N_b(y), ∇N_i = (N_a' N_b, N_a N_b') (Eqs. 4–5); a gather
//!   sums the stencil from 0, row by row (b outer, a inner), and a node
//!   receives the particles' terms in particle order (Eqs. 22–25 and 31 with
//!   the particles as quadrature points);
//! - b_p(t) as `ManufacturedForce::fill` forms it, with the products that do
//!   not depend on t (left operands of hompm's left-to-right products) formed
//!   once per particle;
//! - F ← (I + L Δt) F, J = det F, V = J V⁰, ρ = m/V and
//!   σ = (λ ln J / J) I + (μ/J)(F Fᵀ − I) in nalgebra's order (a 2×2 product
//!   is A_{i0} B_{0j} + A_{i1} B_{1j}, det F = F₀₀F₁₁ − F₁₀F₀₁); σ is
//!   symmetric bit for bit (F₀₀F₁₀ + F₀₁F₁₁ both ways), so σ_xy is kept once.
//!
//! Where it saves work: the basis of a particle is evaluated in the loop
//! that deforms it and kept for the next step; the particle update
//! (Eqs. 29–30) is fused with the end-of-step scatter (Eq. 31), and the
//! deformation and stress (Eqs. 34–37, 41) with the next step's basis, body
//! force and phase-1 scatter (Eqs. 22–25); the nodes' m, (mv), f sit side by
//! side, and a node loop clears what the next scatter fills; the two lanes
//! of the basis and the two components of a vector are computed as pairs
//! (`Pair`), which LLVM turns into packed SSE2 instructions.
//!
//! `Lean2d::from_simulation` takes the scene besides the simulation: the
//! body force is a trait object in `Simulation2d`, so the lean step forms
//! it from the scene's parameters and asserts that it gets hompm's b_p
//! bit for bit.
//!
//! The basis of each axis, x and y in paired lanes, is in
//! benches/lean/mpm2d_axis.rs (re-exported: `Axis`, `OpenBSplines`,
//! `BilinearAxis`).
//!
//! Items: `Lean2d`, `LeanBsmpm2d`, `LeanBilinear2d`.

#[path = "mpm2d_axis.rs"]
mod axis;

use axis::{add, div, mul, splat, sub, Pair};
pub use axis::{Axis, BilinearAxis, OpenBSplines};
use hompm::mpm::conventions::{Conventions, Knots};
use hompm::mpm2d::step::{Formulation, Mapping2d, Simulation2d};
use hompm::scenes::aligned_vibration::AlignedVibration;
use std::f64::consts::PI;

/// Quadratic (W = 3) or cubic (W = 4) B-spline MPM.
pub type LeanBsmpm2d<const W: usize> = Lean2d<W, OpenBSplines>;

/// Bilinear MPM.
pub type LeanBilinear2d = Lean2d<2, BilinearAxis>;

/// A particle's basis: the node of (a, b) = (0, 0), [N_a(x), N_a'(x)] and
/// [N_b(y), N_b'(y)].
#[derive(Clone, Copy)]
struct Stencil<const W: usize> {
    first: usize,
    x: [Pair; W],
    y: [Pair; W],
}

/// A node's phase-1 sums: m_i, (mv)_i and f_i (Eqs. 22–25).
#[derive(Clone, Copy, Default)]
struct Node {
    mass: f64,
    momentum: Pair,
    force: Pair,
}

/// A node's a_i and v_i^{t+1} (Eqs. 27–28).
#[derive(Clone, Copy, Default)]
struct Motion {
    acceleration: Pair,
    velocity: Pair,
}

/// The manufactured body force's constants (`ManufacturedForce::fill`).
#[derive(Clone, Copy)]
struct Force {
    wave_speed: f64,
    length: f64,
    /// n²μ/ρ₀ − c², the bracket's first terms.
    head: f64,
    n2: f64,
    lambda: f64,
    mu: f64,
    rho: f64,
}

impl Force {
    /// [sin cπt/L, sin(cπt/L + π)] (`AlignedVibration::time_factors`).
    fn time_factors(&self, t: f64) -> [f64; 2] {
        let phase = self.wave_speed * PI * t / self.length;
        [phase.sin(), (phase + PI).sin()]
    }

    /// b_p(t) from the particle's [A k cos kX, A k cos kY, π²A/L² sin kX,
    /// π²A/L² sin kY] and the time factors s, x and y in paired lanes.
    #[inline(always)]
    fn at(&self, terms: &[f64; 4], s: Pair) -> Pair {
        let f = add([1.0; 2], mul([terms[0], terms[1]], s));
        let ln_j = (f[0] * f[1]).ln();
        let numerator = self.n2 * (self.lambda * (ln_j - 1.0) - self.mu);
        let bracket = sub(
            splat(self.head),
            div(splat(numerator), mul(mul(splat(self.rho), f), f)),
        );
        mul(mul([terms[2], terms[3]], s), bracket)
    }
}

/// The state of the lean step: the particles as arrays (F row-major,
/// σ as [σ_xx, σ_xy, σ_yy]), their basis, the nodes, the constants.
pub struct Lean2d<const W: usize, A: Axis<W>> {
    /// Positions x_p.
    pub x: Vec<[f64; 2]>,
    /// Initial positions X_p.
    pub x0: Vec<[f64; 2]>,
    /// Displacements u_p = x_p − X_p.
    pub displacement: Vec<[f64; 2]>,
    /// Velocities v_p.
    pub velocity: Vec<[f64; 2]>,
    /// Deformation gradients [F_xx, F_xy, F_yx, F_yy].
    pub deformation: Vec<[f64; 4]>,
    /// Cauchy stresses [σ_xx, σ_xy, σ_yy].
    pub stress: Vec<[f64; 3]>,
    /// Volumes V_p.
    pub volume: Vec<f64>,
    /// Densities ρ_p.
    pub density: Vec<f64>,
    volume0: Vec<f64>,
    mass: Vec<f64>,
    force_terms: Vec<[f64; 4]>,
    stencils: Vec<Stencil<W>>,
    /// Phase 1's m_i, (mv)_i, f_i.
    nodes: Vec<Node>,
    motions: Vec<Motion>,
    /// (mv)_i^L, then v_i^L in place (Eqs. 31–33).
    end: Vec<Pair>,
    axis: A,
    nodes_per_side: usize,
    force: Force,
    lambda: f64,
    mu: f64,
    /// Time reached, summed as `Simulation2d::time` is.
    pub time: f64,
}

impl<const W: usize, A: Axis<W>> Lean2d<W, A> {
    /// The state of a hompm simulation of the aligned vibration `scene` (the
    /// MLS paper's conventions, updated Lagrangian, direct mapping, the
    /// derived body force at the particles) before its next step.
    pub fn from_simulation(sim: &Simulation2d, scene: &AlignedVibration) -> Self {
        let s = &sim.settings;
        assert_eq!(s.formulation, Formulation::UpdatedLagrangian);
        assert_eq!(s.mapping, Mapping2d::Direct);
        assert_eq!(s.conventions, Conventions::MLS_PAPER);
        assert_eq!(sim.grid.knots(), Knots::Open);
        assert_eq!(s.material, scene.material().expect("material"));
        assert_eq!(sim.grid.length(), scene.length);
        let p = &sim.particles;
        let n = p.len();
        let axis = A::of(sim);
        let nodes_per_side = sim.grid.nodes_per_side();
        let material = s.material;
        let waves = scene.solution.waves();
        let c = scene.wave_speed();
        let force = Force {
            wave_speed: c,
            length: scene.length,
            head: waves.powi(2) * material.mu / scene.density - c.powi(2),
            n2: waves.powi(2),
            lambda: material.lambda,
            mu: material.mu,
            rho: scene.density,
        };
        let k = scene.wavenumber();
        let ak = scene.amplitude * waves * PI / scene.length;
        let pa = PI * PI / (scene.length * scene.length) * scene.amplitude;
        let force_terms =
            p.x0.iter()
                .map(|x| {
                    let (sx, cx) = ((k * x[0]).sin(), (k * x[0]).cos());
                    let (sy, cy) = ((k * x[1]).sin(), (k * x[1]).cos());
                    [ak * cx, ak * cy, pa * sx, pa * sy]
                })
                .collect();
        let mut lean = Self {
            x: p.x.clone(),
            x0: p.x0.clone(),
            displacement: p.displacement.clone(),
            velocity: p.velocity.clone(),
            deformation: p
                .deformation
                .iter()
                .map(|f| [f[(0, 0)], f[(0, 1)], f[(1, 0)], f[(1, 1)]])
                .collect(),
            stress: p
                .stress
                .iter()
                .map(|s| {
                    assert_eq!(s[(0, 1)], s[(1, 0)], "symmetric σ");
                    [s[(0, 0)], s[(0, 1)], s[(1, 1)]]
                })
                .collect(),
            volume: p.volume.clone(),
            density: p.density.clone(),
            volume0: p.volume0.clone(),
            mass: p.mass.clone(),
            force_terms,
            stencils: Vec::with_capacity(n),
            nodes: vec![Node::default(); nodes_per_side * nodes_per_side],
            motions: vec![Motion::default(); nodes_per_side * nodes_per_side],
            end: vec![[0.0; 2]; nodes_per_side * nodes_per_side],
            axis,
            nodes_per_side,
            force,
            lambda: material.lambda,
            mu: material.mu,
            time: sim.time,
        };
        let body = sim.body_force.as_ref().expect("the manufactured force");
        let mut expected = vec![[0.0; 2]; n];
        body.fill(sim.time, &p.x0, &mut expected);
        let s = force.time_factors(sim.time);
        for (k, expected) in expected.iter().enumerate() {
            let stencil = lean.evaluate(k);
            lean.stencils.push(stencil);
            let b = force.at(&lean.force_terms[k], s);
            assert_eq!(b, *expected, "b_p of particle {k}");
            lean.scatter(k, b);
        }
        if sim.steps == 0 {
            lean.assert_basis_is_the_workspace_s(sim);
        }
        lean
    }

    /// The stencils hompm evaluated at the same positions (a simulation that
    /// has not stepped), bit for bit.
    fn assert_basis_is_the_workspace_s(&self, sim: &Simulation2d) {
        let n = self.nodes_per_side;
        let (sx, sy) = (&sim.workspace.stencils_x, &sim.workspace.stencils_y);
        for (k, s) in self.stencils.iter().enumerate() {
            assert_eq!(s.first, sy.first[k] * n + sx.first[k]);
            for a in 0..W {
                let ka = k * W + a;
                assert_eq!(s.x[a], [sx.values[ka], sx.gradients[ka]]);
                assert_eq!(s.y[a], [sy.values[ka], sy.gradients[ka]]);
            }
        }
    }

    /// The basis at particle k (Eqs. 4–5 as two 1D stencils).
    fn evaluate(&self, k: usize) -> Stencil<W> {
        stencil_at(&self.axis, self.nodes_per_side, self.x[k])
    }

    /// Particle k's m N_i, m v N_i and m b N_i − V σ ∇N_i added to the nodes
    /// (phase 1, Eqs. 22–25 at the particle).
    fn scatter(&mut self, k: usize, b: Pair) {
        let (m, s, volume) = (self.mass[k], self.stress[k], self.volume[k]);
        let vs = [s[0] * volume, s[1] * volume, s[2] * volume];
        let (mv, mb) = (mul(splat(m), self.velocity[k]), mul(splat(m), b));
        let n = self.nodes_per_side;
        scatter(&mut self.nodes, n, &self.stencils[k], m, mv, mb, vs);
    }

    /// One step of size dt; phase 1's nodal m, (mv) and f were scattered by
    /// the previous step (or by `from_simulation`).
    pub fn step(&mut self, dt: f64) {
        let n = self.nodes_per_side;
        // Eqs. 26–28: a_i = f_i/m_i, v_i^{t+1} = ((mv)_i + f_i Δt)/m_i; the
        // end-of-step momenta start from zero.
        let nodes = self.nodes.iter().zip(&mut self.motions).zip(&mut self.end);
        for ((node, motion), end) in nodes {
            let m = node.mass;
            let next = add(node.momentum, mul(node.force, splat(dt)));
            *motion = if m > 0.0 {
                Motion {
                    acceleration: div(node.force, splat(m)),
                    velocity: div(next, splat(m)),
                }
            } else {
                Motion::default()
            };
            *end = [0.0; 2];
        }
        walls(n, &mut self.motions, |motion, c| {
            motion.acceleration[c] = 0.0;
            motion.velocity[c] = 0.0;
        });
        // Eqs. 29–30 fused with the end-of-step momenta (Eq. 31).
        let (motions, end) = (&self.motions, &mut self.end);
        let particles = self
            .x
            .iter_mut()
            .zip(&self.x0)
            .zip(&mut self.displacement)
            .zip(&mut self.velocity)
            .zip(&self.mass)
            .zip(&self.stencils);
        for (((((x, &x0), u), v), &m), st) in particles {
            let mut nn = [[0.0; W]; W];
            let (mut a, mut w) = ([0.0; 2], [0.0; 2]);
            for b in 0..W {
                let row = &motions[st.first + b * n..][..W];
                for (i, (node, xa)) in row.iter().zip(&st.x).enumerate() {
                    nn[b][i] = xa[0] * st.y[b][0];
                    a = add(a, mul(splat(nn[b][i]), node.acceleration));
                    w = add(w, mul(splat(nn[b][i]), node.velocity));
                }
            }
            *v = add(*v, mul(splat(dt), a));
            *x = add(*x, mul(splat(dt), w));
            *u = sub(*x, x0);
            let mv = mul(splat(m), *v);
            for b in 0..W {
                let row = &mut end[st.first + b * n..][..W];
                for (node, &nn) in row.iter_mut().zip(&nn[b]) {
                    *node = add(*node, mul(splat(nn), mv));
                }
            }
        }
        // Eq. 33, v_i^L = (mv)_i^L / m_i; the nodes are cleared for the
        // next step's scatter.
        for (node, end) in self.nodes.iter_mut().zip(&mut self.end) {
            let m = node.mass;
            *end = if m > 0.0 {
                div(*end, splat(m))
            } else {
                [0.0; 2]
            };
            *node = Node::default();
        }
        walls(n, &mut self.end, |v, c| v[c] = 0.0);
        // Eqs. 34–37 and 41 fused with the next step's basis, body force
        // and scatter.
        self.time += dt;
        let s = self.force.time_factors(self.time);
        let (axis, force, material) = (&self.axis, self.force, [self.lambda, self.mu]);
        let (end, nodes) = (&self.end, &mut self.nodes);
        let particles = self
            .x
            .iter()
            .zip(&self.velocity)
            .zip(&mut self.deformation)
            .zip(&mut self.stress)
            .zip(&mut self.volume)
            .zip(&mut self.density)
            .zip(self.volume0.iter().zip(&self.mass))
            .zip(self.stencils.iter_mut().zip(&self.force_terms));
        for (((((((&x, &v), f), sigma), volume), rho), (&v0, &m)), (st, terms)) in particles {
            let l = velocity_gradient(end, n, st);
            let j = deform(f, l, dt);
            *volume = j * v0;
            *rho = m / *volume;
            *sigma = neo_hookean(material, f, j);
            *st = stencil_at(axis, n, x);
            let b = force.at(terms, s);
            let vs = [sigma[0] * *volume, sigma[1] * *volume, sigma[2] * *volume];
            scatter(nodes, n, st, m, mul(splat(m), v), mul(splat(m), b), vs);
        }
    }
}

/// The basis at x (Eqs. 4–5 as two 1D stencils) on a grid of n nodes per
/// side.
#[inline(always)]
fn stencil_at<const W: usize, A: Axis<W>>(axis: &A, n: usize, x: Pair) -> Stencil<W> {
    let (first, values, gradients) = axis.evaluate(x);
    Stencil {
        first: first[1] * n + first[0],
        x: std::array::from_fn(|a| [values[a][0], gradients[a][0]]),
        y: std::array::from_fn(|b| [values[b][1], gradients[b][1]]),
    }
}

/// L = Σ_i v_i^L ⊗ ∇N_i at a particle (Eq. 34) from the nodes' v^L, as its
/// columns [L_xx, L_yx] and [L_xy, L_yy].
#[inline(always)]
fn velocity_gradient<const W: usize>(end: &[Pair], n: usize, st: &Stencil<W>) -> [Pair; 2] {
    let mut l = [[0.0; 2]; 2];
    for (b, yb) in st.y.iter().enumerate() {
        let row = &end[st.first + b * n..][..W];
        for (&v, xa) in row.iter().zip(&st.x) {
            // ∇N_i = [N_a' N_b, N_a N_b'].
            let dn = mul([xa[1], xa[0]], *yb);
            l[0] = add(l[0], mul(v, splat(dn[0])));
            l[1] = add(l[1], mul(v, splat(dn[1])));
        }
    }
    l
}

/// F ← (I + L Δt) F (Eq. 35, `l` as [`velocity_gradient`]'s); returns
/// J = det F.
#[inline(always)]
fn deform(f: &mut [f64; 4], l: [Pair; 2], dt: f64) -> f64 {
    let g = [
        1.0 + l[0][0] * dt,
        0.0 + l[1][0] * dt,
        0.0 + l[0][1] * dt,
        1.0 + l[1][1] * dt,
    ];
    let (top, bottom) = ([f[0], f[1]], [f[2], f[3]]);
    let f0 = add(mul(splat(g[0]), top), mul(splat(g[1]), bottom));
    let f1 = add(mul(splat(g[2]), top), mul(splat(g[3]), bottom));
    *f = [f0[0], f0[1], f1[0], f1[1]];
    f[0] * f[3] - f[2] * f[1]
}

/// σ = (λ ln J / J) I + (μ/J)(F Fᵀ − I) (Eq. 41) as [σ_xx, σ_xy, σ_yy],
/// with nalgebra's 0·(λ ln J / J) off the diagonal; `material` = [λ, μ].
#[inline(always)]
fn neo_hookean(material: [f64; 2], f: &[f64; 4], j: f64) -> [f64; 3] {
    let (c, d) = (material[0] * j.ln() / j, material[1] / j);
    let b = [
        f[0] * f[0] + f[1] * f[1],
        f[0] * f[2] + f[1] * f[3],
        f[2] * f[2] + f[3] * f[3],
    ];
    [
        c + (b[0] - 1.0) * d,
        0.0 * c + (b[1] - 0.0) * d,
        c + (b[2] - 1.0) * d,
    ]
}

/// Adds one particle's m N_i, (mv) N_i and (mb) N_i − (Vσ)∇N_i, with
/// vs = [Vσ_xx, Vσ_xy, Vσ_yy], to the nodes of its stencil.
#[inline(always)]
fn scatter<const W: usize>(
    nodes: &mut [Node],
    n: usize,
    st: &Stencil<W>,
    m: f64,
    mv: Pair,
    mb: Pair,
    vs: [f64; 3],
) {
    // (Vσ)∇N_i = [Vσ_xx, Vσ_yx] ∂N/∂x + [Vσ_xy, Vσ_yy] ∂N/∂y.
    let (along_x, along_y) = ([vs[0], vs[1]], [vs[1], vs[2]]);
    for (b, yb) in st.y.iter().enumerate() {
        let row = &mut nodes[st.first + b * n..][..W];
        for (node, xa) in row.iter_mut().zip(&st.x) {
            // [N_a N_b, N_a' N_b] and N_a N_b'.
            let [nn, dx] = mul(*xa, splat(yb[0]));
            let dy = xa[0] * yb[1];
            node.mass += nn * m;
            node.momentum = add(node.momentum, mul(splat(nn), mv));
            let stress = add(mul(along_x, splat(dx)), mul(along_y, splat(dy)));
            node.force = add(node.force, sub(mul(splat(nn), mb), stress));
        }
    }
}

/// Zero normal velocity on the walls: `zero(node, 0)` on the first and last
/// column of nodes, `zero(node, 1)` on the first and last row.
fn walls<T>(n: usize, field: &mut [T], zero: impl Fn(&mut T, usize)) {
    for j in 0..n {
        zero(&mut field[j * n], 0);
        zero(&mut field[j * n + n - 1], 0);
    }
    for i in 0..n {
        zero(&mut field[i], 1);
        zero(&mut field[(n - 1) * n + i], 1);
    }
}
