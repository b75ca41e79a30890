//! # MLS shape functions at the Gauss points, inside a time step
//!
//! MLS paper Eqs. (10)–(17) evaluated at every Gauss point x_g of the grid,
//! for the particles as data points: φ_gp = pᵀ(x_g) A⁻¹(x_g) w(x_g − x_p)
//! p(x_p), with p = [1, x, y] (Eq. 15) and the tensor-product
//! quadratic-spline weight w(r_x) w(r_y) (Eqs. 16–17) at r = |x_g − x_p| /
//! (s·h), h the cell size and s the support scale (1 by default; the weight
//! vanishes beyond 1.5·s·h).
//!
//! Two choices that do not change the shape functions, only their cost and
//! rounding (docs/conventions.md, "2D MPM"):
//! - the basis is written in local scaled coordinates, p = [1, (x − x_g)/(s h),
//!   (y − y_g)/(s h)], an affine change of [1, x, y] that spans the same space,
//!   so A⁻¹B and hence φ are the same; then pᵀ(x_g) = [1, 0, 0] and φ_gp is
//!   w_p times the first row of A⁻¹ applied to p(x_p);
//! - the neighbours come from binning the particles by cell (a counting
//!   sort, O(particles + cells)); the weight is separable, so each particle
//!   weighs itself once against the Gauss abscissae of each axis (the 1D
//!   weights w(r_x), w(r_y) of Eq. 17 that are non-zero, a run of
//!   consecutive abscissae on each axis), and is then appended to the list
//!   of every Gauss point of the rectangle the two runs span, with
//!   w = w(r_x) w(r_y) (Eq. 16). The particles are visited in the order of
//!   their cells (rows, then cells, then particles in index order), so each
//!   list holds its particles in that order.
//!
//! A moment matrix A with κ₁(A) = ‖A‖₁‖A⁻¹‖₁ above
//! [`crate::reconstruct::mls::MLS_MAX_CONDITION`] (too few particles in the
//! support, the paper's own warning) is `Error::Singular`, naming the Gauss
//! point and the number of particles its support holds.
//!
//! [`MlsShapes`] is one [`GaussReconstruction`] of the step
//! (`Mapping2d::Mls`).
//!
//! Items: [`MlsShapes`] (and [`GaussGrid`], re-exported from
//! [`super::reconstruction`]).

use super::particles::Particles2d;
pub use super::reconstruction::GaussGrid;
use super::reconstruction::{GaussReconstruction, Reconstruction, ShapeLists};
use crate::error::{Error, Result};
use crate::reconstruct::mls::{quadratic_spline_weight, MLS_MAX_CONDITION};
use nalgebra::Matrix3;

/// The MLS shape functions φ_gp of every Gauss point, as flat lists
/// (`start[g] .. end[g]` index `particle` and `phi`), with the buffers of
/// the neighbour search. Allocated once per simulation.
#[derive(Debug, Clone, Default)]
pub struct MlsShapes {
    /// s: the weight's argument is r = |x − x_p| / (s·h).
    pub support_scale: f64,
    /// Where the list of Gauss point g starts.
    pub start: Vec<usize>,
    /// The particles in the support of each Gauss point.
    pub particle: Vec<u32>,
    /// φ_gp, aligned with `particle`.
    pub phi: Vec<f64>,
    /// The largest κ₁(A) met in the last evaluation.
    pub largest_condition: f64,
    /// Where the list of Gauss point g ends (the lists are stored cell by
    /// cell, the four points of a cell together).
    pub end: Vec<usize>,
    bin_start: Vec<usize>,
    bin_particles: Vec<u32>,
    /// The 1D supports of the particles, in the order of their cells.
    supports: Vec<ParticleSupport>,
    /// (w, d) of the abscissae of each particle's 1D supports, x then y,
    /// at `ParticleSupport::at` (w the 1D weight, d the scaled offset).
    axis_weights: Vec<[f64; 2]>,
    /// The list lengths, as a 2D difference array over the Gauss points
    /// ((2·cells + 1)² entries) until `lay_out_row` sums it, row by row.
    lengths: Vec<isize>,
    /// The next free entry of each list of the row of cells being gathered.
    cursor: Vec<usize>,
    /// (scaled offset d, w) of the entries of the row's lists, from the
    /// row's first entry, aligned with `particle`; d first, so that the
    /// moment sums load the pair d at once.
    local: Vec<([f64; 2], f64)>,
}

impl MlsShapes {
    /// Buffers for `particles` particles on a grid of `cells`² cells.
    pub fn new(support_scale: f64, cells: usize, particles: usize) -> Result<Self> {
        if !(support_scale.is_finite() && support_scale > 0.0) {
            return Err(Error::NotPositive {
                what: "the MLS support scale".into(),
                value: support_scale,
            });
        }
        if particles > u32::MAX as usize {
            return Err(Error::InvalidArgument(format!(
                "{particles} particles is more than the MLS lists index"
            )));
        }
        let gauss_points = 4 * cells * cells;
        // About (3 s)² · 9 neighbours per Gauss point at 9 particles per cell.
        let per_point = ((3.0 * support_scale).powi(2) * particles as f64 / (cells * cells) as f64)
            .ceil() as usize
            + 8;
        // At most 2 (⌈3 s⌉ + 1) abscissae per axis lie within 1.5·s·h.
        let per_axis = 2 * ((3.0 * support_scale).ceil() as usize + 1);
        Ok(Self {
            support_scale,
            start: vec![0; gauss_points + 1],
            particle: Vec::with_capacity(gauss_points * per_point),
            phi: Vec::with_capacity(gauss_points * per_point),
            largest_condition: 0.0,
            end: vec![0; gauss_points],
            bin_start: vec![0; cells * cells + 1],
            bin_particles: vec![0; particles],
            supports: Vec::with_capacity(particles),
            axis_weights: Vec::with_capacity(2 * per_axis * particles),
            lengths: vec![0; (2 * cells + 1) * (2 * cells + 1)],
            cursor: vec![0; 4 * cells],
            local: vec![([0.0; 2], 0.0); 4 * cells * per_point],
        })
    }

    /// Sorts the particles by cell (a counting sort): the particles of cell
    /// c are `bin_particles[bin_start[c] .. bin_start[c + 1]]`, in index order.
    fn bin(&mut self, cell_x: &[usize], cell_y: &[usize], cells: usize) {
        let starts = &mut self.bin_start;
        starts.iter_mut().for_each(|s| *s = 0);
        for (&cx, &cy) in cell_x.iter().zip(cell_y) {
            starts[cx + cells * cy + 1] += 1;
        }
        for c in 0..cells * cells {
            starts[c + 1] += starts[c];
        }
        for (k, (&cx, &cy)) in cell_x.iter().zip(cell_y).enumerate() {
            let c = cx + cells * cy;
            self.bin_particles[starts[c]] = k as u32;
            starts[c] += 1;
        }
        // Each start moved to the next cell's start: shift back.
        for c in (1..=cells * cells).rev() {
            starts[c] = starts[c - 1];
        }
        starts[0] = 0;
    }

    /// φ_gp for every Gauss point g and particle p in its support (MLS paper
    /// Eq. 14), from the particles' positions `x` and cells `cell_x`,
    /// `cell_y`. Errors for a singular moment matrix.
    ///
    /// Row of cells by row of cells: the particles of the rows within reach
    /// weigh themselves along each axis (`MlsShapes::weigh_row`, Eq. 17),
    /// the list of every point of the row is sized and placed
    /// (`MlsShapes::lay_out_row`), the lists of the row are filled
    /// (`MlsShapes::gather`, Eq. 16) and each point solves its moment
    /// system (`MlsShapes::gauss_points`, Eqs. 10 and 14). The lists are
    /// laid out as before the rows were interleaved (all weighed, then all
    /// placed): row-major over the cells, so a row's places depend only on
    /// the rows before it.
    pub fn evaluate(
        &mut self,
        gauss: &GaussGrid,
        x: &[[f64; 2]],
        cell_x: &[usize],
        cell_y: &[usize],
    ) -> Result<()> {
        let cells = gauss.cells;
        self.bin(cell_x, cell_y, cells);
        self.start_weighing(cells);
        self.phi.clear();
        self.largest_condition = 0.0;
        let n = 2 * cells;
        let reach = self.reach_in_cells();
        let (mut weighed, mut at, mut entries) = (0, 0, 0);
        for cy in 0..cells {
            // The rows of cells within reach are weighed just before the
            // row that first needs them, so that their supports are still
            // in the cache when `gather` reads them.
            while weighed < (cy + reach + 1).min(cells) {
                at = self.weigh_row(gauss, x, weighed, at);
                weighed += 1;
            }
            entries = self.lay_out_row(cells, cy, entries);
            // Every entry is written by `gather`: the old ones need no
            // clearing, and the list grows only past the last step's length.
            if self.particle.len() < entries {
                self.particle.resize(entries, 0);
            }
            self.gather(cells, cy);
            // The row's first entry, where its `local` starts.
            let base = self.start[n * 2 * cy];
            for cx in 0..cells {
                // The cell's two points on each row of points, together.
                for gy in [2 * cy, 2 * cy + 1] {
                    let (a, b) = ([2 * cx, gy], [2 * cx + 1, gy]);
                    let xg = [a, b].map(|[gx, gy]| [gauss.abscissae[gx], gauss.abscissae[gy]]);
                    self.gauss_points(xg, [a, b].map(|[gx, gy]| gx + n * gy), base)?;
                }
            }
        }
        // Longer only if a step before held more entries.
        self.particle.truncate(entries);
        Ok(())
    }

    /// How many cells away from its own cell a particle's support reaches:
    /// the cells of the abscissae within 1.5·s·h of a point of the cell are
    /// less than 1.5·s + 1 cells away, and 1 % of a cell more covers the
    /// rounding of the particles' cells.
    fn reach_in_cells(&self) -> usize {
        (1.5 * self.support_scale + 1.01).floor() as usize
    }

    /// Clears the supports and the difference array `lengths`, and makes
    /// room in `axis_weights` for every abscissa near each particle on both
    /// axes, before the rows of cells are weighed ([`MlsShapes::weigh_row`]).
    fn start_weighing(&mut self, cells: usize) {
        let side = 2 * cells + 1;
        let reach = self.reach_in_cells();
        self.supports.clear();
        self.lengths.clear();
        self.lengths.resize(side * side, 0);
        let room = 2 * 2 * (2 * reach + 1) * self.bin_particles.len();
        if self.axis_weights.len() < room {
            self.axis_weights.resize(room, [0.0; 2]);
        }
    }

    /// Eq. (17) along each axis for every particle of row `r` of cells, in
    /// the order of the bins: the run of Gauss abscissae with w(r) > 0
    /// (r = |d|, d = (x_p − x_g)/(s h)) and their (w, d), into `supports`
    /// and `axis_weights` from entry `at` on (returned: the next free
    /// entry); each particle's rectangle of Gauss points is added to the
    /// difference array `lengths`.
    fn weigh_row(&mut self, gauss: &GaussGrid, x: &[[f64; 2]], r: usize, mut at: usize) -> usize {
        let cells = gauss.cells;
        let scale = 1.0 / (self.support_scale * gauss.cell_size);
        let reach = self.reach_in_cells();
        // The abscissae of cells c − reach ..= c + reach.
        let near = |c: usize| 2 * c.saturating_sub(reach)..(2 * (c + reach + 1)).min(2 * cells);
        let side = 2 * cells + 1;
        let Self {
            bin_start,
            bin_particles,
            supports,
            axis_weights,
            lengths,
            ..
        } = self;
        let along_y = near(r);
        for cx in 0..cells {
            let c = cx + cells * r;
            let along_x = near(cx);
            for &k in &bin_particles[bin_start[c]..bin_start[c + 1]] {
                let [px, py] = x[k as usize];
                let (fx, lx) = weigh_along(
                    px,
                    gauss.abscissae,
                    along_x.clone(),
                    scale,
                    &mut axis_weights[at..],
                );
                let (fy, ly) = weigh_along(
                    py,
                    gauss.abscissae,
                    along_y.clone(),
                    scale,
                    &mut axis_weights[at + lx..],
                );
                supports.push(ParticleSupport {
                    particle: k,
                    at,
                    first: [fx, fy],
                    len: [lx, ly],
                });
                at += lx + ly;
                // The rectangle [fx, fx + lx) × [fy, fy + ly) of points.
                lengths[fx + side * fy] += 1;
                lengths[fx + lx + side * fy] -= 1;
                lengths[fx + side * (fy + ly)] -= 1;
                lengths[fx + lx + side * (fy + ly)] += 1;
            }
        }
        at
    }

    /// The lengths of the lists of the Gauss points of row `cy` of cells
    /// (rows 2·cy and 2·cy + 1 of points), summed from the difference
    /// array `lengths` (final once every row of cells within reach of them
    /// is weighed), and from them `start` and `end` in
    /// [`storage_order`](super::reconstruction::storage_order)
    /// (cell by cell, the four points of a cell together), from entry
    /// `entries` on. Returns the number of entries of the lists of rows
    /// 0 ..= cy.
    fn lay_out_row(&mut self, cells: usize, cy: usize, mut entries: usize) -> usize {
        let (n, side) = (2 * cells, 2 * cells + 1);
        // lengths[g] becomes Σ of the differences at or before g on both axes.
        for gy in [2 * cy, 2 * cy + 1] {
            let mut along_row = 0;
            for gx in 0..n {
                along_row += self.lengths[gx + side * gy];
                let below = if gy > 0 {
                    self.lengths[gx + side * (gy - 1)]
                } else {
                    0
                };
                self.lengths[gx + side * gy] = along_row + below;
            }
        }
        // Cell by cell, the four points of a cell together.
        for cx in 0..cells {
            for gy in [2 * cy, 2 * cy + 1] {
                for gx in [2 * cx, 2 * cx + 1] {
                    let g = gx + n * gy;
                    self.start[g] = entries;
                    entries += self.lengths[gx + side * gy].max(0) as usize;
                    self.end[g] = entries;
                }
            }
        }
        entries
    }

    /// MLS paper Eqs. (12) and (16) for the Gauss points of row `cy` of
    /// cells: appends each particle p whose support reaches the row to the
    /// list of every point g of the row in its rectangle, with
    /// w = w(r_x) w(r_y) and the scaled offset d = (x_p − x_g)/(s h). The
    /// particles come in the order of their cells, so each list keeps the
    /// order of [`MlsShapes::evaluate`]'s doc.
    fn gather(&mut self, cells: usize, cy: usize) {
        let n = 2 * cells;
        let reach = self.reach_in_cells();
        let rows = [2 * cy, 2 * cy + 2];
        // The row's lists are start[g] .. end[g] for g in first_point .. first_point + 2n.
        let first_point = n * rows[0];
        let base = self.start[first_point];
        let row_entries = self.end[first_point + 2 * n - 1] - base;
        if self.local.len() < row_entries {
            self.local.resize(row_entries, ([0.0; 2], 0.0));
        }
        // The cursors count from the row's first entry `base`.
        self.cursor.clear();
        self.cursor.extend(
            self.start[first_point..first_point + 2 * n]
                .iter()
                .map(|&s| s - base),
        );
        let cell_rows = cy.saturating_sub(reach)..(cy + reach + 1).min(cells);
        let particles =
            self.bin_start[cell_rows.start * cells]..self.bin_start[cell_rows.end * cells];
        let Self {
            supports,
            axis_weights,
            cursor,
            particle,
            local,
            ..
        } = self;
        // Slices, so that their addresses stay in registers; of one length,
        // so that one bounds check covers both.
        let (particle, local) = (
            &mut particle[base..][..row_entries],
            &mut local[..row_entries],
        );
        for s in &supports[particles] {
            let along_y = s.first[1].max(rows[0])..(s.first[1] + s.len[1]).min(rows[1]);
            let weights_x = &axis_weights[s.at..][..s.len[0]];
            // Read once: the stores below could alias it for the compiler.
            let p = s.particle;
            for gy in along_y {
                let [wy, dy] = axis_weights[s.at + s.len[0] + gy - s.first[1]];
                let cursors = &mut cursor[n * (gy - rows[0]) + s.first[0]..][..s.len[0]];
                for (next, &[wx, dx]) in cursors.iter_mut().zip(weights_x) {
                    let entry = *next;
                    *next = entry + 1;
                    particle[entry] = p;
                    local[entry] = ([dx, dy], wx * wy);
                }
            }
        }
    }

    /// Eqs. (10) and (14) at two Gauss points g (at x_g), one after the
    /// other, from their gathered entries (`local` from the row's first
    /// entry `base`): accumulates both A ([`accumulate_moments`]), then for
    /// each point inverts A and appends φ_gp.
    fn gauss_points(&mut self, xg: [[f64; 2]; 2], g: [usize; 2], base: usize) -> Result<()> {
        let entries = g.map(|g| self.start[g] - base..self.end[g] - base);
        let [a, b] = entries.clone().map(|r| &self.local[r]);
        let moments = accumulate_moments(a, b);
        for ((x, r), a) in xg.into_iter().zip(entries).zip(moments) {
            let gathered = &self.local[r];
            // A that cannot be inverted counts as κ₁ = ∞ (and is not recorded).
            let (z, kappa) = inverse_first_row(&a).unwrap_or(([0.0; 3], f64::INFINITY));
            if kappa.is_finite() {
                self.largest_condition = self.largest_condition.max(kappa);
            }
            if kappa > MLS_MAX_CONDITION {
                return Err(Error::SingularMoments {
                    point: x.to_vec(),
                    points_in_support: gathered.len(),
                    condition_number: kappa,
                    limit: MLS_MAX_CONDITION,
                });
            }
            append_shape_functions(&mut self.phi, gathered, z);
        }
        Ok(())
    }
}

/// The body of [`append_shape_functions`], inlined into its baseline and AVX2 copies.
#[inline(always)]
fn append_shape_functions_kernel(phi: &mut Vec<f64>, gathered: &[([f64; 2], f64)], z: [f64; 3]) {
    let shape = |&(d, w): &([f64; 2], f64)| w * (z[0] + z[1] * d[0] + z[2] * d[1]);
    phi.extend(gathered.iter().map(shape));
}

crate::dispatch::avx2_when_available! {
    /// Appends, for each gathered (w, d), φ_gp = w (z₀ + z₁ d_x + z₂ d_y)
    /// (Eq. 14 with pᵀ(x_g) = [1, 0, 0] and z the first row of A⁻¹). One
    /// extend, not a push per entry (one capacity check), in a function of its
    /// own so that z stays in registers.
    /// AVX2 where the processor has it ([`crate::dispatch`]).
    #[inline(never)]
    fn append_shape_functions(phi: &mut Vec<f64>, gathered: &[([f64; 2], f64)], z: [f64; 3]) = append_shape_functions_kernel;
}

impl Reconstruction for MlsShapes {
    fn name(&self) -> &'static str {
        "MLS"
    }

    fn largest_condition(&self) -> f64 {
        self.largest_condition
    }
}

impl GaussReconstruction for MlsShapes {
    fn evaluate(
        &mut self,
        gauss: &GaussGrid,
        particles: &Particles2d,
        cell_x: &[usize],
        cell_y: &[usize],
    ) -> Result<()> {
        MlsShapes::evaluate(self, gauss, &particles.x, cell_x, cell_y)
    }

    fn lists(&self) -> ShapeLists<'_> {
        ShapeLists {
            start: &self.start,
            end: &self.end,
            particle: &self.particle,
            phi: &self.phi,
        }
    }
}

/// The moment sums of one Gauss point: A₀₀, [A₀₁, A₀₂], [A₁₁, A₂₁] and
/// [A₁₂, A₂₂] (MLS paper Eq. 10), each started at +0.
#[derive(Clone, Copy, Default)]
struct MomentSums {
    a00: f64,
    first: [f64; 2],
    by_x: [f64; 2],
    by_y: [f64; 2],
}

impl MomentSums {
    /// Adds the gathered entry (d, w).
    #[inline(always)]
    fn add(&mut self, &(d, w): &([f64; 2], f64)) {
        let wd = [w * d[0], w * d[1]];
        self.a00 += w;
        // Lane by lane, which the compiler packs better than pairs.
        #[allow(clippy::needless_range_loop)]
        for i in 0..2 {
            self.first[i] += wd[i];
            self.by_x[i] += wd[i] * d[0];
            self.by_y[i] += wd[i] * d[1];
        }
    }

    /// A, symmetric where the products are.
    #[inline(always)]
    fn matrix(self) -> Matrix3<f64> {
        let (first, by_x, by_y) = (self.first, self.by_x, self.by_y);
        #[rustfmt::skip]
        let a = Matrix3::new(
            self.a00, first[0], first[1],
            first[0], by_x[0], by_y[0],
            first[1], by_x[1], by_y[1],
        );
        a
    }
}

/// The body of [`accumulate_moments`], inlined into its baseline and AVX2 copies.
#[inline(always)]
fn accumulate_moments_kernel(a: &[([f64; 2], f64)], b: &[([f64; 2], f64)]) -> [Matrix3<f64>; 2] {
    let common = a.len().min(b.len());
    let (mut sums_a, mut sums_b) = (MomentSums::default(), MomentSums::default());
    for (entry_a, entry_b) in a[..common].iter().zip(&b[..common]) {
        sums_a.add(entry_a);
        sums_b.add(entry_b);
    }
    a[common..].iter().for_each(|e| sums_a.add(e));
    b[common..].iter().for_each(|e| sums_b.add(e));
    [sums_a.matrix(), sums_b.matrix()]
}

crate::dispatch::avx2_when_available! {
    /// A = Σ_p w_p q_p q_pᵀ with q = [1, d_x, d_y] over the gathered
    /// (d, w) of two Gauss points a and b (MLS paper Eq. 10), each entry
    /// summed in list order. Entry (i, j) adds (w q_i) q_j: those with
    /// i = 0 or j = 0 are w q_j or w q_i on both sides of the diagonal and
    /// are summed once; (1, 2) and (2, 1) are not the same product and are
    /// summed each, as the two lanes of a pair with (1, 1) and (2, 2). The
    /// two points' sums are independent chains of additions, which the
    /// processor overlaps (one point's sums waited on each addition; issue
    /// #39): while both lists have entries, one of each is added per round.
    /// Not inlined, so that its sums stay in registers. AVX2 where the
    /// processor has it ([`crate::dispatch`]).
    #[inline(never)]
    fn accumulate_moments(a: &[([f64; 2], f64)], b: &[([f64; 2], f64)]) -> [Matrix3<f64>; 2] = accumulate_moments_kernel;
}

/// One particle's 1D supports: along each axis, the first Gauss abscissa
/// with w(r) > 0 and how many follow it, and where their (w, d) start in
/// `MlsShapes::axis_weights` (x, then y).
#[derive(Debug, Clone, Copy, Default)]
struct ParticleSupport {
    particle: u32,
    at: usize,
    first: [usize; 2],
    len: [usize; 2],
}

/// Eq. (17) along one axis for a particle at `p`: writes (w, d) for the
/// abscissae of `near` with w(|d|) > 0, d = (p − x_g)·`scale`, to the front
/// of `out`, and returns the first of them and their number. The abscissae
/// increase, so d decreases and those with |d| < 1.5 (exactly those with
/// w > 0: below 1.5, 1.5 − |d| is at least 2⁻⁵² and w at least 2⁻¹⁰⁵) are
/// consecutive.
fn weigh_along(
    p: f64,
    abscissae: &[f64],
    near: std::ops::Range<usize>,
    scale: f64,
    out: &mut [[f64; 2]],
) -> (usize, usize) {
    let (mut first, mut len) = (near.start, 0);
    for (a, &g) in abscissae[near.clone()].iter().enumerate() {
        let d = (p - g) * scale;
        if d >= 1.5 {
            first = near.start + a + 1;
            continue;
        }
        // Past the support (or d is NaN): no later abscissa is in it.
        if d <= -1.5 || d.is_nan() {
            break;
        }
        out[len] = [quadratic_spline_weight(d), d];
        len += 1;
    }
    (first, len)
}

/// The first row of A⁻¹ (= its first column, A being symmetric) and
/// κ₁(A) = ‖A‖₁‖A⁻¹‖₁; `None` if A is not invertible or κ is not finite.
fn inverse_first_row(a: &Matrix3<f64>) -> Option<([f64; 3], f64)> {
    let inv = a.try_inverse()?;
    let norm1 = |m: &Matrix3<f64>| {
        (0..3)
            .map(|j| (0..3).map(|i| m[(i, j)].abs()).sum::<f64>())
            .fold(0.0, f64::max)
    };
    let kappa = norm1(a) * norm1(&inv);
    kappa
        .is_finite()
        .then_some(([inv[(0, 0)], inv[(0, 1)], inv[(0, 2)]], kappa))
}
