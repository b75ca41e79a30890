//! # Reconstructions: what 1D and 2D share, and what they do not
//!
//! A mapping through a reconstruction fits a function to the particle data
//! (Taylor least squares: book §4.4.3, Eqs. 4.31–4.37, TLS paper §5; cubic
//! splines: thesis §7.1; MLS: MLS paper Eqs. 10–17), evaluates it at
//! quadrature points and integrates the values there with the grid's basis
//! (book Eqs. 4.38–4.44, thesis §7.2; MLS paper Eqs. 18–25).
//!
//! **Shared by 1D and 2D** ([`Reconstruction`]): what a reconstruction
//! reports of its last step, its name, the largest condition number of the
//! small systems it solved and how many cells or points it repaired (TLS
//! paper §5.3). 2D's `mpm2d::reconstruction::GaussReconstruction` (MLS,
//! TLS) and 1D's [`Reconstruction1d`] (TLS, cubic splines, the MLS
//! paper's code's MLS) both extend it.
//!
//! **Not shared**: how the values are made and integrated. A 2D
//! reconstruction is linear in the data and is known by its shape
//! functions φ_gp at the grid's fixed 2×2 Gauss points per cell, which the
//! 2D step applies to eight packed fields at once. A 1D reconstruction fits
//! each field on its own (conservative TLS prescribes each field's own cell
//! integral, and the density fit may average (x − x_c)² differently), its
//! quadrature points move with the particles (the cells that hold
//! particles; the half spans inside Ω_t), and it integrates its own fits
//! ([`Reconstruction1d::internal_force`],
//! [`Reconstruction1d::accumulate_projection`]). Written as φ_gp, the 1D
//! fits would round differently from the thesis' and the TLS paper's
//! order of operations, which the 1D tables reproduce.
//!
//! A 1D reconstruction is registered by `Mapping::reconstruction`
//! (src/mpm/mapping.rs), which the step's three calls
//! (`MappingWorkspace::begin_step`, `internal_force`, `assemble_projection`)
//! read; the direct mapping has none.
//!
//! Items: [`Reconstruction`], [`Reconstruction1d`].

use super::quadrature::Accumulator;
use crate::error::{Error, Result};
use crate::mpm::grid::Grid;
use crate::mpm::particles::Particles;
use crate::reconstruct::taylor::CellAverage;

/// What a reconstruction reports of its last step, in 1D and 2D alike
/// (book §4.4.3, TLS paper §5.3, MLS paper Eqs. 10–17).
pub trait Reconstruction: std::fmt::Debug + Send + Sync {
    /// Its name in labels and messages ("TLS", "CS", "MLS"; a 1D one's is
    /// its mapping's legend, `MappingInfo1d::legend`).
    fn name(&self) -> &'static str;

    /// The largest condition number of the small systems the last step
    /// solved: 1D TLS, κ₂ of the cells' normal matrices (book Eqs.
    /// 4.26–4.29); 2D TLS, κ₁ of the cells' normal matrices (TLS paper
    /// Eq. 13); MLS, κ₁ of the moment matrix A (MLS paper Eq. 10). 0 when
    /// it solved none (a cubic spline solves one tridiagonal system).
    fn largest_condition(&self) -> f64;

    /// How many cells (TLS) or points the last step repaired (TLS paper
    /// §5.3: virtual points in 1D, a reduced basis in 2D); 0 for a
    /// reconstruction without a repair.
    fn repaired(&self) -> usize {
        0
    }
}

/// A 1D mapping through a reconstruction, with its buffers (book §4.4.3,
/// Eqs. 4.38–4.44; thesis §7.2): prepared once per step from the particles
/// at x^t, then used by the internal force and by the velocity projection.
pub trait Reconstruction1d: Reconstruction {
    /// Prepares the step from the particles at x^t: the quadrature points
    /// with the basis at them (book Eq. 4.38's Gauss points on the cells
    /// that hold particles; thesis §7.2's half-span points inside Ω_t).
    /// `density_average` is how a Taylor fit of the density averages
    /// (x − x_c)² ([`CellAverage`]); a reconstruction without one ignores it.
    fn begin_step(
        &mut self,
        grid: &Grid,
        particles: &Particles,
        density_average: CellAverage,
    ) -> Result<()>;

    /// Adds f_i = ∫ σ̃ ∇φ_i dΩ by this step's quadrature into `force`
    /// (book Eq. 4.38, thesis §7.2).
    fn internal_force(&mut self, particles: &Particles, force: &mut [f64]) -> Result<()>;

    /// Adds the reconstructed ρ̃ w and (ρv)~ w of every quadrature point to
    /// the projection's p and M (book Eqs. 4.39–4.44, thesis §7.2).
    fn accumulate_projection(&mut self, particles: &Particles, acc: &mut Accumulator)
        -> Result<()>;

    /// Adds f_ext,i = ∫ (ρb)~ φ_i dΩ by this step's quadrature into
    /// `force`, with b_p = `body(k)` the body force per unit mass at
    /// particle k: the loads mapped through the reconstruction, as the MLS
    /// paper's code maps them (MLS paper Eqs. 20, 24; its
    /// `MLS_BSMPM_solvertest1.m:298, 332`). Only a mapping registered with
    /// `MappingInfo1d::maps_loads` has it; the others refuse.
    fn body_force(
        &mut self,
        _particles: &Particles,
        _body: &dyn Fn(usize) -> f64,
        _force: &mut [f64],
    ) -> Result<()> {
        Err(Error::Usage(format!(
            "the {} mapping does not map the loads: another code's step runs with the direct mapping or the MLS mappings",
            self.name()
        )))
    }
}
