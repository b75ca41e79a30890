//! # Knot vectors
//!
//! A knot vector Ξ = {ξ_1, …, ξ_{n+p+1}} is a non-decreasing sequence of reals;
//! with the degree p it defines n B-spline basis functions (book §4.3, thesis
//! §6.1, TLS paper §4, MLS paper §2). The non-empty intervals [ξ_i, ξ_{i+1})
//! are the *knot spans*.
//!
//! Conventions (docs/conventions.md, "Knot spans"):
//! - the domain is [ξ_{p+1}, ξ_{n+1}] (1-based), which is [first, last knot]
//!   for an open knot vector;
//! - spans are half-open, [ξ_i, ξ_{i+1}); the right end of the domain belongs
//!   to the last non-empty span, so partition of unity holds there too;
//! - no knot may be repeated more than p+1 times (it would create a basis
//!   function that is identically zero).
//!
//! Items: [`KnotVector`].

use crate::error::{finite, finite_named, Error, Result};

/// A validated knot vector together with the polynomial degree p.
#[derive(Debug, Clone, PartialEq)]
pub struct KnotVector {
    knots: Vec<f64>,
    degree: usize,
    /// True when the spans inside the domain are non-empty and of equal
    /// length (to 1e-9): [`KnotVector::find_span`] then guesses the span from
    /// the spacing in O(1) and corrects the guess against the knots, so the
    /// answer is the same as the binary search's.
    uniform: bool,
    /// (n − p)/(b − a): spans per unit length, for the O(1) guess.
    spans_per_length: f64,
}

impl KnotVector {
    /// Validates a general knot vector for degree `degree`.
    ///
    /// Errors: an empty or non-finite knot, decreasing knots, fewer than p+2
    /// knots, a knot of multiplicity above p+1, a domain of zero length, and
    /// knots too close (a non-zero span below `f64::MIN_POSITIVE`, whose
    /// reciprocal overflows) or too far apart (a span or domain length that
    /// overflows) for double precision.
    /// Book §4.3 (Ξ non-decreasing); thesis §6.1 (repeated knots).
    pub fn new(knots: Vec<f64>, degree: usize) -> Result<Self> {
        Self::check_finite_and_non_decreasing(&knots)?;
        Self::check_degree_and_multiplicity(&knots, degree)?;
        Self::check_representable_spans(&knots)?;
        let n = knots.len() - degree - 1;
        Self::check_domain(&knots, degree, n)?;
        let uniform = Self::has_uniform_spans(&knots, degree, n);
        let spans_per_length = (n - degree) as f64 / (knots[n] - knots[degree]);
        Ok(Self {
            knots,
            degree,
            uniform,
            spans_per_length,
        })
    }

    /// Ξ is non-empty, finite and non-decreasing (book §4.3).
    fn check_finite_and_non_decreasing(knots: &[f64]) -> Result<()> {
        if knots.is_empty() {
            return Err(Error::InvalidKnots("the knot vector is empty".into()));
        }
        for (i, k) in knots.iter().enumerate() {
            finite_named(*k, || format!("knot {i}"))?;
        }
        for i in 1..knots.len() {
            if knots[i] < knots[i - 1] {
                return Err(Error::DecreasingKnot {
                    index: i,
                    knot: knots[i],
                    previous: knots[i - 1],
                });
            }
        }
        Ok(())
    }

    /// At least p + 2 knots, and no knot repeated more than p + 1 times
    /// (thesis §6.1).
    fn check_degree_and_multiplicity(knots: &[f64], degree: usize) -> Result<()> {
        // `degree + 2` written so that no degree overflows it.
        if knots.len() - 1 <= degree {
            return Err(Error::InvalidDegree(format!(
                "degree {degree} needs at least {} knots, got {}",
                degree as u128 + 2,
                knots.len()
            )));
        }
        let mut run = 1;
        for i in 1..=knots.len() {
            if i < knots.len() && knots[i] == knots[i - 1] {
                run += 1;
                continue;
            }
            if run > degree + 1 {
                return Err(Error::InvalidKnots(format!(
                    "knot {} has multiplicity {run}, above degree + 1 = {}",
                    knots[i - 1],
                    degree + 1
                )));
            }
            run = 1;
        }
        Ok(())
    }

    /// Every non-empty span is at least the smallest normal double (so
    /// 1/span is finite) and every span is finite.
    fn check_representable_spans(knots: &[f64]) -> Result<()> {
        for i in 1..knots.len() {
            let d = knots[i] - knots[i - 1];
            if !d.is_finite() || (d > 0.0 && d < f64::MIN_POSITIVE) {
                return Err(Error::InvalidKnots(format!(
                    "knots {} = {:e} and {i} = {:e} differ by {d:e}, which double precision cannot divide by",
                    i - 1,
                    knots[i - 1],
                    knots[i]
                )));
            }
        }
        Ok(())
    }

    /// The domain [ξ_{p+1}, ξ_{n+1}] has a finite, positive length.
    fn check_domain(knots: &[f64], degree: usize, n: usize) -> Result<()> {
        if !(knots[n] - knots[degree]).is_finite() {
            return Err(Error::InvalidKnots(format!(
                "the domain [{:e}, {:e}] is longer than double precision can represent",
                knots[degree], knots[n]
            )));
        }
        if knots[degree] >= knots[n] {
            return Err(Error::InvalidKnots(format!(
                "the domain [{}, {}] has zero length",
                knots[degree], knots[n]
            )));
        }
        Ok(())
    }

    /// Spans ξ_i < ξ_{i+1}, p ≤ i < n, all non-empty and of equal length to 1e-9.
    fn has_uniform_spans(knots: &[f64], p: usize, n: usize) -> bool {
        let h = (knots[n] - knots[p]) / (n - p) as f64;
        (p..n).all(|i| ((knots[i + 1] - knots[i]) - h).abs() <= 1e-9 * h)
    }

    /// The open uniform knot vector on [a, b] with `spans` knot spans and degree
    /// p: a and b repeated p+1 times, interior knots a + kα with α = (b−a)/spans.
    ///
    /// Thesis §6.2 writes it for p = 2 as {0,0,0,α,…,(n−3)α,L,L,L}.
    pub fn open_uniform(a: f64, b: f64, spans: usize, degree: usize) -> Result<Self> {
        finite("left end a", a)?;
        finite("right end b", b)?;
        if b <= a {
            return Err(Error::InvalidKnots(format!(
                "the domain [{a}, {b}] has zero or negative length"
            )));
        }
        if spans == 0 {
            return Err(Error::InvalidArgument(
                "an open uniform knot vector needs at least one span".into(),
            ));
        }
        let count = degree
            .checked_mul(2)
            .and_then(|d| d.checked_add(spans))
            .and_then(|c| c.checked_add(1))
            .ok_or_else(|| {
                Error::InvalidArgument(format!(
                    "{spans} spans of degree {degree} need more knots than can be counted"
                ))
            })?;
        let mut knots = Vec::new();
        knots.try_reserve_exact(count).map_err(|_| {
            Error::InvalidArgument(format!(
                "{count} knots ({spans} spans of degree {degree}) do not fit in memory"
            ))
        })?;
        knots.extend(std::iter::repeat_n(a, degree + 1));
        let alpha = (b - a) / spans as f64;
        for k in 1..spans {
            knots.push(a + k as f64 * alpha);
        }
        knots.extend(std::iter::repeat_n(b, degree + 1));
        Self::new(knots, degree)
    }

    /// The knots ξ_1 … ξ_{n+p+1} (stored 0-based).
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// The polynomial degree p.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The number of basis functions n = (number of knots) − p − 1.
    pub fn num_basis(&self) -> usize {
        self.knots.len() - self.degree - 1
    }

    /// The domain [ξ_{p+1}, ξ_{n+1}] (1-based) on which the basis is a partition of unity.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.num_basis()])
    }

    /// The non-empty knot spans inside the domain, as (left, right) pairs.
    pub fn spans(&self) -> Vec<(f64, f64)> {
        (self.degree..self.num_basis())
            .filter(|&i| self.knots[i] < self.knots[i + 1])
            .map(|i| (self.knots[i], self.knots[i + 1]))
            .collect()
    }

    /// 0-based index of the last non-empty span inside the domain.
    pub(crate) fn last_span(&self) -> usize {
        (self.degree..self.num_basis())
            .rev()
            .find(|&i| self.knots[i] < self.knots[i + 1])
            .expect("validated knot vectors have a non-empty domain")
    }

    /// Checks that `x` is finite and inside the domain. Inlined: the 2D
    /// step calls it twice per particle through [`Self::find_span`], and
    /// LLVM stopped inlining it on its own once `spline::natural` called it
    /// too (+4 % instructions per particle-step, callgrind).
    #[inline]
    pub fn check_point(&self, x: f64) -> Result<f64> {
        finite("evaluation point", x)?;
        let (a, b) = self.domain();
        if x < a || x > b {
            return Err(Error::OutsideDomain { x, a, b });
        }
        Ok(x)
    }

    /// The 0-based index i of the span with ξ_i ≤ x < ξ_{i+1}, p ≤ i < n. The
    /// right end of the domain belongs to the last non-empty span.
    ///
    /// Inlined for the steps' hot path: a point of a uniform knot vector
    /// strictly inside [a, b) (so finite) takes the O(1) guess here, in
    /// registers; every other point (`find_span_checked`) is checked
    /// and searched out of line. The same span either way (issue #39: the
    /// out-of-line call cost about 80 instructions, twice per particle of
    /// the 2D step).
    #[inline(always)]
    pub fn find_span(&self, x: f64) -> Result<usize> {
        if self.uniform {
            let (p, n) = (self.degree, self.num_basis());
            let t = &self.knots[..];
            let a = t[p];
            if x >= a && x < t[n] {
                return Ok(Self::correct_guess(
                    t,
                    p,
                    n,
                    x,
                    (x - a) * self.spans_per_length,
                ));
            }
        }
        self.find_span_checked(x)
    }

    /// The uniform knots' span of x from the guess p + ⌊q⌋, q ≥ 0, corrected
    /// against the knots (the guess is off by at most one span). ⌊q⌋ goes
    /// through u32, which saturates more cheaply than usize; any guess at or
    /// beyond the last span becomes the last span either way.
    #[inline(always)]
    fn correct_guess(t: &[f64], p: usize, n: usize, x: f64, q: f64) -> usize {
        let mut i = (p + q as u32 as usize).min(n - 1);
        while i + 1 < n && t[i + 1] <= x {
            i += 1;
        }
        while i > p && t[i] > x {
            i -= 1;
        }
        i
    }

    /// [`Self::find_span`] for any point: refuses a point that is not
    /// finite or lies outside the domain, gives the right end to the last
    /// non-empty span, and searches non-uniform knots by bisection.
    #[inline(never)]
    fn find_span_checked(&self, x: f64) -> Result<usize> {
        self.check_point(x)?;
        let (_, b) = self.domain();
        if x == b {
            return Ok(self.last_span());
        }
        let (p, n) = (self.degree, self.num_basis());
        if self.uniform {
            let q = (x - self.knots[p]) * self.spans_per_length;
            return Ok(Self::correct_guess(&self.knots, p, n, x, q));
        }
        // Binary search on [p, n): the largest i with knots[i] <= x.
        let (mut lo, mut hi) = (p, n);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if self.knots[mid] <= x {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Ok(lo)
    }

    /// The distinct knots inside the domain with their multiplicities.
    pub fn breakpoints(&self) -> Vec<(f64, usize)> {
        let (a, b) = self.domain();
        let mut out: Vec<(f64, usize)> = Vec::new();
        for &k in &self.knots {
            if k < a || k > b {
                continue;
            }
            match out.last_mut() {
                Some((v, m)) if *v == k => *m += 1,
                _ => out.push((k, 1)),
            }
        }
        out
    }
}
