//! # Cubic-spline interpolation
//!
//! Thesis §7.1: on every interval [x_i, x_{i+1}] a cubic
//! s_i(x) = a_i (x − x_i)³ + b_i (x − x_i)² + c_i (x − x_i) + d_i with
//! s(x_i) = f(x_i) and s, s', s'' continuous at the interior nodes. Two end
//! conditions close the system:
//! - [`EndCondition::Natural`]: s''(x_1) = s''(x_m) = 0 — what the thesis text
//!   states;
//! - [`EndCondition::NotAKnot`]: s''' continuous at x_2 and x_{m−1} — what
//!   reproducing thesis Table 7.1 needs (docs/conventions.md). It reproduces
//!   cubic polynomials exactly.
//!
//! The unknowns are the second derivatives M_i = s''(x_i); the not-a-knot
//! conditions express M_1 and M_m through their neighbours, which keeps the
//! system for M_2 … M_{m−1} tridiagonal, solved by the Thomas algorithm in O(m). Outside
//! [x_1, x_m] the end cubics are extended (as scipy's `CubicSpline` does);
//! spline-based MPM needs values slightly beyond the outermost particles.
//! With fewer than four points, not-a-knot degrades to the interpolating
//! parabola (3 points) or line (2 points); natural works from 2 points.

use crate::error::{finite_named, Error, Result};

/// End condition of the cubic spline.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EndCondition {
    /// s'' = 0 at both ends.
    Natural,
    /// s''' continuous at the second and second-to-last nodes.
    NotAKnot,
}

/// An interpolating cubic spline.
#[derive(Debug, Clone, PartialEq)]
pub struct CubicSpline {
    x: Vec<f64>,
    y: Vec<f64>,
    second: Vec<f64>,
}

impl CubicSpline {
    /// Interpolates (x_i, y_i); x must be strictly increasing with at least
    /// two points.
    pub fn new(x: &[f64], y: &[f64], end: EndCondition) -> Result<Self> {
        if x.len() != y.len() {
            return Err(Error::InvalidArgument(format!(
                "{} abscissae but {} values",
                x.len(),
                y.len()
            )));
        }
        if x.len() < 2 {
            return Err(Error::InvalidArgument(
                "a cubic spline needs at least two points".into(),
            ));
        }
        for (k, (&a, &b)) in x.iter().zip(y).enumerate() {
            finite_named(a, || format!("abscissa {k}"))?;
            finite_named(b, || format!("value {k}"))?;
        }
        if let Some(k) = (1..x.len()).find(|&k| x[k] <= x[k - 1]) {
            return Err(Error::InvalidArgument(format!(
                "abscissae must be strictly increasing: x[{}] = {} ≥ x[{k}] = {}",
                k - 1,
                x[k - 1],
                x[k]
            )));
        }
        let m = x.len();
        let h: Vec<f64> = (0..m - 1).map(|i| x[i + 1] - x[i]).collect();
        let slope: Vec<f64> = (0..m - 1).map(|i| (y[i + 1] - y[i]) / h[i]).collect();
        let mut second = vec![0.0; m];
        match (end, m) {
            (_, 2) => {}
            (EndCondition::NotAKnot, 3) => {
                // The parabola through three points: constant s''.
                let c = 2.0 * (slope[1] - slope[0]) / (x[2] - x[0]);
                second = vec![c; 3];
            }
            (EndCondition::Natural, _) => {
                // Interior rows i = 1..m−1 with M_0 = M_{m−1} = 0.
                let (sub, diag, sup, rhs) = interior_rows(&h, &slope);
                let inner = thomas(&sub, &diag, &sup, &rhs)?;
                second[1..m - 1].copy_from_slice(&inner);
            }
            (EndCondition::NotAKnot, _) => {
                // Not-a-knot: M_0 = ((h0+h1) M_1 − h0 M_2)/h1 and
                // M_{m−1} = ((ha+hb) M_{m−2} − hb M_{m−3})/ha (ha = h_{m−3},
                // hb = h_{m−2}), substituted into the first and last interior rows.
                let (mut sub, mut diag, mut sup, rhs) = interior_rows(&h, &slope);
                let k = m - 2;
                let (h0, h1) = (h[0], h[1]);
                diag[0] += h0 * (h0 + h1) / h1;
                sup[0] -= h0 * h0 / h1;
                let (ha, hb) = (h[m - 3], h[m - 2]);
                diag[k - 1] += hb * (ha + hb) / ha;
                sub[k - 1] -= hb * hb / ha;
                let inner = thomas(&sub, &diag, &sup, &rhs)?;
                second[1..m - 1].copy_from_slice(&inner);
                second[0] = ((h0 + h1) * second[1] - h0 * second[2]) / h1;
                second[m - 1] = ((ha + hb) * second[m - 2] - hb * second[m - 3]) / ha;
            }
        }
        Ok(Self {
            x: x.to_vec(),
            y: y.to_vec(),
            second,
        })
    }

    /// The interval index used for x (end pieces extended outside).
    fn piece(&self, x: f64) -> usize {
        let m = self.x.len();
        match self.x.partition_point(|&t| t <= x) {
            0 => 0,
            k if k >= m => m - 2,
            k => k - 1,
        }
    }

    /// s(x).
    pub fn evaluate(&self, x: f64) -> f64 {
        let i = self.piece(x);
        let h = self.x[i + 1] - self.x[i];
        let (a, b) = (self.x[i + 1] - x, x - self.x[i]);
        let (mi, mj) = (self.second[i], self.second[i + 1]);
        mi * a * a * a / (6.0 * h)
            + mj * b * b * b / (6.0 * h)
            + (self.y[i] / h - mi * h / 6.0) * a
            + (self.y[i + 1] / h - mj * h / 6.0) * b
    }

    /// The nodes x_i.
    pub fn nodes(&self) -> &[f64] {
        &self.x
    }
}

type Rows = (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>);

/// The interior equations h_{i−1} M_{i−1} + 2(h_{i−1}+h_i) M_i + h_i M_{i+1} =
/// 6(s_i − s_{i−1}) for i = 1..m−1, as (sub, diag, sup, rhs).
fn interior_rows(h: &[f64], slope: &[f64]) -> Rows {
    let k = h.len() - 1;
    let mut rows: Rows = (vec![0.0; k], vec![0.0; k], vec![0.0; k], vec![0.0; k]);
    for r in 0..k {
        let i = r + 1;
        rows.0[r] = h[i - 1];
        rows.1[r] = 2.0 * (h[i - 1] + h[i]);
        rows.2[r] = h[i];
        rows.3[r] = 6.0 * (slope[i] - slope[i - 1]);
    }
    rows
}

/// Thomas algorithm for a tridiagonal system.
fn thomas(sub: &[f64], diag: &[f64], sup: &[f64], rhs: &[f64]) -> Result<Vec<f64>> {
    let n = diag.len();
    let mut c = vec![0.0; n];
    let mut d = vec![0.0; n];
    let mut denom = diag[0];
    if denom == 0.0 {
        return Err(Error::Singular(
            "cubic-spline system has a zero pivot".into(),
        ));
    }
    c[0] = sup[0] / denom;
    d[0] = rhs[0] / denom;
    for i in 1..n {
        denom = diag[i] - sub[i] * c[i - 1];
        if denom == 0.0 || !denom.is_finite() {
            return Err(Error::Singular(
                "cubic-spline system has a zero pivot".into(),
            ));
        }
        c[i] = sup[i] / denom;
        d[i] = (rhs[i] - sub[i] * d[i - 1]) / denom;
    }
    let mut x = vec![0.0; n];
    x[n - 1] = d[n - 1];
    for i in (0..n - 1).rev() {
        x[i] = d[i] - c[i] * x[i + 1];
    }
    Ok(x)
}
