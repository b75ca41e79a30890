//! # Another code's step through a reconstruction
//!
//! The MLS paper's code maps everything through its MLS
//! (`MLS_BSMPM_solvertest1.m` of
//! QuocAnh90/CPLS-least-squares-for-Material-Point-Method at f30bc24,
//! issue #40; read, not copied): in its USL step the grid's mass, momentum
//! and body force come from the fits at the Gauss points, as the internal
//! force does, and the acceleration solves its consistent mass. When a
//! mapping registered with `MappingInfo1d::maps_loads` (the MLS mappings,
//! `crate::mpm::mapping::mls`) runs under another code's conventions
//! (`--scheme usl`, …), [`super::Simulation::step`] calls these in place
//! of the particles' sums of steps 1 and 2 (docs/conventions.md, "The MLS
//! paper's code's 1D MLS"):
//!
//! - step 1: m_i = Σ_g ρ̃ φ_i ω_g, p_i = Σ_g (ρv)~ φ_i ω_g (MLS paper
//!   Eqs. 22–23), the body force and gravity Σ_g (ρ(b + g))~ φ_i ω_g
//!   (Eq. 24), the traction from the particles; then v_i^n = p_i/m_i
//!   (lines 388-392; `map_grid_velocity`);
//! - step 2 with `--mass consistent`: M a = f_ext − f_int with M the
//!   fits' consistent mass (lines 358-394); with `--mass lumped`,
//!   a = f/m_i.
//! - steps 5–6 under USL in the code's order of operations (lines
//!   410-423, 534-537): x_p gains one term (Δt φ_i) ṽ_i per function, in
//!   turn, and u_p = x_p − X_p. The order matters here as nowhere else: the
//!   next step's uncentred MLS fit (κ up to 8e10 on 64 cells) turns one
//!   ulp of x_p into 1e-8 in its shape functions.

use super::Simulation;
use crate::error::Result;
use crate::mpm::mapping::{
    assemble_projection, body_force, solve_consistent_acceleration, MassMatrix,
};

impl Simulation {
    /// Whether this step maps its mass, momentum and loads through the
    /// reconstruction: another code's step with a mapping that maps them.
    pub(super) fn through_reconstruction(&self) -> bool {
        self.settings.conventions.needs_grid_velocity()
            && self.settings.velocity_mapping.info().maps_loads
    }

    /// Step 1 through the reconstruction (MLS paper Eqs. 18–24;
    /// `MLS_BSMPM_solvertest1.m:278-335`): the lumped mass m_i (the row
    /// sums of the fits' mass matrix, which is also assembled with
    /// `--mass consistent`), the momentum p_i, the body force and gravity
    /// through the fits, and the traction Σ_p f_p φ_i from the particles.
    pub(super) fn map_mass_and_loads_through_reconstruction(&mut self, dt: f64) -> Result<()> {
        let consistent = matches!(self.settings.mass, MassMatrix::Consistent(_));
        let mapping = self.settings.velocity_mapping;
        let (g, t) = (self.gravity_in_step(dt), self.time);
        let (grid, p, ws) = (&self.grid, &self.particles, &mut self.workspace);
        assemble_projection(grid, p, &ws.stencils, mapping, consistent, &mut ws.mapping)?;
        ws.mass.copy_from_slice(&ws.mapping.lumped);
        ws.nodal_momentum.copy_from_slice(&ws.mapping.momentum);
        ws.gravity_force.fill(0.0);
        ws.traction_force.fill(0.0);
        let field = self.settings.body_force.as_ref().map(|f| &f.at);
        let body = |k: usize| g + field.map_or(0.0, |b| b(p.x0[k], t));
        body_force(
            grid,
            p,
            mapping,
            &body,
            &mut ws.mapping,
            &mut ws.gravity_force,
        )?;
        if p.has_traction() {
            ws.stencils
                .scatter_values(|k| p.traction[k], &mut ws.traction_force);
        }
        Ok(())
    }

    /// Steps 5–6 through the reconstruction under USL, as the code writes
    /// them (`MLS_BSMPM_solvertest1.m:410-423, 534-537`): for each function
    /// i in turn x_p ← x_p + (Δt φ_i(x_p)) ṽ_i, then u_p = x_p − X_p; the
    /// strain increment Δε_p = (Σ_i ṽ_i ∇φ_i(x_p)) Δt (its L Δt).
    pub(super) fn move_and_strain_as_the_mls_code(&mut self, dt: f64) {
        let (p, ws) = (&mut self.particles, &mut self.workspace);
        let (s, v) = (&ws.stencils, &ws.updated_velocity);
        let w = s.width();
        for (k, increment) in ws.strain_increment.iter_mut().enumerate() {
            let first = s.first[k];
            let (values, gradients) = (s.values_of(k), s.gradients_of(k));
            let mut gradient = 0.0;
            for i in 0..w {
                p.x[k] += dt * values[i] * v[first + i];
                gradient += v[first + i] * gradients[i];
            }
            p.displacement[k] = p.x[k] - p.x0[k];
            *increment = gradient * dt;
        }
    }

    /// Step 2 through the reconstruction with a consistent mass:
    /// M a = f_trac + f_ext − f_int on the DOFs with mass that are not
    /// Dirichlet DOFs, M the fits' consistent mass of step 1 (the code's
    /// `nacc = MASS\nforce`, `MLS_BSMPM_solvertest1.m:367-394`); nothing
    /// otherwise.
    pub(super) fn acceleration_through_reconstruction(&mut self) -> Result<()> {
        if !self.through_reconstruction() || self.settings.mass == MassMatrix::Lumped {
            return Ok(());
        }
        let ws = &mut self.workspace;
        let (trac, grav, int) = (&ws.traction_force, &ws.gravity_force, &ws.internal_force);
        solve_consistent_acceleration(
            &mut ws.mapping,
            |i| trac[i] + grav[i] - int[i],
            &self.settings.dirichlet,
            &mut ws.acceleration,
        )
    }
}
