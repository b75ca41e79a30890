//! # Boundary-modified uniform B-splines (`--knots natural`)
//!
//! Karamelo's quadratic and cubic splines (src/basis_functions.h, read, not
//! copied; issue #36). On [a, b] with N cells of size h the nodes are
//! X_k = a + k h, k = 0 … N, and ξ = (x − a)/h. B_p is the uniform cardinal
//! B-spline of degree p centred on its node (p = 2: breakpoints at the half
//! cells, the knots a + (j − 5/2)h of `--knots padded`; p = 3: breakpoints
//! at the nodes). Inside, N_k(x) = B_p(ξ − k). The one B-spline centred on
//! the ghost node beyond each wall (k = −1 and k = N + 1) is folded into the
//! two nearest nodes:
//!
//! - N_0 = B_p(ξ) + 2 B_p(ξ + 1), N_1 = B_p(ξ − 1) − B_p(ξ + 1);
//! - N_N = B_p(ξ − N) + 2 B_p(ξ − N − 1),
//!   N_{N−1} = B_p(ξ − N + 1) − B_p(ξ − N − 1).
//!
//! That is the ghost coefficient extrapolated linearly, c_{−1} = 2c_0 − c_1
//! (and c_{N+1} = 2c_N − c_{N−1}), so s'' = 0 at both walls: for p = 3 the
//! space of natural cubic splines. The N + 1 functions are a partition of
//! unity on [a, b] and N_k(a) = δ_k0, N_k(b) = δ_kN, so a wall's condition
//! sits on its node alone. Quadratic, on [0, h/2]: N_0 = 1 − ξ, N_1 = ξ.
//! Cubic, on [0, h): N_0 = 1 − ξ + ξ³/6, N_1 = ξ − ξ³/3, N_2 = ξ³/6.
//!
//! Two evaluators of the same functions, both folding the unfolded
//! B_p of nodes −1 … N + 1: [`NaturalSplines::values_and_gradients_into`]
//! (what the step calls) takes B_p in closed form at r = (x − X_k)/h, the
//! argument Karamelo evaluates too; `Basis1d::local` (any derivative order)
//! runs Cox–de Boor on the uniform knot vector of the N + 3 node-centred
//! functions. Only degrees 2 and 3 (Karamelo's), for which one ghost
//! function reaches each wall.
//!
//! Items: [`NaturalSplines`].

use crate::basis::{Basis1d, LocalBasis};
use crate::error::{Error, Result};
use crate::spline::knots::KnotVector;

/// The N + 1 boundary-modified uniform B-splines of degree 2 or 3 on
/// [a, b]. Karamelo src/basis_functions.h (read, not copied); issue #36.
#[derive(Debug, Clone)]
pub struct NaturalSplines {
    /// The node-centred uniform B-splines of nodes −1 … N + 1 (function
    /// i is node i − 1).
    uniform: KnotVector,
    cells: usize,
    a: f64,
    b: f64,
    /// h = (b − a)/N and 1/h.
    h: f64,
    inverse: f64,
}

impl NaturalSplines {
    /// The basis of degree 2 or 3 on `cells` equal cells of [a, b].
    /// Karamelo src/basis_functions.h (read, not copied); issue #36.
    pub fn new(a: f64, b: f64, cells: usize, degree: usize) -> Result<Self> {
        if !(degree == 2 || degree == 3) {
            return Err(Error::InvalidDegree(format!(
                "natural knots are Karamelo's quadratic and cubic splines: degree 2 or 3, got {degree}"
            )));
        }
        if cells == 0 || !(a.is_finite() && b.is_finite() && b > a) {
            return Err(Error::InvalidArgument(format!(
                "natural knots need a < b and at least one cell, got [{a}, {b}], {cells} cells"
            )));
        }
        let h = (b - a) / cells as f64;
        // Function i (node i − 1) is centred on a + (i − 1)h: its knots run
        // from a + (i − 1 − (p + 1)/2)h, so knot j sits at a + (j − s)h.
        let shift = 1.0 + (degree as f64 + 1.0) / 2.0;
        let count = cells + 3 + degree + 1;
        let knots = (0..count)
            .map(|j| {
                let s = j as f64 - shift;
                // The wall b is a knot for p = 3: exactly b, so that x = b
                // is inside the cubic knot vector's domain.
                if s == cells as f64 {
                    b
                } else {
                    a + s * h
                }
            })
            .collect();
        Ok(Self {
            uniform: KnotVector::new(knots, degree)?,
            cells,
            a,
            b,
            h,
            inverse: 1.0 / h,
        })
    }

    /// The uniform knot vector of the unfolded node-centred functions
    /// (nodes −1 … N + 1). Karamelo src/basis_functions.h (read, not
    /// copied); issue #36.
    pub fn uniform(&self) -> &KnotVector {
        &self.uniform
    }

    /// Functions per point: p + 1, or N + 1 on fewer than p cells.
    fn width(&self) -> usize {
        (self.uniform.degree() + 1).min(self.cells + 1)
    }

    /// Folds the unfolded functions `unfolded` of nodes k0, k0 + 1, … into
    /// `folded`, `self.width()` long, returning its first node: the ghost
    /// node −1 adds 2× to node 0 and −1× to node 1, the ghost N + 1 2× to
    /// node N and −1× to node N − 1.
    fn fold(&self, first_unfolded: usize, unfolded: &[f64], folded: &mut [f64]) -> usize {
        let n = self.cells;
        let w = folded.len();
        // Unfolded function i is node i − 1.
        let first = first_unfolded.saturating_sub(1).min(n + 1 - w);
        folded.fill(0.0);
        for (r, &v) in unfolded.iter().enumerate() {
            let i = first_unfolded + r;
            if i == 0 {
                folded[0 - first] += 2.0 * v;
                folded[1 - first] -= v;
            } else if i == n + 2 {
                folded[n - first] += 2.0 * v;
                folded[n - 1 - first] -= v;
            } else {
                folded[i - 1 - first] += v;
            }
        }
        first
    }

    fn check_point(&self, x: f64) -> Result<()> {
        crate::error::finite("evaluation point", x)?;
        if x < self.a || x > self.b {
            return Err(Error::OutsideDomain {
                x,
                a: self.a,
                b: self.b,
            });
        }
        Ok(())
    }

    /// N_k(x) and N_k'(x) of the functions that may be non-zero at x, into
    /// `values` and `gradients` (each p + 1 long, N + 1 on fewer cells;
    /// other lengths are an error); returns the first node. Karamelo
    /// src/basis_functions.h (read, not copied); issue #36.
    pub fn values_and_gradients_into(
        &self,
        x: f64,
        values: &mut [f64],
        gradients: &mut [f64],
    ) -> Result<usize> {
        self.check_point(x)?;
        for (what, got) in [("values", values.len()), ("gradients", gradients.len())] {
            if got != self.width() {
                return Err(Error::LengthMismatch {
                    what: format!("{what} (one per function that reaches x)"),
                    expected: self.width(),
                    got,
                });
            }
        }
        let p = self.uniform.degree();
        let n = self.cells as f64;
        let (h, inverse) = (self.h, self.inverse);
        let xi = (x - self.a) * inverse;
        let half = if p == 2 { 0.5 } else { 1.0 };
        // The first of the p + 1 nodes whose B_p reaches x, −1 … N + 1 − p.
        let k0 = (xi - half).floor().clamp(-1.0, n + 1.0 - p as f64);
        let (mut v, mut g) = ([0.0; 4], [0.0; 4]);
        for r in 0..=p {
            let node = self.a + (k0 + r as f64) * h;
            let (b, db) = cardinal(p, (x - node) * inverse);
            v[r] = b;
            g[r] = db * inverse;
        }
        let first = (k0 + 1.0) as usize;
        let node = self.fold(first, &v[..=p], values);
        self.fold(first, &g[..=p], gradients);
        Ok(node)
    }
}

/// The uniform cardinal B-spline of degree 2 or 3 centred on 0 and its
/// derivative at r (in cells): p = 2, 3/4 − r² for |r| ≤ 1/2 and
/// (3/2 − |r|)²/2 up to 3/2; p = 3, 2/3 − r² + |r|³/2 for |r| ≤ 1 and
/// (2 − |r|)³/6 up to 2 (de Boor, *A Practical Guide to Splines*, ch. IX).
fn cardinal(p: usize, r: f64) -> (f64, f64) {
    let s = r.abs();
    if p == 2 {
        if s <= 0.5 {
            (0.75 - r * r, -2.0 * r)
        } else if s < 1.5 {
            let t = 1.5 - s;
            (0.5 * t * t, -r.signum() * t)
        } else {
            (0.0, 0.0)
        }
    } else if s <= 1.0 {
        (2.0 / 3.0 - r * r + 0.5 * s * s * s, -2.0 * r + 1.5 * r * s)
    } else if s < 2.0 {
        let t = 2.0 - s;
        (t * t * t / 6.0, -r.signum() * 0.5 * t * t)
    } else {
        (0.0, 0.0)
    }
}

impl Basis1d for NaturalSplines {
    fn num_basis(&self) -> usize {
        self.cells + 1
    }
    fn degree(&self) -> usize {
        self.uniform.degree()
    }
    fn domain(&self) -> (f64, f64) {
        (self.a, self.b)
    }
    fn local(&self, x: f64, order: usize) -> Result<LocalBasis> {
        self.check_point(x)?;
        let unfolded = self.uniform.local_basis(x, order)?;
        let mut derivatives = vec![vec![0.0; self.width()]; order + 1];
        let mut first = 0;
        for (row, out) in unfolded.derivatives.iter().zip(&mut derivatives) {
            first = self.fold(unfolded.first, row, out);
        }
        Ok(LocalBasis { first, derivatives })
    }
    /// None: the functions are C^{p−1} (p ≥ 2), their gradients continuous.
    fn gradient_breaks(&self) -> Vec<f64> {
        Vec::new()
    }
    /// The polynomial pieces inside [a, b]: for p = 2 the half cells at the
    /// walls and the cells offset by h/2 between them (N + 1 pieces), for
    /// p = 3 the N cells.
    fn cells(&self) -> Vec<(f64, f64)> {
        self.uniform
            .spans()
            .into_iter()
            .map(|(c0, c1)| (c0.max(self.a), c1.min(self.b)))
            .filter(|(c0, c1)| c0 < c1)
            .collect()
    }
}
