//! # What a 2D step writes besides the particles
//!
//! The nodal quantities of MLS paper Eqs. (22)–(33), the Gauss-point values
//! of Eqs. (18)–(21) and the per-particle stencils, allocated once per run
//! ([`StepWorkspace2d`]), and the largest mapping errors of a run
//! ([`Conservation2d`]).
//!
//! Items: [`StepWorkspace2d`], [`Conservation2d`].

use super::reconstruction::GaussReconstruction;
use crate::basis::Stencils;
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
    /// The same eight values at every Gauss point g = gx + 2·cells·gy after
    /// the reconstruction of phase 1, Eqs. (18)–(21).
    pub gauss_values: Vec<[f64; 8]>,
}
