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
//! The unknowns are the second derivatives M_i = s''(x_i); the system is
//! tridiagonal (the not-a-knot rows are reduced to bidiagonal form by one
//! elimination step) and solved by the Thomas algorithm in O(m). Outside
//! [x_1, x_m] the end cubics are extended (as scipy's `CubicSpline` does);
//! spline-based MPM needs values slightly beyond the outermost particles.
//! With fewer than four points, not-a-knot degrades to the interpolating
//! parabola (3 points) or line (2 points); natural works from 2 points.

use crate::error::{finite, Error, Result};

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
            finite(&format!("abscissa {k}"), a)?;
            finite(&format!("value {k}"), b)?;
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
            _ => {
                // Rows i = 0..m: sub[i] M_{i−1} + diag[i] M_i + sup[i] M_{i+1} = rhs[i].
                let mut sub = vec![0.0; m];
                let mut diag = vec![0.0; m];
                let mut sup = vec![0.0; m];
                let mut rhs = vec![0.0; m];
                for i in 1..m - 1 {
                    sub[i] = h[i - 1];
                    diag[i] = 2.0 * (h[i - 1] + h[i]);
                    sup[i] = h[i];
                    rhs[i] = 6.0 * (slope[i] - slope[i - 1]);
                }
                match end {
                    EndCondition::Natural => {
                        diag[0] = 1.0;
                        diag[m - 1] = 1.0;
                    }
                    EndCondition::NotAKnot => {
                        // h1 M0 − (h0 + h1) M1 + h0 M2 = 0; eliminate M2 with row 1.
                        let (h0, h1) = (h[0], h[1]);
                        let f = h0 / sup[1];
                        diag[0] = h1 - f * sub[1];
                        sup[0] = -(h0 + h1) - f * diag[1];
                        rhs[0] = -f * rhs[1];
                        // h_{m−2} M_{m−3} − (h_{m−3} + h_{m−2}) M_{m−2} + h_{m−3} M_{m−1} = 0;
                        // eliminate M_{m−3} with row m−2.
                        let (ha, hb) = (h[m - 3], h[m - 2]);
                        let g = hb / sub[m - 2];
                        sub[m - 1] = -(ha + hb) - g * diag[m - 2];
                        diag[m - 1] = ha - g * sup[m - 2];
                        rhs[m - 1] = -g * rhs[m - 2];
                    }
                }
                second = thomas(&sub, &diag, &sup, &rhs)?;
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
