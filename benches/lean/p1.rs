//! # A lean 1D P1 MUSL step: the speed limit hompm's step is measured against
//!
//! Issue #39 asks how far hompm's step is from the machine. This module is
//! the yardstick: the same step as `mpm::musl::Simulation::step` for linear
//! Lagrange elements (thesis §5.1), the direct mapping, a lumped mass, MUSL
//! with FLIP and the book's positions, small strain (book §4.2.2,
//! Eqs. 4.5–4.18), written as two particle loops and one node loop, with
//! no diagnostics. It computes **bit for bit** what hompm computes
//! (tests/spec/speed/lean_p1.rs), because every sum is formed from the same
//! products in the same order:
//! - the basis of element k = ⌊(x − a)/h⌋ at ξ = (x − x_k)/h clamped to
//!   [0, 1]: φ = (1 − ξ, ξ), ∇φ = (−1/h, 1/h) with 1/h rounded once;
//! - m_i and f_i accumulate particle by particle in particle order
//!   (book Eqs. 4.5, 4.6); a_i = (0 + 0 − f_i)/m_i (Eq. 4.8);
//! - the projection's lumped mass Σ_p m_p φ_i Σ_j φ_j is m_i itself, since
//!   fl(fl(1 − ξ) + ξ) = 1 for ξ in [0, 1] (Eq. 4.10);
//! - Δu_p = Σ φ_i (Δt v_i), Δε_p = Σ ∇φ_i (Δt v_i) (Eqs. 4.11–4.14).
//!
//! Where it saves time: nodal sums stay in registers while consecutive
//! particles share an element (`Pair`); the basis of a particle is evaluated in the loop
//! that moves it and kept for the next step; the velocity update (Eq. 4.9)
//! is fused with the projection's scatter, and the position, stress and
//! volume updates (Eqs. 4.11–4.18) with the next step's basis and its
//! scatter of mass and internal force.
//!
//! Items: `LeanP1`.

use hompm::mpm::musl::{Constitutive, Simulation};

/// The state of the lean step: particles as arrays, the basis at them
/// (element and ξ), the nodal vectors, the constants.
pub struct LeanP1 {
    pub x: Vec<f64>,
    pub displacement: Vec<f64>,
    pub velocity: Vec<f64>,
    pub stress: Vec<f64>,
    pub volume: Vec<f64>,
    pub density: Vec<f64>,
    pub strain: Vec<f64>,
    mass: Vec<f64>,
    element: Vec<usize>,
    xi: Vec<f64>,
    nodal_mass: Vec<f64>,
    nodal_force: Vec<f64>,
    acceleration: Vec<f64>,
    momentum: Vec<f64>,
    a: f64,
    h: f64,
    inverse_h: f64,
    elements: usize,
    young: f64,
    dirichlet: Vec<usize>,
}

impl LeanP1 {
    /// The state of a hompm simulation of P1 MPM (direct mapping, lumped
    /// mass, the book's conventions, small strain) before its next step.
    pub fn from_simulation(sim: &Simulation) -> Self {
        let s = &sim.settings;
        assert_eq!(s.constitutive, Constitutive::SmallStrain);
        assert_eq!(s.gravity, 0.0);
        let p = &sim.particles;
        assert!(p.traction.iter().all(|&t| t == 0.0));
        let (a, b) = sim.grid.domain();
        let elements = sim.grid.num_cells();
        let h = (b - a) / elements as f64;
        let n = p.len();
        let mut lean = Self {
            x: p.x.clone(),
            displacement: p.displacement.clone(),
            velocity: p.velocity.clone(),
            stress: p.stress.clone(),
            volume: p.volume.clone(),
            density: p.density.clone(),
            strain: p.strain.clone(),
            mass: p.mass.clone(),
            element: vec![0; n],
            xi: vec![0.0; n],
            nodal_mass: vec![0.0; elements + 1],
            nodal_force: vec![0.0; elements + 1],
            acceleration: vec![0.0; elements + 1],
            momentum: vec![0.0; elements + 1],
            a,
            h,
            inverse_h: 1.0 / h,
            elements,
            young: s.young,
            dirichlet: s.dirichlet.clone(),
        };
        lean.nodal_mass.fill(0.0);
        lean.nodal_force.fill(0.0);
        for k in 0..n {
            lean.locate_and_scatter(k);
        }
        lean
    }

    /// The basis of particle k (element, ξ) and its mass and internal
    /// force added to the nodes (book Eqs. 4.5–4.6).
    fn locate_and_scatter(&mut self, k: usize) {
        let grid = Basis {
            a: self.a,
            h: self.h,
            inverse_h: self.inverse_h,
            last: self.elements - 1,
        };
        let (e, xi) = grid.locate(self.x[k]);
        self.element[k] = e;
        self.xi[k] = xi;
        let sv = self.stress[k] * self.volume[k];
        grid.scatter(
            e,
            xi,
            self.mass[k],
            sv,
            &mut self.nodal_mass,
            &mut self.nodal_force,
        );
    }

    /// One MUSL step of size dt; the nodal mass and force of its start were
    /// scattered by the previous step (or by `from_simulation`).
    pub fn step(&mut self, dt: f64) {
        let nodes = self.elements + 1;
        for i in 0..nodes {
            let m = self.nodal_mass[i];
            self.acceleration[i] = if m != 0.0 {
                (0.0 + 0.0 - self.nodal_force[i]) / m
            } else {
                0.0
            };
        }
        for &i in &self.dirichlet {
            self.acceleration[i] = 0.0;
        }
        // Eq. 4.9 (FLIP) fused with the projection's momentum (Eq. 4.10).
        self.momentum.fill(0.0);
        let (acceleration, momentum) = (&self.acceleration, &mut self.momentum);
        let particles = self
            .velocity
            .iter_mut()
            .zip(&self.mass)
            .zip(self.element.iter().zip(&self.xi));
        let mut p = Pair::EMPTY;
        for ((velocity, &m), (&e, &xi)) in particles {
            let phi = [1.0 - xi, xi];
            let a = &acceleration[e..e + 2];
            *velocity += dt * (phi[0] * a[0] + phi[1] * a[1]);
            let mv = m * *velocity;
            p.move_to(e, momentum);
            p.sums[0] += mv * phi[0];
            p.sums[1] += mv * phi[1];
        }
        p.finish(momentum);
        // v_i = p_i / m_i where the mass reaches (the lumped mass of the
        // projection is the nodal mass, bit for bit, for P1).
        for i in 0..nodes {
            let m = self.nodal_mass[i];
            self.momentum[i] = if m != 0.0 { self.momentum[i] / m } else { 0.0 };
        }
        for &i in &self.dirichlet {
            self.momentum[i] = 0.0;
        }
        // Eqs. 4.11–4.18 fused with the next step's basis and scatter.
        self.nodal_mass.fill(0.0);
        self.nodal_force.fill(0.0);
        let grid = Basis {
            a: self.a,
            h: self.h,
            inverse_h: self.inverse_h,
            last: self.elements - 1,
        };
        let v = std::mem::take(&mut self.momentum);
        let (young, ih) = (self.young, self.inverse_h);
        let (nodal_mass, nodal_force) = (&mut self.nodal_mass, &mut self.nodal_force);
        let particles = self
            .x
            .iter_mut()
            .zip(&mut self.displacement)
            .zip(&mut self.stress)
            .zip(&mut self.volume)
            .zip(&mut self.density)
            .zip(&mut self.strain)
            .zip(&self.mass)
            .zip(self.element.iter_mut().zip(&mut self.xi));
        let (mut mass_sums, mut force_sums) = (Pair::EMPTY, Pair::EMPTY);
        for (((((((x, u), stress), volume), density), strain), &m), (e, xi)) in particles {
            let (dv0, dv1) = (dt * v[*e], dt * v[*e + 1]);
            let du = 0.0 + (1.0 - *xi) * dv0 + *xi * dv1;
            let deps = 0.0 + -ih * dv0 + ih * dv1;
            *u += du;
            *x += du;
            *stress += young * deps;
            *volume *= 1.0 + deps;
            *density /= 1.0 + deps;
            *strain += deps;
            (*e, *xi) = grid.locate(*x);
            mass_sums.move_to(*e, nodal_mass);
            force_sums.move_to(*e, nodal_force);
            let sv = *stress * *volume;
            mass_sums.sums[0] += m * (1.0 - *xi);
            mass_sums.sums[1] += m * *xi;
            force_sums.sums[0] += sv * -ih;
            force_sums.sums[1] += sv * ih;
        }
        mass_sums.finish(nodal_mass);
        force_sums.finish(nodal_force);
        self.momentum = v;
    }
}

/// The uniform P1 mesh: element k = ⌊(x − a)/h⌋ (at most the last), ξ and
/// the scatter of one particle's mass and σV∇φ (book Eqs. 4.5–4.6).
#[derive(Clone, Copy)]
struct Basis {
    a: f64,
    h: f64,
    inverse_h: f64,
    last: usize,
}

impl Basis {
    #[inline(always)]
    fn locate(&self, x: f64) -> (usize, f64) {
        let e = ((((x - self.a) / self.h) as i64).max(0) as usize).min(self.last);
        let xi = ((x - (self.a + e as i64 as f64 * self.h)) / self.h).clamp(0.0, 1.0);
        (e, xi)
    }

    #[inline(always)]
    fn scatter(&self, e: usize, xi: f64, m: f64, sv: f64, mass: &mut [f64], force: &mut [f64]) {
        let (mass, force) = (&mut mass[e..e + 2], &mut force[e..e + 2]);
        mass[0] += m * (1.0 - xi);
        mass[1] += m * xi;
        force[0] += sv * -self.inverse_h;
        force[1] += sv * self.inverse_h;
    }
}

/// The two nodal sums of the element a run of particles shares, kept in
/// registers (the lean step): when the element changes to the next
/// one, the shared node's sum stays in a register and only the node that
/// leaves is stored and the one that enters loaded; any other change
/// stores both and loads both. The same additions in the same order as
/// adding into the nodal vector, so the same bits.
#[derive(Clone, Copy)]
struct Pair {
    element: usize,
    sums: [f64; 2],
}

impl Pair {
    /// No element yet.
    const EMPTY: Self = Self {
        element: usize::MAX,
        sums: [0.0; 2],
    };

    #[inline(always)]
    fn move_to(&mut self, e: usize, nodal: &mut [f64]) {
        if e == self.element {
            return;
        }
        if self.element != usize::MAX && e == self.element + 1 {
            nodal[self.element] = self.sums[0];
            self.sums = [self.sums[1], nodal[e + 1]];
        } else {
            self.finish(nodal);
            self.sums = [nodal[e], nodal[e + 1]];
        }
        self.element = e;
    }

    /// Stores the sums of the current element.
    #[inline(always)]
    fn finish(&self, nodal: &mut [f64]) {
        if self.element != usize::MAX {
            nodal[self.element] = self.sums[0];
            nodal[self.element + 1] = self.sums[1];
        }
    }
}
