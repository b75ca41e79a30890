//! # A manufactured solution's pieces, in the 1D step
//!
//! What the MLS paper's code needs of the 1D step on its strip (issue #40;
//! `Vibration.m`, `BSMPM_solvertest.m`, `Update_Stress.m` of
//! QuocAnh90/CPLS-least-squares-for-Material-Point-Method at f30bc24, read,
//! not copied): a body force b(X, t) evaluated at each particle's initial
//! position at the start of the step and mapped as Σ_p b_p m_p φ_i, and the
//! neo-Hookean law of MLS paper Eq. (37) in one dimension, with the
//! deformation gradient kept per particle and the volume V_p = V_p⁰ F_p.
//! [`super::Simulation::step`] calls them from steps 1, 7 and 8 when the
//! settings ask for them ([`super::Settings::body_force`],
//! [`super::Constitutive::NeoHookean`]).
//!
//! Items: [`neo_hookean_1d`].

use super::{BodyForceAt, Constitutive, Settings, Simulation};
use crate::error::{Error, Result};

/// The material and loads a run can take: E > 0, a finite gravity, for
/// the neo-Hookean law −1 < ν < 0.5, and a body-force field mapped from
/// the particles only (its code's `b_sp·m·N`; `--body-force nodes` is
/// refused with it).
pub(super) fn check_material(settings: &Settings) -> Result<()> {
    if settings.young.is_nan() || settings.young <= 0.0 {
        return Err(Error::InvalidArgument(format!(
            "Young's modulus must be positive, got {}",
            settings.young
        )));
    }
    crate::error::finite("gravity", settings.gravity)?;
    let nu = settings.poisson;
    if settings.constitutive == Constitutive::NeoHookean && !(nu > -1.0 && nu < 0.5) {
        return Err(Error::InvalidArgument(format!(
            "the neo-Hookean law needs −1 < ν < 0.5, got {nu}"
        )));
    }
    if settings.body_force.is_some() && settings.conventions.body_force == BodyForceAt::Nodes {
        return Err(Error::Usage(
            "--body-force nodes: the manufactured body force is mapped from the particles (b_p m_p φ_i), as its code does".into(),
        ));
    }
    Ok(())
}

/// The 1D neo-Hookean stress σ = (λ ln F + μ(F² − 1))/F: MLS paper
/// Eq. (37), σ = (λ ln J/J) I + (μ/J)(F Fᵀ − I), with F_yy = F_zz = 1 and
/// J = F (its code's `Neo_Hookean_elastic.m`; issue #40).
pub fn neo_hookean_1d(lambda: f64, mu: f64, f: f64) -> f64 {
    (lambda * f.ln() + mu * (f * f - 1.0)) / f
}

impl Simulation {
    /// Step 1's body force: gravity_force_i += Σ_p b(X_p, tⁿ) m_p φ_i(x_p)
    /// (`Interpolate_Particle_To_Grid.m`: b_sp·m·N), nothing without a
    /// field.
    pub(super) fn map_body_force_field(&mut self) {
        let Some(field) = &self.settings.body_force else {
            return;
        };
        let (p, ws, t) = (&self.particles, &mut self.workspace, self.time);
        let b = &field.at;
        ws.stencils
            .scatter_values(|k| b(p.x0[k], t) * p.mass[k], &mut ws.gravity_force);
    }

    /// Step 7, neo-Hookean: F_p ← (1 + Δε_p) F_p (Δε_p = Δt ∂v/∂x, the
    /// code's (1 + L Δt) F) and σ_p = [`neo_hookean_1d`](λ, μ, F_p).
    pub(super) fn update_neo_hookean_stresses(&mut self) {
        let (lambda, mu) = self.settings.lame();
        let p = &mut self.particles;
        let deps = &self.workspace.strain_increment;
        for ((s, de), f) in p.stress.iter_mut().zip(deps).zip(&mut p.deformation) {
            *f *= 1.0 + de;
            *s = neo_hookean_1d(lambda, mu, *f);
        }
    }

    /// Step 8, neo-Hookean: V_p = V_p⁰ F_p and ρ_p = m_p/V_p
    /// (`Update_Stress.m`); the accumulated strain grows by Δε_p.
    pub(super) fn update_neo_hookean_volumes(&mut self) {
        let p = &mut self.particles;
        for (k, &de) in self.workspace.strain_increment.iter().enumerate() {
            p.volume[k] = p.initial_volume[k] * p.deformation[k];
            p.density[k] = p.mass[k] / p.volume[k];
            p.strain[k] += de;
        }
    }
}
