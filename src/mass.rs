//! # Mass matrices
//!
//! The consistent mass matrix M^C = ∫ ρ φ φᵀ dΩ (book Eqs. 4.2 and 4.58,
//! thesis §3.1) and its lumped forms: row-sum lumping M_ii = Σ_j M^C_ij
//! (book Eq. 4.3, thesis A.2) and variational lumping m = ∫ ρ φ dΩ (book
//! Eq. 4.4). The assembly from element matrices, M = Σ_e T_eᵀ M_e T_e, is
//! thesis Appendix A.1.
//!
//! Items: [`assemble`], [`row_sum_lumping`], [`lumped_by_row_sum`],
//! [`consistent_mass`], [`consistent_mass_constant`], [`mixed_mass`],
//! [`lumped_variational`], [`material_point_mass`],
//! [`material_point_lumped_mass`], [`add_lumped_mass`], [`interior_indices`],
//! [`with_dirichlet`], [`Kronecker2d`], [`unit_density_mass`], [`LevelMatrices`],
//! [`unit_density_levels`],
//! [`unit_density_mass_2d`].

use crate::basis::{Basis1d, Stencils};
use crate::error::{finite, finite_named, Error, Result};
use crate::quadrature::GaussLegendre;
use crate::sparse::SparseMatrix;
use faer::Mat;

/// Assembles element matrices into a global matrix, thesis Appendix A.1:
/// M = Σ_e T_eᵀ M_e T_e, where T_e is the Boolean matrix that maps the local
/// DOFs of element e to the global ones listed in `connectivity[e]`.
///
/// This dense form is for small worked examples; production paths use banded
/// or sparse storage.
pub fn assemble(
    element_matrices: &[Mat<f64>],
    connectivity: &[Vec<usize>],
    size: usize,
) -> Result<Mat<f64>> {
    if element_matrices.len() != connectivity.len() {
        return Err(Error::LengthMismatch {
            what: "connectivity lists (one per element matrix)".into(),
            expected: element_matrices.len(),
            got: connectivity.len(),
        });
    }
    let mut global = Mat::<f64>::zeros(size, size);
    for (e, (me, dofs)) in element_matrices.iter().zip(connectivity).enumerate() {
        if me.nrows() != dofs.len() || me.ncols() != dofs.len() {
            return Err(Error::InvalidArgument(format!(
                "element {e}: matrix is {}×{} but it has {} DOFs",
                me.nrows(),
                me.ncols(),
                dofs.len()
            )));
        }
        for (a, &i) in dofs.iter().enumerate() {
            for (b, &j) in dofs.iter().enumerate() {
                if i >= size || j >= size {
                    return Err(Error::InvalidArgument(format!(
                        "element {e}: DOF {} outside 0..{size}",
                        i.max(j)
                    )));
                }
                global[(i, j)] += me[(a, b)];
            }
        }
    }
    Ok(global)
}

/// Row-sum lumping, book Eq. (4.3) and thesis A.2: M_ii = Σ_j M_ij.
pub fn row_sum_lumping(matrix: &Mat<f64>) -> Vec<f64> {
    (0..matrix.nrows())
        .map(|i| (0..matrix.ncols()).map(|j| matrix[(i, j)]).sum())
        .collect()
}

/// Row sums of a sparse mass matrix: book Eq. (4.3), M_ii = Σ_j M^C_ij.
pub fn lumped_by_row_sum(consistent: &SparseMatrix) -> Vec<f64> {
    consistent.row_sums()
}

/// The consistent mass matrix M^C_ij = ∫ ρ φ_i φ_j dΩ, book Eqs. (4.2) and
/// (4.58), by Gauss quadrature with `points_per_cell` points on every cell
/// (p+1 points are exact for a polynomial ρ of degree ≤ 1… and for constant ρ).
pub fn consistent_mass(
    basis: &dyn Basis1d,
    density: &dyn Fn(f64) -> f64,
    points_per_cell: usize,
) -> Result<SparseMatrix> {
    let n = basis.num_basis();
    let rule = GaussLegendre::new(points_per_cell)?;
    let width = basis.degree() + 1;
    let cells = basis.cells();
    let mut t = Vec::with_capacity(cells.len() * points_per_cell * width * width);
    for (a, b) in cells {
        for q in rule.on_interval(a, b) {
            let rho = finite("density", density(q.x))?;
            let loc = basis.local(q.x, 0)?;
            let v = loc.values();
            for (ja, &va) in v.iter().enumerate() {
                for (jb, &vb) in v.iter().enumerate() {
                    t.push((loc.first + ja, loc.first + jb, q.weight * rho * va * vb));
                }
            }
        }
    }
    SparseMatrix::from_triplets(n, n, &t)
}

/// Consistent mass with constant density ρ and the exact rule (p+1 points).
pub fn consistent_mass_constant(basis: &dyn Basis1d, rho: f64) -> Result<SparseMatrix> {
    finite("density", rho)?;
    consistent_mass(basis, &|_| rho, basis.degree() + 1)
}

/// The mixed mass matrix P_ij = ∫ φ_i^{fine} φ_j^{coarse} dΩ (book §4.7; the
/// p-multigrid transfer of Tielen et al., book ref. \[235\], docs/bibliography.md). Both bases must share their
/// cells; `points_per_cell` must integrate degree p_fine + p_coarse exactly.
pub fn mixed_mass(
    fine: &dyn Basis1d,
    coarse: &dyn Basis1d,
    points_per_cell: usize,
) -> Result<SparseMatrix> {
    let rule = GaussLegendre::new(points_per_cell)?;
    let mut t = Vec::new();
    for (a, b) in fine.cells() {
        for q in rule.on_interval(a, b) {
            let lf = fine.local(q.x, 0)?;
            let lc = coarse.local(q.x, 0)?;
            for (ja, &va) in lf.values().iter().enumerate() {
                for (jb, &vb) in lc.values().iter().enumerate() {
                    t.push((lf.first + ja, lc.first + jb, q.weight * va * vb));
                }
            }
        }
    }
    SparseMatrix::from_triplets(fine.num_basis(), coarse.num_basis(), &t)
}

/// Variational lumping, book Eq. (4.4) and thesis A.2 ("direct lumping"):
/// m_i = ∫ ρ φ_i dΩ, by Gauss quadrature with `points_per_cell` points.
pub fn lumped_variational(
    basis: &dyn Basis1d,
    density: &dyn Fn(f64) -> f64,
    points_per_cell: usize,
) -> Result<Vec<f64>> {
    let rule = GaussLegendre::new(points_per_cell)?;
    let mut m = vec![0.0; basis.num_basis()];
    for (a, b) in basis.cells() {
        for q in rule.on_interval(a, b) {
            let rho = finite("density", density(q.x))?;
            let loc = basis.local(q.x, 0)?;
            for (j, &v) in loc.values().iter().enumerate() {
                m[loc.first + j] += q.weight * rho * v;
            }
        }
    }
    Ok(m)
}

fn check_particles(positions: &[f64], masses: &[f64]) -> Result<()> {
    if positions.len() != masses.len() {
        return Err(Error::LengthMismatch {
            what: "masses (one per position)".into(),
            expected: positions.len(),
            got: masses.len(),
        });
    }
    for (k, (&x, &m)) in positions.iter().zip(masses).enumerate() {
        finite_named(x, || format!("position of particle {k}"))?;
        finite_named(m, || format!("mass of particle {k}"))?;
    }
    Ok(())
}

/// The consistent mass matrix with the material points as quadrature points,
/// thesis §3.1: M_ij ≈ Σ_p m_p φ_i(x_p) φ_j(x_p).
pub fn material_point_mass(
    basis: &dyn Basis1d,
    positions: &[f64],
    masses: &[f64],
) -> Result<SparseMatrix> {
    check_particles(positions, masses)?;
    let n = basis.num_basis();
    let mut t = Vec::new();
    for (&x, &m) in positions.iter().zip(masses) {
        let loc = basis.local(x, 0)?;
        let v = loc.values();
        for (ja, &va) in v.iter().enumerate() {
            for (jb, &vb) in v.iter().enumerate() {
                t.push((loc.first + ja, loc.first + jb, m * va * vb));
            }
        }
    }
    SparseMatrix::from_triplets(n, n, &t)
}

/// The lumped mass from material points, book Eq. (4.5) / (4.7):
/// m_i = Σ_p m_p φ_i(x_p).
pub fn material_point_lumped_mass(
    basis: &dyn Basis1d,
    positions: &[f64],
    masses: &[f64],
) -> Result<Vec<f64>> {
    check_particles(positions, masses)?;
    let stencils = Stencils::evaluate(basis, positions)?;
    let mut out = vec![0.0; basis.num_basis()];
    add_lumped_mass(&stencils, masses, &mut out);
    Ok(out)
}

/// Book Eq. (4.5), the kernel the MPM step calls: adds m_i = Σ_p m_p φ_i(x_p)
/// into `out`, from the basis values at the particles, in particle order.
pub fn add_lumped_mass(stencils: &Stencils, masses: &[f64], out: &mut [f64]) {
    stencils.scatter_values(|k| masses[k], out);
}

/// The indices that remain after homogeneous Dirichlet conditions remove the
/// first and last function (book §4.6 tables; open knots interpolate there).
pub fn interior_indices(n: usize) -> Vec<usize> {
    (1..n.saturating_sub(1)).collect()
}

/// Removes the first and last row and column.
pub fn with_dirichlet(m: &SparseMatrix) -> SparseMatrix {
    let rows = interior_indices(m.rows());
    let cols = interior_indices(m.cols());
    m.submatrix(&rows, &cols)
}

/// A 2D operator with Kronecker structure, `y ⊗ x` (x index fastest, as in
/// `spline::tensor`): the tensor-product mass matrix M_2D = M_y ⊗ M_x is
/// never assembled for products, (M_y ⊗ M_x) vec(X) = vec(M_x X M_yᵀ).
#[derive(Debug, Clone, PartialEq)]
pub struct Kronecker2d {
    /// Factor acting along x (rows vary fastest).
    pub x: SparseMatrix,
    /// Factor acting along y.
    pub y: SparseMatrix,
}

impl Kronecker2d {
    /// Pairs two factors.
    pub fn new(x: SparseMatrix, y: SparseMatrix) -> Self {
        Self { x, y }
    }

    /// Rows of the 2D operator.
    pub fn rows(&self) -> usize {
        self.x.rows() * self.y.rows()
    }

    /// Columns of the 2D operator.
    pub fn cols(&self) -> usize {
        self.x.cols() * self.y.cols()
    }

    /// out = (Y ⊗ X) v = vec(X V Yᵀ), where V is the x.cols × y.cols matrix
    /// stored column-major in `v`.
    pub fn apply(&self, v: &[f64], out: &mut [f64]) {
        let (mx, nx) = (self.x.rows(), self.x.cols());
        let (my, ny) = (self.y.rows(), self.y.cols());
        // T = X V: apply X to each of the ny columns of V.
        let mut t = vec![0.0; mx * ny];
        for j in 0..ny {
            self.x
                .mul_vec(&v[j * nx..(j + 1) * nx], &mut t[j * mx..(j + 1) * mx]);
        }
        // out = T Yᵀ: row i of out = Y · (row i of T).
        let mut row = vec![0.0; ny];
        let mut res = vec![0.0; my];
        for i in 0..mx {
            for j in 0..ny {
                row[j] = t[j * mx + i];
            }
            self.y.mul_vec(&row, &mut res);
            for (jj, r) in res.iter().enumerate() {
                out[jj * mx + i] = *r;
            }
        }
    }

    /// The assembled 2D matrix (sparse), for Gauss–Seidel and for checks.
    pub fn assemble(&self) -> SparseMatrix {
        SparseMatrix::kron(&self.y, &self.x)
    }
}

/// The book's test problem (book §4.6–4.7, Tables 4.2–4.4; thesis §7.2):
/// the consistent mass of ρ = 1 for open uniform B-splines of degree p on
/// `spans` spans of [0, 1], with the first and last function removed when
/// `dirichlet` holds (homogeneous Dirichlet conditions).
pub fn unit_density_mass(spans: usize, degree: usize, dirichlet: bool) -> Result<SparseMatrix> {
    let kv = crate::spline::KnotVector::open_uniform(0.0, 1.0, spans, degree)?;
    let m = consistent_mass_constant(&kv, 1.0)?;
    Ok(if dirichlet { with_dirichlet(&m) } else { m })
}

/// One level of a p-multigrid hierarchy in 1D (book §4.7): the mass
/// matrix M_q of degree q and, above the coarsest level, the mixed mass
/// P_ij = ∫ φ_i^q φ_j^{q−1} to the level below.
#[derive(Debug, Clone, PartialEq)]
pub struct LevelMatrices {
    /// M_q.
    pub mass: SparseMatrix,
    /// P = ∫ φ^q φ^{q−1} (None on the coarsest level).
    pub mixed_to_coarser: Option<SparseMatrix>,
}

/// The book's test problem on every p-multigrid level, coarsest first
/// (book §4.7, Eqs. 4.59–4.62): degrees 1 … `degree` on the same `spans`
/// uniform spans of [0, 1] with maximal continuity, ρ = 1, each matrix with
/// the first and last function removed when `dirichlet` holds.
pub fn unit_density_levels(
    spans: usize,
    degree: usize,
    dirichlet: bool,
) -> Result<Vec<LevelMatrices>> {
    let keep = |m: SparseMatrix| if dirichlet { with_dirichlet(&m) } else { m };
    let bases: Vec<crate::spline::KnotVector> = (1..=degree)
        .map(|q| crate::spline::KnotVector::open_uniform(0.0, 1.0, spans, q))
        .collect::<Result<_>>()?;
    (0..degree)
        .map(|q| {
            let mass = keep(consistent_mass_constant(&bases[q], 1.0)?);
            let mixed_to_coarser = if q == 0 {
                None
            } else {
                Some(keep(mixed_mass(&bases[q], &bases[q - 1], q + 2)?))
            };
            Ok(LevelMatrices {
                mass,
                mixed_to_coarser,
            })
        })
        .collect()
}

/// The 2D matrix of the book's tables, M_y ⊗ M_x with both factors
/// [`unit_density_mass`] (book Eq. 4.53), in Kronecker form.
pub fn unit_density_mass_2d(spans: usize, degree: usize, dirichlet: bool) -> Result<Kronecker2d> {
    let m = unit_density_mass(spans, degree, dirichlet)?;
    Ok(Kronecker2d::new(m.clone(), m))
}
