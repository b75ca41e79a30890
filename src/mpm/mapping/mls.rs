//! # The MLS paper's code's 1D MLS mapping
//!
//! The third solver of the MLS paper's own code (issue #40:
//! QuocAnh90/CPLS-least-squares-for-Material-Point-Method, first commit
//! f30bc24, `MLS_BSMPM_solvertest1.m`, called by `Vibration.m:229-231`;
//! read, not copied). On the strip it maps every particle quantity to the
//! grid through a moving least squares fit evaluated at Gauss points, and
//! integrates the fits with the grid's B-splines:
//!
//! - **Gauss points**: two per cell that holds particles
//!   (`GaussCount = 2`, line 8, overriding `Vibration.m:46`'s 4; the
//!   first two points of the code's 2×2 rule, `lgwt(2, …)`,
//!   `Vibration.m:59-67`, both on the lower Gauss row), placed with the
//!   code's arithmetic (`MlsWorkspace::code_gauss_point`);
//! - **weight**: the quadratic B-spline w(r) of MLS paper Eq. (17) at
//!   r = |x_g − x_p|/h, support 1.5h (lines 177-186: `rx = abs(dx)/le(1)`,
//!   not the paper's /(2h));
//! - **particles of one cell**: a particle enters only the fits of its own
//!   cell's Gauss points (`CONNECT_TEMP_G(p,1) = spElems(p)`, line 141);
//! - **basis**: [1, x, x²] in global, uncentred coordinates (`r = 3`,
//!   line 7; `Pxy = [1; x; x²]`, lines 197-198, 218-219, 233);
//! - **shape functions**: A_g = Σ_p w_pg p(x_p) p(x_p)ᵀ (MLS paper Eq. 10,
//!   lines 201-207) and N_p(x_g) = p(x_g)ᵀ A_g⁻¹ w_pg p(x_p) (Eq. 14,
//!   lines 238-239), solved as Octave solves it: a Cholesky factorisation
//!   of the symmetric positive definite A_g, in LAPACK's order of
//!   operations (`solve_as_lapack`, whose docs say why the order matters);
//! - **the fits** at the Gauss points, particles in index order (MLS paper
//!   Eqs. 18-21, lines 294-300): ρ̃ = Σ ρ_p N_p, (ρv)~ = Σ ρ_p v_p N_p,
//!   (ρb)~ = Σ ρ_p b_p N_p, σ̃ = Σ σ_p N_p;
//! - **the integrals** (MLS paper Eqs. 22-25, lines 308-335):
//!   m_i = Σ_g ρ̃ φ_i ω_g, p_i = Σ_g (ρv)~ φ_i ω_g, f_int,i = Σ_g σ̃ ∇φ_i ω_g,
//!   f_ext,i = Σ_g (ρb)~ φ_i ω_g, and the consistent mass
//!   M_ij = Σ_g ρ̃ φ_i φ_j (h/2) (lines 358-371).
//!
//! **The code's weights** ([`MlsWeights::Code`]): ω_g in lines 322-332 is
//! `omega_gauss`, the weight of the code's 2D rule, (h/2)·(h/2)
//! (`Vibration.m:82-83`), while the consistent mass uses ρ̃h/2 (line 363,
//! `p_sc*(le(1)/GaussCount)`). The forces are thus integrated over a strip
//! of height h/2 and the mass over a unit height: the acceleration
//! M⁻¹f is h/2 times the strip's. The lumped mass and the momentum carry
//! the same factor and it cancels in v_i = p_i/m_i (line 391); hompm
//! integrates them at h/2 and the forces at h/2 · h/2. **The consistent
//! weights** ([`MlsWeights::Consistent`], the fix): h/2 everywhere
//! (docs/conventions.md, "The MLS paper's code's 1D MLS").
//!
//! Two quirks of the code change no number: the internal force reads
//! `omega_gauss(c,g)` with c the index among active cells rather than the
//! cell (line 329; every cell has the same weight to rounding), and the
//! particle update skips on `nmass(i)` with i the local index (line 413;
//! never zero).
//!
//! The step that calls this mapping for its mass, momentum and loads is
//! another code's step through a reconstruction
//! (`crate::mpm::musl`, docs/conventions.md).
//!
//! Items: [`MlsWeights`], [`MLS_STRIP_GAUSS_POINTS`], [`MlsWorkspace`],
//! [`cell_shape_functions`].

use super::quadrature::{Accumulator, QuadratureStencils};
use super::reconstruction::{Reconstruction, Reconstruction1d};
use crate::error::{Error, Result};
use crate::mpm::grid::Grid;
use crate::mpm::particles::Particles;
use crate::quadrature::{GaussLegendre, QuadraturePoint};
use crate::reconstruct::mls::{quadratic_spline_weight, MLS_MAX_CONDITION};
use crate::reconstruct::taylor::{CellAverage, CellBins};
use crate::spline::bspline::SpanScratch;
use nalgebra::{Matrix3, Vector3};
use serde::Serialize;

/// Gauss points per cell of the code's 1D MLS (`GaussCount = 2`,
/// `MLS_BSMPM_solvertest1.m:8`).
pub const MLS_STRIP_GAUSS_POINTS: usize = 2;

/// The quadrature weights of the forces (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum MlsWeights {
    /// As the code at f30bc24: the forces at the 2D Gauss weight
    /// (h/2)·(h/2) (`MLS_BSMPM_solvertest1.m:322-332`), the consistent mass
    /// at ρ̃h/2 (line 363).
    Code,
    /// The fix: every integral at the 1D Gauss weight h/2.
    Consistent,
}

/// The buffers of the code's 1D MLS mapping, allocated once per
/// simulation: the particles binned by cell, the Gauss points of the cells
/// that hold them with the B-splines there, each particle's MLS shape
/// functions at its cell's two Gauss points, and two fields at the points.
#[derive(Debug, Clone)]
pub struct MlsWorkspace {
    weights: MlsWeights,
    rule: GaussLegendre,
    scratch: SpanScratch,
    bins: CellBins,
    quadrature: QuadratureStencils,
    /// The index in `quadrature` of the first Gauss point of particle k's
    /// cell (its second follows).
    first_point: Vec<usize>,
    /// N_p(x_g) of particle k at its cell's Gauss points: `shape[2k + g]`.
    shape: Vec<f64>,
    /// Two fields at the Gauss points.
    fields: (Vec<f64>, Vec<f64>),
    /// One cell's shape functions at one Gauss point.
    cell_shapes: Vec<f64>,
    /// The factor of the forces' weights: h/2 (the code's second Gauss
    /// direction) or 1.
    force_factor: f64,
    /// The index, counted from x = 0, of the grid's first cell, when the
    /// grid's left end lies on the lattice kh as the code's grids do
    /// (`code_gauss_point`).
    first_cell_from_zero: Option<f64>,
    largest_condition: f64,
}

impl MlsWorkspace {
    /// Buffers for `grid` and `particles` particles, with the forces'
    /// weights `weights`.
    pub fn new(grid: &Grid, particles: usize, weights: MlsWeights) -> Result<Self> {
        Ok(Self {
            weights,
            rule: GaussLegendre::new(MLS_STRIP_GAUSS_POINTS)?,
            scratch: SpanScratch::default(),
            bins: CellBins::default(),
            quadrature: QuadratureStencils::default(),
            first_point: Vec::with_capacity(particles),
            shape: Vec::with_capacity(MLS_STRIP_GAUSS_POINTS * particles),
            fields: (Vec::new(), Vec::new()),
            cell_shapes: Vec::new(),
            force_factor: match weights {
                MlsWeights::Code => 0.5 * grid.cell_size(),
                MlsWeights::Consistent => 1.0,
            },
            first_cell_from_zero: {
                let (left, h) = (grid.domain().0, grid.cell_size());
                let k = (left / h).round();
                ((k * h - left).abs() <= 1e-12 * h).then_some(k)
            },
            largest_condition: 0.0,
        })
    }

    /// The fields Σ_p a_p N_p(x_g) and Σ_p b_p N_p(x_g) at every Gauss
    /// point, particles in index order (`MLS_BSMPM_solvertest1.m:278-305`).
    fn fit(&mut self, a: impl Fn(usize) -> f64, b: impl Fn(usize) -> f64) {
        let n = self.quadrature.points.len();
        let (fa, fb) = &mut self.fields;
        fa.clear();
        fa.resize(n, 0.0);
        fb.clear();
        fb.resize(n, 0.0);
        for (k, &first) in self.first_point.iter().enumerate() {
            let (ak, bk) = (a(k), b(k));
            for g in 0..MLS_STRIP_GAUSS_POINTS {
                let shape = self.shape[MLS_STRIP_GAUSS_POINTS * k + g];
                fa[first + g] += ak * shape;
                fb[first + g] += bk * shape;
            }
        }
    }

    /// Gauss point g of cell e, at the position the code's `lgwt.m`
    /// computes (`Vibration.m:62-67`): x_g = (a(1 − y_g) + b(1 + y_g))/2
    /// with a, b = c ∓ h/2 about the code's centroid c = kh + h/2
    /// (`Grid_Generation.m:25`, k counted from x = 0) and y_g = ∓1/√3 as
    /// `lgwt.m`'s Newton iteration ends in double precision, 1/√3 correctly
    /// rounded (hompm's own Gauss–Legendre node is one ulp lower), when the
    /// grid lies on that lattice; the rule's own point otherwise. One ulp
    /// of x_g moves the uncentred fit by up to 1e-7 at 64 cells
    /// (`solve_as_lapack`), so the code's arithmetic is kept. The weight is
    /// the rule's, (b − a)/2 of hompm's cell.
    fn code_gauss_point(&self, grid: &Grid, e: usize, g: usize) -> QuadraturePoint {
        let (a, b) = grid.cell_bounds(e);
        let own = self.rule.point(g, a, b);
        let Some(first) = self.first_cell_from_zero else {
            return own;
        };
        let h = grid.cell_size();
        let centre = (first + e as f64) * h + h / 2.0;
        let (a, b) = (centre - 0.5 * h, centre + 0.5 * h);
        let root = 1.0 / 3f64.sqrt();
        let y = if g == 0 { -root } else { root };
        QuadraturePoint {
            x: (a * (1.0 - y) + b * (1.0 + y)) / 2.0,
            weight: own.weight,
        }
    }

    /// The forces' weight at Gauss point q: ω_q times h/2 (the code's) or 1.
    fn force_weight(&self, q: usize) -> f64 {
        self.quadrature.points[q].weight * self.force_factor
    }
}

/// The MLS shape functions of MLS paper Eq. (14) at a Gauss point x_g of
/// one cell, as the code computes them (`MLS_BSMPM_solvertest1.m:170-247`):
/// the moment matrix A = Σ_p w_p p(x_p) p(x_p)ᵀ with
/// p(x) = [1, x − c, (x − c)²] and w_p = w(|x_g − x_p|/h) (Eq. 17 at the
/// code's scale), then N_p = (A⁻¹ p(x_g))ᵀ w_p p(x_p), written into
/// `shape` (one per point). The code's basis is uncentred, c = 0; any c
/// spans the same polynomials and gives the same N_p but for rounding,
/// which grows with κ(A). Returns κ₂(A); a moment matrix that is not
/// positive definite, or whose κ exceeds [`MLS_MAX_CONDITION`], is
/// [`Error::SingularMoments`]; a non-finite position or centre, a cell
/// size that is not positive, or a `shape` of another length than the
/// points is an error too.
pub fn cell_shape_functions(
    x_gauss: f64,
    points: impl Iterator<Item = f64> + Clone,
    cell_size: f64,
    centre: f64,
    shape: &mut [f64],
) -> Result<f64> {
    crate::error::finite("Gauss point", x_gauss)?;
    crate::error::finite("centre", centre)?;
    if !(cell_size > 0.0 && cell_size.is_finite()) {
        return Err(Error::InvalidArgument(format!(
            "the MLS cell size must be positive and finite, got {cell_size}"
        )));
    }
    let count = points.clone().count();
    if count != shape.len() {
        return Err(Error::LengthMismatch {
            what: "MLS shape functions (one per point)".into(),
            expected: count,
            got: shape.len(),
        });
    }
    for xp in points.clone() {
        crate::error::finite("particle position", xp)?;
    }
    let weight = |xp: f64| quadratic_spline_weight((x_gauss - xp) / cell_size);
    let basis = |x: f64| {
        let d = x - centre;
        Vector3::new(1.0, d, d * d)
    };
    let mut a = Matrix3::zeros();
    let mut active = 0;
    for xp in points.clone() {
        let (w, p) = (weight(xp), basis(xp));
        active += usize::from(w > 0.0);
        a += w * (p * p.transpose());
    }
    let singular = |kappa: f64| Error::SingularMoments {
        point: vec![x_gauss],
        points_in_support: active,
        condition_number: kappa,
        limit: MLS_MAX_CONDITION,
    };
    let kappa = crate::reconstruct::least_squares::condition_number_of(a);
    if kappa.is_nan() || kappa > MLS_MAX_CONDITION {
        return Err(singular(kappa));
    }
    let r = solve_as_lapack(&a, &basis(x_gauss)).ok_or_else(|| singular(f64::INFINITY))?;
    for (s, xp) in shape.iter_mut().zip(points) {
        let (w, p) = (weight(xp), basis(xp));
        *s = (r[0] * w) * p[0] + (r[1] * w) * p[1] + (r[2] * w) * p[2];
    }
    Ok(kappa)
}

/// A r = b for the symmetric positive definite 3×3 moment matrix, in the
/// order of operations of the code's `rc = Ac{cpid,g} \ pc`
/// (`MLS_BSMPM_solvertest1.m:238`)
/// under Octave with OpenBLAS: Octave factors a symmetric matrix with a
/// positive diagonal by Cholesky, A = UᵀU (LAPACK `dpotrf`, whose
/// unblocked `dpotf2` scales row j of U by the reciprocal 1/u_jj), and
/// solves Uᵀy = b and U r = y with the triangular kernels, which multiply
/// by the reciprocals of the pivots. The uncentred basis makes A
/// ill-conditioned (κ up to 8e10 on 64 cells), so the order shows: with
/// it the shape functions agree with those the code printed to 5e-12 at
/// 64 cells (8e-14 at 8), against 3e-8 with a Cholesky solve that divides
/// by the pivots (docs/reproduction-notes.md). `None` if A is not positive
/// definite.
fn solve_as_lapack(a: &Matrix3<f64>, b: &Vector3<f64>) -> Option<Vector3<f64>> {
    let mut u = Matrix3::<f64>::zeros();
    for j in 0..3 {
        let mut square = 0.0;
        for i in 0..j {
            square += u[(i, j)] * u[(i, j)];
        }
        let pivot = a[(j, j)] - square;
        if pivot.is_nan() || pivot <= 0.0 {
            return None;
        }
        u[(j, j)] = pivot.sqrt();
        let reciprocal = 1.0 / u[(j, j)];
        for k in j + 1..3 {
            let mut t = a[(j, k)];
            for i in 0..j {
                t -= u[(i, j)] * u[(i, k)];
            }
            u[(j, k)] = t * reciprocal;
        }
    }
    let mut y = Vector3::zeros();
    for i in 0..3 {
        let mut t = b[i];
        for k in 0..i {
            t -= u[(k, i)] * y[k];
        }
        y[i] = t * (1.0 / u[(i, i)]);
    }
    let mut r = Vector3::zeros();
    for i in (0..3).rev() {
        let mut t = y[i];
        for k in i + 1..3 {
            t -= u[(i, k)] * r[k];
        }
        r[i] = t * (1.0 / u[(i, i)]);
    }
    Some(r)
}

impl Reconstruction for MlsWorkspace {
    fn name(&self) -> &'static str {
        match self.weights {
            MlsWeights::Code => "MLS (code's weights)",
            MlsWeights::Consistent => "MLS",
        }
    }

    fn largest_condition(&self) -> f64 {
        self.largest_condition
    }
}

impl Reconstruction1d for MlsWorkspace {
    /// Bins the particles by cell, puts two Gauss points on every cell that
    /// holds one and computes each particle's MLS shape functions at its
    /// cell's points ([`cell_shape_functions`]).
    fn begin_step(&mut self, grid: &Grid, particles: &Particles, _: CellAverage) -> Result<()> {
        let x = &particles.x;
        self.bins.fill(grid.num_cells(), x.len(), |k| {
            Ok((grid.cell_of(x[k])?, None))
        })?;
        self.quadrature.clear();
        self.first_point.clear();
        self.first_point.resize(x.len(), 0);
        self.shape.clear();
        self.shape.resize(MLS_STRIP_GAUSS_POINTS * x.len(), 0.0);
        self.largest_condition = 0.0;
        let h = grid.cell_size();
        for e in 0..grid.num_cells() {
            let members = self.bins.points_of(e);
            if members.is_empty() {
                continue;
            }
            let points: [QuadraturePoint; MLS_STRIP_GAUSS_POINTS] =
                std::array::from_fn(|g| self.code_gauss_point(grid, e, g));
            let local = &mut self.cell_shapes;
            local.clear();
            local.resize(members.len(), 0.0);
            for (g, point) in points.into_iter().enumerate() {
                let first = self.quadrature.points.len() - g;
                let positions = members.iter().map(|&k| x[k]);
                let kappa = cell_shape_functions(point.x, positions, h, 0.0, local)?;
                self.largest_condition = self.largest_condition.max(kappa);
                for (&k, &s) in members.iter().zip(local.iter()) {
                    self.first_point[k] = first;
                    self.shape[MLS_STRIP_GAUSS_POINTS * k + g] = s;
                }
                self.quadrature.push(point, e);
            }
        }
        self.quadrature.evaluate(grid, &mut self.scratch)
    }

    /// f_int,i = Σ_g σ̃(x_g) ∇φ_i(x_g) ω_g, ω_g at the forces' weight
    /// (MLS paper Eq. 25; `MLS_BSMPM_solvertest1.m:300, 329`).
    fn internal_force(&mut self, particles: &Particles, force: &mut [f64]) -> Result<()> {
        self.fit(|k| particles.stress[k], |_| 0.0);
        let q = &self.quadrature;
        q.stencils
            .scatter_gradients(|g| self.force_weight(g) * self.fields.0[g], force);
        Ok(())
    }

    /// m_i, p_i and M_ij from ρ̃ = Σ ρ_p N_p and (ρv)~ = Σ ρ_p v_p N_p at
    /// the Gauss points, weight h/2 (MLS paper Eqs. 18-19, 22-23;
    /// `MLS_BSMPM_solvertest1.m:294-296, 322-325, 358-371`).
    fn accumulate_projection(
        &mut self,
        particles: &Particles,
        acc: &mut Accumulator,
    ) -> Result<()> {
        let (rho, v) = (&particles.density, &particles.velocity);
        self.fit(|k| rho[k], |k| rho[k] * v[k]);
        let q = &self.quadrature;
        for g in 0..q.points.len() {
            let w = q.points[g].weight;
            acc.add(&q.stencils, g, w * self.fields.0[g], w * self.fields.1[g]);
        }
        Ok(())
    }

    /// f_ext,i = Σ_g (ρb)~(x_g) φ_i(x_g) ω_g with (ρb)~ = Σ ρ_p b_p N_p, ω_g
    /// at the forces' weight (MLS paper Eqs. 20, 24;
    /// `MLS_BSMPM_solvertest1.m:298, 332`).
    fn body_force(
        &mut self,
        particles: &Particles,
        body: &dyn Fn(usize) -> f64,
        force: &mut [f64],
    ) -> Result<()> {
        let rho = &particles.density;
        self.fit(|k| rho[k] * body(k), |_| 0.0);
        let q = &self.quadrature;
        q.stencils
            .scatter_values(|g| self.force_weight(g) * self.fields.0[g], force);
        Ok(())
    }
}
