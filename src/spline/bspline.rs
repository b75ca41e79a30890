//! # B-spline basis functions: Cox–de Boor
//!
//! Two evaluators of the same functions:
//!
//! 1. [`cox_de_boor`] and [`cox_de_boor_derivative`] are the recursion of book
//!    Eqs. (4.19)–(4.20) and the derivative formula (4.23), written literally,
//!    one function at a time. They are the specification.
//! 2. [`KnotVector::local_basis`] returns the p+1 non-zero functions on one
//!    span and their derivatives at once (the triangular scheme of Piegl &
//!    Tiller, *The NURBS Book*, A2.2–A2.3). It is what the rest of hompm
//!    calls; property tests check it against the literal recursion.
//!
//! The quotient convention 0/0 := 0: a term of Eq. (4.20) or (4.23) whose
//! denominator ξ_{i+p} − ξ_i (or ξ_{i+p+1} − ξ_{i+1}) vanishes is dropped,
//! because its companion function φ_{i,p−1} (or φ_{i+1,p−1}) is then zero
//! everywhere.
//!
//! The derivative carries a minus sign between its two terms (book Eq. 4.23,
//! TLS paper §4). The MLS paper's Eq. (3) prints "+"; a finite-difference test
//! (`derivative_sign_is_minus` in tests/spec/properties/properties_bspline.rs) decides for the
//! book, and docs/conventions.md records it.
//!
//! Items: [`cox_de_boor`], [`cox_de_boor_derivative`], [`SpanScratch`].

use crate::basis::{Basis1d, LocalBasis};
use crate::error::{Error, Result};
use crate::spline::knots::KnotVector;

/// a / b with the convention 0/0 := 0 (and x/0 := 0: a zero-length support
/// always multiplies a function that is identically zero).
fn ratio(a: f64, b: f64) -> f64 {
    if b == 0.0 {
        0.0
    } else {
        a / b
    }
}

/// φ_{i,p}(x) by the literal Cox–de Boor recursion, book Eqs. (4.19)–(4.20).
///
/// `i` is 0-based; `p` may be any degree up to the knot vector's own. The
/// degree-0 functions follow Eq. (4.19), ξ_i ≤ x < ξ_{i+1}, except that at the
/// right end of the domain the last non-empty span is taken (half-open span
/// convention, docs/conventions.md). Errors for a point outside the domain or
/// an index out of range.
pub fn cox_de_boor(knots: &KnotVector, i: usize, p: usize, x: f64) -> Result<f64> {
    knots.check_point(x)?;
    check_index(knots, i, p)?;
    Ok(cox_de_boor_unchecked(knots, i, p, x))
}

fn check_index(knots: &KnotVector, i: usize, p: usize) -> Result<()> {
    if p > knots.degree() {
        return Err(Error::InvalidDegree(format!(
            "degree {p} exceeds the knot vector's degree {}",
            knots.degree()
        )));
    }
    if i + p + 1 >= knots.knots().len() {
        return Err(Error::InvalidArgument(format!(
            "basis index {i} out of range for degree {p} ({} functions)",
            knots.knots().len() - p - 1
        )));
    }
    Ok(())
}

fn cox_de_boor_unchecked(knots: &KnotVector, i: usize, p: usize, x: f64) -> f64 {
    let t = knots.knots();
    if p == 0 {
        let (_, b) = knots.domain();
        // Eq. (4.19), with the right end of the domain given to the last
        // non-empty span (and to no span beyond the domain).
        let on = if x == b {
            i == knots.last_span()
        } else {
            t[i] <= x && x < t[i + 1]
        };
        return if on { 1.0 } else { 0.0 };
    }
    let left = ratio(x - t[i], t[i + p] - t[i]) * cox_de_boor_unchecked(knots, i, p - 1, x);
    let right = ratio(t[i + p + 1] - x, t[i + p + 1] - t[i + 1])
        * cox_de_boor_unchecked(knots, i + 1, p - 1, x);
    left + right
}

/// dφ_{i,p}/dx by book Eq. (4.23), literally:
/// p/(ξ_{i+p} − ξ_i) φ_{i,p−1} − p/(ξ_{i+p+1} − ξ_{i+1}) φ_{i+1,p−1}.
pub fn cox_de_boor_derivative(knots: &KnotVector, i: usize, p: usize, x: f64) -> Result<f64> {
    knots.check_point(x)?;
    check_index(knots, i, p)?;
    if p == 0 {
        return Ok(0.0);
    }
    let t = knots.knots();
    let pf = p as f64;
    Ok(
        ratio(pf, t[i + p] - t[i]) * cox_de_boor_unchecked(knots, i, p - 1, x)
            - ratio(pf, t[i + p + 1] - t[i + 1]) * cox_de_boor_unchecked(knots, i + 1, p - 1, x),
    )
}

/// Book Eqs. (4.19)–(4.20) for all p+1 functions of span `span` at once, by
/// the triangle of NURBS Book A2.2: afterwards ndu[r][j] (r ≤ j, row-major
/// with width p+1) holds φ_{span−j+r, j}(x), the functions of degree j, and
/// ndu[j][r] (r < j) the knot differences that divide them. Every entry is
/// written before it is read.
fn cox_de_boor_triangle(
    t: &[f64],
    span: usize,
    x: f64,
    p: usize,
    ndu: &mut [f64],
    left: &mut [f64],
    right: &mut [f64],
) {
    let w = p + 1;
    ndu[0] = 1.0;
    for j in 1..=p {
        left[j] = x - t[span + 1 - j];
        right[j] = t[span + j] - x;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j * w + r] = right[r + 1] + left[j - r];
            let temp = ndu[r * w + j - 1] / ndu[j * w + r];
            ndu[r * w + j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j * w + j] = saved;
    }
}

impl KnotVector {
    /// The p+1 functions that may be non-zero at `x`, with derivatives up to
    /// `order` (orders above p are zero). Same functions as [`cox_de_boor`];
    /// derivatives as Eq. (4.23) applied repeatedly (NURBS Book A2.3).
    pub fn local_basis(&self, x: f64, order: usize) -> Result<LocalBasis> {
        let span = self.find_span(x)?;
        Ok(self.evaluate_on_span(span, x, order))
    }

    /// The polynomial piece of span `span` (0-based knot index, ξ_span < ξ_{span+1})
    /// evaluated at any `x` in the closed span [ξ_span, ξ_{span+1}]: at the
    /// span's right end this is the one-sided limit from the left, which
    /// [`KnotVector::local_basis`] does not give (spans are half-open).
    pub fn local_basis_on_span(&self, span: usize, x: f64, order: usize) -> Result<LocalBasis> {
        crate::error::finite("evaluation point", x)?;
        let t = self.knots();
        if span < self.degree() || span >= self.num_basis() || t[span] >= t[span + 1] {
            return Err(Error::InvalidArgument(format!(
                "{span} is not the index of a non-empty knot span inside the domain"
            )));
        }
        if x < t[span] || x > t[span + 1] {
            return Err(Error::OutsideDomain {
                x,
                a: t[span],
                b: t[span + 1],
            });
        }
        Ok(self.evaluate_on_span(span, x, order))
    }

    fn evaluate_on_span(&self, span: usize, x: f64, order: usize) -> LocalBasis {
        let mut scratch = SpanScratch::default();
        let first = self.evaluate_on_span_into(span, x, order, &mut scratch);
        let w = self.degree() + 1;
        LocalBasis {
            first,
            derivatives: scratch.ders.chunks(w).map(|row| row.to_vec()).collect(),
        }
    }

    /// The triangular scheme of NURBS Book A2.2–A2.3 on span `span` at `x`,
    /// written into `scratch` (no allocation once the scratch has grown to
    /// this degree and order): afterwards `scratch.derivative(k)` holds the
    /// k-th derivatives of the functions `first ..= first + p`. Returns
    /// `first = span − p`. The caller guarantees that `span` is a non-empty
    /// span and x lies in its closure.
    pub(crate) fn evaluate_on_span_into(
        &self,
        span: usize,
        x: f64,
        order: usize,
        scratch: &mut SpanScratch,
    ) -> usize {
        let p = self.degree();
        let t = self.knots();
        let w = p + 1;
        scratch.prepare(w, order);
        let SpanScratch {
            ndu,
            left,
            right,
            a,
            ders,
            ..
        } = scratch;
        cox_de_boor_triangle(t, span, x, p, ndu, left, right);
        for j in 0..w {
            ders[j] = ndu[j * w + p];
        }
        let n = order.min(p);
        for r in 0..=p {
            let (mut s1, mut s2) = (0usize, 1usize);
            a[0] = 1.0;
            for k in 1..=n {
                let mut d = 0.0;
                let rk = r as isize - k as isize;
                let pk = p - k;
                if r >= k {
                    a[s2 * w] = a[s1 * w] / ndu[(pk + 1) * w + rk as usize];
                    d = a[s2 * w] * ndu[rk as usize * w + pk];
                }
                let j1: usize = if rk >= -1 { 1 } else { (-rk) as usize };
                let j2: usize = if r as isize - 1 <= pk as isize {
                    k - 1
                } else {
                    p - r
                };
                for j in j1..=j2 {
                    let idx = (rk + j as isize) as usize;
                    a[s2 * w + j] = (a[s1 * w + j] - a[s1 * w + j - 1]) / ndu[(pk + 1) * w + idx];
                    d += a[s2 * w + j] * ndu[idx * w + pk];
                }
                if r <= pk {
                    a[s2 * w + k] = -a[s1 * w + k - 1] / ndu[(pk + 1) * w + r];
                    d += a[s2 * w + k] * ndu[r * w + pk];
                }
                ders[k * w + r] = d;
                std::mem::swap(&mut s1, &mut s2);
            }
        }
        let mut factor = p as f64;
        for k in 1..=n {
            for v in ders[k * w..(k + 1) * w].iter_mut() {
                *v *= factor;
            }
            factor *= (p - k) as f64;
        }
        span - p
    }

    /// The p+1 values and first derivatives at `x`, written straight into
    /// `values` and `gradients` (each p+1 long): the specialisation of
    /// [`KnotVector::local_basis`] with order 1 that the MPM step calls for
    /// every particle. Book Eqs. (4.19)–(4.20) by the triangle of NURBS Book
    /// A2.2; the derivative is A2.3 at k = 1, which reduces to book Eq. (4.23):
    /// φ'_{r} = p (ndu\[r−1\]\[p−1\]/ndu\[p\]\[r−1\] − ndu\[r\]\[p−1\]/ndu\[p\]\[r\]), with
    /// the same operations in the same order, so the numbers are bit for bit
    /// those of `local_basis(x, 1)` (tests/spec/properties/properties_bspline.rs). Returns
    /// the index of the first function.
    pub fn values_and_gradients_into(
        &self,
        x: f64,
        scratch: &mut SpanScratch,
        values: &mut [f64],
        gradients: &mut [f64],
    ) -> Result<usize> {
        let span = self.find_span(x)?;
        let p = self.degree();
        let t = self.knots();
        let w = p + 1;
        scratch.ensure(w);
        let SpanScratch {
            ndu, left, right, ..
        } = scratch;
        cox_de_boor_triangle(t, span, x, p, ndu, left, right);
        for r in 0..w {
            values[r] = ndu[r * w + p];
        }
        if p == 0 {
            gradients[0] = 0.0;
            return Ok(span);
        }
        let pf = p as f64;
        for r in 0..w {
            let mut d = 0.0;
            if r >= 1 {
                d = 1.0 / ndu[p * w + r - 1] * ndu[(r - 1) * w + p - 1];
            }
            if r < p {
                d += -1.0 / ndu[p * w + r] * ndu[r * w + p - 1];
            }
            gradients[r] = d * pf;
        }
        Ok(span - p)
    }

    /// [`KnotVector::values_and_gradients_into`] for a degree known when
    /// compiling, W = p + 1 (the step's hot path: the triangle lives in
    /// registers, not in a scratch). The same operations in the same order as
    /// `cox_de_boor_triangle` and the derivative of Eq. (4.23), so the numbers
    /// are bit for bit those of the general code (tests/spec/properties/properties_bspline.rs).
    /// The caller guarantees W = p + 1. Always inlined: once
    /// `Grid::fill_stencils` became generic over the points' type (1D
    /// values, 2D `[x, y]`), LLVM kept this call out of line in the 1D step
    /// (+30 instructions per particle-step, callgrind, bsmpm 1024 cells).
    #[inline(always)]
    pub fn values_and_gradients_fixed<const W: usize>(
        &self,
        x: f64,
        values: &mut [f64; W],
        gradients: &mut [f64; W],
    ) -> Result<usize> {
        debug_assert_eq!(W, self.degree() + 1);
        let span = self.find_span(x)?;
        let p = W - 1;
        let t = self.knots();
        // ndu[r][j] as in cox_de_boor_triangle, with left/right of A2.2.
        let mut ndu = [[0.0; W]; W];
        let (mut left, mut right) = ([0.0; W], [0.0; W]);
        ndu[0][0] = 1.0;
        for j in 1..=p {
            left[j] = x - t[span + 1 - j];
            right[j] = t[span + j] - x;
            let mut saved = 0.0;
            for r in 0..j {
                ndu[j][r] = right[r + 1] + left[j - r];
                let temp = ndu[r][j - 1] / ndu[j][r];
                ndu[r][j] = saved + right[r + 1] * temp;
                saved = left[j - r] * temp;
            }
            ndu[j][j] = saved;
        }
        for r in 0..W {
            values[r] = ndu[r][p];
        }
        if p == 0 {
            gradients[0] = 0.0;
            return Ok(span);
        }
        let pf = p as f64;
        // 1/ndu[p][r], each used by functions r and r + 1: one division
        // instead of two, and −1/a = −(1/a) exactly, so no bit changes.
        let mut inverse = [0.0; W];
        for r in 0..p {
            inverse[r] = 1.0 / ndu[p][r];
        }
        for r in 0..W {
            let mut d = 0.0;
            if r >= 1 {
                d = inverse[r - 1] * ndu[r - 1][p - 1];
            }
            if r < p {
                d += -inverse[r] * ndu[r][p - 1];
            }
            gradients[r] = d * pf;
        }
        Ok(span - p)
    }

    /// [`KnotVector::values_and_gradients_fixed`] at two points x = [x₀, x₁]
    /// at once (a 2D particle's two axes, MLS paper Eqs. 4–5): each
    /// operation of the triangle on a pair [lane 0, lane 1], which LLVM can
    /// issue as one SSE2 instruction, and every lane the same operations in
    /// the same order as one call, so the same bits. `values[l]` and
    /// `gradients[l]` receive lane l's row; returns each lane's first
    /// function. The caller guarantees W = p + 1 ≥ 2.
    #[inline(always)]
    pub fn values_and_gradients_pair<const W: usize>(
        &self,
        x: [f64; 2],
        values: &mut [[f64; W]; 2],
        gradients: &mut [[f64; W]; 2],
    ) -> Result<[usize; 2]> {
        debug_assert!(W >= 2 && W == self.degree() + 1);
        let span = [self.find_span(x[0])?, self.find_span(x[1])?];
        let p = W - 1;
        let t = self.knots();
        #[inline(always)]
        fn lanes(f: impl Fn(usize) -> f64) -> [f64; 2] {
            [f(0), f(1)]
        }
        // ndu[r][j], left and right as in `values_and_gradients_fixed`,
        // each entry a pair of lanes.
        let mut ndu = [[[0.0; 2]; W]; W];
        let (mut left, mut right) = ([[0.0; 2]; W], [[0.0; 2]; W]);
        ndu[0][0] = [1.0; 2];
        for j in 1..=p {
            left[j] = lanes(|l| x[l] - t[span[l] + 1 - j]);
            right[j] = lanes(|l| t[span[l] + j] - x[l]);
            let mut saved = [0.0; 2];
            for r in 0..j {
                ndu[j][r] = lanes(|l| right[r + 1][l] + left[j - r][l]);
                let temp = lanes(|l| ndu[r][j - 1][l] / ndu[j][r][l]);
                ndu[r][j] = lanes(|l| saved[l] + right[r + 1][l] * temp[l]);
                saved = lanes(|l| left[j - r][l] * temp[l]);
            }
            ndu[j][j] = saved;
        }
        let pf = p as f64;
        let mut inverse = [[0.0; 2]; W];
        for r in 0..p {
            inverse[r] = lanes(|l| 1.0 / ndu[p][r][l]);
        }
        for r in 0..W {
            let mut d = [0.0; 2];
            if r >= 1 {
                d = lanes(|l| inverse[r - 1][l] * ndu[r - 1][p - 1][l]);
            }
            if r < p {
                d = lanes(|l| d[l] + -inverse[r][l] * ndu[r][p - 1][l]);
            }
            for l in 0..2 {
                values[l][r] = ndu[r][p][l];
                gradients[l][r] = d[l] * pf;
            }
        }
        Ok([span[0] - p, span[1] - p])
    }

    /// [`KnotVector::local_basis`] into a reusable scratch: finds the span of
    /// `x` and evaluates the p+1 functions and `order` derivatives there.
    /// Returns the index of the first function; read the results with
    /// [`SpanScratch::derivative`].
    pub fn local_basis_into(
        &self,
        x: f64,
        order: usize,
        scratch: &mut SpanScratch,
    ) -> Result<usize> {
        let span = self.find_span(x)?;
        Ok(self.evaluate_on_span_into(span, x, order, scratch))
    }

    /// All n basis values at `x` as a dense vector (for the CLI and tests).
    pub fn dense_values(&self, x: f64) -> Result<Vec<f64>> {
        Ok(self.local_basis(x, 0)?.dense(0, self.num_basis()))
    }

    /// All n first derivatives at `x` as a dense vector.
    pub fn dense_derivatives(&self, x: f64) -> Result<Vec<f64>> {
        Ok(self.local_basis(x, 1)?.dense(1, self.num_basis()))
    }
}

/// Work arrays of the Cox–de Boor triangle (NURBS Book A2.2–A2.3), reused
/// between evaluations so that evaluating a B-spline basis allocates nothing.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SpanScratch {
    ndu: Vec<f64>,
    left: Vec<f64>,
    right: Vec<f64>,
    a: Vec<f64>,
    ders: Vec<f64>,
    width: usize,
}

impl SpanScratch {
    /// Sizes and zeroes the arrays for `width` = p+1 functions and derivatives
    /// up to `order` (every array starts at zero, as in a fresh evaluation).
    fn prepare(&mut self, width: usize, order: usize) {
        self.width = width;
        for (v, len) in [
            (&mut self.ndu, width * width),
            (&mut self.left, width),
            (&mut self.right, width),
            (&mut self.a, 2 * width),
            (&mut self.ders, (order + 1) * width),
        ] {
            v.clear();
            v.resize(len, 0.0);
        }
    }

    /// Sizes the triangle and knot-difference arrays for `width` = p+1
    /// functions without zeroing them: A2.2 writes every entry before it
    /// reads it.
    fn ensure(&mut self, width: usize) {
        if self.ndu.len() != width * width {
            self.ndu.resize(width * width, 0.0);
            self.left.resize(width, 0.0);
            self.right.resize(width, 0.0);
        }
        self.width = width;
    }

    /// The k-th derivatives of the p+1 functions of the last evaluation
    /// (k = 0: the values).
    pub fn derivative(&self, k: usize) -> &[f64] {
        &self.ders[k * self.width..(k + 1) * self.width]
    }
}

impl Basis1d for KnotVector {
    fn num_basis(&self) -> usize {
        KnotVector::num_basis(self)
    }
    fn degree(&self) -> usize {
        KnotVector::degree(self)
    }
    fn domain(&self) -> (f64, f64) {
        KnotVector::domain(self)
    }
    fn local(&self, x: f64, order: usize) -> Result<LocalBasis> {
        self.local_basis(x, order)
    }
    /// Interior knots of multiplicity ≥ p, where the functions are at most C⁰
    /// (thesis §6.1: C^{p−k} at a knot of multiplicity k).
    fn gradient_breaks(&self) -> Vec<f64> {
        let (a, b) = self.domain();
        self.breakpoints()
            .into_iter()
            .filter(|&(k, m)| k > a && k < b && m >= self.degree().max(1))
            .map(|(k, _)| k)
            .collect()
    }
    fn cells(&self) -> Vec<(f64, f64)> {
        self.spans()
    }
}
