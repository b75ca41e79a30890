//! # Taylor basis and Taylor least squares (TLS)
//!
//! On a 1D cell Ω_e = [x_min, x_max] with centroid x_c = (x_max + x_min)/2 and
//! half-width Δx = (x_max − x_min)/2, the Taylor basis is (book Eq. 4.31, TLS
//! paper §5.2, continued in the same pattern beyond ψ_3):
//!
//! ψ_1 = 1,  ψ_{k+1}(x) = [(x − x_c)^k − \overline{(x − x_c)^k}] / (k! Δx^k),  k ≥ 1,
//!
//! where the bar is the cell average (book Eq. 4.30), computed exactly:
//! 0 for odd k and Δx^k/(k+1) for even k. Hence ∫_{Ω_e} ψ_i = |Ω_e| δ_{i1}
//! (book Eq. 4.32, TLS paper Eq. 12).
//!
//! The average of (x − x_c)² may instead be taken as the TLS paper's first
//! author computes it in her public `TLS1D.py` (repository `ewob/TLS`,
//! 2020; read and run, not copied): from the antiderivative
//! F(x) = x³/3 − x_c x² + x_c² x of (x − x_c)² at the absolute cell ends,
//! divided by b − a ([`CellAverage`]). It is the same number in exact
//! arithmetic; in floating point its rounding grows like ε·b³/(b − a), and
//! that rounding is what the TLS paper's printed TLS mass errors measure
//! (docs/conventions.md, "The TLS author's cell average").
//!
//! *Conservative* TLS fixes α_1 = c/|Ω_e| (book Eq. 4.35, TLS paper Eq. 14) and
//! fits the rest, ψ_2 … ψ_{n_b}, to f − α_1 by least squares; the integral of
//! the reconstruction is then c exactly (Eq. 4.34). *Unconstrained* TLS
//! (book Eq. 4.36) fits all coefficients. The global reconstruction is the sum
//! of the cell reconstructions, each zero outside its cell (Eq. 4.37).
//!
//! Degenerate cells (TLS paper §5.3, Figs. 4–5) are detected by κ(D). They are
//! repaired either with *virtual data points* — the neighbouring cell's TLS
//! evaluated at the shared boundary, added to the data but not to the
//! constraint — or with a reduced basis, or reported as an error.
//!
//! Longer than 600 lines: the basis, the cell fit, the repair of
//! degenerate cells and the two drivers (particle lists and counting-sort
//! bins) share the fit's internals, and the repair needs the neighbours'
//! fits, so it lives with the drivers.
//!
//! Items: [`MAX_ORDER`], [`CellAverage`], [`TaylorBasis`], [`CellFit`], [`fit_cell`],
//! [`DegenerateCells`], [`Assignment`], [`TlsOptions`],
//! [`TlsReconstruction`], [`reconstruct`], [`CellBins`], [`TlsScratch`],
//! [`reconstruct_binned`].

use super::least_squares::fit_rows;
use crate::error::{finite, finite_named, Error, Result};
use serde::Serialize;

/// The largest n_b hompm accepts. The seeds use n_b ≤ 3 (TLS paper §5);
/// at n_b = 20 the scaled monomials of degree 19 already put κ(D) far
/// beyond 1/ε for clustered data, and a larger n_b would only hide that.
pub const MAX_ORDER: usize = 20;

/// How the cell average of (x − x_c)² in ψ_3 is computed (book Eq. 4.30).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CellAverage {
    /// Δx²/3, exact up to one rounding (hompm's reading of Eq. 4.30).
    #[default]
    Exact,
    /// [F(b) − F(a)]/(b − a) with F(x) = x³/3 − x_c x² + x_c² x in absolute
    /// coordinates, F evaluated at each end and the two values subtracted.
    /// Its rounding error grows with |x|³/(b − a); it gives the TLS paper's
    /// printed TLS mass errors (docs/conventions.md). Only ψ_3 is affected;
    /// higher even powers stay exact.
    AntiderivativeDifference,
    /// The same antiderivative as the TLS author's `TLS1D.py` (ewob/TLS)
    /// writes it: (1/3)b³ − x_c b² + x_c² b − (1/3)a³ + x_c a² − x_c² a,
    /// summed from the left, over b − a. Its values agree with that code's
    /// to rounding (scripts/author_tls_check.sh).
    AntiderivativeSixTerms,
}

impl CellAverage {
    /// Whether this is [`CellAverage::Exact`] (for serde's
    /// `skip_serializing_if`, so that default settings print as before).
    pub fn is_exact(&self) -> bool {
        *self == CellAverage::Exact
    }
}

/// The Taylor basis of order n_b on one cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TaylorBasis {
    a: f64,
    b: f64,
    order: usize,
    average: CellAverage,
}

fn factorial(k: usize) -> f64 {
    (1..=k).map(|i| i as f64).product()
}

impl TaylorBasis {
    /// The first `order` = n_b Taylor functions on [a, b].
    pub fn new(a: f64, b: f64, order: usize) -> Result<Self> {
        finite("cell end", a)?;
        finite("cell end", b)?;
        if b <= a {
            return Err(Error::NotPositive {
                what: format!("the length of cell [{a}, {b}]"),
                value: b - a,
            });
        }
        if !(b - a).is_finite() {
            return Err(Error::InvalidArgument(format!(
                "cell [{a:e}, {b:e}] is longer than double precision can represent"
            )));
        }
        if order == 0 || order > MAX_ORDER {
            return Err(Error::InvalidDegree(format!(
                "a Taylor basis needs 1 ≤ n_b ≤ {MAX_ORDER}, got {order}"
            )));
        }
        Ok(Self {
            a,
            b,
            order,
            average: CellAverage::Exact,
        })
    }

    /// The same basis with ψ_3's average computed by `average`.
    pub fn with_average(self, average: CellAverage) -> Self {
        Self { average, ..self }
    }

    /// n_b.
    pub fn order(&self) -> usize {
        self.order
    }

    /// The cell [x_min, x_max].
    pub fn cell(&self) -> (f64, f64) {
        (self.a, self.b)
    }

    /// |Ω_e| = x_max − x_min.
    pub fn volume(&self) -> f64 {
        self.b - self.a
    }

    /// x_c.
    pub fn centroid(&self) -> f64 {
        0.5 * (self.a + self.b)
    }

    /// Δx.
    pub fn half_width(&self) -> f64 {
        0.5 * (self.b - self.a)
    }

    /// The cell average of (x − x_c)^k, book Eq. (4.30): exact, or for
    /// k = 2 by an antiderivative in absolute coordinates ([`CellAverage`]).
    pub fn average_of_power(&self, k: usize) -> f64 {
        if k == 2 {
            let (a, b, c) = (self.a, self.b, self.centroid());
            match self.average {
                CellAverage::Exact => {}
                CellAverage::AntiderivativeDifference => {
                    let antiderivative = |x: f64| x * x * x / 3.0 - c * x * x + c * c * x;
                    return (antiderivative(b) - antiderivative(a)) / (b - a);
                }
                CellAverage::AntiderivativeSixTerms => {
                    // Each cube and square first, (1/3) rounded on its own,
                    // the six terms summed from the left.
                    let third = 1.0 / 3.0;
                    let difference = third * (b * b * b) - c * (b * b) + (c * c) * b
                        - third * (a * a * a)
                        + c * (a * a)
                        - (c * c) * a;
                    return difference / (b - a);
                }
            }
        }
        if k % 2 == 1 {
            0.0
        } else {
            self.half_width().powi(k as i32) / (k as f64 + 1.0)
        }
    }

    /// ψ_1(x) … ψ_{n_b}(x), book Eq. (4.31).
    pub fn evaluate(&self, x: f64) -> Vec<f64> {
        (0..self.order).map(|k| self.function(k, x)).collect()
    }

    /// ψ_{k+1}(x) alone (k = 0 is ψ_1 = 1), book Eq. (4.31), without allocating.
    pub fn function(&self, k: usize, x: f64) -> f64 {
        taylor_function(k, x - self.centroid(), self.constants(k))
    }

    /// The constants of ψ_{k+1}: the cell average avg_k of (x − x_c)^k
    /// (book Eq. 4.30) and the denominator k! Δx^k (book Eq. 4.31).
    fn constants(&self, k: usize) -> (f64, f64) {
        (
            self.average_of_power(k),
            factorial(k) * self.half_width().powi(k as i32),
        )
    }
}

/// Book Eq. (4.31), the one place it is written: ψ_{k+1} = 1 for k = 0,
/// else ((x − x_c)^k − avg_k)/(k! Δx^k), from the offset s = x − x_c and
/// the constants (avg_k, k! Δx^k) of [`TaylorBasis::constants`].
fn taylor_function(k: usize, offset: f64, (average, denominator): (f64, f64)) -> f64 {
    if k == 0 {
        1.0
    } else {
        (offset.powi(k as i32) - average) / denominator
    }
}

/// The Taylor functions of one cell with their constants computed once:
/// ψ_{k+1}(x) = ((x − x_c)^k − avg_k)/(k! Δx^k), where avg_k and k! Δx^k are
/// evaluated by the same expressions as [`TaylorBasis::function`], so the
/// values are the same to the bit. Used for the rows of a cell's
/// least-squares fit, where every data point needs every function.
struct TaylorRows {
    basis: TaylorBasis,
    /// (avg_k, k! Δx^k) for k = 1 … min(n_b, 8) − 1.
    constants: [(f64, f64); 8],
}

impl TaylorRows {
    fn new(basis: &TaylorBasis) -> Self {
        let mut constants = [(0.0, 1.0); 8];
        for (k, c) in constants.iter_mut().enumerate().take(basis.order()).skip(1) {
            *c = basis.constants(k);
        }
        Self {
            basis: *basis,
            constants,
        }
    }

    /// ψ_{skip+1}(x) … ψ_{n_b}(x) into `out`, by [`taylor_function`] with
    /// the constants computed once.
    fn fill(&self, x: f64, skip: usize, out: &mut [f64]) {
        let s = x - self.basis.centroid();
        for (i, v) in out.iter_mut().enumerate() {
            let k = i + skip;
            *v = match self.constants.get(k) {
                Some(&constants) => taylor_function(k, s, constants),
                None => self.basis.function(k, x),
            };
        }
    }
}

/// The TLS fit on one cell.
#[derive(Debug, Clone, PartialEq)]
pub struct CellFit {
    /// The Taylor basis actually used (its order may be reduced).
    pub basis: TaylorBasis,
    /// α_1 … α_{n_b}.
    pub coefficients: Vec<f64>,
    /// κ(D) of the least-squares system solved (1 if nothing was fitted).
    pub condition_number: f64,
    /// Number of virtual data points that were added.
    pub virtual_points: usize,
}

impl CellFit {
    /// f̃(x) = Σ α_i ψ_i(x), book Eq. (4.33).
    pub fn evaluate(&self, x: f64) -> f64 {
        self.coefficients
            .iter()
            .enumerate()
            .map(|(k, a)| self.basis.function(k, x) * a)
            .sum()
    }

    /// ∫_{Ω_e} f̃ = α_1 |Ω_e|, book Eq. (4.34).
    pub fn integral(&self) -> f64 {
        self.coefficients.first().copied().unwrap_or(0.0) * self.basis.volume()
    }
}

/// TLS on one cell: conservative with `integral = Some(c)` (book Eqs.
/// 4.33–4.35), unconstrained with `None` (Eq. 4.36). `Error::Singular` when
/// κ(D) exceeds `max_condition` or there are too few points.
pub fn fit_cell(
    basis: TaylorBasis,
    points: &[f64],
    values: &[f64],
    integral: Option<f64>,
    max_condition: f64,
) -> Result<CellFit> {
    if points.len() != values.len() {
        return Err(Error::LengthMismatch {
            what: "data values (one per point)".into(),
            expected: points.len(),
            got: values.len(),
        });
    }
    // Conservative TLS fixes α_1 = c/|Ω_e| (Eq. 4.35) and fits ψ_2 … ψ_{n_b}
    // to f − α_1; unconstrained TLS fits ψ_1 … ψ_{n_b} to f (Eq. 4.36).
    let (skip, a1) = match integral {
        Some(c) => {
            finite("cell integral", c)?;
            (1, Some(c / basis.volume()))
        }
        None => (0, None),
    };
    if let (Some(a1), 1) = (a1, basis.order()) {
        return Ok(CellFit {
            basis,
            coefficients: vec![a1],
            condition_number: 1.0,
            virtual_points: 0,
        });
    }
    let shift = a1.unwrap_or(0.0);
    let rows = TaylorRows::new(&basis);
    let f = fit_rows(
        points.len(),
        basis.order() - skip,
        |p, psi| rows.fill(points[p], skip, psi),
        |p| match a1 {
            Some(_) => values[p] - shift,
            None => values[p],
        },
        Some(max_condition),
    )?;
    let mut coefficients = Vec::with_capacity(basis.order());
    coefficients.extend(a1);
    coefficients.extend(f.coefficients);
    Ok(CellFit {
        basis,
        coefficients,
        condition_number: f.condition_number,
        virtual_points: 0,
    })
}

/// What to do with a cell whose data cannot determine its TLS fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DegenerateCells {
    /// Return `Error::SingularCell` naming the cell.
    Error,
    /// Lower n_b until the fit is well conditioned.
    ReduceBasis,
    /// Add virtual points from well-conditioned neighbours (TLS paper §5.3),
    /// then reduce the basis if that is still not enough.
    VirtualPoints,
}

/// How data points on a shared cell boundary are assigned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Assignment {
    /// A point on a boundary serves both cells (TLS paper §5.3 example).
    Closed,
    /// Half-open cells [a, b), the last one closed (MPM particles).
    HalfOpen,
}

/// Options of a global TLS reconstruction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TlsOptions {
    /// n_b (3 = quadratic, the seeds' choice).
    pub order: usize,
    /// Degenerate-cell policy.
    pub degenerate: DegenerateCells,
    /// κ(D) above which a cell counts as degenerate.
    pub max_condition: f64,
    /// Boundary-point assignment of [`reconstruct`], which bins the points
    /// itself; [`reconstruct_binned`] takes the bins as given and ignores it.
    pub assignment: Assignment,
    /// How ψ_3's cell average is computed ([`CellAverage`]).
    pub average: CellAverage,
}

impl Default for TlsOptions {
    /// Quadratic TLS, virtual points, κ limit 1e10, closed cells.
    fn default() -> Self {
        Self {
            order: 3,
            degenerate: DegenerateCells::VirtualPoints,
            max_condition: 1e10,
            assignment: Assignment::Closed,
            average: CellAverage::Exact,
        }
    }
}

/// A global TLS reconstruction: one [`CellFit`] per cell (book Eq. 4.37).
#[derive(Debug, Clone, PartialEq)]
pub struct TlsReconstruction {
    /// The cell fits, in cell order; `None` for a cell with no data and no
    /// prescribed integral (the reconstruction is zero there).
    pub cells: Vec<Option<CellFit>>,
    /// The union of the cells, [first a, last b].
    pub domain: (f64, f64),
}

impl TlsReconstruction {
    /// f̃(x): the fit of the cell containing x (half-open cells, last one
    /// closed); zero outside every cell.
    pub fn evaluate(&self, x: f64) -> f64 {
        let n = self.cells.len();
        for (e, c) in self.cells.iter().enumerate() {
            if let Some(c) = c {
                let (a, b) = c.basis.cell();
                if (a <= x && x < b) || (e + 1 == n && x == b) {
                    return c.evaluate(x);
                }
            }
        }
        // Cells may be None; locate by the fitted cells only.
        0.0
    }

    /// f̃(x) as [`TlsReconstruction::evaluate`], but a point outside the
    /// cells is [`Error::OutsideDomain`], as for every reconstruction the
    /// CLI offers (a NaN point is [`Error::NonFinite`]).
    pub fn value_at(&self, x: f64) -> Result<f64> {
        finite("query point", x)?;
        let (a, b) = self.domain;
        if x < a || x > b {
            return Err(Error::OutsideDomain { x, a, b });
        }
        Ok(self.evaluate(x))
    }

    /// ∫_{Ω_e} f̃ for every cell.
    pub fn cell_integrals(&self) -> Vec<f64> {
        self.cells
            .iter()
            .map(|c| c.as_ref().map_or(0.0, |c| c.integral()))
            .collect()
    }

    /// κ(D) per cell (1 for an empty cell).
    pub fn condition_numbers(&self) -> Vec<f64> {
        self.cells
            .iter()
            .map(|c| c.as_ref().map_or(1.0, |c| c.condition_number))
            .collect()
    }
}

/// TLS reconstruction over consecutive cells (book Eqs. 4.33–4.37, TLS paper
/// §5.3–5.4). With `integrals = Some(c)`, cell e conserves c\[e\]; otherwise
/// every coefficient is fitted. Data outside every cell is an error.
pub fn reconstruct(
    cells: &[(f64, f64)],
    points: &[f64],
    values: &[f64],
    integrals: Option<&[f64]>,
    options: TlsOptions,
) -> Result<TlsReconstruction> {
    if points.len() != values.len() {
        return Err(Error::LengthMismatch {
            what: "values (one per point)".into(),
            expected: points.len(),
            got: values.len(),
        });
    }
    if options.order == 0 || options.order > MAX_ORDER {
        return Err(Error::InvalidDegree(format!(
            "TLS needs 1 ≤ n_b ≤ {MAX_ORDER}, got {}",
            options.order
        )));
    }
    if let Some(c) = integrals {
        if c.len() != cells.len() {
            return Err(Error::LengthMismatch {
                what: "integrals (one per cell)".into(),
                expected: cells.len(),
                got: c.len(),
            });
        }
    }
    for w in cells.windows(2) {
        if w[0].1 != w[1].0 {
            return Err(Error::InvalidArgument(format!(
                "cells [{}, {}] and [{}, {}] are not consecutive",
                w[0].0, w[0].1, w[1].0, w[1].1
            )));
        }
    }
    let (lo, hi) = match (cells.first(), cells.last()) {
        (Some(f), Some(l)) => (f.0, l.1),
        _ => return Err(Error::Empty("cells".into())),
    };
    for (k, (&x, &v)) in points.iter().zip(values).enumerate() {
        finite_named(x, || format!("data point {k}"))?;
        finite_named(v, || format!("data value {k}"))?;
        if x < lo || x > hi {
            return Err(Error::OutsideDomain { x, a: lo, b: hi });
        }
    }
    let mut bins = CellBins::default();
    bins.fill(cells.len(), points.len(), |k| {
        Ok(cells_of_point(cells, points[k], options.assignment))
    })?;
    reconstruct_binned(
        cells,
        &bins,
        points,
        values,
        integrals,
        options,
        &mut TlsScratch::default(),
    )
}

/// The cell of x among consecutive cells that cover it, and for a point on
/// a shared boundary under [`Assignment::Closed`] the second cell.
fn cells_of_point(cells: &[(f64, f64)], x: f64, assignment: Assignment) -> (usize, Option<usize>) {
    let e = cells.partition_point(|c| c.0 <= x).max(1) - 1;
    match assignment {
        Assignment::Closed if e > 0 && x == cells[e].0 => (e - 1, Some(e)),
        _ => (e, None),
    }
}

/// Data points grouped by cell in one counting-sort pass: the points of
/// cell e are `points_of(e)`, in input order. Reused between steps, it
/// allocates only when the data grow.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CellBins {
    offsets: Vec<usize>,
    indices: Vec<usize>,
    cell: Vec<(usize, Option<usize>)>,
}

impl CellBins {
    /// Bins `points` data points into `cells` cells; `cells_of(k)` names the
    /// cell of point k (and a second one for a point that serves two).
    pub fn fill(
        &mut self,
        cells: usize,
        points: usize,
        cells_of: impl Fn(usize) -> Result<(usize, Option<usize>)>,
    ) -> Result<()> {
        self.offsets.clear();
        self.offsets.resize(cells + 2, 0);
        self.cell.clear();
        for k in 0..points {
            let (e, f) = cells_of(k)?;
            self.cell.push((e, f));
            self.offsets[e + 2] += 1;
            if let Some(f) = f {
                self.offsets[f + 2] += 1;
            }
        }
        for e in 2..cells + 2 {
            self.offsets[e] += self.offsets[e - 1];
        }
        // offsets[e + 1] is now the start of cell e; it advances as cell e
        // is filled and ends as the start of cell e + 1.
        self.indices.resize(self.offsets[cells + 1], 0);
        for (k, &(e, f)) in self.cell.iter().enumerate() {
            for c in std::iter::once(e).chain(f) {
                self.indices[self.offsets[c + 1]] = k;
                self.offsets[c + 1] += 1;
            }
        }
        Ok(())
    }

    /// Indices of the data points in cell e.
    pub fn points_of(&self, e: usize) -> &[usize] {
        &self.indices[self.offsets[e]..self.offsets[e + 1]]
    }

    /// Number of data points in cell e.
    pub fn count(&self, e: usize) -> usize {
        self.offsets[e + 1] - self.offsets[e]
    }
}

/// Reusable buffers of [`reconstruct_binned`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TlsScratch {
    x: Vec<f64>,
    y: Vec<f64>,
}

/// [`reconstruct`] on data already grouped by cell ([`CellBins`]): the MPM
/// step bins its particles once and calls this, so a reconstruction costs
/// O(points + cells). Same fits, same degenerate-cell repair, same order:
/// first every cell is fitted; then the degenerate ones are repaired, after
/// every regular cell is fitted, so their neighbours' fits exist (TLS paper
/// §5.3). The bins decide which cell a boundary point belongs to, so
/// `options.assignment` plays no part here.
pub fn reconstruct_binned(
    cells: &[(f64, f64)],
    bins: &CellBins,
    points: &[f64],
    values: &[f64],
    integrals: Option<&[f64]>,
    options: TlsOptions,
    scratch: &mut TlsScratch,
) -> Result<TlsReconstruction> {
    let data = BinnedData {
        cells,
        bins,
        points,
        values,
        integrals,
        max_condition: options.max_condition,
        average: options.average,
    };
    let TlsScratch { x: px, y: pv } = scratch;
    let mut out: Vec<Option<CellFit>> = Vec::with_capacity(cells.len());
    let mut degenerate = Vec::new();
    for e in 0..cells.len() {
        data.gather(e, px, pv);
        match data.fit(e, options.order, px, pv) {
            Ok(f) => out.push(f),
            Err(err) => {
                out.push(None);
                degenerate.push((e, err));
            }
        }
    }
    for (e, err) in degenerate {
        let (a, b) = cells[e];
        if options.degenerate == DegenerateCells::Error {
            return Err(singular_cell(e, a, b, err));
        }
        out[e] = data.repair(e, options, &out, px, pv)?;
    }
    let domain = match (cells.first(), cells.last()) {
        (Some(first), Some(last)) => (first.0, last.1),
        _ => (0.0, 0.0),
    };
    Ok(TlsReconstruction { cells: out, domain })
}

/// The binned data of [`reconstruct_binned`].
struct BinnedData<'a> {
    cells: &'a [(f64, f64)],
    bins: &'a CellBins,
    points: &'a [f64],
    values: &'a [f64],
    integrals: Option<&'a [f64]>,
    max_condition: f64,
    average: CellAverage,
}

impl BinnedData<'_> {
    /// The points and values of cell `e`, into the scratch buffers.
    fn gather(&self, e: usize, px: &mut Vec<f64>, pv: &mut Vec<f64>) {
        px.clear();
        pv.clear();
        for &k in self.bins.points_of(e) {
            px.push(self.points[k]);
            pv.push(self.values[k]);
        }
    }

    /// The fit of cell `e` of the given order to `px`, `pv` (and the cell's
    /// integral when conservative); `None` for a cell with nothing to fit.
    fn fit(&self, e: usize, order: usize, px: &[f64], pv: &[f64]) -> Result<Option<CellFit>> {
        let (a, b) = self.cells[e];
        let c = self.integrals.map(|c| c[e]);
        if px.is_empty() && c.is_none() {
            return Ok(None);
        }
        fit_cell(
            TaylorBasis::new(a, b, order)?.with_average(self.average),
            px,
            pv,
            c,
            self.max_condition,
        )
        .map(Some)
    }

    /// TLS paper §5.3 for a degenerate cell `e`: with virtual points, add the
    /// neighbours' values first; then lower the order until the fit is
    /// regular (order 1 failing is `Error::SingularCell`).
    fn repair(
        &self,
        e: usize,
        options: TlsOptions,
        fitted: &[Option<CellFit>],
        px: &mut Vec<f64>,
        pv: &mut Vec<f64>,
    ) -> Result<Option<CellFit>> {
        self.gather(e, px, pv);
        let added = if options.degenerate == DegenerateCells::VirtualPoints {
            add_virtual_points(e, self.cells[e], fitted, px, pv)
        } else {
            0
        };
        let mut order = options.order;
        let fit = loop {
            match self.fit(e, order, px, pv) {
                Ok(f) => break f,
                Err(_) if order > 1 => order -= 1,
                Err(err) => {
                    let (a, b) = self.cells[e];
                    return Err(singular_cell(e, a, b, err));
                }
            }
        };
        Ok(fit.map(|mut f| {
            f.virtual_points = added;
            f
        }))
    }
}

/// The typed error of a degenerate cell (TLS paper §5.3) when degenerate
/// cells are errors.
fn singular_cell(cell: usize, a: f64, b: f64, err: Error) -> Error {
    let detail = match err {
        Error::Singular(m) => m,
        other => other.to_string(),
    };
    Error::SingularCell {
        cell: vec![cell],
        lower: vec![a],
        upper: vec![b],
        detail,
    }
}

/// TLS paper §5.3's repair of a degenerate cell: each fitted neighbour adds
/// a virtual point at the shared cell end, valued by its own fit (unless a
/// data point already sits there). Returns how many were added.
fn add_virtual_points(
    e: usize,
    (a, b): (f64, f64),
    fitted: &[Option<CellFit>],
    px: &mut Vec<f64>,
    pv: &mut Vec<f64>,
) -> usize {
    let n = fitted.len();
    let mut added = 0;
    for (neighbour, at) in [(e.checked_sub(1), a), (Some(e + 1).filter(|&k| k < n), b)] {
        if let Some(Some(fit)) = neighbour.map(|k| &fitted[k]) {
            if !px.contains(&at) {
                px.push(at);
                pv.push(fit.evaluate(at));
                added += 1;
            }
        }
    }
    added
}
