//! # The 2D background grid: a tensor product of two 1D grids
//!
//! MLS paper Eqs. (4)–(5): N_{(i,j)}(x, y) = N_i(x) N_j(y) and
//! ∇N_{(i,j)} = (N_i'(x) N_j(y), N_i(x) N_j'(y)). Each axis is a 1D
//! [`crate::mpm::grid::Grid`] on [0, L]: P1 Lagrange for bilinear MPM, or
//! open-uniform B-splines of degree p for BSMPM, so no 2D basis is written
//! twice. The 2D functions are never stored: the step evaluates the two 1D
//! stencils at every particle and forms the products on the fly (the
//! Kronecker structure).
//!
//! Node (i, j) has the global index i + n_x·j (x fastest, docs/conventions.md
//! "2D numbering"). The integration points of the MLS mapping are the 2×2
//! Gauss points of every cell (MLS paper: "Each cell contains 4 Gauss
//! quadrature points"), also a tensor product: 2·cells abscissae per axis.
//!
//! Items: [`Basis2d`], [`Grid2d`].

use crate::basis::{with_width, Stencils};
use crate::error::{Error, Result};
use crate::lagrange::LagrangeBasis;
use crate::mpm::conventions::Knots;
use crate::mpm::grid::{Grid, Method};
use crate::quadrature::GaussLegendre;
use crate::spline::bspline::SpanScratch;
use crate::spline::KnotVector;
use serde::Serialize;

/// The basis of the 2D grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Basis2d {
    /// Bilinear P1 ⊗ P1 (standard MPM).
    Bilinear,
    /// Open-uniform B-splines of the given degree in each direction (BSMPM).
    BSpline {
        /// Polynomial degree p ≥ 1.
        degree: usize,
    },
}

impl Basis2d {
    fn method_1d(self) -> Method {
        match self {
            Basis2d::Bilinear => Method::Mpm,
            Basis2d::BSpline { degree } => Method::Bsmpm { degree },
        }
    }
}

/// The tensor-product grid on [0, L]² with `cells` cells per direction.
#[derive(Debug)]
pub struct Grid2d {
    basis: Basis2d,
    knots: Knots,
    axis: Grid,
    length: f64,
    cells: usize,
    /// The 2·cells Gauss abscissae of one axis, cell by cell.
    gauss_abscissae: Vec<f64>,
    /// The basis of one axis at [`Grid2d::gauss_abscissae`].
    gauss_stencils: Stencils,
    /// The weight of one 2D Gauss point: (h/2)², the 2-point rule's weights
    /// being 1 on [−1, 1].
    gauss_weight: f64,
}

impl Grid2d {
    /// The grid of `cells` × `cells` equal cells on [0, L]².
    pub fn new(basis: Basis2d, length: f64, cells: usize) -> Result<Self> {
        Self::with_knots(basis, length, cells, Knots::Open)
    }

    /// The grid with `--knots` (`mpm::conventions`): open knot vectors, or
    /// Taichi's padded uniform quadratic B-splines
    /// ([`Grid::padded_quadratic`], quadratic B-splines only).
    pub fn with_knots(basis: Basis2d, length: f64, cells: usize, knots: Knots) -> Result<Self> {
        if !(length.is_finite() && length > 0.0) || cells == 0 {
            return Err(Error::InvalidArgument(format!(
                "a 2D grid needs L > 0 and at least one cell, got L = {length}, {cells} cells"
            )));
        }
        let axis = match (knots, basis) {
            (Knots::Open, _) => Grid::new(basis.method_1d(), 0.0, length, cells)?,
            (Knots::Padded, Basis2d::BSpline { degree: 2 }) => {
                Grid::padded_quadratic(0.0, length, cells)?
            }
            (Knots::Padded, _) => return Err(Error::InvalidArgument(
                "--knots padded is Taichi's quadratic B-spline grid: use --method bsmpm --degree 2"
                    .into(),
            )),
            (Knots::Natural, _) => {
                return Err(Error::InvalidArgument(
                    "--knots natural is 1D only (Karamelo's 1D splines)".into(),
                ))
            }
        };
        let rule = GaussLegendre::new(2)?;
        let gauss_abscissae: Vec<f64> = axis
            .cells()
            .iter()
            .flat_map(|&(c0, c1)| rule.on_interval(c0, c1).into_iter().map(|q| q.x))
            .collect();
        let mut gauss_stencils = axis.stencils(gauss_abscissae.len());
        axis.fill_stencils(
            &gauss_abscissae,
            |&x| x,
            &mut gauss_stencils,
            &mut SpanScratch::default(),
        )?;
        let h = length / cells as f64;
        Ok(Self {
            basis,
            knots,
            axis,
            length,
            cells,
            gauss_abscissae,
            gauss_stencils,
            gauss_weight: 0.25 * h * h,
        })
    }

    /// The basis.
    pub fn basis(&self) -> Basis2d {
        self.basis
    }

    /// The 1D grid of each axis.
    pub fn axis(&self) -> &Grid {
        &self.axis
    }

    /// L, the side of the square.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Cells per direction (the 1D grid's `num_cells` along one axis; its
    /// `cells()` are the cells' intervals).
    pub fn cells_per_side(&self) -> usize {
        self.cells
    }

    /// h = L / cells.
    pub fn cell_size(&self) -> f64 {
        self.length / self.cells as f64
    }

    /// Basis functions per direction, n_x = n_y.
    pub fn nodes_per_side(&self) -> usize {
        self.axis.num_dofs()
    }

    /// The position X_i of every node i = ix + n_x·iy: the grid point for
    /// bilinear MPM, the Greville abscissa (t_{i+1} + … + t_{i+p})/p of the
    /// open-uniform knot vector for B-splines (where a B-spline's
    /// coefficient sits when it interpolates a linear function). Only
    /// `--body-force nodes` evaluates anything there.
    pub fn node_positions(&self) -> Vec<[f64; 2]> {
        let along = self.node_positions_along();
        let n = along.len();
        (0..n * n).map(|i| [along[i % n], along[i / n]]).collect()
    }

    /// The node positions along one axis ([`Grid2d::node_positions`]); with
    /// padded knots the centres (i − 1)·h of the node-centred splines.
    pub fn node_positions_along(&self) -> Vec<f64> {
        let (h, n) = (self.cell_size(), self.nodes_per_side());
        match (self.knots, self.basis) {
            (Knots::Padded, _) => (0..n).map(|i| (i as f64 - 1.0) * h).collect(),
            (_, Basis2d::Bilinear) => (0..n).map(|i| i as f64 * h).collect(),
            (_, Basis2d::BSpline { degree }) => {
                let knot = |j: usize| (j.saturating_sub(degree) as f64 * h).min(self.length);
                (0..n)
                    .map(|i| (i + 1..=i + degree).map(knot).sum::<f64>() / degree as f64)
                    .collect()
            }
        }
    }

    /// The knots of the grid.
    pub fn knots(&self) -> Knots {
        self.knots
    }

    /// Node rows at each wall that carry its condition: 1 with open knots
    /// (the only functions non-zero on the wall), 2 with padded ones (the
    /// wall node and the one beyond it, as Taichi does).
    pub fn wall_rows(&self) -> usize {
        match self.knots {
            Knots::Open | Knots::Natural => 1,
            Knots::Padded => 2,
        }
    }

    /// n_x · n_y, the functions of the tensor-product basis (the MLS
    /// paper's nodes; the 1D grid's `num_dofs`).
    pub fn num_dofs(&self) -> usize {
        self.nodes_per_side() * self.nodes_per_side()
    }

    /// Non-zero functions per direction at a point, p + 1.
    pub fn stencil_width(&self) -> usize {
        self.axis.stencil_width()
    }

    /// Gauss abscissae of one axis (2 per cell, cell by cell).
    pub fn gauss_abscissae(&self) -> &[f64] {
        &self.gauss_abscissae
    }

    /// The 1D basis at [`Grid2d::gauss_abscissae`].
    pub fn gauss_stencils(&self) -> &Stencils {
        &self.gauss_stencils
    }

    /// ω_g of every 2D Gauss point, (h/2)².
    pub fn gauss_weight(&self) -> f64 {
        self.gauss_weight
    }
}

impl Grid2d {
    /// MLS paper Eqs. (4)–(5) at every point of `xs`: the stencils of both
    /// axes in one pass, x and y in paired lanes
    /// ([`KnotVector::values_and_gradients_pair`]), bit for bit what
    /// [`Grid::fill_stencils`] writes along each axis; a Lagrange axis (P1,
    /// bilinear MPM) also pairs them
    /// ([`LagrangeBasis::evaluate_pair_of_width`]).
    /// `None` unless the axis is a B-spline grid ([`Grid::plain_knot_vector`])
    /// or a Lagrange grid of width 2 to 4; `Some(Err)` if a point lies
    /// outside the grid, and the caller then takes the axis-by-axis path,
    /// which names it.
    pub(crate) fn fill_stencils_paired(
        &self,
        xs: &[[f64; 2]],
        stencils_x: &mut Stencils,
        stencils_y: &mut Stencils,
    ) -> Option<Result<()>> {
        if let Some(lagrange) = self.axis.plain_lagrange() {
            return with_width!(
                self.stencil_width(),
                fill_lagrange::<W>(lagrange, xs, stencils_x, stencils_y)
            );
        }
        let kv = self.axis.plain_knot_vector()?;
        with_width!(
            self.stencil_width(),
            fill_bspline::<W>(kv, xs, stencils_x, stencils_y)
        )
    }
}

/// B-splines: both axes in paired lanes.
#[inline(always)]
fn fill_bspline<const W: usize>(
    kv: &KnotVector,
    xs: &[[f64; 2]],
    sx: &mut Stencils,
    sy: &mut Stencils,
) -> Option<Result<()>> {
    fill_both::<W>(xs, sx, sy, |x, v, g| {
        Some(kv.values_and_gradients_pair::<W>(x, v, g))
    })
}

/// Lagrange (P1, bilinear MPM, in paired lanes; P2, x then y): both axes
/// in the same pass ([`LagrangeBasis::evaluate_pair_of_width`]).
#[inline(always)]
fn fill_lagrange<const W: usize>(
    lagrange: &LagrangeBasis,
    xs: &[[f64; 2]],
    sx: &mut Stencils,
    sy: &mut Stencils,
) -> Option<Result<()>> {
    if W != lagrange.order().degree() + 1 {
        return None;
    }
    fill_both::<W>(xs, sx, sy, |x, v, g| {
        Some(lagrange.evaluate_pair_of_width::<W>(x, v, g))
    })
}

/// [`Grid2d::fill_stencils_paired`] for width `W` (0: `None`), with
/// `evaluate(x, values, gradients)` the basis of both axes at one point,
/// their first functions (`None`: this width has no fixed evaluation).
#[inline(always)]
fn fill_both<const W: usize>(
    xs: &[[f64; 2]],
    sx: &mut Stencils,
    sy: &mut Stencils,
    evaluate: impl Fn([f64; 2], &mut [[f64; W]; 2], &mut [[f64; W]; 2]) -> Option<Result<[usize; 2]>>,
) -> Option<Result<()>> {
    if W == 0 {
        return None;
    }
    sx.resize(xs.len());
    sy.resize(xs.len());
    let rows_x = sx.values.as_chunks_mut::<W>().0.iter_mut();
    let rows_x = rows_x.zip(sx.gradients.as_chunks_mut::<W>().0.iter_mut());
    let rows_y = sy.values.as_chunks_mut::<W>().0.iter_mut();
    let rows_y = rows_y.zip(sy.gradients.as_chunks_mut::<W>().0.iter_mut());
    let firsts = sx.first.iter_mut().zip(sy.first.iter_mut());
    for ((x, (fx, fy)), ((vx, gx), (vy, gy))) in xs.iter().zip(firsts).zip(rows_x.zip(rows_y)) {
        let (mut values, mut gradients) = ([[0.0; W]; 2], [[0.0; W]; 2]);
        match evaluate(*x, &mut values, &mut gradients)? {
            Ok(first) => [*fx, *fy] = first,
            Err(e) => return Some(Err(e)),
        }
        [*vx, *vy] = values;
        [*gx, *gy] = gradients;
    }
    Some(Ok(()))
}
