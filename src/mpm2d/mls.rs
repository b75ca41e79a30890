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
//!   sort, O(particles + cells)), and each Gauss point scans only the 4×4
//!   cells its support can reach.
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
    /// (particle, w, scaled offset) gathered for the four points of a cell.
    local: [Vec<(u32, f64, [f64; 2])>; 4],
    /// How many entries of each `local` list are kept.
    count: [usize; 4],
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
        Ok(Self {
            support_scale,
            start: vec![0; gauss_points + 1],
            particle: Vec::with_capacity(gauss_points * per_point),
            phi: Vec::with_capacity(gauss_points * per_point),
            largest_condition: 0.0,
            end: vec![0; gauss_points],
            bin_start: vec![0; cells * cells + 1],
            bin_particles: vec![0; particles],
            local: std::array::from_fn(|_| vec![(0, 0.0, [0.0; 2]); 4 * per_point]),
            count: [0; 4],
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
    /// The four Gauss points of a cell share one gathering of candidates
    /// (the particles of the 5×5 cells around it, which hold every particle
    /// within 1.5·s·h of any of them when s ≤ 1, and of more cells when s > 1),
    /// and the weight w(r_x) w(r_y) is separable, so each candidate costs
    /// at most four 1D weights for the four points. A cell of the border of
    /// the 5×5 reaches only the points on its side (two, or one at a corner):
    /// its candidates are weighed and listed for those alone.
    pub fn evaluate(
        &mut self,
        gauss: &GaussGrid,
        x: &[[f64; 2]],
        cell_x: &[usize],
        cell_y: &[usize],
    ) -> Result<()> {
        let cells = gauss.cells;
        self.bin(cell_x, cell_y, cells);
        self.particle.clear();
        self.phi.clear();
        self.largest_condition = 0.0;
        let n = 2 * cells;
        for cy in 0..cells {
            for cx in 0..cells {
                self.gather(gauss, [cx, cy], x);
                for (j, gy) in [2 * cy, 2 * cy + 1].into_iter().enumerate() {
                    for (i, gx) in [2 * cx, 2 * cx + 1].into_iter().enumerate() {
                        let g = gx + n * gy;
                        self.start[g] = self.particle.len();
                        let xg = [gauss.abscissae[gx], gauss.abscissae[gy]];
                        self.gauss_point(xg, 2 * j + i)?;
                        self.end[g] = self.particle.len();
                    }
                }
            }
        }
        Ok(())
    }

    /// Collects, for the four Gauss points of cell (cx, cy), the particles
    /// with w > 0: `local[q]` holds (particle, w, offset) of point q = 2j + i.
    fn gather(&mut self, gauss: &GaussGrid, cell: [usize; 2], x: &[[f64; 2]]) {
        let (h, cells) = (gauss.cell_size, gauss.cells);
        let scale = 1.0 / (self.support_scale * h);
        let reach = 1.5 * self.support_scale * h;
        let gx = [
            gauss.abscissae[2 * cell[0]],
            gauss.abscissae[2 * cell[0] + 1],
        ];
        let gy = [
            gauss.abscissae[2 * cell[1]],
            gauss.abscissae[2 * cell[1] + 1],
        ];
        let xr = Self::cell_range(gx[0] - reach, gx[1] + reach, h, cells);
        let yr = Self::cell_range(gy[0] - reach, gy[1] + reach, h, cells);
        let candidates: usize = yr
            .clone()
            .map(|cy| {
                self.bin_start[cy * cells + xr.end() + 1] - self.bin_start[cy * cells + xr.start()]
            })
            .sum();
        for l in self.local.iter_mut() {
            if l.len() < candidates {
                l.resize(candidates, (0, 0.0, [0.0; 2]));
            }
        }
        self.count = [0; 4];
        let Self {
            bin_start,
            bin_particles,
            local,
            count,
            ..
        } = self;
        // Cell by cell in the bins' order (rows, then cells, then particles
        // in index order), so every list keeps the candidates' order; a cell
        // is offered only to the points whose support it can reach.
        for cy in yr {
            let my = Self::reachable(cy, gy, reach, h);
            for cx in xr.clone() {
                let mx = Self::reachable(cx, gx, reach, h);
                let c = cy * cells + cx;
                let particles = &bin_particles[bin_start[c]..bin_start[c + 1]];
                let scan = Scan {
                    x,
                    gx,
                    gy,
                    scale,
                    local: &mut *local,
                    count: &mut *count,
                };
                macro_rules! masks {
                    ($(($i:literal, $j:literal)),*) => {
                        match (mx, my) {
                            $(($i, $j) => scan.cell::<$i, $j>(particles),)*
                            _ => {}
                        }
                    };
                }
                masks!(
                    (1, 1),
                    (1, 2),
                    (1, 3),
                    (2, 1),
                    (2, 2),
                    (2, 3),
                    (3, 1),
                    (3, 2),
                    (3, 3)
                );
            }
        }
    }

    /// Which of the two points g[0], g[1] of an axis the particles of cell
    /// c of that axis may lie within `reach` of: bit i for g[i]. The cell
    /// [c h, (c + 1) h] is widened by h/100, far more than the rounding of
    /// the particles' cells and of the scaled offsets, so a point left out
    /// has w = 0 for every particle of the cell.
    fn reachable(c: usize, g: [f64; 2], reach: f64, h: f64) -> u8 {
        let (lo, hi) = (c as f64 * h - 0.01 * h, (c + 1) as f64 * h + 0.01 * h);
        let near = |g: f64| lo < g + reach && hi > g - reach;
        u8::from(near(g[0])) | (u8::from(near(g[1])) << 1)
    }

    /// The cells a reach [lo, hi] on one axis touches.
    fn cell_range(lo: f64, hi: f64, h: f64, cells: usize) -> std::ops::RangeInclusive<usize> {
        let first = (lo / h).floor().max(0.0) as usize;
        let last = ((hi / h).floor().max(0.0) as usize).min(cells - 1);
        first..=last
    }

    /// Eqs. (10), (14), (16)–(17) at one Gauss point from its gathered
    /// particles `local[q]`: accumulates A, inverts it and appends φ_gp.
    fn gauss_point(&mut self, xg: [f64; 2], q: usize) -> Result<()> {
        let a = accumulate_moment(&self.local[q][..self.count[q]]);
        // A that cannot be inverted counts as κ₁ = ∞ (and is not recorded).
        let (z, kappa) = inverse_first_row(&a).unwrap_or(([0.0; 3], f64::INFINITY));
        if kappa.is_finite() {
            self.largest_condition = self.largest_condition.max(kappa);
        }
        if kappa > MLS_MAX_CONDITION {
            return Err(Error::SingularMoments {
                point: xg.to_vec(),
                points_in_support: self.count[q],
                condition_number: kappa,
                limit: MLS_MAX_CONDITION,
            });
        }
        let gathered = &self.local[q][..self.count[q]];
        append_shape_functions(&mut self.particle, &mut self.phi, gathered, z);
        Ok(())
    }
}

/// Appends, for each gathered (particle, w, d), the particle and
/// φ_gp = w (z₀ + z₁ d_x + z₂ d_y) (Eq. 14 with pᵀ(x_g) = [1, 0, 0] and
/// z the first row of A⁻¹). Two extends, not a push per entry (one
/// capacity check each), in a function of its own so that z stays in
/// registers.
#[inline(never)]
fn append_shape_functions(
    particle: &mut Vec<u32>,
    phi: &mut Vec<f64>,
    gathered: &[(u32, f64, [f64; 2])],
    z: [f64; 3],
) {
    particle.extend(gathered.iter().map(|&(k, _, _)| k));
    let shape = |&(_, w, d): &(u32, f64, [f64; 2])| w * (z[0] + z[1] * d[0] + z[2] * d[1]);
    phi.extend(gathered.iter().map(shape));
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

/// A = Σ_p w_p q_p q_pᵀ with q = [1, d_x, d_y] over the gathered
/// (particle, w, d) (MLS paper Eq. 10), each entry summed in list order.
/// Entry (i, j) adds (w q_i) q_j: those with i = 0 or j = 0 are w q_j or
/// w q_i on both sides of the diagonal and are summed once; (1, 2) and
/// (2, 1) are not the same product and are summed each, as the two lanes
/// of a pair with (1, 1) and (2, 2). Not inlined, so that its sums stay in
/// registers.
#[inline(never)]
fn accumulate_moment(gathered: &[(u32, f64, [f64; 2])]) -> Matrix3<f64> {
    let mut a00 = 0.0;
    // [A01, A02], [A11, A21], [A12, A22].
    let (mut first, mut by_x, mut by_y) = ([0.0; 2], [0.0; 2], [0.0; 2]);
    for &(_, w, d) in gathered {
        let wd = [w * d[0], w * d[1]];
        a00 += w;
        first = [first[0] + wd[0], first[1] + wd[1]];
        by_x = [by_x[0] + wd[0] * d[0], by_x[1] + wd[1] * d[0]];
        by_y = [by_y[0] + wd[0] * d[1], by_y[1] + wd[1] * d[1]];
    }
    #[rustfmt::skip]
    let a = Matrix3::new(
        a00, first[0], first[1],
        first[0], by_x[0], by_y[0],
        first[1], by_x[1], by_y[1],
    );
    a
}

/// One cell's candidates offered to the points of a cell
/// ([`Scan::cell`]).
struct Scan<'a> {
    x: &'a [[f64; 2]],
    gx: [f64; 2],
    gy: [f64; 2],
    scale: f64,
    local: &'a mut [Vec<(u32, f64, [f64; 2])>; 4],
    count: &'a mut [usize; 4],
}

impl Scan<'_> {
    /// Appends (particle, w, scaled offset) of each of `particles` to the
    /// list of every point q = 2j + i with bit i of `MX` and bit j of `MY`
    /// set, kept where w = w(d_x) w(d_y) > 0 (Eqs. 16–17; a branch-free
    /// compaction, as about half of the candidates fall outside a support,
    /// which a branch would mispredict).
    #[inline(always)]
    fn cell<const MX: u8, const MY: u8>(self, particles: &[u32]) {
        let (gx, gy, scale) = (self.gx, self.gy, self.scale);
        let weight = |on: bool, d: f64| if on { quadratic_spline_weight(d) } else { 0.0 };
        for &k in particles {
            let [px, py] = self.x[k as usize];
            let dx = [(px - gx[0]) * scale, (px - gx[1]) * scale];
            let dy = [(py - gy[0]) * scale, (py - gy[1]) * scale];
            let wx = [weight(MX & 1 != 0, dx[0]), weight(MX & 2 != 0, dx[1])];
            let wy = [weight(MY & 1 != 0, dy[0]), weight(MY & 2 != 0, dy[1])];
            for j in 0..2 {
                for i in 0..2 {
                    if MY >> j & 1 == 0 || MX >> i & 1 == 0 {
                        continue;
                    }
                    let q = 2 * j + i;
                    let w = wx[i] * wy[j];
                    self.local[q][self.count[q]] = (k, w, [dx[i], dy[j]]);
                    self.count[q] += usize::from(w > 0.0);
                }
            }
        }
    }
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
