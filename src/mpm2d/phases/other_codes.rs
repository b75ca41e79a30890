//! # The 2D phases of other codes' steps
//!
//! Phase 3 and the position update under another code's conventions
//! (`mpm::conventions`): the FLIP/PIC blend of the particle velocity and
//! `--positions projected`, which moves the particles after Eqs. (31)–(33)
//! with v^L (book Eq. 4.11's rule in 2D). The paper's own phase 3 is
//! [`super::update_particles`].
//!
//! With `--transfer apic` (Jiang et al. 2015) the particles carry C_p:
//! phase 1 maps m_p (v_p + C_p (x_i − x_p)), phase 3 sets v_p = Σ N_i v_i
//! and C_p = Σ N_i v_i ⊗ (x_i − x_p) D_p⁻¹ with
//! D_p = Σ_i N_i (x_i − x_p) ⊗ (x_i − x_p), diagonal for a tensor-product
//! basis (h²/4 for uniform quadratic B-splines); with `--gradient affine`
//! (MLS-MPM, Hu et al. 2018) the internal force is
//! −Σ_p V_p σ_p D_p⁻¹ (x_i − x_p) N_i and the velocity gradient is C_p.
//!
//! Items: [`move_particles`], [`map_direct_apic`], [`update_particles_apic`],
//! [`update_deformation_affine`].

use super::{set_deformation, TensorStencil};
use crate::basis::Stencils;
use crate::error::Result;
use crate::mpm::conventions::{Conventions, Gradient, Positions};
use crate::mpm2d::grid::Grid2d;
use crate::mpm2d::material::NeoHookean;
use crate::mpm2d::particles::Particles2d;
use crate::mpm2d::workspace::StepWorkspace2d;
use nalgebra::Matrix2;

/// Phase 3 with `--transfer pic|flip:α` or `--positions projected`:
/// v_p = α (v_p + Δt Σ_i N_i a_i) + (1 − α) Σ_i N_i v_i^{t+1}, and x_p as
/// Eq. (30) when the positions are the grid's.
pub(super) fn update_particles_blended(
    grid: &Grid2d,
    p: &mut Particles2d,
    ws: &StepWorkspace2d,
    conventions: Conventions,
    dt: f64,
) {
    let alpha = conventions.transfer.flip_weight();
    let moves = conventions.positions == Positions::Grid;
    let (n, w) = (grid.nodes_per_side(), grid.stencil_width());
    let (sx, sy) = (&ws.stencils_x, &ws.stencils_y);
    for k in 0..p.len() {
        let (mut a, mut v) = ([0.0; 2], [0.0; 2]);
        TensorStencil::of(sx, k, sy, k, w, n).for_each(|i, nn, _| {
            a[0] += nn * ws.acceleration[i][0];
            a[1] += nn * ws.acceleration[i][1];
            v[0] += nn * ws.velocity_next[i][0];
            v[1] += nn * ws.velocity_next[i][1];
        });
        for d in 0..2 {
            let flip = p.velocity[k][d] + dt * a[d];
            p.velocity[k][d] = alpha * flip + (1.0 - alpha) * v[d];
        }
        if moves {
            p.x[k][0] += dt * v[0];
            p.x[k][1] += dt * v[1];
            p.displacement[k] = [p.x[k][0] - p.x0[k][0], p.x[k][1] - p.x0[k][1]];
        }
    }
}

/// `--positions projected` in 2D, after Eqs. (31)–(33): x_p += Δt Σ_i N_i
/// v_i^L with the basis at x_p^t (book Eq. 4.11's rule); u_p = x_p − X_p.
pub fn move_particles(grid: &Grid2d, p: &mut Particles2d, ws: &StepWorkspace2d, dt: f64) {
    let (n, w) = (grid.nodes_per_side(), grid.stencil_width());
    let (sx, sy) = (&ws.stencils_x, &ws.stencils_y);
    for k in 0..p.len() {
        let mut v = [0.0; 2];
        TensorStencil::of(sx, k, sy, k, w, n).for_each(|i, nn, _| {
            v[0] += nn * ws.velocity_end[i][0];
            v[1] += nn * ws.velocity_end[i][1];
        });
        p.x[k][0] += dt * v[0];
        p.x[k][1] += dt * v[1];
        p.displacement[k] = [p.x[k][0] - p.x0[k][0], p.x[k][1] - p.x0[k][1]];
    }
}

/// D along one axis for point k of `s`: Σ_a N_a (x_a − x)², the diagonal
/// entry of D_p (the other axis' functions sum to one).
fn inertia_along(s: &Stencils, k: usize, nodes: &[f64], x: f64) -> f64 {
    let first = s.first[k];
    s.values_of(k)
        .iter()
        .zip(&nodes[first..])
        .map(|(n, xa)| n * (xa - x) * (xa - x))
        .sum()
}

/// (D_x⁻¹, D_y⁻¹) of particle k.
fn inverse_inertia(ws: &StepWorkspace2d, k: usize, x: f64, y: f64) -> [f64; 2] {
    [
        1.0 / inertia_along(&ws.stencils_x, k, &ws.node_along, x),
        1.0 / inertia_along(&ws.stencils_y, k, &ws.node_along, y),
    ]
}

/// Phase 1 with APIC: m_i = Σ_p N_i m_p, (mv)_i = Σ_p N_i m_p (v_p + C_p
/// (x_i − x_p)), f_i = Σ_p N_i m_p b_p − V_p σ_p g_ip with g_ip = ∇N_i
/// (`--gradient basis`) or D_p⁻¹ (x_i − x_p) N_i (`affine`, MLS-MPM).
pub fn map_direct_apic(
    grid: &Grid2d,
    p: &Particles2d,
    ws: &mut StepWorkspace2d,
    gradient: Gradient,
) {
    let (n, w) = (grid.nodes_per_side(), grid.stencil_width());
    for m in ws.mass.iter_mut() {
        *m = 0.0;
    }
    ws.momentum.iter_mut().for_each(|m| *m = [0.0; 2]);
    ws.force.iter_mut().for_each(|f| *f = [0.0; 2]);
    for k in 0..p.len() {
        let [x, y] = p.x[k];
        let m = p.mass[k];
        let (v, c, b) = (p.velocity[k], p.affine[k], ws.body_force[k]);
        let s = p.stress[k] * p.volume[k];
        let d_inv = inverse_inertia(ws, k, x, y);
        let (sx, sy) = (&ws.stencils_x, &ws.stencils_y);
        let stencil = TensorStencil::of(sx, k, sy, k, w, n);
        let node = &ws.node_along;
        stencil.for_each(|i, nn, dn| {
            let d = [node[i % n] - x, node[i / n] - y];
            let g = match gradient {
                Gradient::Basis => dn,
                Gradient::Affine => [d_inv[0] * d[0] * nn, d_inv[1] * d[1] * nn],
            };
            let cd = [
                c[(0, 0)] * d[0] + c[(0, 1)] * d[1],
                c[(1, 0)] * d[0] + c[(1, 1)] * d[1],
            ];
            ws.mass[i] += nn * m;
            ws.momentum[i][0] += nn * m * (v[0] + cd[0]);
            ws.momentum[i][1] += nn * m * (v[1] + cd[1]);
            ws.force[i][0] += nn * m * b[0] - (s[(0, 0)] * g[0] + s[(0, 1)] * g[1]);
            ws.force[i][1] += nn * m * b[1] - (s[(1, 0)] * g[0] + s[(1, 1)] * g[1]);
        });
    }
}

/// Phase 3 with APIC: v_p = Σ N_i v_i^{t+1}, C_p = Σ N_i v_i^{t+1} ⊗
/// (x_i − x_p) D_p⁻¹ (at x_p^t), then x_p += Δt v_p (Eq. 30).
pub fn update_particles_apic(grid: &Grid2d, p: &mut Particles2d, ws: &StepWorkspace2d, dt: f64) {
    let (n, w) = (grid.nodes_per_side(), grid.stencil_width());
    let (sx, sy, node) = (&ws.stencils_x, &ws.stencils_y, &ws.node_along);
    for k in 0..p.len() {
        let [x, y] = p.x[k];
        let d_inv = inverse_inertia(ws, k, x, y);
        let (mut v, mut b) = ([0.0; 2], [0.0; 4]);
        TensorStencil::of(sx, k, sy, k, w, n).for_each(|i, nn, _| {
            let vi = ws.velocity_next[i];
            let d = [node[i % n] - x, node[i / n] - y];
            v[0] += nn * vi[0];
            v[1] += nn * vi[1];
            b[0] += nn * vi[0] * d[0];
            b[1] += nn * vi[0] * d[1];
            b[2] += nn * vi[1] * d[0];
            b[3] += nn * vi[1] * d[1];
        });
        p.velocity[k] = v;
        p.affine[k] = Matrix2::new(
            b[0] * d_inv[0],
            b[1] * d_inv[1],
            b[2] * d_inv[0],
            b[3] * d_inv[1],
        );
        p.x[k][0] += dt * v[0];
        p.x[k][1] += dt * v[1];
        p.displacement[k] = [p.x[k][0] - p.x0[k][0], p.x[k][1] - p.x0[k][1]];
    }
}

/// Eqs. (35)–(37) and (41) with the MLS-MPM velocity gradient
/// (`--gradient affine`): F_p ← (I + Δt C_p) F_p, V_p = det F_p V_p⁰,
/// ρ_p = m_p/V_p, σ_p neo-Hookean. det F ≤ 0 is
/// `Error::InvertedDeformation` and a velocity that is not finite
/// `Error::NonFiniteVelocity`, naming the particle.
pub fn update_deformation_affine(
    p: &mut Particles2d,
    material: &NeoHookean,
    dt: f64,
) -> Result<()> {
    for k in 0..p.len() {
        let f = (Matrix2::identity() + p.affine[k] * dt) * p.deformation[k];
        set_deformation(p, k, f, material)?;
    }
    Ok(())
}
