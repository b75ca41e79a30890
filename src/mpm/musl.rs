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
//!
//! [`Simulation::step`] reads as this list: one function per numbered step,
//! each over struct-of-arrays data and a [`StepWorkspace`] that is allocated
//! when the simulation starts. A step therefore costs O(particles + DOFs)
//! and, with the direct mapping and a lumped mass, allocates nothing
//! (tests/allocations.rs). The monitors of a run are recorded in one place,
//! [`RunDiagnostics`].
//!
//! [`Simulation::step_observed`] calls a [`StepObserver`] after each
//! numbered function with the simulation as that function left it
//! ([`StepPoint`] names the point): `hompm trace` records the quantities of
//! each equation from the step that runs, never from a copy of it, and
//! tests plant defects through it. [`Simulation::step`] passes
//! [`NoObserver`], whose empty calls the compiler removes.
//!
//! Another code's step (`--scheme usl`, …; [`super::conventions`]) adds
//! the grid velocity at the start of the step; with a mapping that maps
//! the loads too (the MLS paper's code's MLS, `super::mapping::mls`),
//! steps 1–2 take the mass, momentum, loads and, with a consistent mass,
//! the acceleration from the mapping (the child module `reconstructed`).
//!
//! What a run is set up with, [`Settings`] and [`Constitutive`], is in
//! [`super::settings`] (re-exported here).
//!
//! Items: [`StepWorkspace`], [`Simulation`], [`StepPoint`],
//! [`StepObserver`], [`NoObserver`], [`StepSummary`].

use super::conventions::{BodyForceAt, Positions, Scheme, Transfer};
use super::diagnostics::{LumpedMassScan, RunDiagnostics};
use super::grid::Grid;
use super::mapping::{internal_force, project_velocity};
use super::particles::Particles;
pub use super::settings::{BodyForceField, Constitutive, GravityRamp, RampTimeLevel, Settings};
pub use super::workspace::StepWorkspace;
pub use manufactured::neo_hookean_1d;
use monitors::particle_energy;
pub use monitors::StepSummary;

mod fused;
mod loads;
mod manufactured;
mod monitors;
mod other_codes;
mod particle_equations;
mod physical;
mod reconstructed;
use crate::basis::{with_width, Stencils};
use crate::error::{Error, Result};
use other_codes::{check_conventions, move_and_strain};
use particle_equations::{
    displacement_and_strain_increment, large_strain_stress, small_strain_stress,
    update_volume_density_strain,
};
use serde::Serialize;

/// The points of a step after which a [`StepObserver`] is called, in the
/// order a step reaches them; each names the equations whose quantities
/// are then final.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum StepPoint {
    /// Step 1: m_i (book Eq. 4.5) and the external loads (thesis §3.2)
    /// in `workspace().mass`, `gravity_force`, `traction_force`.
    MassAndLoads,
    /// Another code's step only ([`super::conventions`]): the grid momentum
    /// p_i and velocity v_i^n = p_i/m_i (0 on Dirichlet DOFs) in
    /// `workspace().nodal_momentum`, `nodal_velocity`.
    GridVelocity,
    /// Step 1: f_int (book Eq. 4.6) in `workspace().internal_force`.
    InternalForce,
    /// Step 2: a_i (book Eq. 4.8) before the boundary conditions, in
    /// `workspace().acceleration`.
    Acceleration,
    /// Step 2: a_i = 0 on the Dirichlet DOFs.
    AccelerationConditions,
    /// Another code's step only: ṽ_i = v_i^n + Δt a_i (0 on Dirichlet
    /// DOFs) in `workspace().updated_velocity`.
    UpdatedGridVelocity,
    /// Step 3: v_p (book Eq. 4.9) in `particles.velocity`.
    ParticleVelocity,
    /// Step 4: the projection's right-hand side p_i and v_i (book Eq. 4.10)
    /// before the boundary conditions, in `workspace().mapping`.
    NodalVelocity,
    /// Step 4: v_i = 0 on the Dirichlet DOFs.
    NodalVelocityConditions,
    /// Steps 5–6: u_p, x_p and Δε_p (book Eqs. 4.11–4.14).
    Positions,
    /// Step 7: σ_p (book Eq. 4.15 or 4.16).
    Stress,
    /// Step 8: V_p and ρ_p (book Eqs. 4.17–4.18).
    VolumeAndDensity,
}

/// Called by [`Simulation::step_observed`] after each numbered function of
/// a step, with the simulation as that function left it. An observer that
/// only reads leaves the run bit-identical to [`Simulation::step`]; one
/// that writes plants a defect (the tests of `hompm check` do).
pub trait StepObserver {
    /// Whether the observer looks: a step nobody observes may take the
    /// fused loops (`fused`), the same numbers without the [`StepPoint`]s.
    const OBSERVES: bool = true;

    /// The step has just passed `point`; `sim.diagnostics.steps` is the
    /// number of steps completed before this one.
    fn observe(&mut self, point: StepPoint, sim: &mut Simulation) -> Result<()>;
}

/// The observer that does nothing ([`Simulation::step`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct NoObserver;

impl StepObserver for NoObserver {
    const OBSERVES: bool = false;

    #[inline(always)]
    fn observe(&mut self, _: StepPoint, _: &mut Simulation) -> Result<()> {
        Ok(())
    }
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
    /// Whether a step records [`RunDiagnostics`] (true unless turned off
    /// with [`Simulation::without_diagnostics`]).
    records_diagnostics: bool,
    workspace: StepWorkspace,
}

/// Kinetic plus strain energy Σ_p ½ m_p v_p² + ½ σ_p ε_p V_p.
fn energy(p: &Particles) -> f64 {
    (0..p.len())
        .map(|k| {
            particle_energy(
                p.mass[k],
                p.velocity[k],
                p.stress[k],
                p.strain[k],
                p.volume[k],
            )
        })
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
        manufactured::check_material(&settings)?;
        check_conventions(&settings, &grid)?;
        let diagnostics = RunDiagnostics {
            min_lumped_mass: f64::INFINITY,
            min_mass_diagonal_ratio: f64::INFINITY,
            initial_energy: energy(&particles),
            ..Default::default()
        };
        let workspace = StepWorkspace::new(&grid, particles.len())?;
        Ok(Self {
            grid,
            particles,
            settings,
            time: 0.0,
            diagnostics,
            records_diagnostics: true,
            workspace,
        })
    }

    /// Kinetic plus strain energy Σ_p ½ m_p v_p² + ½ σ_p ε_p V_p of the
    /// particles now (the quantity `diagnostics.initial_energy` and
    /// `final_energy` record; the stability monitor watches it every step).
    pub fn energy(&self) -> f64 {
        energy(&self.particles)
    }

    /// The buffers of the last step: the basis at the particles, the nodal
    /// mass, forces, acceleration and projected velocity.
    pub fn workspace(&self) -> &StepWorkspace {
        &self.workspace
    }

    /// The buffers of the step, writable: for an observer that plants a
    /// defect between two numbered functions.
    pub fn workspace_mut(&mut self) -> &mut StepWorkspace {
        &mut self.workspace
    }

    /// One MUSL step of size dt (module docs, steps 1–8).
    pub fn step(&mut self, dt: f64) -> Result<()> {
        self.step_observed(dt, &mut NoObserver)
    }

    /// One MUSL step of size dt that calls `observer` after each numbered
    /// function ([`StepPoint`]).
    pub fn step_observed<O: StepObserver>(&mut self, dt: f64, observer: &mut O) -> Result<()> {
        super::check_time_step(dt)?;
        if !O::OBSERVES && self.step_is_fused() {
            return self.step_fused(dt, false).map(|_| ());
        }
        let conventions = self.settings.conventions;
        let other_code = conventions.needs_grid_velocity();
        self.evaluate_basis_at_particles()?;
        self.map_mass_and_loads(dt)?;
        observer.observe(StepPoint::MassAndLoads, self)?;
        if other_code {
            self.map_grid_velocity();
            observer.observe(StepPoint::GridVelocity, self)?;
        }
        if conventions.scheme == Scheme::Usf {
            self.strain_from_grid_velocity(dt);
            self.update_stresses();
            observer.observe(StepPoint::Stress, self)?;
            self.update_volumes_and_densities();
            observer.observe(StepPoint::VolumeAndDensity, self)?;
        }
        self.map_internal_force()?;
        observer.observe(StepPoint::InternalForce, self)?;
        self.nodal_acceleration()?;
        observer.observe(StepPoint::Acceleration, self)?;
        self.apply_acceleration_conditions();
        observer.observe(StepPoint::AccelerationConditions, self)?;
        if other_code {
            self.update_grid_velocity(dt);
            observer.observe(StepPoint::UpdatedGridVelocity, self)?;
        }
        self.update_particle_velocities(dt);
        observer.observe(StepPoint::ParticleVelocity, self)?;
        if conventions.scheme == Scheme::Musl {
            self.project_nodal_velocities()?;
            observer.observe(StepPoint::NodalVelocity, self)?;
            self.apply_velocity_conditions();
            observer.observe(StepPoint::NodalVelocityConditions, self)?;
        }
        self.update_particle_positions(dt);
        observer.observe(StepPoint::Positions, self)?;
        if conventions.scheme != Scheme::Usf {
            self.update_stresses();
            observer.observe(StepPoint::Stress, self)?;
            self.update_volumes_and_densities();
            observer.observe(StepPoint::VolumeAndDensity, self)?;
        }
        if self.records_diagnostics {
            self.record_particle_monitors();
        }
        self.time += dt;
        self.diagnostics.steps += 1;
        self.check_particles_are_physical()
    }

    /// `steps` steps of size dt; the final energy is recorded (unless the
    /// diagnostics are off).
    pub fn run(&mut self, dt: f64, steps: usize) -> Result<()> {
        for _ in 0..steps {
            self.step(dt)?;
        }
        if self.records_diagnostics {
            self.diagnostics.final_energy = energy(&self.particles);
        }
        Ok(())
    }

    /// φ_i(x_p) and ∇φ_i(x_p) (or DDMPM's ∇̄φ_i) at every particle, the
    /// break counts for the crossing monitor, and what the mappings need
    /// (particles binned by cell, quadrature stencils).
    fn evaluate_basis_at_particles(&mut self) -> Result<()> {
        self.grid
            .refresh_node_integrals(&self.particles.x, &self.particles.volume)?;
        let (grid, p, ws) = (&self.grid, &self.particles, &mut self.workspace);
        // Δε_p's buffer (a fused step leaves it empty) and the crossing
        // monitor's: the breaks at or below each particle as the step
        // starts, N(x_p^t), with the diagnostics on (the count kept from
        // the last step, checked).
        ws.strain_increment.resize(p.len(), 0.0);
        grid.fill_stencils(&p.x, |&x| x, &mut ws.stencils, &mut ws.scratch)?;
        if self.records_diagnostics {
            ws.breaks_before.resize(p.len(), 0);
            for (count, &x) in ws.breaks_before.iter_mut().zip(&p.x) {
                grid.keep_break_count(count, x);
            }
        }
        let mappings = [self.settings.force_mapping, self.settings.velocity_mapping];
        ws.mapping
            .begin_step_with(grid, p, &mappings, self.settings.tls_density_average)
    }

    /// Step 1, book Eq. (4.5) and thesis §3.2: the lumped mass
    /// m_i = Σ_p m_p φ_i(x_p), and the gravity and traction loads
    /// Σ_p m_p g φ_i(x_p) and Σ_p f_p^trac φ_i(x_p).
    fn map_mass_and_loads(&mut self, dt: f64) -> Result<()> {
        if self.through_reconstruction() {
            return self.map_mass_and_loads_through_reconstruction(dt);
        }
        let g = self.gravity_in_step(dt);
        let (p, ws) = (&self.particles, &mut self.workspace);
        for v in [&mut ws.mass, &mut ws.gravity_force, &mut ws.traction_force] {
            v.fill(0.0);
        }
        crate::mass::add_lumped_mass(&ws.stencils, &p.mass, &mut ws.mass);
        // A load with every weight zero stays +0.0, exactly what adding its
        // ±0 terms would give, so it is skipped.
        if g != 0.0 {
            match self.settings.conventions.body_force {
                BodyForceAt::Particles => ws
                    .stencils
                    .scatter_values(|k| p.mass[k] * g, &mut ws.gravity_force),
                BodyForceAt::Nodes => {
                    for (f, m) in ws.gravity_force.iter_mut().zip(&ws.mass) {
                        *f = m * g;
                    }
                }
            }
        }
        if p.has_traction() {
            ws.stencils
                .scatter_values(|k| p.traction[k], &mut ws.traction_force);
        }
        self.map_body_force_field();
        Ok(())
    }

    /// Step 1, book Eq. (4.6) (or Eq. 4.38 with TLS, thesis §7.2 with
    /// splines): the internal force f_i = Σ_p σ_p V_p ∇φ_i(x_p).
    fn map_internal_force(&mut self) -> Result<()> {
        let ws = &mut self.workspace;
        ws.internal_force.fill(0.0);
        internal_force(
            &self.grid,
            &self.particles,
            &ws.stencils,
            self.settings.force_mapping,
            &mut ws.mapping,
            &mut ws.internal_force,
        )
    }

    /// Step 2, book Eq. (4.8): a_i = (f_trac + f_grav − f_int)_i / m_i on DOFs
    /// with mass (a_i = 0 elsewhere). With
    /// `consistent_acceleration` the material-point consistent mass replaces
    /// m_i (book Eq. 4.1). Negative lumped masses (P2, thesis §5.2) are
    /// recorded, in the same pass over the nodes.
    fn nodal_acceleration(&mut self) -> Result<()> {
        let ws = &mut self.workspace;
        let loads = ws.traction_force.iter().zip(&ws.gravity_force);
        let nodes = ws.acceleration.iter_mut().zip(&ws.mass);
        let (mut scan, records) = (LumpedMassScan::default(), self.records_diagnostics);
        for ((a, &m), ((&trac, &grav), &int)) in nodes.zip(loads.zip(&ws.internal_force)) {
            *a = if m != 0.0 {
                (trac + grav - int) / m
            } else {
                0.0
            };
            if records {
                scan.add(m);
            }
        }
        if records {
            self.diagnostics.record_lumped_mass_scan(scan);
        }
        if self.settings.consistent_acceleration {
            self.consistent_nodal_acceleration()?;
        }
        self.acceleration_through_reconstruction()
    }

    /// Step 2's boundary conditions: a_i = 0 on the Dirichlet DOFs.
    fn apply_acceleration_conditions(&mut self) {
        for &i in &self.settings.dirichlet {
            self.workspace.acceleration[i] = 0.0;
        }
    }

    /// Step 2 with the consistent mass M^C = Σ_p m_p φ φᵀ (sparse Cholesky on
    /// the DOFs with mass that are not Dirichlet DOFs).
    fn consistent_nodal_acceleration(&mut self) -> Result<()> {
        let (p, ws) = (&self.particles, &mut self.workspace);
        let mc = crate::mass::material_point_mass(self.grid.basis(), &p.x, &p.mass)?;
        let n = ws.mass.len();
        let free: Vec<usize> = (0..n)
            .filter(|&i| mc.get(i, i) > 0.0 && !self.settings.dirichlet.contains(&i))
            .collect();
        let rhs: Vec<f64> = free
            .iter()
            .map(|&i| ws.traction_force[i] + ws.gravity_force[i] - ws.internal_force[i])
            .collect();
        let sol = crate::solve::direct::cholesky_solve(&mc.submatrix(&free, &free), &rhs)?;
        ws.acceleration.fill(0.0);
        for (k, &i) in free.iter().enumerate() {
            ws.acceleration[i] = sol[k];
        }
        Ok(())
    }

    /// Step 3, book Eq. (4.9): v_p ← v_p + Δt Σ_i φ_i(x_p) a_i (FLIP).
    /// With `--transfer pic` v_p ← Σ_i φ_i ṽ_i; with `flip:α`
    /// v_p ← α (v_p + Δt Σ_i φ_i a_i) + (1 − α) Σ_i φ_i ṽ_i.
    fn update_particle_velocities(&mut self, dt: f64) {
        let ws = &self.workspace;
        let velocity = &mut self.particles.velocity;
        match self.settings.conventions.transfer {
            Transfer::Flip => ws.stencils.add_interpolated(dt, &ws.acceleration, velocity),
            // APIC is refused in 1D (`check_conventions`); its particle
            // velocity is PIC's.
            Transfer::Pic | Transfer::Apic => {
                for (k, vp) in velocity.iter_mut().enumerate() {
                    *vp = ws.stencils.interpolate(k, &ws.updated_velocity);
                }
            }
            Transfer::Blend(alpha) => {
                for (k, vp) in velocity.iter_mut().enumerate() {
                    let flip = *vp + dt * ws.stencils.interpolate(k, &ws.acceleration);
                    let pic = ws.stencils.interpolate(k, &ws.updated_velocity);
                    *vp = alpha * flip + (1.0 - alpha) * pic;
                }
            }
        }
    }

    /// Step 4, book Eq. (4.10) (or Eqs. 4.39–4.44 with TLS, thesis §7.2
    /// with splines): the nodal velocity from M v = p with the updated
    /// particle velocities. Records the projection's conservation errors
    /// and velocity extremes.
    fn project_nodal_velocities(&mut self) -> Result<()> {
        let p = &self.particles;
        let ws = &mut self.workspace;
        let proj = project_velocity(
            &self.grid,
            p,
            &ws.stencils,
            self.settings.velocity_mapping,
            self.settings.mass,
            &mut ws.mapping,
        )?;
        if !self.records_diagnostics {
            return Ok(());
        }
        let total_mass = p.total_mass();
        let total_momentum = p.total_momentum();
        self.diagnostics.record_projection(
            &proj,
            &ws.mapping.velocity,
            &p.velocity,
            total_mass,
            total_momentum,
        );
        Ok(())
    }

    /// Step 4's boundary conditions: v_i = 0 on the Dirichlet DOFs.
    fn apply_velocity_conditions(&mut self) {
        for &i in &self.settings.dirichlet {
            self.workspace.mapping.velocity[i] = 0.0;
        }
    }

    /// Steps 5–6, book Eqs. (4.11)–(4.14): Δu_i = Δt v_i; u_p and x_p grow by
    /// Σ_i φ_i(x_p) Δu_i; the strain increment is Δε_p = Σ_i ∇φ_i(x_p) Δu_i.
    ///
    /// Another code's step: `--positions grid` moves the particles with ṽ_i
    /// (MLS paper Eq. 30); USL takes Δε_p from ṽ_i too; USF has taken it
    /// already and only moves the particles.
    fn update_particle_positions(&mut self, dt: f64) {
        let conventions = self.settings.conventions;
        if conventions.scheme == Scheme::Usl && self.through_reconstruction() {
            return self.move_and_strain_as_the_mls_code(dt);
        }
        let (p, ws) = (&mut self.particles, &mut self.workspace);
        let s = &ws.stencils;
        let moved_by = match conventions.positions {
            Positions::Projected => &ws.mapping.velocity,
            Positions::Grid => &ws.updated_velocity,
        };
        let deps = &mut ws.strain_increment;
        match conventions.scheme {
            Scheme::Musl if conventions.positions == Positions::Projected => {
                let v = &ws.mapping.velocity;
                with_width!(s.width(), update_positions::<W>(p, s, v, dt, deps));
            }
            Scheme::Musl => move_and_strain(p, s, moved_by, &ws.mapping.velocity, dt, deps),
            Scheme::Usl => move_and_strain(p, s, moved_by, moved_by, dt, deps),
            Scheme::Usf => {
                for k in 0..p.len() {
                    let du = dt * s.interpolate(k, moved_by);
                    p.displacement[k] += du;
                    p.x[k] += du;
                }
            }
        }
    }

    /// Step 7: σ_p ← σ_p + E Δε_p (small strain, book Eq. 4.15) or
    /// σ_p ← σ_p + (E − σ_p) Δε_p (large strain, Eq. 4.16).
    fn update_stresses(&mut self) {
        let young = self.settings.young;
        let deps = &self.workspace.strain_increment;
        let stress = &mut self.particles.stress;
        match self.settings.constitutive {
            Constitutive::SmallStrain => {
                for (s, &de) in stress.iter_mut().zip(deps) {
                    *s = small_strain_stress(*s, young, de);
                }
            }
            Constitutive::LargeStrain => {
                for (s, &de) in stress.iter_mut().zip(deps) {
                    *s = large_strain_stress(*s, young, de);
                }
            }
            Constitutive::NeoHookean => self.update_neo_hookean_stresses(),
        }
    }

    /// Step 8, book Eqs. (4.17)–(4.18): V_p ← (1 + Δε_p) V_p,
    /// ρ_p ← ρ_p / (1 + Δε_p); the accumulated strain ε_p grows by Δε_p.
    fn update_volumes_and_densities(&mut self) {
        if self.settings.constitutive == Constitutive::NeoHookean {
            return self.update_neo_hookean_volumes();
        }
        let p = &mut self.particles;
        for (k, &de) in self.workspace.strain_increment.iter().enumerate() {
            update_volume_density_strain(&mut p.volume[k], &mut p.density[k], &mut p.strain[k], de);
        }
    }

    /// The per-particle monitors of [`RunDiagnostics`]: the largest |ε_p| and
    /// this step's grid crossings |N(x_p^{t+Δt}) − N(x_p^t)|, N(x) the
    /// number of gradient breaks at or below x (thesis §3.3).
    fn record_particle_monitors(&mut self) {
        let (p, ws) = (&self.particles, &mut self.workspace);
        let mut crossings = 0;
        for (before, &x) in ws.breaks_before.iter_mut().zip(&p.x) {
            crossings += self.grid.crossings_to(before, x);
        }
        self.diagnostics.record_particles(&p.strain, crossings);
    }
}

/// The loop of [`Simulation::update_particle_positions`] with the stencil
/// width `W` known at compile time (0: read it from the stencils).
fn update_positions<const W: usize>(
    p: &mut Particles,
    s: &Stencils,
    v: &[f64],
    dt: f64,
    strain_increment: &mut [f64],
) {
    let w = if W == 0 { s.width() } else { W };
    for (k, increment) in strain_increment.iter_mut().enumerate() {
        let first = s.first[k];
        let values = &s.values[k * w..k * w + w];
        let gradients = &s.gradients[k * w..k * w + w];
        let (du, deps) = displacement_and_strain_increment(values, gradients, &v[first..], dt);
        p.displacement[k] += du;
        p.x[k] += du;
        *increment = deps;
    }
}
