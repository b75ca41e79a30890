//! # Reconstructions at the Gauss points: one interface, one registration
//!
//! The MLS paper's phase 1 (Eqs. 18–21) and its second mapping (Eqs. 31–33)
//! carry particle values to the 2×2 Gauss points of every cell by a
//! reconstruction that is *linear in the data*: for any particle value f_p,
//!
//! f̃(x_g) = Σ_p φ_gp f_p,
//!
//! so a reconstruction is known by its shape functions φ_gp at the Gauss
//! points. MLS (MLS paper Eq. 14, [`super::mls::MlsShapes`]) and Taylor least
//! squares (TLS paper §5.2–5.5 on a rectangular cell,
//! [`super::tls::TlsShapes`]) are two implementations of
//! [`GaussReconstruction`]; the step ([`super::step`]) sees only this
//! interface, and Eqs. (22)–(25) then integrate the Gauss-point values with
//! the grid's basis.
//!
//! What a reconstruction reports of its last evaluation, its name, the
//! largest condition number of its small systems and the cells it
//! repaired, is [`Reconstruction`], the trait that the 1D reconstructions
//! (`mpm::mapping::reconstruction`) share; the 2D step records the two
//! numbers. The rest is 2D's own: the 1D reconstructions fit each field on
//! its own at quadrature points that move with the particles, and
//! integrate their own fits, where a 2D reconstruction is its φ_gp at the
//! grid's fixed Gauss points (`mpm::mapping::reconstruction` says why).
//!
//! ## How to add a reconstruction
//! 1. Implement [`Reconstruction`] and [`GaussReconstruction`] in a new
//!    module of `mpm2d` (fill φ_gp in the order of [`storage_order`]) and
//!    declare it in `mpm2d/mod.rs`.
//! 2. Register it in src/mpm2d/step.rs: one variant of
//!    [`super::step::Mapping2d`] (and in [`super::step::Mapping2d::ALL`]),
//!    its arm in [`super::step::Mapping2d::reconstruction`] and its names
//!    and cost in [`super::step::Mapping2d::info`]. The step maps every
//!    mapping but the direct one through the registered reconstruction, in
//!    both mappings of a step unless the mapping is a phase-1-only
//!    diagnostic.
//!
//! That is three files (TLS was added so: tls.rs, step.rs, mod.rs). The
//! aligned vibration, its labels and JSON, and the command line's
//! `--method bsmpm-<name>` follow from the registration
//! (tests/spec/meta/extensions.rs walks it).
//!
//! Items: [`GaussGrid`], [`ShapeLists`], [`ShapeBuffers`], [`GaussReconstruction`],
//! [`storage_order`] (and [`Reconstruction`], re-exported from
//! `mpm::mapping`).

use super::particles::Particles2d;
use crate::error::Result;
pub use crate::mpm::mapping::Reconstruction;

/// The Gauss points of the grid: 2·cells abscissae per axis, g = gx + n·gy.
pub struct GaussGrid<'a> {
    /// The abscissae of one axis.
    pub abscissae: &'a [f64],
    /// Cells per direction.
    pub cells: usize,
    /// h.
    pub cell_size: f64,
}

/// The shape functions φ_gp of every Gauss point g as flat lists:
/// `start[g] .. end[g]` index `particle` and `phi`.
#[derive(Debug, Clone, Copy)]
pub struct ShapeLists<'a> {
    /// Where the list of Gauss point g starts.
    pub start: &'a [usize],
    /// Where the list of Gauss point g ends.
    pub end: &'a [usize],
    /// The particles of each list.
    pub particle: &'a [u32],
    /// φ_gp, aligned with `particle`.
    pub phi: &'a [f64],
}

/// Owned lists behind [`ShapeLists`], for a reconstruction to fill.
#[derive(Debug, Clone, Default)]
pub struct ShapeBuffers {
    /// Where the list of Gauss point g starts.
    pub start: Vec<usize>,
    /// Where the list of Gauss point g ends.
    pub end: Vec<usize>,
    /// The particles of each list.
    pub particle: Vec<u32>,
    /// φ_gp, aligned with `particle`.
    pub phi: Vec<f64>,
}

impl ShapeBuffers {
    /// The lists, borrowed.
    pub fn lists(&self) -> ShapeLists<'_> {
        ShapeLists {
            start: &self.start,
            end: &self.end,
            particle: &self.particle,
            phi: &self.phi,
        }
    }
}

/// A reconstruction from the particles to the Gauss points that is linear
/// in the data, known by its shape functions φ_gp (MLS paper Eqs. 14,
/// 18–21 and 31–33; TLS paper Eq. 13 with its constraint, Eq. 14). What it
/// reports of its last evaluation (name, largest condition number,
/// repaired cells) is the [`Reconstruction`] that 1D reconstructions share.
pub trait GaussReconstruction: Reconstruction {
    /// φ_gp for every Gauss point from the particles at the start of a
    /// step; `cell_x[p]`, `cell_y[p]` are the cells of particle p. Errors
    /// when a point or cell cannot be reconstructed under the
    /// implementation's policy.
    fn evaluate(
        &mut self,
        gauss: &GaussGrid,
        particles: &Particles2d,
        cell_x: &[usize],
        cell_y: &[usize],
    ) -> Result<()>;

    /// The lists of the last evaluation, stored cell by cell in
    /// [`storage_order`].
    fn lists(&self) -> ShapeLists<'_>;
}

/// The Gauss points (gx, gy) in the order the lists are stored: cell by
/// cell, the four points of a cell together. Reading the lists in this
/// order reads `particle` and `phi` front to back.
///
/// The k-th point is point q = k mod 4 of cell k / 4, (i, j) = (q mod 2,
/// q / 2) in the cell: one counter, which the step's loops over the
/// lists inline (nested `flat_map`s cost about 100 instructions a point
/// where the compiler called them out of line).
pub fn storage_order(cells: usize) -> impl Iterator<Item = (usize, usize)> {
    (0..4 * cells * cells).map(move |k| {
        let (cell, q) = (k / 4, k % 4);
        let (cx, cy) = (cell % cells, cell / cells);
        (2 * cx + q % 2, 2 * cy + q / 2)
    })
}
