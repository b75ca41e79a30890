//! # What a 2D step writes besides the particles
//!
//! The nodal quantities of MLS paper Eqs. (22)–(33), the Gauss-point values
//! of Eqs. (18)–(21) and the per-particle stencils, allocated once per run
//! ([`StepWorkspace2d`]), and the largest mapping errors of a run
//! ([`Conservation2d`], recorded after phase 1 by `record_conservation`).
//!
//! Items: [`StepWorkspace2d`], [`Conservation2d`].

use super::particles::Particles2d;
use super::reconstruction::GaussReconstruction;
use crate::basis::Stencils;
use crate::mpm::diagnostics::CompensatedSum;
use crate::spline::bspline::SpanScratch;
use serde::{Deserialize, Serialize};

/// The largest relative mapping errors of a run: mass |Σ_i m_i − Σ_p m_p| /
/// Σ_p m_p and momentum |Σ_i (mv)_i − Σ_p m_p v_p| / Σ_p m_p |v_p|, taken
/// over every phase-1 mapping (before the wall conditions).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Conservation2d {
    /// Largest relative mass error.
    pub mass: f64,
    /// Largest relative momentum error.
    pub momentum: f64,
}

/// Everything a step writes besides the particles, allocated once: the 2D
/// counterpart of the 1D `mpm::workspace::StepWorkspace` (issue #37's one
/// vocabulary; the 1D step's `stencils` are here one per axis, since the
/// 2D basis is their tensor product, MLS paper Eqs. 4–5).
#[derive(Debug)]
pub struct StepWorkspace2d {
    /// The x-axis basis N_a(x_p), N_a'(x_p) at every particle.
    pub stencils_x: Stencils,
    /// The y-axis basis N_b(y_p), N_b'(y_p) at every particle.
    pub stencils_y: Stencils,
    pub(super) scratch: SpanScratch,
    /// b_p(t) per unit mass.
    pub body_force: Vec<[f64; 2]>,
    /// `--body-force nodes`: b(X_i, t) per unit mass at every node (empty
    /// otherwise).
    pub nodal_body_force: Vec<[f64; 2]>,
    /// `--transfer apic`: the node positions along one axis (x_i of
    /// x_i − x_p; empty otherwise).
    pub node_along: Vec<f64>,
    /// Lumped nodal masses m_i (Eq. 22).
    pub mass: Vec<f64>,
    /// Nodal momenta (mv)_i^t of phase 1 (Eq. 23).
    pub momentum: Vec<[f64; 2]>,
    /// Nodal forces f_i = f_i^b + f_i^int of phase 1 (Eqs. 24–26), before
    /// the walls' conditions.
    pub force: Vec<[f64; 2]>,
    /// Nodal accelerations a_i = f_i/m_i (Eq. 27), zero normal to the walls.
    pub acceleration: Vec<[f64; 2]>,
    /// Updated nodal momenta (mv)_i^{t+1} = (mv)_i^t + f_i Δt (Eq. 28).
    pub momentum_next: Vec<[f64; 2]>,
    /// Updated nodal velocities v_i^{t+1} = (mv)_i^{t+1}/m_i, which move the
    /// particles (Eq. 30).
    pub velocity_next: Vec<[f64; 2]>,
    /// End-of-step nodal momenta (mv)_i^L (Eqs. 31–32).
    pub momentum_end: Vec<[f64; 2]>,
    /// End-of-step nodal velocities v_i^L = (mv)_i^L/m_i (Eq. 33), which
    /// update the deformation (Eq. 34).
    pub velocity_end: Vec<[f64; 2]>,
    /// The Gauss-point reconstruction (MLS or TLS) of a reconstructed
    /// mapping; `None` for the direct mapping.
    pub reconstruction: Option<Box<dyn GaussReconstruction>>,
    /// [ρ, ρv_x, ρv_y, ρb_x, ρb_y, σ_xx, σ_yy, σ_xy] per particle, the values
    /// a reconstruction carries to the Gauss points (Eqs. 18–21).
    pub particle_values: Vec<[f64; 8]>,
    /// [ρ_p, v_x, v_y] per particle at the end of a step, the values the
    /// reconstructed Eq. (31) reads side by side.
    pub end_values: Vec<[f64; 3]>,
    /// The same eight values at every Gauss point g = gx + 2·cells·gy after
    /// the reconstruction of phase 1, Eqs. (18)–(21).
    pub gauss_values: Vec<[f64; 8]>,
}

/// The body of [`record_conservation`], inlined into its baseline and AVX2 copies.
#[inline(always)]
fn record_conservation_kernel(p: &Particles2d, ws: &StepWorkspace2d, c: &mut Conservation2d) {
    // Compensated sums on both sides, so that the monitor measures the
    // mapping's rounding and not that of its own sums.
    let [mut particle_mass, mut scale, mut px, mut py] = [CompensatedSum::default(); 4];
    for (&m, v) in p.mass.iter().zip(&p.velocity) {
        particle_mass.add(m);
        scale.add(m * (v[0] * v[0] + v[1] * v[1]).sqrt());
        px.add(m * v[0]);
        py.add(m * v[1]);
    }
    let [mut grid_mass, mut gx, mut gy] = [CompensatedSum::default(); 3];
    for (&m, mv) in ws.mass.iter().zip(&ws.momentum) {
        grid_mass.add(m);
        gx.add(mv[0]);
        gy.add(mv[1]);
    }
    let (particle_mass, scale) = (particle_mass.total(), scale.total());
    c.mass = c
        .mass
        .max((grid_mass.total() - particle_mass).abs() / particle_mass);
    if scale > 0.0 {
        let (dx, dy) = (gx.total() - px.total(), gy.total() - py.total());
        c.momentum = c.momentum.max(dx.hypot(dy) / scale);
    }
}

crate::dispatch::avx2_when_available! {
    /// The mapping errors of phase 1 into `c` (mass |Σ_i m_i − Σ_p m_p| / Σ_p m_p,
    /// momentum |Σ_i (mv)_i − Σ_p m_p v_p| / Σ_p m_p |v_p|, [`Conservation2d`]):
    /// the four particle sums in one pass and the three nodal sums in another,
    /// each a [`CompensatedSum`] over the same terms in the same order as one
    /// pass per sum. AVX2 where the processor has it ([`crate::dispatch`]).
    pub(crate) fn record_conservation(p: &Particles2d, ws: &StepWorkspace2d, c: &mut Conservation2d) = record_conservation_kernel;
}
