//! # Quadrature rules
//!
//! - [`GaussLegendre`]: the n-point Gauss–Legendre rule on [−1, 1], exact for
//!   polynomials of degree ≤ 2n − 1 (thesis Appendix A.3, Eqs. (A.1)–(A.2)).
//!   Nodes are the roots of the Legendre polynomial P_n, found by Newton's
//!   method from the Chebyshev-like guess cos(π(i − ¼)/(n + ½)); weights are
//!   w_i = 2 / ((1 − x_i²) P_n'(x_i)²). Nothing is typed in from a table.
//! - [`gauss_on_cells`]: a rule mapped onto each cell of a partition (book
//!   Eq. (4.38): N_g/N_e points per element).
//! - [`half_span_rule`]: the thesis' rule of §7.2, two Gauss points on each half
//!   of every non-empty knot span, weights (ξ_{j+1} − ξ_j)/4.
//!
//! Items: [`QuadraturePoint`], [`GaussLegendre`], [`MAX_GAUSS_POINTS`],
//! [`gauss_on_cells`], [`half_span_rule`], [`half_span_points`].

use crate::error::{finite, Error, Result};

/// A quadrature point: position and weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuadraturePoint {
    /// Position x_g.
    pub x: f64,
    /// Weight ω_g.
    pub weight: f64,
}

/// The n-point Gauss–Legendre rule on [−1, 1] (thesis Appendix A.3).
#[derive(Debug, Clone, PartialEq)]
pub struct GaussLegendre {
    nodes: Vec<f64>,
    weights: Vec<f64>,
}

/// Largest number of points accepted by [`GaussLegendre::new`].
pub const MAX_GAUSS_POINTS: usize = 128;

/// P_n(x) and P_n'(x) by the three-term recurrence.
fn legendre_and_derivative(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    let nf = n as f64;
    let dp = nf * (x * p1 - p0) / (x * x - 1.0);
    (p1, dp)
}

impl GaussLegendre {
    /// The n-point rule, 1 ≤ n ≤ [`MAX_GAUSS_POINTS`]. Nodes ascending.
    pub fn new(n: usize) -> Result<Self> {
        if n == 0 || n > MAX_GAUSS_POINTS {
            return Err(Error::InvalidArgument(format!(
                "a Gauss–Legendre rule needs 1 to {MAX_GAUSS_POINTS} points, got {n}"
            )));
        }
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        let nf = n as f64;
        for i in 0..n.div_ceil(2) {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
            for _ in 0..100 {
                let (p, dp) = legendre_and_derivative(n, x);
                let dx = p / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let (_, dp) = legendre_and_derivative(n, x);
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            // roots come out descending from +1: mirror them.
            nodes[i] = -x;
            nodes[n - 1 - i] = x;
            weights[i] = w;
            weights[n - 1 - i] = w;
        }
        if n % 2 == 1 {
            nodes[n / 2] = 0.0;
        }
        Ok(Self { nodes, weights })
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Always false: a rule has at least one point.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Nodes on [−1, 1], ascending.
    pub fn nodes(&self) -> &[f64] {
        &self.nodes
    }

    /// Weights on [−1, 1]; they sum to 2.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// The rule mapped to [a, b], thesis Eq. (A.2):
    /// x = (b−a)/2 · t + (a+b)/2, ω = (b−a)/2 · w.
    pub fn on_interval(&self, a: f64, b: f64) -> Vec<QuadraturePoint> {
        (0..self.len()).map(|i| self.point(i, a, b)).collect()
    }

    /// Point i of the rule mapped to [a, b] (thesis Eq. A.2), without
    /// allocating: x = (b−a)/2 · t_i + (a+b)/2, ω = (b−a)/2 · w_i.
    pub fn point(&self, i: usize, a: f64, b: f64) -> QuadraturePoint {
        let half = 0.5 * (b - a);
        let mid = 0.5 * (a + b);
        QuadraturePoint {
            x: mid + half * self.nodes[i],
            weight: half * self.weights[i],
        }
    }

    /// ∫_a^b f dx by this rule.
    pub fn integrate(&self, a: f64, b: f64, f: impl Fn(f64) -> f64) -> f64 {
        self.on_interval(a, b)
            .iter()
            .map(|q| q.weight * f(q.x))
            .sum()
    }
}

/// The n-point Gauss rule on every cell of a partition, in cell order
/// (book Eq. (4.38), TLS paper §5.4).
pub fn gauss_on_cells(
    cells: &[(f64, f64)],
    points_per_cell: usize,
) -> Result<Vec<QuadraturePoint>> {
    let rule = GaussLegendre::new(points_per_cell)?;
    let mut out = Vec::with_capacity(cells.len() * points_per_cell);
    for &(a, b) in cells {
        check_cell(a, b)?;
        out.extend(rule.on_interval(a, b));
    }
    Ok(out)
}

/// The thesis' rule of §7.2: on each non-empty span [ξ_j, ξ_{j+1}], the 2-point
/// Gauss rule on each half, i.e. four points
/// x = ±(ξ_{j+1} − ξ_j)/4 · √(1/3) + (3ξ_j + ξ_{j+1})/4 and the same about
/// (ξ_j + 3ξ_{j+1})/4, each with weight (ξ_{j+1} − ξ_j)/4.
pub fn half_span_rule(spans: &[(f64, f64)]) -> Result<Vec<QuadraturePoint>> {
    let rule = GaussLegendre::new(2)?;
    let mut out = Vec::with_capacity(4 * spans.len());
    for &(a, b) in spans {
        let m = 0.5 * (a + b);
        for (c, d) in [(a, m), (m, b)] {
            check_cell(c, d)?;
        }
        out.extend(half_span_points(&rule, a, b).into_iter().flatten());
    }
    Ok(out)
}

/// The four points of [`half_span_rule`] on one span [a, b], as the two
/// halves' 2-point rules, from a 2-point [`GaussLegendre`] rule (no
/// allocation; spline-based MPM calls this every step, thesis §7.2).
pub fn half_span_points(rule: &GaussLegendre, a: f64, b: f64) -> [[QuadraturePoint; 2]; 2] {
    let m = 0.5 * (a + b);
    [
        [rule.point(0, a, m), rule.point(1, a, m)],
        [rule.point(0, m, b), rule.point(1, m, b)],
    ]
}

/// A cell must have finite ends and positive length.
fn check_cell(a: f64, b: f64) -> Result<()> {
    finite("cell end", a)?;
    finite("cell end", b)?;
    if b <= a {
        return Err(Error::NotPositive {
            what: format!("the length of cell [{a}, {b}]"),
            value: b - a,
        });
    }
    Ok(())
}
