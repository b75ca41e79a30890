//! # The total-Lagrangian reference's basis and deformation update
//!
//! hompm's reference without grid crossing (`Formulation::TotalLagrangian`):
//! the basis evaluated once at the initial positions X_p, and F updated by
//! Ḟ = ∇_X v (MLS paper Eqs. 34–37 in the reference configuration). Its
//! phase 1 is [`super::map_direct_reference`].
//!
//! Items: [`update_deformation_reference`] (and the crate's
//! `evaluate_basis_at_reference`).

use super::update_deformation_with;
use crate::basis::with_width;
use crate::error::Result;
use crate::mpm2d::grid::Grid2d;
use crate::mpm2d::material::NeoHookean;
use crate::mpm2d::particles::Particles2d;
use crate::mpm2d::workspace::StepWorkspace2d;
use nalgebra::Matrix2;

/// The stencils at the initial positions X_p, once, for the
/// total-Lagrangian reference (`Formulation::TotalLagrangian`).
pub(crate) fn evaluate_basis_at_reference(
    grid: &Grid2d,
    p: &Particles2d,
    ws: &mut StepWorkspace2d,
) -> Result<()> {
    let axis = grid.axis();
    axis.fill_stencils(&p.x0, |x| x[0], &mut ws.stencils_x, &mut ws.scratch)?;
    axis.fill_stencils(&p.x0, |x| x[1], &mut ws.stencils_y, &mut ws.scratch)
}

/// [`super::update_deformation`] of the total-Lagrangian reference: Ḟ = ∇_X v, so
/// F_p ← F_p + Δt Σ_i v_i^L ⊗ ∇_X N_i(X_p).
pub fn update_deformation_reference(
    grid: &Grid2d,
    p: &mut Particles2d,
    ws: &StepWorkspace2d,
    material: &NeoHookean,
    dt: f64,
) -> Result<()> {
    let rule = |l: Matrix2<f64>, f: Matrix2<f64>| f + l * dt;
    with_width!(
        grid.stencil_width(),
        update_deformation_with::<W>(grid, p, ws, material, rule)
    )
}
