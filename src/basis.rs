//! # The common interface of one-dimensional bases
//!
//! hompm has two families of 1D bases: B-splines on a knot vector
//! (book §4.3, thesis §6.1) and Lagrange elements (thesis §5.1–5.2). Both have
//! compact support, so at a point only a few functions are non-zero. A
//! [`LocalBasis`] holds those few values and derivatives together with the
//! index of the first one; the [`Basis1d`] trait lets the mass matrices, the
//! reconstructions and the MPM step work with either family.
//!
//! [`Stencils`] holds such local values and gradients for many points at
//! once, flat (point k owns `width` consecutive entries), so that an MPM step
//! evaluates the basis at every particle without allocating, and scatters
//! particle quantities to the nodes (book Eqs. 4.5–4.6) and interpolates
//! nodal ones back (Eq. 4.9) in particle order. [`interpolate_row`] is
//! that interpolation for one point whose row a loop already holds, and
//! [`StencilSums`] keeps a scatter's nodal sums in registers while
//! consecutive particles share a stencil (the fused 1D step).

use crate::error::Result;

/// The non-zero basis functions (and derivatives) at one point.
///
/// `derivatives[k][j]` is the k-th derivative of basis function `first + j`;
/// `derivatives[0]` holds the values themselves.
#[derive(Debug, Clone, PartialEq)]
pub struct LocalBasis {
    /// Global index of the first non-zero function.
    pub first: usize,
    /// `derivatives[k][j]`: k-th derivative of function `first + j`.
    pub derivatives: Vec<Vec<f64>>,
}

impl LocalBasis {
    /// The values φ_{first+j}(x).
    pub fn values(&self) -> &[f64] {
        &self.derivatives[0]
    }

    /// The first derivatives φ'_{first+j}(x); zeros if they were not asked for.
    pub fn gradients(&self) -> &[f64] {
        self.derivatives.get(1).map(|d| d.as_slice()).unwrap_or(&[])
    }

    /// Scatters derivative order `k` into a dense vector of length `n`.
    pub fn dense(&self, k: usize, n: usize) -> Vec<f64> {
        let mut out = vec![0.0; n];
        if let Some(d) = self.derivatives.get(k) {
            for (j, v) in d.iter().enumerate() {
                out[self.first + j] = *v;
            }
        }
        out
    }
}

/// A one-dimensional basis with compact support on a bounded domain.
pub trait Basis1d {
    /// Number of basis functions (degrees of freedom).
    fn num_basis(&self) -> usize;
    /// Polynomial degree on each cell (so that p+1 Gauss points integrate
    /// φ_i φ_j exactly).
    fn degree(&self) -> usize;
    /// The closed domain [a, b] on which the functions form a partition of unity.
    fn domain(&self) -> (f64, f64);
    /// Values and derivatives up to `order` of the non-zero functions at `x`.
    /// Errors for a non-finite `x` or one outside [`Basis1d::domain`].
    fn local(&self, x: f64, order: usize) -> Result<LocalBasis>;
    /// The points where some basis-function derivative is discontinuous
    /// (element boundaries for P1/P2, knots of multiplicity p for B-splines),
    /// used to count grid crossings.
    fn gradient_breaks(&self) -> Vec<f64>;
    /// The integration cells: maximal intervals on which every function is a
    /// polynomial (elements or non-empty knot spans).
    fn cells(&self) -> Vec<(f64, f64)>;
}

/// Calls a function generic over `const W: usize` with the stencil width as
/// a compile-time constant for the widths of the seeds' bases (2, 3, 4; P1,
/// P2 and quadratic B-splines, cubic B-splines and DDMPM), so that the inner
/// loops over a stencil are unrolled; `W = 0` stands for any other width.
/// The arithmetic is the same in every case.
macro_rules! with_width {
    ($width:expr, $f:ident::<W>($($arg:expr),*)) => {
        match $width {
            2 => $f::<2>($($arg),*),
            3 => $f::<3>($($arg),*),
            4 => $f::<4>($($arg),*),
            _ => $f::<0>($($arg),*),
        }
    };
}
pub(crate) use with_width;

/// Σ_k w_k s_j(x_k) into out[first_k + j], point by point (the loop of
/// [`Stencils::scatter_values`] and [`Stencils::scatter_gradients`]);
/// `W` is the width, or 0 for `width`.
///
/// While consecutive points share a stencil (the particles of one cell), the
/// W sums are held in registers and stored when the stencil moves: every
/// entry of `out` still receives the same additions in the same order, so
/// the result is bit for bit that of adding into memory point by point, but
/// no addition waits for the previous one's store.
fn scatter<const W: usize>(
    first: &[usize],
    slots: &[f64],
    width: usize,
    weight: impl Fn(usize) -> f64,
    out: &mut [f64],
) {
    if W == 0 {
        for (k, &f) in first.iter().enumerate() {
            let wk = weight(k);
            for (o, &s) in out[f..f + width]
                .iter_mut()
                .zip(&slots[k * width..(k + 1) * width])
            {
                *o += wk * s;
            }
        }
        return;
    }
    let Some(&start) = first.first() else {
        return;
    };
    let mut current = start;
    let mut sums: [f64; W] = out[current..current + W].try_into().expect("W entries");
    for (k, &f) in first.iter().enumerate() {
        if f != current {
            out[current..current + W].copy_from_slice(&sums);
            current = f;
            sums = out[current..current + W].try_into().expect("W entries");
        }
        let wk = weight(k);
        for (o, &s) in sums.iter_mut().zip(&slots[k * W..(k + 1) * W]) {
            *o += wk * s;
        }
    }
    out[current..current + W].copy_from_slice(&sums);
}

/// The non-zero basis values and gradients at many points, stored flat.
///
/// Point k owns the `width` entries `values[k·width .. (k+1)·width]`, which
/// belong to the global functions `first[k] .. first[k] + width`; likewise
/// for `gradients`. One `Stencils` is allocated when a simulation starts and
/// refilled every step, so evaluating the basis at the particles allocates
/// nothing (no `Vec` per particle). Entries that a point does not need (the
/// padding of a dual-domain stencil near the boundary) are exact zeros.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Stencils {
    width: usize,
    /// Global index of the first function of each point's stencil.
    pub first: Vec<usize>,
    /// φ_{first+j}(x_k) at `k·width + j`.
    pub values: Vec<f64>,
    /// ∇φ_{first+j}(x_k) (or a modified gradient) at `k·width + j`.
    pub gradients: Vec<f64>,
}

impl Stencils {
    /// Room for `points` stencils of `width` functions each.
    pub fn new(width: usize, points: usize) -> Self {
        let mut s = Self {
            width,
            ..Self::default()
        };
        s.resize(points);
        s
    }

    /// Values and first derivatives of `basis` at every point of `xs`, one
    /// stencil of p+1 functions per point (through [`Basis1d::local`]; for
    /// specification functions and tests, not for a time step).
    pub fn evaluate(basis: &dyn Basis1d, xs: &[f64]) -> Result<Self> {
        let width = basis.degree() + 1;
        let mut s = Self::new(width, xs.len());
        for (k, &x) in xs.iter().enumerate() {
            let loc = basis.local(x, 1)?;
            s.first[k] = loc.first;
            let (v, g) = s.slots_mut(k);
            v.copy_from_slice(loc.values());
            g.copy_from_slice(loc.gradients());
        }
        Ok(s)
    }

    /// Number of functions per stencil.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.first.len()
    }

    /// True if there are no points.
    pub fn is_empty(&self) -> bool {
        self.first.is_empty()
    }

    /// Changes the number of points; allocates only when it grows beyond
    /// what was ever held.
    pub fn resize(&mut self, points: usize) {
        self.first.resize(points, 0);
        self.values.resize(points * self.width, 0.0);
        self.gradients.resize(points * self.width, 0.0);
    }

    /// The values of point k.
    pub fn values_of(&self, k: usize) -> &[f64] {
        &self.values[k * self.width..(k + 1) * self.width]
    }

    /// The gradients of point k.
    pub fn gradients_of(&self, k: usize) -> &[f64] {
        &self.gradients[k * self.width..(k + 1) * self.width]
    }

    /// Mutable values and gradients of point k.
    pub fn slots_mut(&mut self, k: usize) -> (&mut [f64], &mut [f64]) {
        let r = k * self.width..(k + 1) * self.width;
        (&mut self.values[r.clone()], &mut self.gradients[r])
    }

    /// Σ_k w_k φ_i(x_k) added into `out` in point order (book Eq. 4.5 with
    /// w_k = m_p; loads Σ_p m_p g φ_i and Σ_p f_p φ_i of thesis §3.2).
    pub fn scatter_values(&self, weight: impl Fn(usize) -> f64, out: &mut [f64]) {
        with_width!(
            self.width,
            scatter::<W>(&self.first, &self.values, self.width, weight, out)
        )
    }

    /// Σ_k w_k ∇φ_i(x_k) added into `out` in point order (book Eq. 4.6 with
    /// w_k = σ_p V_p).
    pub fn scatter_gradients(&self, weight: impl Fn(usize) -> f64, out: &mut [f64]) {
        with_width!(
            self.width,
            scatter::<W>(&self.first, &self.gradients, self.width, weight, out)
        )
    }

    /// Σ_i φ_i(x_k) a_i: a nodal field interpolated at point k (book Eq. 4.9).
    pub fn interpolate(&self, k: usize, nodal: &[f64]) -> f64 {
        let first = self.first[k];
        self.values_of(k)
            .iter()
            .zip(&nodal[first..first + self.width])
            .map(|(phi, a)| phi * a)
            .sum()
    }

    /// out_k += c · Σ_i φ_i(x_k) a_i for every point k (book Eq. 4.9 with
    /// c = Δt, a = the nodal acceleration).
    pub fn add_interpolated(&self, c: f64, nodal: &[f64], out: &mut [f64]) {
        with_width!(self.width, add_interpolated::<W>(self, c, nodal, out))
    }
}

/// The loop of [`Stencils::add_interpolated`]; `W` is the width, or 0.
fn add_interpolated<const W: usize>(s: &Stencils, c: f64, nodal: &[f64], out: &mut [f64]) {
    let w = if W == 0 { s.width } else { W };
    for (k, (o, &f)) in out.iter_mut().zip(&s.first).enumerate() {
        *o += c * interpolate_row(&s.values[k * w..k * w + w], &nodal[f..]);
    }
}

/// Σ_i φ_i a_i over one point's stencil `values` and the nodal field from
/// its first function on (book Eq. 4.9): the sum of [`Stencils::interpolate`]
/// and [`Stencils::add_interpolated`], in the same order, for a loop that
/// holds the row itself (the fused 1D step, `mpm::musl`).
#[inline(always)]
pub fn interpolate_row(values: &[f64], nodal_from_first: &[f64]) -> f64 {
    values
        .iter()
        .zip(nodal_from_first)
        .map(|(phi, a)| phi * a)
        .sum()
}

/// N nodal vectors' sums over a stencil of width `W`, kept in registers
/// while consecutive points share their first function (particles sorted
/// by cell do): [`StencilSums::move_to`] stores the sums back and loads the
/// next stencil's only when the first function changes. The additions are
/// the same, in the same order, as adding into the vectors directly, so
/// the sums are bit for bit those of [`Stencils::scatter_values`] (book
/// Eqs. 4.5–4.6, 4.10 in a fused particle loop).
#[derive(Debug, Clone, Copy)]
pub struct StencilSums<const W: usize, const N: usize> {
    first: Option<usize>,
    /// `sums[n][a]`: vector n's entry at the current stencil's function a.
    pub sums: [[f64; W]; N],
}

impl<const W: usize, const N: usize> Default for StencilSums<W, N> {
    fn default() -> Self {
        Self {
            first: None,
            sums: [[0.0; W]; N],
        }
    }
}

impl<const W: usize, const N: usize> StencilSums<W, N> {
    /// Makes the stencil starting at `first` current, storing the previous
    /// one's sums into `vectors` and loading this one's.
    #[inline(always)]
    pub fn move_to(&mut self, first: usize, vectors: &mut [&mut [f64]; N]) {
        let Some(current) = self.first else {
            return self.load(first, vectors);
        };
        if first == current {
            return;
        }
        if first == current + 1 && W > 1 {
            // The next cell's stencil (B-splines, P1): one sum leaves and
            // one enters; the W − 1 shared ones stay in registers. (Storing
            // the whole stencil and loading the next, which overlaps it,
            // would stall: a load that straddles a recent store is not
            // forwarded from it.)
            for (sums, v) in self.sums.iter_mut().zip(vectors.iter_mut()) {
                v[current] = sums[0];
                sums.copy_within(1.., 0);
                sums[W - 1] = v[first + W - 1];
            }
            self.first = Some(first);
            return;
        }
        self.store(vectors);
        self.load(first, vectors);
    }

    /// Loads the sums of the stencil starting at `first`.
    #[inline(always)]
    fn load(&mut self, first: usize, vectors: &[&mut [f64]; N]) {
        for (sums, v) in self.sums.iter_mut().zip(vectors.iter()) {
            sums.copy_from_slice(&v[first..first + W]);
        }
        self.first = Some(first);
    }

    /// Stores the current stencil's sums into `vectors`.
    pub fn store(&self, vectors: &mut [&mut [f64]; N]) {
        if let Some(f) = self.first {
            for (sums, v) in self.sums.iter().zip(vectors.iter_mut()) {
                v[f..f + W].copy_from_slice(sums);
            }
        }
    }
}
