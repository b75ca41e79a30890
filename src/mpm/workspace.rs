//! # The buffers of a 1D step
//!
//! [`StepWorkspace`] holds everything one step of [`super::musl`] writes
//! besides the particles: the basis at the particles (book Eqs. 4.5–4.6's
//! φ_i(x_p), ∇φ_i(x_p)), the nodal vectors of Eqs. (4.5)–(4.10), the grid
//! velocities of another code's step ([`super::conventions`]) and the
//! per-particle increments of Eqs. (4.14)–(4.18). It is allocated once,
//! when the simulation starts (the 2D step's is `mpm2d::workspace`).
//!
//! Items: [`StepWorkspace`].

use super::grid::Grid;
use super::mapping::MappingWorkspace;
use crate::basis::Stencils;
use crate::error::Result;
use crate::spline::bspline::SpanScratch;

/// The buffers of one step, allocated when the simulation starts: the basis
/// at the particles (flat stencils), the nodal vectors, and the per-particle
/// increments of steps 5–8.
#[derive(Debug)]
pub struct StepWorkspace {
    /// φ_i(x_p) and (modified) ∇φ_i(x_p) at the start of the step.
    pub stencils: Stencils,
    pub(super) scratch: SpanScratch,
    /// Lumped nodal mass m_i (Eq. 4.5).
    pub mass: Vec<f64>,
    /// Internal force f_int (Eq. 4.6).
    pub internal_force: Vec<f64>,
    /// Gravity load Σ_p m_p g φ_i (thesis §3.2).
    pub gravity_force: Vec<f64>,
    /// Traction load Σ_p f_p φ_i (thesis §3.2).
    pub traction_force: Vec<f64>,
    /// Nodal acceleration a_i (Eq. 4.8).
    pub acceleration: Vec<f64>,
    /// Another code's step ([`super::conventions`]): the grid momentum
    /// p_i = Σ_p m_p v_p φ_i at the start of the step.
    pub nodal_momentum: Vec<f64>,
    /// The grid velocity v_i^n = p_i/m_i at the start of the step.
    pub nodal_velocity: Vec<f64>,
    /// The updated grid velocity ṽ_i = v_i^n + Δt a_i.
    pub updated_velocity: Vec<f64>,
    /// The mappings' buffers, and the projected velocity v_i (Eq. 4.10).
    pub mapping: MappingWorkspace,
    /// Δε_p (Eq. 4.14) of the last step taken pass by pass: an observed
    /// step (`hompm trace` records it as book-4.14) or one the fused loops
    /// do not serve. A fused step keeps each Δε_p in a register and leaves
    /// this empty, so that it never holds an older step's values
    /// (`Simulation::step_is_fused`; docs/conventions.md, issue #39).
    pub strain_increment: Vec<f64>,
    /// The crossing monitor's break counts (thesis §3.3): N(x_p) of the
    /// position each particle was last counted at. Both shapes of the step
    /// check the count against x_p^t (`Grid::keep_break_count`): the pass
    /// per equation as it starts, the fused step in the loop that moves
    /// the particle (`Grid::crossings_between`).
    pub(super) breaks_before: Vec<usize>,
}

impl StepWorkspace {
    /// Buffers for `grid` and `particles` particles.
    pub fn new(grid: &Grid, particles: usize) -> Result<Self> {
        let n = grid.num_dofs();
        Ok(Self {
            stencils: grid.stencils(particles),
            scratch: SpanScratch::default(),
            mass: vec![0.0; n],
            internal_force: vec![0.0; n],
            gravity_force: vec![0.0; n],
            traction_force: vec![0.0; n],
            acceleration: vec![0.0; n],
            nodal_momentum: vec![0.0; n],
            nodal_velocity: vec![0.0; n],
            updated_velocity: vec![0.0; n],
            mapping: MappingWorkspace::new(grid, particles)?,
            strain_increment: vec![0.0; particles],
            breaks_before: vec![0; particles],
        })
    }
}
