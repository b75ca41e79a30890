//! # One MUSL step
//!
//! Book §4.2.2, TLS paper §3.1, thesis §3.2. With the basis evaluated at the
//! particle positions x_p^t:
//!
//! 1. lumped mass m_i = Σ m_p φ_i (Eq. 4.5) and internal force (Eq. 4.6, or
//!    its TLS / spline counterpart);
//! 2. a_i = (f_ext − f_int)_i / m_i (Eq. 4.8) with gravity Σ m_p g φ_i and
//!    traction Σ f_p φ_i (thesis §3.2); Dirichlet DOFs get a_i = 0;
//! 3. v_p ← v_p + Δt Σ φ_i a_i (Eq. 4.9);
//! 4. nodal velocity by projection (Eq. 4.10, or TLS/spline with lumped or
//!    consistent mass); Dirichlet DOFs get v_i = 0;
//! 5. Δu_i = Δt v_i (Eq. 4.11);
//! 6. u_p, x_p ← + Σ φ_i Δu_i; Δε_p = Σ ∇φ_i Δu_i (Eqs. 4.12–4.14);
//! 7. σ_p ← σ_p + E Δε_p (small strain, Eq. 4.15) or + (E − σ_p) Δε_p (large
//!    strain, Eq. 4.16);
//! 8. V_p ← (1 + Δε_p) V_p, ρ_p ← ρ_p/(1 + Δε_p) (Eqs. 4.17–4.18).
//!
//! This is Euler–Cromer: explicit in velocity, implicit in displacement. DOFs
//! that receive no mass are inactive (a_i = v_i = 0).

use super::diagnostics::RunDiagnostics;
use super::grid::Grid;
use super::mapping::{
    internal_force, lumped_mass, particle_shapes, project_velocity, scatter, Mapping, MassMatrix,
};
use super::particles::Particles;
use crate::error::{Error, Result};
use serde::Serialize;

/// The constitutive update of step 7.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Constitutive {
    /// σ ← σ + E Δε (book Eq. 4.15).
    SmallStrain,
    /// σ ← σ + (E − σ) Δε (book Eq. 4.16).
    LargeStrain,
}

/// Everything a run needs besides the grid and the particles.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Settings {
    /// Mapping of the internal force.
    pub force_mapping: Mapping,
    /// Mapping of the nodal velocity.
    pub velocity_mapping: Mapping,
    /// Mass matrix of the velocity projection.
    pub mass: MassMatrix,
    /// Constitutive update.
    pub constitutive: Constitutive,
    /// Young's modulus E.
    pub young: f64,
    /// Gravitational acceleration g (signed: −9.81 points down the axis).
    pub gravity: f64,
    /// If set, gravity ramps linearly from 0 to `gravity` over this time and
    /// then stays (the body force of the column compaction, TLS paper §6.2).
    pub gravity_ramp: Option<f64>,
    /// DOFs with homogeneous Dirichlet conditions.
    pub dirichlet: Vec<usize>,
    /// Solve step 2 with the material-point consistent mass M^C = Σ m_p φφᵀ
    /// (sparse Cholesky) instead of the lumped mass (CFL study; book Eq. 4.1).
    pub consistent_acceleration: bool,
}

/// A running simulation.
#[derive(Debug)]
pub struct Simulation {
    /// The background grid.
    pub grid: Grid,
    /// The material points.
    pub particles: Particles,
    /// Run settings.
    pub settings: Settings,
    /// Current time.
    pub time: f64,
    /// Accumulated monitors.
    pub diagnostics: RunDiagnostics,
    breaks: Vec<f64>,
}

fn energy(p: &Particles) -> f64 {
    (0..p.len())
        .map(|k| 0.5 * p.mass[k] * p.v[k] * p.v[k] + 0.5 * p.stress[k] * p.strain[k] * p.volume[k])
        .sum()
}

impl Simulation {
    /// Checks the inputs and starts at t = 0. Every particle must lie in the grid.
    pub fn new(grid: Grid, particles: Particles, settings: Settings) -> Result<Self> {
        let (a, b) = grid.domain();
        if let Some(&x) = particles.x.iter().find(|&&x| x < a || x > b) {
            return Err(Error::OutsideDomain { x, a, b });
        }
        if let Some(&d) = settings.dirichlet.iter().find(|&&d| d >= grid.num_dofs()) {
            return Err(Error::InvalidArgument(format!(
                "Dirichlet DOF {d} outside 0..{}",
                grid.num_dofs()
            )));
        }
        if settings.young.is_nan() || settings.young <= 0.0 {
            return Err(Error::InvalidArgument(format!(
                "Young's modulus must be positive, got {}",
                settings.young
            )));
        }
        crate::error::finite("gravity", settings.gravity)?;
        let breaks = grid.gradient_breaks();
        let diagnostics = RunDiagnostics {
            min_lumped_mass: f64::INFINITY,
            min_mass_diagonal_ratio: f64::INFINITY,
            initial_energy: energy(&particles),
            ..Default::default()
        };
        Ok(Self {
            grid,
            particles,
            settings,
            time: 0.0,
            diagnostics,
            breaks,
        })
    }

    /// The gravitational acceleration at time t.
    pub fn gravity_at(&self, t: f64) -> f64 {
        match self.settings.gravity_ramp {
            Some(t_ramp) if t_ramp > 0.0 => self.settings.gravity * (t / t_ramp).min(1.0),
            _ => self.settings.gravity,
        }
    }

    /// One MUSL step of size dt (module docs, steps 1–8).
    pub fn step(&mut self, dt: f64) -> Result<()> {
        if dt.is_nan() || dt <= 0.0 || dt.is_infinite() {
            return Err(Error::InvalidArgument(format!(
                "the time step must be positive and finite, got {dt}"
            )));
        }
        let n = self.grid.num_dofs();
        let shapes = particle_shapes(&self.grid, &self.particles)?;
        let g = self.gravity_at(self.time);
        let p = &mut self.particles;
        // 1. lumped mass and internal force.
        let m = lumped_mass(n, p, &shapes);
        let f_int = internal_force(&self.grid, p, &shapes, self.settings.force_mapping)?;
        // 2. nodal acceleration.
        let gravity_weights: Vec<f64> = p.mass.iter().map(|m| m * g).collect();
        let f_grav = scatter(n, &gravity_weights, &shapes);
        let f_trac = scatter(n, &p.traction, &shapes);
        let mut a = vec![0.0; n];
        let mut negative = false;
        for i in 0..n {
            if m[i] == 0.0 {
                continue;
            }
            if m[i] < 0.0 {
                negative = true;
            }
            self.diagnostics.min_lumped_mass = self.diagnostics.min_lumped_mass.min(m[i]);
            a[i] = (f_trac[i] + f_grav[i] - f_int[i]) / m[i];
        }
        if negative {
            self.diagnostics.negative_mass_steps += 1;
        }
        if self.settings.consistent_acceleration {
            let mc = crate::mass::material_point_mass(self.grid.basis(), &p.x, &p.mass)?;
            let free: Vec<usize> = (0..n)
                .filter(|&i| mc.get(i, i) > 0.0 && !self.settings.dirichlet.contains(&i))
                .collect();
            let rhs: Vec<f64> = free
                .iter()
                .map(|&i| f_trac[i] + f_grav[i] - f_int[i])
                .collect();
            let sol = crate::solve::direct::cholesky_solve(&mc.submatrix(&free, &free), &rhs)?;
            a = vec![0.0; n];
            for (k, &i) in free.iter().enumerate() {
                a[i] = sol[k];
            }
        }
        for &d in &self.settings.dirichlet {
            a[d] = 0.0;
        }
        // 3. particle velocity.
        for (k, s) in shapes.iter().enumerate() {
            let acc: f64 = s
                .values
                .iter()
                .enumerate()
                .map(|(j, phi)| phi * a[s.first + j])
                .sum();
            p.v[k] += dt * acc;
        }
        // 4. nodal velocity.
        let total_mass = p.total_mass();
        let total_momentum = p.total_momentum();
        let proj = project_velocity(
            &self.grid,
            p,
            &shapes,
            self.settings.velocity_mapping,
            self.settings.mass,
        )?;
        self.diagnostics.solver_iterations += proj.solver_iterations;
        self.diagnostics.min_mass_diagonal_ratio = self
            .diagnostics
            .min_mass_diagonal_ratio
            .min(proj.diagonal_ratio);
        let vmax = proj.velocity.iter().map(|v| v.abs()).fold(0.0, f64::max);
        self.diagnostics.max_nodal_velocity = self.diagnostics.max_nodal_velocity.max(vmax);
        let pmax = p.v.iter().map(|v| v.abs()).fold(0.0, f64::max);
        self.diagnostics.max_particle_velocity = self.diagnostics.max_particle_velocity.max(pmax);
        self.diagnostics.max_mass_error = self
            .diagnostics
            .max_mass_error
            .max((proj.grid_mass - total_mass).abs() / total_mass);
        if total_momentum != 0.0 {
            let e = (proj.grid_momentum - total_momentum).abs() / total_momentum.abs();
            self.diagnostics.max_momentum_error = self.diagnostics.max_momentum_error.max(e);
        }
        let mut v = proj.velocity;
        for &d in &self.settings.dirichlet {
            v[d] = 0.0;
        }
        // 5.–8. particle update.
        let young = self.settings.young;
        for (k, s) in shapes.iter().enumerate() {
            let mut du = 0.0;
            let mut deps = 0.0;
            for (j, (phi, grad)) in s.values.iter().zip(&s.gradients).enumerate() {
                let dui = dt * v[s.first + j];
                du += phi * dui;
                deps += grad * dui;
            }
            let x_old = p.x[k];
            p.u[k] += du;
            p.x[k] += du;
            p.stress[k] += match self.settings.constitutive {
                Constitutive::SmallStrain => young * deps,
                Constitutive::LargeStrain => (young - p.stress[k]) * deps,
            };
            p.volume[k] *= 1.0 + deps;
            p.density[k] /= 1.0 + deps;
            p.strain[k] += deps;
            self.diagnostics.max_abs_strain =
                self.diagnostics.max_abs_strain.max(p.strain[k].abs());
            let (lo, hi) = if x_old < p.x[k] {
                (x_old, p.x[k])
            } else {
                (p.x[k], x_old)
            };
            self.diagnostics.grid_crossings +=
                self.breaks.iter().filter(|&&b| lo < b && b <= hi).count();
        }
        self.time += dt;
        self.diagnostics.steps += 1;
        let bad = (0..p.len()).find(|&k| {
            !(p.x[k].is_finite() && p.v[k].is_finite() && p.stress[k].is_finite())
                || p.volume[k] <= 0.0
        });
        if let Some(k) = bad {
            return Err(Error::BlowUp(format!(
                "particle {k} became non-physical at step {} (t = {:e}): x = {}, v = {}, σ = {}, V = {}{}",
                self.diagnostics.steps,
                self.time,
                p.x[k],
                p.v[k],
                p.stress[k],
                p.volume[k],
                if self.diagnostics.negative_mass_steps > 0 { "; negative lumped masses were seen" } else { "" }
            )));
        }
        let (lo, hi) = self.grid.domain();
        if let Some(k) = (0..p.len()).find(|&k| p.x[k] < lo || p.x[k] > hi) {
            return Err(Error::BlowUp(format!(
                "particle {k} left the grid [{lo}, {hi}] at step {}: x = {}",
                self.diagnostics.steps, p.x[k]
            )));
        }
        Ok(())
    }

    /// `steps` steps of size dt; the final energy is recorded.
    pub fn run(&mut self, dt: f64, steps: usize) -> Result<()> {
        for _ in 0..steps {
            self.step(dt)?;
        }
        self.diagnostics.final_energy = energy(&self.particles);
        Ok(())
    }
}
