//! # p-multigrid
//!
//! Book §4.7, Eqs. (4.59)–(4.62), after Tielen et al. (book ref. \[235\], docs/bibliography.md). The hierarchy is
//! built on the *same* knot spans with degrees p, p−1, …, 1 and maximal
//! continuity C^{q−1} on every level q; each level's mass matrix is
//! rediscretised. One two-grid step on level q:
//!
//! 1. ν₁ smoothing steps a ← a + S(f − M a) (Eq. 4.60);
//! 2. restrict the residual, r_{q−1} = I_q^{q−1}(f − M a), and solve
//!    M_{q−1} e = r_{q−1} (Eq. 4.61) — recursively by the same cycle (V-cycle),
//!    and on level 1 by CG to a relative tolerance of 1e-4 (Eq. 4.53);
//! 3. prolongate and correct, a ← a + I_{q−1}^q e (Eq. 4.62);
//! 4. ν₂ smoothing steps.
//!
//! Transfers use the mixed mass matrix P_ij = ∫ φ_i^q φ_j^{q−1}:
//! prolongation I_{q−1}^q = M_q⁻¹ P and restriction I_q^{q−1} = M_{q−1}⁻¹ Pᵀ,
//! with M either the lumped (row-sum) or the consistent mass matrix. In 2D
//! every transfer is a Kronecker product of 1D transfers, and each level's
//! forward Gauss–Seidel sweep reads the entries of M_q ⊗ M_q from the 1D
//! M_q ([`gauss_seidel_sweep_kronecker`], the bits of the assembled sweep).
//!
//! When the finest level is already p = 1 (book Table 4.4, first row) a cycle
//! is ν₁ smoothing, a CG solve (tolerance 1e-4) of the residual equation on
//! that level, and ν₂ smoothing (docs/conventions.md).
//!
//! Items: [`Smoother`], [`Transfer`], [`PMultigridOptions`], [`PMultigrid`],
//! [`gauss_seidel_sweep`], [`gauss_seidel_sweep_kronecker`].

use super::cg::{conjugate_gradient, CgVariant};
use super::direct::cholesky_solve;
use super::{check_rhs, norm, IterativeResult};
use crate::error::{Error, Result};
use crate::mass::{unit_density_levels, Kronecker2d, LevelMatrices};
use crate::sparse::SparseMatrix;

/// The smoother S of Eq. (4.60).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Smoother {
    /// One forward Gauss–Seidel sweep per step (the book's choice).
    ForwardGaussSeidel,
    /// A forward then a backward sweep per step.
    SymmetricGaussSeidel,
    /// a ← a + ω D⁻¹ (f − M a).
    DampedJacobi {
        /// Damping ω.
        omega: f64,
    },
}

/// Which mass matrix the transfer operators invert.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Transfer {
    /// Row-sum lumped M_L (the book's choice).
    Lumped,
    /// Consistent M.
    Consistent,
}

/// Options of a p-multigrid solve. [`Default`] is the book's setting.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PMultigridOptions {
    /// Smoother.
    pub smoother: Smoother,
    /// Transfer operators.
    pub transfer: Transfer,
    /// ν₁.
    pub pre_smoothing: usize,
    /// ν₂.
    pub post_smoothing: usize,
    /// Relative tolerance of the CG solve on level p = 1.
    pub coarse_tolerance: f64,
    /// Whether the coarse-grid correction is applied at all (false leaves a
    /// pure smoother with ν₁ + ν₂ steps per cycle).
    pub coarse_correction: bool,
}

impl Default for PMultigridOptions {
    /// Book §4.7: forward Gauss–Seidel, ν₁ = ν₂ = 8, lumped transfer, CG to 1e-4.
    fn default() -> Self {
        Self {
            smoother: Smoother::ForwardGaussSeidel,
            transfer: Transfer::Lumped,
            pre_smoothing: 8,
            post_smoothing: 8,
            coarse_tolerance: 1e-4,
            coarse_correction: true,
        }
    }
}

/// A linear map between levels: 1D sparse, or a 2D Kronecker product.
#[derive(Debug, Clone, PartialEq)]
enum LevelMap {
    OneD(SparseMatrix),
    TwoD(Kronecker2d),
}

impl LevelMap {
    fn rows(&self) -> usize {
        match self {
            LevelMap::OneD(m) => m.rows(),
            LevelMap::TwoD(k) => k.rows(),
        }
    }
    fn apply(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.rows()];
        match self {
            LevelMap::OneD(m) => m.mul_vec(x, &mut y),
            LevelMap::TwoD(k) => k.apply(x, &mut y),
        }
        y
    }
}

#[derive(Debug, Clone)]
struct Level {
    matrix: SparseMatrix,
    /// The diagonal of `matrix`, for the smoother (found once, not per
    /// smoothing call).
    diagonal: Vec<f64>,
    /// In 2D, the 1D mass M_q with `matrix` = M_q ⊗ M_q: the forward
    /// sweep reads its entries instead of the assembled ones
    /// ([`gauss_seidel_sweep_kronecker`]).
    factor: Option<SparseMatrix>,
    /// I_{q−1}^q (absent on level 1).
    prolongation: Option<LevelMap>,
    /// I_q^{q−1} (absent on level 1).
    restriction: Option<LevelMap>,
}

/// The p-multigrid hierarchy for a tensor-product mass matrix (book §4.7):
/// [`PMultigrid::unit_mass`] builds the book's ρ = 1 test problem,
/// [`PMultigrid::from_levels`] any other.
#[derive(Debug, Clone)]
pub struct PMultigrid {
    levels: Vec<Level>,
    options: PMultigridOptions,
}

/// M⁻¹ B for a 1D SPD M (column by column, Cholesky), or diag(1/rowsum(M)) B.
fn inverse_times(m: &SparseMatrix, b: &SparseMatrix, transfer: Transfer) -> Result<SparseMatrix> {
    match transfer {
        Transfer::Lumped => {
            let inv: Vec<f64> = m.row_sums().iter().map(|s| 1.0 / s).collect();
            Ok(b.scale_rows(&inv))
        }
        Transfer::Consistent => {
            let mut t = Vec::new();
            let bt = b.transpose();
            for j in 0..b.cols() {
                let mut col = vec![0.0; b.rows()];
                let (c, v) = bt.row(j);
                for (&i, &a) in c.iter().zip(v) {
                    col[i] = a;
                }
                let x = cholesky_solve(m, &col)?;
                for (i, xi) in x.into_iter().enumerate() {
                    if xi != 0.0 {
                        t.push((i, j, xi));
                    }
                }
            }
            SparseMatrix::from_triplets(b.rows(), b.cols(), &t)
        }
    }
}

impl PMultigrid {
    /// Builds the hierarchy for the book's test problem (book §4.7): degree
    /// `degree` on `spans` uniform spans per direction, ρ = 1, in `dim` = 1
    /// or 2 dimensions, optionally with homogeneous Dirichlet conditions.
    /// The matrices come from [`crate::mass::unit_density_levels`]; the
    /// hierarchy itself is [`PMultigrid::from_levels`].
    pub fn unit_mass(
        spans: usize,
        degree: usize,
        dim: usize,
        dirichlet: bool,
        options: PMultigridOptions,
    ) -> Result<Self> {
        if degree == 0 {
            return Err(Error::InvalidDegree("p-multigrid needs degree ≥ 1".into()));
        }
        if dim != 1 && dim != 2 {
            return Err(Error::InvalidArgument(format!(
                "dimension must be 1 or 2, got {dim}"
            )));
        }
        let levels = unit_density_levels(spans, degree, dirichlet)?;
        if let Some(q) = levels.iter().position(|l| l.mass.rows() == 0) {
            return Err(Error::InvalidArgument(format!(
                "{spans} spans with degree {} leave no interior DOFs",
                q + 1
            )));
        }
        Self::from_levels(&levels, dim, options)
    }

    /// Builds the hierarchy from 1D level matrices, coarsest first (book
    /// Eqs. 4.61–4.62): level q's mass M_q and, from the second level on,
    /// the mixed mass P = ∫ φ^q φ^{q−1} to the level below. In 2D
    /// (`dim` = 2) each level is M_q ⊗ M_q and each transfer the Kronecker
    /// product of the 1D transfers. Any SPD 1D masses with matching mixed
    /// matrices will do, not only the book's ρ = 1.
    pub fn from_levels(
        levels: &[LevelMatrices],
        dim: usize,
        options: PMultigridOptions,
    ) -> Result<Self> {
        if levels.is_empty() || !(dim == 1 || dim == 2) {
            return Err(Error::InvalidArgument(format!(
                "p-multigrid needs at least one level and dimension 1 or 2, got {} levels, dimension {dim}",
                levels.len()
            )));
        }
        let mut out = Vec::with_capacity(levels.len());
        for (q, level) in levels.iter().enumerate() {
            let matrix = if dim == 1 {
                level.mass.clone()
            } else {
                SparseMatrix::kron(&level.mass, &level.mass)
            };
            let (prolongation, restriction) = match (q, &level.mixed_to_coarser) {
                (0, _) => (None, None),
                (_, None) => {
                    return Err(Error::InvalidArgument(format!(
                        "level {q} has no mixed mass matrix to level {}",
                        q - 1
                    )))
                }
                (_, Some(mixed)) => {
                    let p1 = inverse_times(&level.mass, mixed, options.transfer)?;
                    let r1 =
                        inverse_times(&levels[q - 1].mass, &mixed.transpose(), options.transfer)?;
                    if dim == 1 {
                        (Some(LevelMap::OneD(p1)), Some(LevelMap::OneD(r1)))
                    } else {
                        (
                            Some(LevelMap::TwoD(Kronecker2d::new(p1.clone(), p1))),
                            Some(LevelMap::TwoD(Kronecker2d::new(r1.clone(), r1))),
                        )
                    }
                }
            };
            out.push(Level {
                diagonal: matrix.diagonal(),
                factor: (dim == 2).then(|| level.mass.clone()),
                matrix,
                prolongation,
                restriction,
            });
        }
        Ok(Self {
            levels: out,
            options,
        })
    }

    /// The finest-level matrix M_{h,p}.
    pub fn matrix(&self) -> &SparseMatrix {
        &self.levels[self.levels.len() - 1].matrix
    }

    /// Level q's mass matrix and, in 1D, its transfers to and from level
    /// q − 1 (book Eqs. 4.61–4.62): `(M_q, Some((I_{q−1}^q, I_q^{q−1})))`.
    /// Levels count from 0 (degree 1); level 0 and 2D levels have no 1D
    /// transfers. For tests that state what the V-cycle applies.
    pub fn level(
        &self,
        q: usize,
    ) -> Option<(&SparseMatrix, Option<(&SparseMatrix, &SparseMatrix)>)> {
        let lv = self.levels.get(q)?;
        let transfers = match (&lv.prolongation, &lv.restriction) {
            (Some(LevelMap::OneD(p)), Some(LevelMap::OneD(r))) => Some((p, r)),
            _ => None,
        };
        Some((&lv.matrix, transfers))
    }

    fn smooth(&self, level: &Level, f: &[f64], x: &mut [f64], steps: usize) {
        let (a, diag) = (&level.matrix, &level.diagonal);
        let n = a.rows();
        for _ in 0..steps {
            match self.options.smoother {
                Smoother::ForwardGaussSeidel => match &level.factor {
                    Some(m) => gauss_seidel_sweep_kronecker(m, m, diag, f, x),
                    None => gauss_seidel_sweep(a, diag, f, x, false),
                },
                Smoother::SymmetricGaussSeidel => {
                    gauss_seidel_sweep(a, diag, f, x, false);
                    gauss_seidel_sweep(a, diag, f, x, true);
                }
                Smoother::DampedJacobi { omega } => {
                    let mut ax = vec![0.0; n];
                    a.mul_vec(x, &mut ax);
                    for i in 0..n {
                        x[i] += omega * (f[i] - ax[i]) / diag[i];
                    }
                }
            }
        }
    }

    fn coarse_solve(&self, r: &[f64]) -> Result<Vec<f64>> {
        let a = &self.levels[0].matrix;
        if norm(r) == 0.0 {
            return Ok(vec![0.0; r.len()]);
        }
        Ok(conjugate_gradient(
            a,
            r,
            self.options.coarse_tolerance,
            10 * a.rows() + 100,
            CgVariant::Recursive,
        )?
        .solution)
    }

    fn cycle(&self, level: usize, f: &[f64], x: &mut [f64]) -> Result<()> {
        let lv = &self.levels[level];
        let a = &lv.matrix;
        self.smooth(lv, f, x, self.options.pre_smoothing);
        if self.options.coarse_correction {
            let mut ax = vec![0.0; a.rows()];
            a.mul_vec(x, &mut ax);
            let r: Vec<f64> = f.iter().zip(&ax).map(|(b, c)| b - c).collect();
            let e = match (&lv.restriction, &lv.prolongation) {
                (Some(restrict), Some(prolong)) => {
                    let rc = restrict.apply(&r);
                    let ec = if level == 1 {
                        self.coarse_solve(&rc)?
                    } else {
                        let mut ec = vec![0.0; rc.len()];
                        self.cycle(level - 1, &rc, &mut ec)?;
                        ec
                    };
                    prolong.apply(&ec)
                }
                _ => self.coarse_solve(&r)?,
            };
            for (xi, ei) in x.iter_mut().zip(e) {
                *xi += ei;
            }
        }
        self.smooth(lv, f, x, self.options.post_smoothing);
        Ok(())
    }

    /// V-cycles from a = 0 until ‖f − M a‖/‖f‖ < `tol` (the book's rule for
    /// Table 4.4); returns the cycle count and residual history.
    pub fn solve(&self, f: &[f64], tol: f64, max_cycles: usize) -> Result<IterativeResult> {
        let a = self.matrix();
        check_rhs(a.rows(), f, tol)?;
        let fnorm = norm(f);
        let mut x = vec![0.0; f.len()];
        let mut residuals = vec![if fnorm == 0.0 { 0.0 } else { 1.0 }];
        if fnorm == 0.0 {
            return Ok(IterativeResult {
                solution: x,
                iterations: 0,
                residuals,
            });
        }
        let top = self.levels.len() - 1;
        let mut ax = vec![0.0; f.len()];
        for k in 1..=max_cycles {
            self.cycle(top, f, &mut x)?;
            a.mul_vec(&x, &mut ax);
            let rel = f
                .iter()
                .zip(&ax)
                .map(|(b, c)| (b - c) * (b - c))
                .sum::<f64>()
                .sqrt()
                / fnorm;
            residuals.push(rel);
            if !rel.is_finite() {
                return Err(Error::BlowUp(format!(
                    "p-multigrid residual became {rel} at cycle {k}"
                )));
            }
            if rel < tol {
                return Ok(IterativeResult {
                    solution: x,
                    iterations: k,
                    residuals,
                });
            }
        }
        Err(Error::NotConverged(format!(
            "p-multigrid reached {max_cycles} cycles with relative residual {:e}",
            residuals.last().copied().unwrap_or(f64::NAN)
        )))
    }
}

/// One Gauss–Seidel sweep, forward (i = 0..n) or backward, in place.
pub fn gauss_seidel_sweep(
    a: &SparseMatrix,
    diag: &[f64],
    f: &[f64],
    x: &mut [f64],
    backward: bool,
) {
    let n = a.rows();
    let mut step = |i: usize| {
        let (c, v) = a.row(i);
        let s: f64 = c.iter().zip(v).map(|(&j, &aij)| aij * x[j]).sum();
        x[i] += (f[i] - s) / diag[i];
    };
    if backward {
        (0..n).rev().for_each(&mut step);
    } else {
        (0..n).for_each(&mut step);
    }
}

/// The forward sweep of [`gauss_seidel_sweep`] on B ⊗ A (A varies
/// fastest, as [`SparseMatrix::kron`]) without reading the assembled
/// matrix: entry (i_a + m_a i_b, j_a + n_a j_b) is formed as A(i_a, j_a)
/// B(i_b, j_b), the product `kron` stores, and a row's entries come in the
/// order of its assembled row (j_b, then j_a), so the sweep gives the bits
/// of the assembled one (the property
/// `kronecker_sweep_is_the_assembled_sweep`). It reads two small 1D
/// matrices instead of (2p + 1)² stored entries and column indices per
/// row. `diag` is the diagonal of B ⊗ A.
pub fn gauss_seidel_sweep_kronecker(
    b: &SparseMatrix,
    a: &SparseMatrix,
    diag: &[f64],
    f: &[f64],
    x: &mut [f64],
) {
    let (rows_a, cols_a) = (a.rows(), a.cols());
    for ib in 0..b.rows() {
        let (cb, vb) = b.row(ib);
        for ia in 0..rows_a {
            let (ca, va) = a.row(ia);
            let i = ia + rows_a * ib;
            // A banded row's columns are one run: its x are then one slice.
            let run = match (ca.first(), ca.last()) {
                (Some(&first), Some(&last)) if last - first + 1 == ca.len() => Some(first),
                _ => None,
            };
            let mut s = -0.0;
            for (&jb, &bv) in cb.iter().zip(vb) {
                let block = &x[cols_a * jb..][..cols_a];
                match run {
                    Some(first) => {
                        for (&av, &xj) in va.iter().zip(&block[first..][..va.len()]) {
                            s += av * bv * xj;
                        }
                    }
                    None => {
                        for (&ja, &av) in ca.iter().zip(va) {
                            s += av * bv * block[ja];
                        }
                    }
                }
            }
            x[i] += (f[i] - s) / diag[i];
        }
    }
}
