//! # The 2D phases of other codes' steps
//!
//! Phase 3 and the position update under another code's conventions
//! (`mpm::conventions`): the FLIP/PIC blend of the particle velocity and
//! `--positions projected`, which moves the particles after Eqs. (31)–(33)
//! with v^L (book Eq. 4.11's rule in 2D). The paper's own phase 3 is
//! [`super::update_particles`].
//!
//! Items: [`move_particles`].

use super::TensorStencil;
use crate::mpm::conventions::{Conventions, Positions};
use crate::mpm2d::grid::Grid2d;
use crate::mpm2d::particles::Particles2d;
use crate::mpm2d::workspace::Workspace2d;

/// Phase 3 with `--transfer pic|flip:α` or `--positions projected`:
/// v_p = α (v_p + Δt Σ_i N_i a_i) + (1 − α) Σ_i N_i v_i^{t+1}, and x_p as
/// Eq. (30) when the positions are the grid's.
pub(super) fn update_particles_blended(
    grid: &Grid2d,
    p: &mut Particles2d,
    ws: &Workspace2d,
    conventions: Conventions,
    dt: f64,
) {
    let alpha = conventions.transfer.flip_weight();
    let moves = conventions.positions == Positions::Grid;
    let (n, w) = (grid.nodes_per_side(), grid.stencil_width());
    let (sx, sy) = (&ws.along_x, &ws.along_y);
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
            p.x[k] += dt * v[0];
            p.y[k] += dt * v[1];
            p.displacement[k] = [p.x[k] - p.x0[k][0], p.y[k] - p.x0[k][1]];
        }
    }
}

/// `--positions projected` in 2D, after Eqs. (31)–(33): x_p += Δt Σ_i N_i
/// v_i^L with the basis at x_p^t (book Eq. 4.11's rule); u_p = x_p − X_p.
pub fn move_particles(grid: &Grid2d, p: &mut Particles2d, ws: &Workspace2d, dt: f64) {
    let (n, w) = (grid.nodes_per_side(), grid.stencil_width());
    let (sx, sy) = (&ws.along_x, &ws.along_y);
    for k in 0..p.len() {
        let mut v = [0.0; 2];
        TensorStencil::of(sx, k, sy, k, w, n).for_each(|i, nn, _| {
            v[0] += nn * ws.velocity_end[i][0];
            v[1] += nn * ws.velocity_end[i][1];
        });
        p.x[k] += dt * v[0];
        p.y[k] += dt * v[1];
        p.displacement[k] = [p.x[k] - p.x0[k][0], p.y[k] - p.x0[k][1]];
    }
}
