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

/// An interpolating cubic spline. Two splines are equal when their nodes,
/// values and second derivatives are (their work arrays do not count).
#[derive(Debug, Clone)]
pub struct CubicSpline {
    x: Vec<f64>,
    y: Vec<f64>,
    second: Vec<f64>,
    /// Work arrays of the tridiagonal solve, kept so that [`CubicSpline::refit`]
    /// allocates nothing once they have grown to the data's size.
    work: Work,
}

impl PartialEq for CubicSpline {
    fn eq(&self, other: &Self) -> bool {
        (&self.x, &self.y, &self.second) == (&other.x, &other.y, &other.second)
    }
}

/// h_i, slopes, the tridiagonal rows (sub, diag, sup, rhs) and Thomas'
/// forward-sweep coefficients.
#[derive(Debug, Clone, PartialEq, Default)]
struct Work {
    h: Vec<f64>,
    slope: Vec<f64>,
    sub: Vec<f64>,
    diag: Vec<f64>,
    sup: Vec<f64>,
    rhs: Vec<f64>,
    c: Vec<f64>,
    d: Vec<f64>,
}

impl CubicSpline {
    /// Interpolates (x_i, y_i); x must be strictly increasing with at least
    /// two points.
    pub fn new(x: &[f64], y: &[f64], end: EndCondition) -> Result<Self> {
        let empty = Self {
            x: Vec::new(),
            y: Vec::new(),
            second: Vec::new(),
            work: Work::default(),
        };
        empty.refit(x, y, end)
    }

    /// Interpolates new data (x_i, y_i), reusing this spline's buffers
    /// (spline-based MPM refits three splines every step): the same numbers
    /// as [`CubicSpline::new`]. The spline is consumed, so on an error no
    /// half-built spline remains.
    pub fn refit(mut self, x: &[f64], y: &[f64], end: EndCondition) -> Result<Self> {
        self.x.clear();
        self.y.clear();
        self.second.clear();
        check_data(x, y)?;
        let m = x.len();
        let w = &mut self.work;
        w.h.clear();
        w.h.extend((0..m - 1).map(|i| x[i + 1] - x[i]));
        w.slope.clear();
        w.slope
            .extend((0..m - 1).map(|i| (y[i + 1] - y[i]) / w.h[i]));
        let second = &mut self.second;
        second.resize(m, 0.0);
        match (end, m) {
            (_, 2) => {}
            (EndCondition::NotAKnot, 3) => {
                // The parabola through three points: constant s''.
                let c = 2.0 * (w.slope[1] - w.slope[0]) / (x[2] - x[0]);
                second.fill(c);
            }
            (EndCondition::Natural, _) => {
                // Interior rows i = 1..m−1 with M_0 = M_{m−1} = 0.
                w.interior_rows();
                w.thomas(&mut second[1..m - 1])?;
            }
            (EndCondition::NotAKnot, _) => {
                // Not-a-knot: M_0 = ((h0+h1) M_1 − h0 M_2)/h1 and
                // M_{m−1} = ((ha+hb) M_{m−2} − hb M_{m−3})/ha (ha = h_{m−3},
                // hb = h_{m−2}), substituted into the first and last interior rows.
                w.interior_rows();
                let k = m - 2;
                let (h0, h1) = (w.h[0], w.h[1]);
                w.diag[0] += h0 * (h0 + h1) / h1;
                w.sup[0] -= h0 * h0 / h1;
                let (ha, hb) = (w.h[m - 3], w.h[m - 2]);
                w.diag[k - 1] += hb * (ha + hb) / ha;
                w.sub[k - 1] -= hb * hb / ha;
                w.thomas(&mut second[1..m - 1])?;
                second[0] = ((h0 + h1) * second[1] - h0 * second[2]) / h1;
                second[m - 1] = ((ha + hb) * second[m - 2] - hb * second[m - 3]) / ha;
            }
        }
        self.x.extend_from_slice(x);
        self.y.extend_from_slice(y);
        Ok(self)
    }

    /// The interval index used for x (end pieces extended outside), from the
    /// number of nodes at or below x.
    fn piece_of(&self, nodes_at_or_below: usize) -> usize {
        let m = self.x.len();
        match nodes_at_or_below {
            0 => 0,
            k if k >= m => m - 2,
            k => k - 1,
        }
    }

    /// s(x).
    pub fn evaluate(&self, x: f64) -> f64 {
        let i = self.piece_of(self.x.partition_point(|&t| t <= x));
        self.evaluate_piece(i, x)
    }

    /// s(x) for a run of queries in increasing (or slowly varying) order:
    /// `cursor` carries the number of nodes at or below the previous query
    /// and is walked to x, O(1) per query when the queries advance by about
    /// one node, as the Gauss points of spline-based MPM do. The same piece,
    /// hence the same number, as [`CubicSpline::evaluate`]. Start with 0.
    pub fn evaluate_from(&self, x: f64, cursor: &mut usize) -> f64 {
        let t = &self.x;
        let mut k = (*cursor).min(t.len());
        while k < t.len() && t[k] <= x {
            k += 1;
        }
        while k > 0 && t[k - 1] > x {
            k -= 1;
        }
        *cursor = k;
        self.evaluate_piece(self.piece_of(k), x)
    }

    /// The cubic of piece i at x, in the form of the second derivatives M_i.
    fn evaluate_piece(&self, i: usize, x: f64) -> f64 {
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

impl Work {
    /// The interior equations h_{i−1} M_{i−1} + 2(h_{i−1}+h_i) M_i + h_i M_{i+1} =
    /// 6(s_i − s_{i−1}) for i = 1..m−1, as (sub, diag, sup, rhs).
    fn interior_rows(&mut self) {
        let k = self.h.len() - 1;
        for v in [&mut self.sub, &mut self.diag, &mut self.sup, &mut self.rhs] {
            v.clear();
            v.resize(k, 0.0);
        }
        let (h, slope) = (&self.h, &self.slope);
        for r in 0..k {
            let i = r + 1;
            self.sub[r] = h[i - 1];
            self.diag[r] = 2.0 * (h[i - 1] + h[i]);
            self.sup[r] = h[i];
            self.rhs[r] = 6.0 * (slope[i] - slope[i - 1]);
        }
    }

    /// Thomas algorithm for the tridiagonal system (sub, diag, sup, rhs),
    /// solution into `x`.
    fn thomas(&mut self, x: &mut [f64]) -> Result<()> {
        let (sub, diag, sup, rhs) = (&self.sub, &self.diag, &self.sup, &self.rhs);
        let n = diag.len();
        let (c, d) = (&mut self.c, &mut self.d);
        c.clear();
        c.resize(n, 0.0);
        d.clear();
        d.resize(n, 0.0);
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
        x[n - 1] = d[n - 1];
        for i in (0..n - 1).rev() {
            x[i] = d[i] - c[i] * x[i + 1];
        }
        Ok(())
    }
}

/// Data a cubic spline can interpolate: equal lengths, at least two finite
/// points, strictly increasing abscissae, and gaps whose cube is finite.
fn check_data(x: &[f64], y: &[f64]) -> Result<()> {
    if x.len() != y.len() {
        return Err(Error::LengthMismatch {
            what: "values (one per abscissa)".into(),
            expected: x.len(),
            got: y.len(),
        });
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
    // The pieces evaluate (x_{i+1} − x)³ and (x − x_i)³ (see `evaluate_piece`),
    // so a gap whose cube overflows would give ∞ or NaN at its own points.
    if let Some(k) = (1..x.len()).find(|&k| !(x[k] - x[k - 1]).powi(3).is_finite()) {
        return Err(Error::InvalidArgument(format!(
            "the gap x[{k}] − x[{}] = {:e} is too wide for a cubic: its cube overflows",
            k - 1,
            x[k] - x[k - 1]
        )));
    }
    Ok(())
}
