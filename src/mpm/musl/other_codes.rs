//! # The steps of other codes, in the 1D step
//!
//! The numbered functions that only another code's conventions call
//! ([`crate::mpm::conventions`]): the grid momentum and velocity at the
//! start of a step, USF's strain from it, the updated grid velocity
//! ṽ_i = v_i^n + Δt a_i, and steps 5–6 when the velocity that moves the
//! particles is not the one that strains them. [`super::Simulation::step`]
//! calls them in place of, or besides, the book's.

use super::{Particles, Result, Settings, Simulation, Stencils};
use crate::error::Error;
use crate::mpm::grid::Grid;
use crate::mpm::mapping::Mapping;

impl Simulation {
    /// Another code's step ([`super::conventions`]), step 1: the grid
    /// momentum p_i = Σ_p m_p v_p φ_i(x_p) and velocity v_i^n = p_i/m_i
    /// (0 without mass and on the Dirichlet DOFs). Through a
    /// reconstruction, p_i and m_i are its own, from step 1.
    pub(super) fn map_grid_velocity(&mut self) {
        let through_reconstruction = self.through_reconstruction();
        let (p, ws) = (&self.particles, &mut self.workspace);
        if !through_reconstruction {
            ws.nodal_momentum.fill(0.0);
            ws.stencils
                .scatter_values(|k| p.mass[k] * p.velocity[k], &mut ws.nodal_momentum);
        }
        for ((v, &pi), &m) in ws
            .nodal_velocity
            .iter_mut()
            .zip(&ws.nodal_momentum)
            .zip(&ws.mass)
        {
            *v = if m != 0.0 { pi / m } else { 0.0 };
        }
        for &i in &self.settings.dirichlet {
            ws.nodal_velocity[i] = 0.0;
        }
    }

    /// USF (Bardenhagen 2002), before the internal force: the strain
    /// increment Δε_p = Δt Σ_i ∇φ_i(x_p) v_i^n from the grid velocity at
    /// the start of the step (then steps 7–8 run on it).
    pub(super) fn strain_from_grid_velocity(&mut self, dt: f64) {
        let ws = &mut self.workspace;
        let (s, v) = (&ws.stencils, &ws.nodal_velocity);
        let w = s.width();
        for (k, deps) in ws.strain_increment.iter_mut().enumerate() {
            let first = s.first[k];
            let gradients = &s.gradients[k * w..k * w + w];
            *deps = gradients
                .iter()
                .zip(&v[first..first + w])
                .map(|(g, vi)| g * (dt * vi))
                .sum();
        }
    }

    /// Another code's step, step 2: the updated grid velocity
    /// ṽ_i = v_i^n + Δt a_i (MLS paper Eqs. 27–28 per unit mass), 0 on
    /// the Dirichlet DOFs.
    pub(super) fn update_grid_velocity(&mut self, dt: f64) {
        let ws = &mut self.workspace;
        for ((u, v), a) in ws
            .updated_velocity
            .iter_mut()
            .zip(&ws.nodal_velocity)
            .zip(&ws.acceleration)
        {
            *u = v + dt * a;
        }
        for &i in &self.settings.dirichlet {
            ws.updated_velocity[i] = 0.0;
        }
    }
}

/// Refuses another code's conventions where they mean nothing: they are
/// defined for the direct mapping with a lumped mass, or a mapping that
/// maps the loads too (`Mapping::takes_other_conventions`; natural knots
/// for B-splines of degree 2 or 3), and the grid's knots must be the ones
/// `--knots` names.
pub(super) fn check_conventions(settings: &Settings, grid: &Grid) -> Result<()> {
    let plain = Mapping::takes_other_conventions(
        settings.force_mapping,
        settings.velocity_mapping,
        settings.mass,
    ) && !settings.consistent_acceleration;
    settings.conventions.check_1d(plain, grid.method())?;
    if grid.knots() != settings.conventions.knots {
        return Err(Error::InvalidArgument(format!(
            "the grid has {} knots but the conventions name --knots {}",
            grid.knots().name(),
            settings.conventions.knots.name()
        )));
    }
    Ok(())
}

/// Steps 5–6 of another code: u_p, x_p grow by Δt Σ_i φ_i v_i with v the
/// velocity that moves the particles; Δε_p = Δt Σ_i ∇φ_i w_i with w the one
/// that strains them.
pub(super) fn move_and_strain(
    p: &mut Particles,
    s: &Stencils,
    moved_by: &[f64],
    strained_by: &[f64],
    dt: f64,
    strain_increment: &mut [f64],
) {
    let w = s.width();
    for (k, increment) in strain_increment.iter_mut().enumerate() {
        let first = s.first[k];
        let values = &s.values[k * w..k * w + w];
        let gradients = &s.gradients[k * w..k * w + w];
        let (mut du, mut deps) = (0.0, 0.0);
        for i in 0..w {
            du += values[i] * (dt * moved_by[first + i]);
            deps += gradients[i] * (dt * strained_by[first + i]);
        }
        p.displacement[k] += du;
        p.x[k] += du;
        *increment = deps;
    }
}
