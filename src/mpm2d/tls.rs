//! # Taylor least squares in 2D, at the Gauss points
//!
//! The TLS paper writes its Taylor basis out in 1D (§5.2, book Eq. 4.31);
//! this module writes it for a rectangular cell Ω_e = [x₀, x₁] × [y₀, y₁]
//! with centroid (x_c, y_c) and half-widths Δx = (x₁ − x₀)/2,
//! Δy = (y₁ − y₀)/2, in the same pattern: with ξ = (x − x_c)/Δx and
//! η = (y − y_c)/Δy, each Taylor term (x − x_c)^a (y − y_c)^b /(a! b!)
//! scaled by Δx^a Δy^b, minus its cell average,
//!
//! ψ₁ = 1, ψ₂ = ξ, ψ₃ = η, ψ₄ = (ξ² − 1/3)/2, ψ₅ = ξη, ψ₆ = (η² − 1/3)/2.
//!
//! The averages of ξ² and η² over the cell are 1/3 and that of ξη is 0, so
//! ∫_{Ω_e} ψ_i = |Ω_e| δ_{i1}: the integral property of TLS paper Eq. (12),
//! the only property its conservation proof (§5.5) uses.
//!
//! **The fit** (TLS paper Eqs. 13–14, book Eqs. 4.33–4.36), per cell, from
//! the particles p of the cell with values f_p and volumes V_p:
//! - *conservative* ([`TlsVariant::Conservative`], the engine's choice):
//!   α₁ = Σ_p V_p f_p / |Ω_e| (Eq. 14), and ψ₂ … ψ_{n_b} fitted to
//!   f_p − α₁ by least squares, so ∫_{Ω_e} f̃ = α₁|Ω_e| = Σ_p V_p f_p;
//! - *unconstrained* ([`TlsVariant::Unconstrained`]): all n_b coefficients
//!   fitted (Eq. 13).
//!
//! Both are linear in f, so each is a [`GaussReconstruction`]: with D the
//! normal matrix Σ_p ψ̂(x_p) ψ̂(x_p)ᵀ of the fitted functions ψ̂ and
//! z_g = D⁻¹ ψ̂(x_g), r_gp = z_gᵀ ψ̂(x_p), the shape functions are
//!
//! φ_gp = r_gp + (V_p/|Ω_e|)(1 − Σ_q r_gq)   (conservative),
//! φ_gp = r_gp                                (unconstrained).
//!
//! Since the 2×2 Gauss rule integrates every ψ_i exactly and Σ_g ω_g = |Ω_e|,
//! Σ_g ω_g φ_gp = V_p in the conservative variant: the mapped mass and
//! momentum Σ_g ω_g f̃_g equal the particles' Σ_p V_p f_p to rounding, at
//! every step (the TLS paper's §5.5 proof, in 2D).
//!
//! **Degenerate cells** (TLS paper §5.3). A cell is degenerate when its
//! normal matrix has κ₁(D) = ‖D‖₁‖D⁻¹‖₁ above [`TLS_2D_MAX_CONDITION`] or
//! cannot be inverted: fewer particles than fitted functions, or particles
//! on a line (a quadratic fit needs them off every conic). hompm's 2D
//! repair is the reduced basis: quadratic → linear → constant, the first
//! that is well conditioned ([`DegenerateCells::ReduceBasis`], the engine's
//! choice; docs/conventions.md "2D TLS"). It keeps the constraint, so the
//! repaired cell still conserves. The paper's virtual points (the
//! neighbour's fit at the shared boundary) have no unique 2D counterpart
//! (an edge, not a point, is shared) and are not offered; with
//! [`DegenerateCells::Error`] a degenerate cell is `Error::SingularCell`
//! naming the cell. A TLS fit is per cell, so the MLS failure at a corner
//! Gauss point whose support loses its particles has no TLS counterpart: a
//! cell without particles has f̃ = 0, which is exactly its particles' sum.
//!
//! **Which basis a cell starts from** ([`BasisRule`]). The engine starts
//! every cell at the quadratic basis and lowers it only when the fit is
//! degenerate ([`BasisRule::Conditioning`]). The 2D TLS of QuocAnh90/MPM2D_basic
//! (commit cc01c1b, `SubFunctions/TLS2D.m:56-76`) chooses by the particle
//! count instead ([`BasisRule::ParticleCount`]): under the constraint, the
//! constant alone below 3 particles, linear below 6, quadratic from 6;
//! without it, linear below 6, quadratic from 6. The two differ in a
//! conservative cell of 5 particles (five points determine the five fitted
//! quadratic functions, so the engine interpolates where the count rule
//! fits a plane) and of 2 (the engine interpolates a plane through two
//! points off a line through the centroid, the count rule keeps the
//! average). hompm's count rule still reduces a basis that is degenerate
//! (six particles on two rows, where the unconstrained fit's ψ₁ and ψ₆ agree), where that code solves a singular
//! system (docs/reproduction-notes.md, "The 2D TLS of MPM2D_basic").
//!
//! Items: [`TLS_2D_MAX_CONDITION`], [`TaylorOrder2d`], [`TlsVariant`],
//! [`BasisRule`], [`TaylorBasis2d`], [`TlsShapes`].

use super::lu::try_inverse_lu;
use super::particles::Particles2d;
use super::reconstruction::{
    GaussGrid, GaussReconstruction, Reconstruction, ShapeBuffers, ShapeLists,
};
use crate::error::{Error, Result};
use crate::reconstruct::taylor::{CellBins, DegenerateCells};
use nalgebra::SMatrix;

/// κ₁(D) above which a 2D cell is degenerate: 1e10, the 1D TLS default
/// (`TlsOptions::default().max_condition`).
pub const TLS_2D_MAX_CONDITION: f64 = 1e10;

/// The number of 2D Taylor functions n_b.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum TaylorOrder2d {
    /// ψ₁ (n_b = 1).
    Constant,
    /// ψ₁, ψ₂, ψ₃ (n_b = 3).
    Linear,
    /// ψ₁ … ψ₆ (n_b = 6), the 2D counterpart of the seeds' quadratic n_b = 3.
    Quadratic,
}

impl TaylorOrder2d {
    /// n_b.
    pub fn functions(self) -> usize {
        match self {
            TaylorOrder2d::Constant => 1,
            TaylorOrder2d::Linear => 3,
            TaylorOrder2d::Quadratic => 6,
        }
    }

    /// The next smaller basis of the reduced-basis repair.
    pub fn reduced(self) -> Option<Self> {
        match self {
            TaylorOrder2d::Quadratic => Some(TaylorOrder2d::Linear),
            TaylorOrder2d::Linear => Some(TaylorOrder2d::Constant),
            TaylorOrder2d::Constant => None,
        }
    }

    fn name(self) -> &'static str {
        match self {
            TaylorOrder2d::Constant => "constant",
            TaylorOrder2d::Linear => "linear",
            TaylorOrder2d::Quadratic => "quadratic",
        }
    }
}

/// Conservative (TLS paper Eq. 14) or unconstrained (Eq. 13) TLS.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TlsVariant {
    /// α₁ = Σ_p V_p f_p/|Ω_e|, the rest fitted: conserves by construction.
    Conservative,
    /// Every coefficient fitted.
    Unconstrained,
}

/// The basis a cell's fit starts from (module doc, "Which basis a cell
/// starts from"); either is reduced further while the fit is degenerate
/// (TLS paper §5.3, under [`DegenerateCells::ReduceBasis`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BasisRule {
    /// The order the shapes were built with, in every cell (hompm's engine).
    Conditioning,
    /// By the number of particles n of the cell, as `TLS2D.m:56-76` of
    /// MPM2D_basic (cc01c1b): conservative, constant for n < 3, linear for
    /// n < 6, quadratic otherwise; unconstrained, linear for n < 6,
    /// quadratic otherwise. Never above the order the shapes were built with;
    /// [`Reconstruction::repaired`] then counts every cell fitted below that
    /// order, whether the count or the repair lowered it.
    ParticleCount,
}

impl BasisRule {
    /// The starting basis of a cell of `particles` particles, at most
    /// `order`, for `variant` (the variants of [`BasisRule`]).
    pub fn start(
        self,
        order: TaylorOrder2d,
        variant: TlsVariant,
        particles: usize,
    ) -> TaylorOrder2d {
        let by_count = match (self, variant, particles) {
            (BasisRule::Conditioning, _, _) => TaylorOrder2d::Quadratic,
            (BasisRule::ParticleCount, TlsVariant::Conservative, 0..=2) => TaylorOrder2d::Constant,
            (BasisRule::ParticleCount, _, 0..=5) => TaylorOrder2d::Linear,
            (BasisRule::ParticleCount, _, _) => TaylorOrder2d::Quadratic,
        };
        by_count.min(order)
    }
}

/// The 2D Taylor basis of one rectangular cell (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TaylorBasis2d {
    centroid: [f64; 2],
    half_width: [f64; 2],
}

impl TaylorBasis2d {
    /// The basis of [lower₀, upper₀] × [lower₁, upper₁].
    pub fn new(lower: [f64; 2], upper: [f64; 2]) -> Result<Self> {
        for k in 0..2 {
            let size = upper[k] - lower[k];
            if !(lower[k].is_finite() && upper[k].is_finite() && size.is_finite() && size > 0.0) {
                return Err(Error::InvalidArgument(format!(
                    "a 2D Taylor cell needs lower < upper on both axes, got {lower:?} to {upper:?}"
                )));
            }
        }
        Ok(Self {
            centroid: [0.5 * (lower[0] + upper[0]), 0.5 * (lower[1] + upper[1])],
            half_width: [0.5 * (upper[0] - lower[0]), 0.5 * (upper[1] - lower[1])],
        })
    }

    /// (x_c, y_c).
    pub fn centroid(&self) -> [f64; 2] {
        self.centroid
    }

    /// |Ω_e| = 4 Δx Δy.
    pub fn area(&self) -> f64 {
        4.0 * self.half_width[0] * self.half_width[1]
    }

    /// ψ₁ … ψ₆ at `point` (module doc).
    pub fn evaluate(&self, point: [f64; 2]) -> [f64; 6] {
        let xi = (point[0] - self.centroid[0]) / self.half_width[0];
        let eta = (point[1] - self.centroid[1]) / self.half_width[1];
        [
            1.0,
            xi,
            eta,
            0.5 * (xi * xi - 1.0 / 3.0),
            xi * eta,
            0.5 * (eta * eta - 1.0 / 3.0),
        ]
    }
}

/// The 2D TLS shape functions at the Gauss points, with their buffers.
#[derive(Debug, Clone)]
pub struct TlsShapes {
    order: TaylorOrder2d,
    variant: TlsVariant,
    degenerate: DegenerateCells,
    rule: BasisRule,
    max_condition: f64,
    shapes: ShapeBuffers,
    largest_condition: f64,
    repaired: usize,
    bins: CellBins,
    /// ψ(x_p) of the particles of the cell being fitted.
    rows: Vec<[f64; 6]>,
    /// V_p/|Ω_e| of the same particles (the conservative correction's
    /// weights, divided once per particle rather than once per Gauss point).
    shares: Vec<f64>,
}

/// The result of one cell's fit: z_g = D⁻¹ψ̂(x_g) for its four Gauss
/// points, κ₁(D), and the basis used.
struct CellSolution {
    z: [[f64; 6]; 4],
    condition: f64,
    order: TaylorOrder2d,
}

impl TlsShapes {
    /// Buffers for `particles` particles on `cells`² cells. The degenerate
    /// policy is `Error` or `ReduceBasis`; `VirtualPoints` has no 2D form
    /// (module doc) and is refused.
    pub fn new(
        order: TaylorOrder2d,
        variant: TlsVariant,
        degenerate: DegenerateCells,
        cells: usize,
        particles: usize,
    ) -> Result<Self> {
        if degenerate == DegenerateCells::VirtualPoints {
            return Err(Error::InvalidArgument(
                "2D TLS repairs degenerate cells by reducing the basis or refuses them; virtual points are 1D only".into(),
            ));
        }
        if particles > u32::MAX as usize {
            return Err(Error::InvalidArgument(format!(
                "{particles} particles is more than the TLS lists index"
            )));
        }
        let gauss_points = 4 * cells * cells;
        Ok(Self {
            order,
            variant,
            degenerate,
            rule: BasisRule::Conditioning,
            max_condition: TLS_2D_MAX_CONDITION,
            shapes: ShapeBuffers {
                start: vec![0; gauss_points],
                end: vec![0; gauss_points],
                // Each particle appears in the four lists of its cell.
                particle: Vec::with_capacity(4 * particles),
                phi: Vec::with_capacity(4 * particles),
            },
            largest_condition: 0.0,
            repaired: 0,
            bins: CellBins::default(),
            rows: Vec::new(),
            shares: Vec::new(),
        })
    }

    /// The same with another κ₁(D) limit of a degenerate cell (default
    /// [`TLS_2D_MAX_CONDITION`]).
    pub fn with_max_condition(mut self, limit: f64) -> Self {
        self.max_condition = limit;
        self
    }

    /// The same with another rule for a cell's starting basis (default
    /// [`BasisRule::Conditioning`]).
    pub fn with_basis_rule(mut self, rule: BasisRule) -> Self {
        self.rule = rule;
        self
    }

    /// The engine's TLS: quadratic, conservative, reduced-basis repair.
    pub fn for_engine(cells: usize, particles: usize) -> Result<Self> {
        Self::new(
            TaylorOrder2d::Quadratic,
            TlsVariant::Conservative,
            DegenerateCells::ReduceBasis,
            cells,
            particles,
        )
    }

    /// Fits one cell at the basis `order` or, under `ReduceBasis`, the
    /// largest smaller one that is well conditioned.
    fn solve_cell(
        &self,
        basis: &TaylorBasis2d,
        gauss: [[f64; 2]; 4],
        cell: [usize; 2],
        h: f64,
    ) -> Result<CellSolution> {
        let skip = usize::from(self.variant == TlsVariant::Conservative);
        let at = gauss.map(|x| basis.evaluate(x));
        let mut order = self.rule.start(self.order, self.variant, self.rows.len());
        loop {
            let fitted = order.functions() - skip;
            let solved = match fitted {
                0 => Some(([[0.0; 6]; 4], 1.0)),
                1 => normal_solve::<1>(&self.rows, skip, &at),
                2 => normal_solve::<2>(&self.rows, skip, &at),
                3 => normal_solve::<3>(&self.rows, skip, &at),
                5 => normal_solve::<5>(&self.rows, skip, &at),
                6 => normal_solve::<6>(&self.rows, skip, &at),
                _ => None,
            };
            let kappa = solved.as_ref().map_or(f64::INFINITY, |s| s.1);
            match solved {
                Some((z, condition)) if condition <= self.max_condition => {
                    return Ok(CellSolution {
                        z,
                        condition,
                        order,
                    })
                }
                _ => {}
            }
            match (self.degenerate, order.reduced()) {
                (DegenerateCells::ReduceBasis, Some(lower)) => order = lower,
                _ => {
                    let lower = [cell[0] as f64 * h, cell[1] as f64 * h];
                    return Err(Error::SingularCell {
                        cell: cell.to_vec(),
                        lower: lower.to_vec(),
                        upper: vec![lower[0] + h, lower[1] + h],
                        detail: format!(
                            "{} particles for the {} Taylor basis ({} fitted functions), κ₁(D) = {kappa:e} > {:e}",
                            self.rows.len(),
                            order.name(),
                            fitted,
                            self.max_condition
                        ),
                    });
                }
            }
        }
    }
}

/// D = Σ_p ψ̂(x_p) ψ̂(x_p)ᵀ over the M functions ψ_{skip+1} … ψ_{skip+M}
/// (TLS paper Eq. 13's normal matrix), accumulated particle by particle.
/// Only D_ij with i ≤ j is summed, and D_ji is that sum: each term of D_ji
/// is ψ̂_j ψ̂_i, the same product as ψ̂_i ψ̂_j (IEEE 754 multiplication is
/// commutative), added in the same order, so the two sums have one value
/// bit for bit.
fn normal_matrix<const M: usize>(rows: &[[f64; 6]], skip: usize) -> [[f64; M]; M] {
    let mut d = [[0.0; M]; M];
    for row in rows {
        let r = &row[skip..skip + M];
        for (i, (d_i, r_i)) in d.iter_mut().zip(r).enumerate() {
            for (d_ij, r_j) in d_i[i..].iter_mut().zip(&r[i..]) {
                *d_ij += r_i * r_j;
            }
        }
    }
    std::array::from_fn(|i| std::array::from_fn(|j| d[i.min(j)][i.max(j)]))
}

/// The body of [`normal_solve`], inlined into its baseline and AVX2 copies.
#[inline(always)]
fn normal_solve_kernel<const M: usize>(
    rows: &[[f64; 6]],
    skip: usize,
    at: &[[f64; 6]; 4],
) -> Option<([[f64; 6]; 4], f64)> {
    let d = normal_matrix::<M>(rows, skip);
    let inverse = if M >= 5 {
        try_inverse_lu(&d)?
    } else {
        let inverse = SMatrix::<f64, M, M>::from_fn(|i, j| d[i][j]).try_inverse()?;
        std::array::from_fn(|i| std::array::from_fn(|j| inverse[(i, j)]))
    };
    let norm1 = |m: &[[f64; M]; M]| {
        (0..M)
            .map(|j| (0..M).map(|i| m[i][j].abs()).sum::<f64>())
            .fold(0.0, f64::max)
    };
    let kappa = norm1(&d) * norm1(&inverse);
    if !kappa.is_finite() {
        return None;
    }
    let mut z = [[0.0; 6]; 4];
    for (zq, psi) in z.iter_mut().zip(at) {
        for i in 0..M {
            zq[skip + i] = (0..M).map(|j| inverse[i][j] * psi[skip + j]).sum();
        }
    }
    // Conservative TLS (skip = 1): the four Gauss points have equal
    // weights and integrate every ψ_i, i ≥ 2, to zero, so Σ_q ψ̂(x_q) = 0
    // and the mean of the z_q is zero in exact arithmetic; the computed
    // mean (its rounding, amplified by D⁻¹) is removed. This is rounding
    // hygiene with no measured effect: the rounding of the φ_gp themselves,
    // of size ε·max|φ_gp|, remains, and it grows with κ(D)
    // (docs/reproduction-notes.md, "BSMPM with Taylor least squares in
    // 2D"). Unconstrained TLS fits ψ₁ too, whose z_q have a non-zero mean.
    for i in (skip..skip + M).filter(|_| skip == 1) {
        let mean = 0.25 * z.iter().map(|zq| zq[i]).sum::<f64>();
        z.iter_mut().for_each(|zq| zq[i] -= mean);
    }
    Some((z, kappa))
}

crate::dispatch::avx2_when_available! {
    /// z_q = D⁻¹ ψ̂(x_q) for the four Gauss points and κ₁(D), with
    /// D = Σ_p ψ̂(x_p) ψ̂(x_p)ᵀ over the M functions ψ_{skip+1} … ψ_{skip+M};
    /// `None` if D cannot be inverted or κ is not finite. Not inlined, so that
    /// its per-cell code compiles alike whatever code surrounds it (issue #39:
    /// inlined, it varied by ~35 instructions per particle-step with changes
    /// elsewhere in the crate). AVX2 where the processor has it
    /// ([`crate::dispatch`]; TLS 64 cells: 128.1 -> 125.5 ns per particle-step).
    #[inline(never)]
    fn normal_solve<const M: usize>(
        rows: &[[f64; 6]],
        skip: usize,
        at: &[[f64; 6]; 4],
    ) -> Option<([[f64; 6]; 4], f64)> = normal_solve_kernel;
}

impl Reconstruction for TlsShapes {
    fn name(&self) -> &'static str {
        "TLS"
    }

    fn largest_condition(&self) -> f64 {
        self.largest_condition
    }

    fn repaired(&self) -> usize {
        self.repaired
    }
}

impl GaussReconstruction for TlsShapes {
    /// TLS paper Eqs. (13)–(14) on every cell, then φ_gp at its four Gauss
    /// points (module doc).
    fn evaluate(
        &mut self,
        gauss: &GaussGrid,
        particles: &Particles2d,
        cell_x: &[usize],
        cell_y: &[usize],
    ) -> Result<()> {
        let (cells, h) = (gauss.cells, gauss.cell_size);
        let n = particles.len();
        self.bins.fill(cells * cells, n, |k| {
            Ok((cell_x[k] + cells * cell_y[k], None))
        })?;
        self.shapes.particle.clear();
        self.shapes.phi.clear();
        self.largest_condition = 0.0;
        self.repaired = 0;
        let ng = 2 * cells;
        for cy in 0..cells {
            for cx in 0..cells {
                let lower = [cx as f64 * h, cy as f64 * h];
                let basis = TaylorBasis2d::new(lower, [lower[0] + h, lower[1] + h])?;
                let members = self.bins.points_of(cx + cells * cy);
                self.rows.clear();
                self.rows
                    .extend(members.iter().map(|&k| basis.evaluate(particles.x[k])));
                let points = [(0, 0), (1, 0), (0, 1), (1, 1)]
                    .map(|(i, j)| [gauss.abscissae[2 * cx + i], gauss.abscissae[2 * cy + j]]);
                let solution = if members.is_empty() {
                    None
                } else {
                    Some(self.solve_cell(&basis, points, [cx, cy], h)?)
                };
                if let Some(s) = &solution {
                    self.largest_condition = self.largest_condition.max(s.condition);
                    self.repaired += usize::from(s.order < self.order);
                }
                let area = basis.area();
                self.shares.clear();
                if self.variant == TlsVariant::Conservative {
                    self.shares
                        .extend(members.iter().map(|&k| particles.volume[k] / area));
                }
                for (q, (i, j)) in [(0, 0), (1, 0), (0, 1), (1, 1)].into_iter().enumerate() {
                    let g = (2 * cx + i) + ng * (2 * cy + j);
                    let first = self.shapes.particle.len();
                    self.shapes.start[g] = first;
                    if let Some(s) = &solution {
                        let z = &s.z[q];
                        // r_gp = z_gᵀ ψ̂(x_p), appended by two extends (one
                        // capacity check each, not one per entry).
                        let r =
                            |row: &[f64; 6]| -> f64 { z.iter().zip(row).map(|(a, b)| a * b).sum() };
                        self.shapes
                            .particle
                            .extend(members.iter().map(|&k| k as u32));
                        self.shapes.phi.extend(self.rows.iter().map(r));
                        let sum = self.shapes.phi[first..].iter().fold(0.0, |s, r| s + r);
                        if self.variant == TlsVariant::Conservative {
                            let rest = 1.0 - sum;
                            for (phi, share) in
                                self.shapes.phi[first..].iter_mut().zip(&self.shares)
                            {
                                *phi += share * rest;
                            }
                        }
                    }
                    self.shapes.end[g] = self.shapes.particle.len();
                }
            }
        }
        Ok(())
    }

    fn lists(&self) -> ShapeLists<'_> {
        self.shapes.lists()
    }
}
