//! # The background grid and its basis
//!
//! The MPM variants of the seeds differ in the basis of the background grid:
//!
//! | method | basis | gradient | seed |
//! |---|---|---|---|
//! | `mpm` | P1 Lagrange | ∇φ_i | thesis §5.1, TLS paper §3.2 |
//! | `mpm-p2` | P2 Lagrange | ∇φ_i | thesis §5.2 |
//! | `ddmpm` | P1 Lagrange | ∇̄φ_i = α∇φ_i + (1−α)∇̃φ_i | TLS paper §3.3 |
//! | `bsmpm` | B-splines, degree p, open uniform knots | ∇φ_i | book §4.3, thesis §6.2 |
//! | `bsmpm` with `--knots natural` | Karamelo's boundary-modified uniform B-splines, p = 2, 3 ([`NaturalSplines`]) | ∇φ_i | issue #36 |
//!
//! DDMPM (TLS paper §3.3): ∇̃φ_i(x) = Σ_j φ_j(x)/V_j ∫_Ω φ_j ∇φ_i dΩ with
//! V_j = ∫_Ω φ_j dΩ, blended by α(x) = 2 Σ_i φ_i(x) φ_{i+1}(x), which vanishes
//! on the element boundaries. The seeds do not say how the node integrals
//! are evaluated, so the rule is a choice, [`NodeIntegrals`]:
//! - `Exact`: over the (fixed) grid domain Ω, exactly by two Gauss points
//!   per element, once per run (hompm's default; docs/conventions.md);
//! - `Particles`: by the material points as quadrature points,
//!   V_j ≈ Σ_p V_p φ_j(x_p) and ∫φ_j∇φ_i ≈ Σ_p V_p φ_j(x_p)∇φ_i(x_p),
//!   every step (the integrals then carry the grid-crossing noise);
//! - `Subpoints(n)`: the same sums over n subpoints per particle, at the
//!   midpoints of n equal parts of its domain [x_p − V_p/2, x_p + V_p/2]
//!   with weight V_p/n each, every step (after Dhakal and Zhang 2016, the
//!   TLS paper's ref. 18 and Table 8).
//!
//! The per-step rules are refreshed by [`Grid::refresh_node_integrals`].
//!
//! Every step evaluates the basis at every particle, so [`Grid::evaluate`]
//! writes into caller-owned slices and allocates nothing, and a particle's
//! cell ([`Grid::cell_of`]) and its count of gradient breaks
//! ([`Grid::breaks_at_or_below`], for grid crossings) cost O(1) on the
//! uniform grids of the seeds: a guess from the spacing, corrected against
//! the stored cell boundaries so that the answer is exact.
//!
//! The methods themselves, their names and their families on the command
//! line are in [`super::method`] (re-exported here).
//!
//! Items: [`Shape`], [`Grid`].

mod dual;
pub(crate) mod fill;
use super::conventions::Knots;
pub use super::method::{Method, MethodFamily, NodeIntegrals, METHOD_FAMILIES};
use crate::basis::{with_width, Basis1d, Stencils};
use crate::error::{Error, Result};
use crate::lagrange::{LagrangeBasis, LagrangeOrder};
use crate::spline::bspline::SpanScratch;
use crate::spline::{KnotVector, NaturalSplines};
use dual::{dual_domain, DualDomain};
use fill::{fill_bspline_stencils, fill_lagrange_stencils};

/// Values and (possibly modified) gradients of the basis at one point, over
/// the index range `first .. first + values.len()`.
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    /// First global index.
    pub first: usize,
    /// φ_i(x).
    pub values: Vec<f64>,
    /// ∇φ_i(x), or ∇̄φ_i(x) for DDMPM.
    pub gradients: Vec<f64>,
}

/// The families of grid bases, held concretely so that the per-particle
/// evaluation is a direct call.
#[derive(Debug, Clone)]
enum GridBasis {
    Lagrange(LagrangeBasis),
    BSpline(KnotVector),
    Natural(NaturalSplines),
}

/// The background grid.
pub struct Grid {
    method: Method,
    basis: GridBasis,
    dual: Option<DualDomain>,
    cells: usize,
    /// c_0 = a < c_1 < … < c_cells = b: the ends of [`Grid::cells`].
    boundaries: Vec<f64>,
    /// The sorted points where a basis gradient jumps.
    breaks: Vec<f64>,
    /// −∞, the breaks, +∞: particle k lies between `fenced_breaks[n]` and
    /// `fenced_breaks[n + 1]` when n breaks lie at or below it. A second
    /// copy on purpose: reading `breaks` as its inner slice cost the
    /// watched P1 step 302 → 308 instructions per particle-step (callgrind).
    fenced_breaks: Vec<f64>,
    /// cells/(b − a): turns a position into a guess of its cell.
    cells_per_length: f64,
    /// The node spacing h ([`Grid::cell_size`]).
    spacing: f64,
    /// The knots of a B-spline grid (`Open` for Lagrange grids).
    knots: Knots,
}

impl std::fmt::Debug for Grid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "Grid({:?}, {} cells on {:?})",
            self.method,
            self.cells,
            self.basis().domain()
        )
    }
}

impl Grid {
    /// A grid of `cells` equal elements (or knot spans) on [a, b].
    pub fn new(method: Method, a: f64, b: f64, cells: usize) -> Result<Self> {
        let basis = match method {
            Method::Mpm | Method::Ddmpm { .. } => {
                GridBasis::Lagrange(LagrangeBasis::new(a, b, cells, LagrangeOrder::Linear)?)
            }
            Method::MpmP2 => {
                GridBasis::Lagrange(LagrangeBasis::new(a, b, cells, LagrangeOrder::Quadratic)?)
            }
            Method::Bsmpm { degree } => {
                GridBasis::BSpline(KnotVector::open_uniform(a, b, cells, degree)?)
            }
        };
        Self::with_basis(method, basis, cells)
    }

    /// Taichi's grid on [a, b] (`--knots padded`, `mpm::conventions`):
    /// uniform quadratic B-splines centred on the nodes a + i·h,
    /// i = −1 … cells + 1, from the uniform knots a + (j − 5/2)h,
    /// j = 0 … cells + 5. The basis is a partition of unity on
    /// [a − h/2, b + h/2], its cells + 1 spans are offset by half a cell, and
    /// the functions of nodes −1, 0, 1 (and cells − 1 … cells + 1) reach
    /// past the walls.
    pub fn padded_quadratic(a: f64, b: f64, cells: usize) -> Result<Self> {
        if cells == 0 || !(a.is_finite() && b.is_finite() && b > a) {
            return Err(Error::InvalidArgument(format!(
                "a padded grid needs a < b and at least one cell, got [{a}, {b}], {cells} cells"
            )));
        }
        let h = (b - a) / cells as f64;
        let knots = (0..cells + 6).map(|j| a + (j as f64 - 2.5) * h).collect();
        let basis = GridBasis::BSpline(KnotVector::new(knots, 2)?);
        let mut grid = Self::with_basis(Method::Bsmpm { degree: 2 }, basis, cells + 1)?;
        grid.knots = Knots::Padded;
        Ok(grid)
    }

    /// Karamelo's grid on [a, b] (`--knots natural`, `mpm::conventions`):
    /// the N + 1 boundary-modified uniform B-splines of degree 2 or 3 of
    /// [`NaturalSplines`], one per node a + k·h, k = 0 … cells. Its cells
    /// are the polynomial pieces (N + 1 for p = 2, whose breakpoints sit at
    /// the half cells; N for p = 3); [`Grid::cell_size`] is h.
    /// Karamelo src/basis_functions.h (read, not copied); issue #36.
    pub fn natural(a: f64, b: f64, cells: usize, degree: usize) -> Result<Self> {
        let basis = NaturalSplines::new(a, b, cells, degree)?;
        let pieces = basis.cells().len();
        let mut grid =
            Self::with_basis(Method::Bsmpm { degree }, GridBasis::Natural(basis), pieces)?;
        grid.spacing = (b - a) / cells as f64;
        grid.knots = Knots::Natural;
        Ok(grid)
    }

    /// The 1D grid of `method` with `knots` on [a, b]: [`Grid::new`] for
    /// open knots, [`Grid::natural`] for natural ones (B-splines of degree
    /// 2 or 3). Padded knots are the 2D grid's ([`Grid::padded_quadratic`]).
    /// docs/conventions.md, "Conventions of other codes" (issue #36).
    pub fn with_knots(method: Method, a: f64, b: f64, cells: usize, knots: Knots) -> Result<Self> {
        match (knots, method) {
            (Knots::Open, _) => Self::new(method, a, b, cells),
            (Knots::Natural, Method::Bsmpm { degree }) => Self::natural(a, b, cells, degree),
            (Knots::Natural, _) => Err(Error::InvalidArgument(format!(
                "--knots natural is Karamelo's quadratic and cubic splines: use --method bsmpm --degree 2 or 3, not {}",
                method.label()
            ))),
            (Knots::Padded, _) => Err(Error::InvalidArgument(
                "--knots padded is the 2D grid's (Taichi's)".into(),
            )),
        }
    }

    /// The grid of a basis with `cells` spans.
    fn with_basis(method: Method, basis: GridBasis, cells: usize) -> Result<Self> {
        let mut grid = Self {
            method,
            basis,
            dual: None,
            cells,
            boundaries: Vec::new(),
            breaks: Vec::new(),
            fenced_breaks: Vec::new(),
            cells_per_length: 0.0,
            spacing: 0.0,
            knots: Knots::Open,
        };
        let (a0, b0) = grid.basis().domain();
        grid.cells_per_length = cells as f64 / (b0 - a0);
        grid.spacing = (b0 - a0) / cells as f64;
        let spans = grid.basis().cells();
        grid.boundaries = std::iter::once(spans[0].0)
            .chain(spans.iter().map(|c| c.1))
            .collect();
        grid.breaks = grid.basis().gradient_breaks();
        grid.fenced_breaks = std::iter::once(f64::NEG_INFINITY)
            .chain(grid.breaks.iter().copied())
            .chain([f64::INFINITY])
            .collect();
        if let Method::Ddmpm { node_integrals } = method {
            match node_integrals {
                NodeIntegrals::Subpoints(0) => {
                    return Err(Error::InvalidArgument(
                        "DDMPM needs at least one subpoint per particle".into(),
                    ))
                }
                NodeIntegrals::EndSubpoints(n) if n < 2 => {
                    return Err(Error::InvalidArgument(format!(
                        "subpoints that include both ends of a particle need n ≥ 2, got {n}"
                    )))
                }
                _ => {}
            }
            // Every rule starts from the exact integrals, so that the basis
            // can be evaluated before the first refresh.
            let GridBasis::Lagrange(basis) = &grid.basis else {
                unreachable!("DDMPM is built on P1 Lagrange functions above");
            };
            let mut dual = dual_domain(basis)?;
            dual.set_rule(node_integrals);
            grid.dual = Some(dual);
        }
        Ok(grid)
    }

    /// The method.
    pub fn method(&self) -> Method {
        self.method
    }

    /// Number of degrees of freedom.
    pub fn num_dofs(&self) -> usize {
        self.basis().num_basis()
    }

    /// Number of elements or knot spans.
    pub fn num_cells(&self) -> usize {
        self.cells
    }

    /// The domain [a, b].
    pub fn domain(&self) -> (f64, f64) {
        self.basis().domain()
    }

    /// Element (or knot-span) size h; the node spacing with natural knots.
    pub fn cell_size(&self) -> f64 {
        self.spacing
    }

    /// The knots of the grid: open for [`Grid::new`] (and the Lagrange
    /// grids), padded or natural for [`Grid::padded_quadratic`] and
    /// [`Grid::natural`]. docs/conventions.md (issue #36).
    pub fn knots(&self) -> Knots {
        self.knots
    }

    /// The cells (elements or non-empty knot spans).
    pub fn cells(&self) -> Vec<(f64, f64)> {
        self.basis().cells()
    }

    /// The ends of cell e, the same numbers as `cells()[e]`, without allocating.
    pub fn cell_bounds(&self, e: usize) -> (f64, f64) {
        (self.boundaries[e], self.boundaries[e + 1])
    }

    /// Polynomial degree of the basis.
    pub fn degree(&self) -> usize {
        self.basis().degree()
    }

    /// Points where a basis gradient is discontinuous (grid crossings).
    pub fn gradient_breaks(&self) -> Vec<f64> {
        self.breaks.clone()
    }

    /// The underlying basis (values and exact derivatives).
    pub fn basis(&self) -> &(dyn Basis1d + Send + Sync) {
        match &self.basis {
            GridBasis::Lagrange(l) => l,
            GridBasis::BSpline(k) => k,
            GridBasis::Natural(n) => n,
        }
    }

    /// Functions per particle stencil: 2 for P1, 3 for P2, p+1 for B-splines,
    /// and 4 for DDMPM, whose modified gradient ∇̄φ_i reaches one node beyond
    /// the element on each side (TLS paper §3.3; fewer on a grid of fewer
    /// than four DOFs).
    pub fn stencil_width(&self) -> usize {
        self.method.functions_per_particle().min(self.num_dofs())
    }

    /// Re-evaluates the DDMPM node integrals V_j and ∫φ_j∇φ_i from the
    /// particles at `positions` with `volumes` (TLS paper §3.3), by the
    /// grid's [`NodeIntegrals`] rule: particle quadrature, or n subpoints per
    /// particle (a subpoint beyond the grid is moved onto its end; a
    /// particle beyond it is an error). Does nothing for the exact
    /// rule and for the other methods. O(particles × subpoints), no
    /// allocation.
    pub fn refresh_node_integrals(&mut self, positions: &[f64], volumes: &[f64]) -> Result<()> {
        let (GridBasis::Lagrange(basis), Some(dd)) = (&self.basis, &mut self.dual) else {
            return Ok(());
        };
        if dd.rule == NodeIntegrals::Exact {
            return Ok(());
        }
        if positions.len() != volumes.len() {
            return Err(Error::LengthMismatch {
                what: "volumes (one per position)".into(),
                expected: positions.len(),
                got: volumes.len(),
            });
        }
        // Subpoint s of n sits at x_p + V_p·(t_s − ½), t_s in [0, 1].
        dual::accumulate_node_integrals(dd, basis, positions, volumes)
    }

    /// The DDMPM node volumes V_j as last evaluated (empty for the other
    /// methods).
    pub fn node_volumes(&self) -> &[f64] {
        self.dual.as_ref().map_or(&[], |d| &d.node_volume)
    }

    /// The DDMPM node integrals ∫φ_j∇φ_i as last evaluated, per node j:
    /// [i = j − 1, j, j + 1] (empty for the other methods).
    pub fn node_gradient_integrals(&self) -> &[[f64; 3]] {
        self.dual.as_ref().map_or(&[], |d| &d.g)
    }

    /// Empty stencils of this grid's width for `points` points.
    pub fn stencils(&self, points: usize) -> Stencils {
        Stencils::new(self.stencil_width(), points)
    }

    /// The cell e with c_e ≤ x < c_{e+1} (the last cell closed): the same
    /// half-open assignment as the reconstructions. O(1) on a uniform grid.
    pub fn cell_of(&self, x: f64) -> Result<usize> {
        let (a, b) = self.domain();
        if !(a..=b).contains(&x) {
            crate::error::finite("position", x)?;
            return Err(Error::OutsideDomain { x, a, b });
        }
        let c = &self.boundaries;
        // x ≥ a and the quotient is at most about `cells`: through i64, one
        // instruction (as `LagrangeBasis::element_of`), the same e.
        let mut e = (((x - a) * self.cells_per_length) as i64 as usize).min(self.cells - 1);
        while e + 1 < self.cells && c[e + 1] <= x {
            e += 1;
        }
        while e > 0 && c[e] > x {
            e -= 1;
        }
        Ok(e)
    }

    /// The number of gradient breaks b ≤ x. A particle moving from x to y
    /// crosses |N(y) − N(x)| breaks (thesis §3.3). O(1) on a uniform grid.
    pub fn breaks_at_or_below(&self, x: f64) -> usize {
        let br = &self.breaks;
        if br.is_empty() {
            return 0;
        }
        let a = self.boundaries[0];
        // A negative guess saturates to 0 (float-to-integer casts saturate).
        let guess = ((x - a) * self.cells_per_length) as usize;
        let mut k = guess.min(br.len());
        while k < br.len() && br[k] <= x {
            k += 1;
        }
        while k > 0 && br[k - 1] > x {
            k -= 1;
        }
        k
    }

    /// Whether exactly `n` gradient breaks lie at or below x: the check that
    /// a particle is still between the same two breaks, b_n ≤ x < b_{n+1}
    /// with the breaks fenced by −∞ and +∞ (two comparisons, no test for the
    /// ends). False for a NaN x and for x = +∞, whose count
    /// [`Grid::breaks_at_or_below`] then finds.
    #[inline(always)]
    pub fn breaks_at_or_below_is(&self, n: usize, x: f64) -> bool {
        match self
            .fenced_breaks
            .get(n..)
            .and_then(|f| f.first_chunk::<2>())
        {
            Some(&[below, above]) => below <= x && x < above,
            None => false,
        }
    }

    /// The grid crossings of a particle that moved to x from where
    /// `breaks_before` gradient breaks lay at or below it,
    /// |N(x) − breaks_before| (thesis §3.3); `breaks_before` becomes N(x).
    #[inline(always)]
    pub fn crossings_to(&self, breaks_before: &mut usize, x: f64) -> usize {
        if self.breaks_at_or_below_is(*breaks_before, x) {
            return 0;
        }
        let after = self.breaks_at_or_below(x);
        let crossed = after.abs_diff(*breaks_before);
        *breaks_before = after;
        crossed
    }

    /// The grid crossings of a particle that moved from x to y,
    /// |N(y) − N(x)| (thesis §3.3), given `count`, N(x) as it was last
    /// counted: it is checked against x first (two comparisons) and found
    /// again if x has changed since (the first step, a particle moved by
    /// hand); then [`Grid::crossings_to`], and `count` becomes N(y).
    #[inline(always)]
    pub fn crossings_between(&self, count: &mut usize, x: f64, y: f64) -> usize {
        self.keep_break_count(count, x);
        self.crossings_to(count, y)
    }

    /// Makes `count` N(x), the breaks at or below x: two comparisons when
    /// it already is ([`Grid::breaks_at_or_below_is`]), the count found
    /// again when it is not (thesis §3.3's crossing monitor).
    #[inline(always)]
    pub fn keep_break_count(&self, count: &mut usize, x: f64) {
        if !self.breaks_at_or_below_is(*count, x) {
            *count = self.breaks_at_or_below(x);
        }
    }

    /// φ and the method's gradient at x (book Eqs. 4.5–4.6, TLS paper §3.3),
    /// written into `values` and `gradients` (each [`Grid::stencil_width`]
    /// long) without allocating. Returns the global index of the first
    /// function. `scratch` holds the Cox–de Boor work arrays between calls.
    pub fn evaluate(
        &self,
        x: f64,
        scratch: &mut SpanScratch,
        values: &mut [f64],
        gradients: &mut [f64],
    ) -> Result<usize> {
        match (&self.basis, &self.dual) {
            (GridBasis::Lagrange(l), None) => l.evaluate_into(x, values, gradients),
            (GridBasis::Lagrange(l), Some(dd)) => {
                let mut phi = [0.0; 2];
                let mut grad = [0.0; 2];
                let k = l.evaluate_into(x, &mut phi, &mut grad)?;
                Ok(dual_domain_gradients(dd, k, phi, grad, values, gradients))
            }
            (GridBasis::BSpline(kv), _) => {
                kv.values_and_gradients_into(x, scratch, values, gradients)
            }
            (GridBasis::Natural(n), _) => n.values_and_gradients_into(x, values, gradients),
        }
    }

    /// Fills `stencils` with the basis at `coordinate(point)` for every
    /// point of `points` (one [`Grid::evaluate`] per point): the 1D step's
    /// particles (`coordinate` the identity) or one axis of the 2D
    /// particles' positions `[x, y]` (the tensor product's basis along that
    /// axis, MLS paper Eqs. 4–5).
    pub fn fill_stencils<P>(
        &self,
        points: &[P],
        coordinate: impl Fn(&P) -> f64 + Copy,
        stencils: &mut Stencils,
        scratch: &mut SpanScratch,
    ) -> Result<()> {
        stencils.resize(points.len());
        if let (GridBasis::BSpline(kv), None) = (&self.basis, &self.dual) {
            // The step's hot path: the degree is dispatched once per batch,
            // and each point's triangle is evaluated in registers.
            return with_width!(
                stencils.width(),
                fill_bspline_stencils::<W>(kv, points.iter().map(coordinate), stencils, scratch)
            );
        }
        if let (GridBasis::Lagrange(l), None) = (&self.basis, &self.dual) {
            return with_width!(
                stencils.width(),
                fill_lagrange_stencils::<W>(l, points.iter().map(coordinate), stencils)
            );
        }
        for (k, point) in points.iter().enumerate() {
            let (v, g) = stencils.slots_mut(k);
            let first = self.evaluate(coordinate(point), scratch, v, g)?;
            stencils.first[k] = first;
        }
        Ok(())
    }

    /// The knot vector of a B-spline grid without DDMPM's dual domain, whose
    /// stencils [`Grid::fill_stencils`] fills by
    /// [`KnotVector::values_and_gradients_fixed`]; `None` for any other grid.
    /// The 2D step evaluates its two axes with it in paired lanes
    /// (`Grid2d::fill_stencils_paired`).
    pub(crate) fn plain_knot_vector(&self) -> Option<&KnotVector> {
        match (&self.basis, &self.dual) {
            (GridBasis::BSpline(kv), None) => Some(kv),
            _ => None,
        }
    }

    /// The Lagrange basis of a grid without DDMPM's dual domain, whose
    /// stencils [`Grid::fill_stencils`] fills by
    /// [`LagrangeBasis::evaluate_fixed`]; `None` for any other grid.
    pub(crate) fn plain_lagrange(&self) -> Option<&LagrangeBasis> {
        match (&self.basis, &self.dual) {
            (GridBasis::Lagrange(l), None) => Some(l),
            _ => None,
        }
    }

    /// The basis at every point of `xs`, in freshly allocated stencils.
    pub fn stencils_at(&self, xs: &[f64]) -> Result<Stencils> {
        let mut s = self.stencils(xs.len());
        self.fill_stencils(xs, |&x| x, &mut s, &mut SpanScratch::default())?;
        Ok(s)
    }

    /// φ and the method's gradient at one point, as owned vectors.
    pub fn shape(&self, x: f64) -> Result<Shape> {
        let s = self.stencils_at(&[x])?;
        Ok(Shape {
            first: s.first[0],
            values: s.values,
            gradients: s.gradients,
        })
    }
}

/// DDMPM, TLS paper §3.3, on P1 element k with values φ_k, φ_{k+1} and
/// gradients ∇φ_k, ∇φ_{k+1} at x:
/// ∇̄φ_i = α ∇φ_i + (1 − α) Σ_j φ_j/V_j ∫ φ_j ∇φ_i, α = 2 φ_k φ_{k+1}.
/// The stencil covers nodes k−1 … k+2, shifted inwards at the ends of the
/// grid (padding entries are exact zeros). Returns its first node.
fn dual_domain_gradients(
    dd: &DualDomain,
    k: usize,
    phi: [f64; 2],
    grad: [f64; 2],
    values: &mut [f64],
    gradients: &mut [f64],
) -> usize {
    let n = dd.node_volume.len();
    let width = values.len();
    let first = k.saturating_sub(1).min(n - width);
    values.fill(0.0);
    gradients.fill(0.0);
    let alpha = 2.0 * phi[0] * phi[1];
    values[k - first] = phi[0];
    values[k + 1 - first] = phi[1];
    for (a_, &phi_j) in phi.iter().enumerate() {
        let j = k + a_;
        // (1 − α) φ_j / V_j, shared by the three ∇φ_i that φ_j meets. A node
        // that no particle reaches (V_j = 0 under a particle rule) carries no
        // dual-domain stress, so its term is dropped instead of dividing by 0.
        if dd.node_volume[j] <= 0.0 {
            continue;
        }
        let weight = (1.0 - alpha) * phi_j / dd.node_volume[j];
        for (slot, gji) in dd.g[j].iter().enumerate() {
            let Some(i) = (j + slot).checked_sub(1).filter(|&i| i < n) else {
                continue;
            };
            gradients[i - first] += weight * gji;
        }
    }
    for (a_, &gr) in grad.iter().enumerate() {
        gradients[k + a_ - first] += alpha * gr;
    }
    first
}
