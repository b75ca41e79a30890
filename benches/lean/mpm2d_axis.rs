//! # The basis of the lean 2D step (benches/lean/mpm2d.rs), x and y in
//! paired lanes
//!
//! MLS paper Eqs. (4)–(5) need two 1D stencils per particle, one along x
//! and one along y. This module evaluates both at once, each operation on a
//! pair [along x, along y] (`Pair`), so that LLVM can issue one SSE2
//! instruction for two, with the same bits as hompm's one at a time:
//! - `OpenBSplines`: the Cox–de Boor triangle of
//!   `KnotVector::values_and_gradients_fixed` (NURBS Book A2.2; book
//!   Eqs. 4.19–4.20, the derivative of Eq. 4.23 with 1/ndu[p][r] formed
//!   once) on the span `KnotVector::find_span` finds;
//! - `BilinearAxis`: `LagrangeBasis::evaluate_fixed` for P1.
//!
//! Items: `Pair`, `Axis`, `OpenBSplines`, `BilinearAxis` and the pair
//! arithmetic `add`, `sub`, `mul`, `div`, `splat`.

use hompm::mpm2d::step::Simulation2d;
use hompm::mpm2d::Basis2d;
use hompm::spline::KnotVector;

/// Two numbers computed side by side by the same operation (the x and y
/// lanes of the basis, the two components of a vector): the same bits as
/// one at a time, in one SSE2 instruction where LLVM pairs them.
pub type Pair = [f64; 2];

/// a + b, lane by lane.
#[inline(always)]
pub fn add(a: Pair, b: Pair) -> Pair {
    [a[0] + b[0], a[1] + b[1]]
}

/// a − b, lane by lane.
#[inline(always)]
pub fn sub(a: Pair, b: Pair) -> Pair {
    [a[0] - b[0], a[1] - b[1]]
}

/// a · b, lane by lane.
#[inline(always)]
pub fn mul(a: Pair, b: Pair) -> Pair {
    [a[0] * b[0], a[1] * b[1]]
}

/// a / b, lane by lane.
#[inline(always)]
pub fn div(a: Pair, b: Pair) -> Pair {
    [a[0] / b[0], a[1] / b[1]]
}

/// [a, a].
#[inline(always)]
pub fn splat(a: f64) -> Pair {
    [a, a]
}

/// The basis of the grid's two (equal) axes, W functions wide.
pub trait Axis<const W: usize>: Sized {
    /// The axis of a simulation's grid; panics unless the grid has this basis.
    fn of(sim: &Simulation2d) -> Self;
    /// At the point (x, y): the first function along each axis and the W
    /// values and W gradients, each a pair [along x at x, along y at y].
    fn evaluate(&self, x: Pair) -> ([usize; 2], [Pair; W], [Pair; W]);
}

/// Open-uniform B-splines of degree W − 1 on [0, L].
pub struct OpenBSplines {
    knots: Vec<f64>,
    functions: usize,
    spans_per_length: f64,
}

impl OpenBSplines {
    /// The span i with ξ_i ≤ x < ξ_{i+1} (the last one at x = L), as
    /// `KnotVector::find_span` finds it: a guess from the spacing, corrected.
    #[inline(always)]
    fn span(&self, x: f64, p: usize) -> usize {
        let (t, n) = (&self.knots[..], self.functions);
        // A guess below 2³² saturates as cheaply as u32 allows; the loops
        // below correct any guess.
        let guess = ((x - t[p]) * self.spans_per_length) as u32 as usize;
        let mut span = (p + guess).min(n - 1);
        while span + 1 < n && t[span + 1] <= x {
            span += 1;
        }
        while span > p && t[span] > x {
            span -= 1;
        }
        span
    }
}

impl<const W: usize> Axis<W> for OpenBSplines {
    fn of(sim: &Simulation2d) -> Self {
        let grid = &sim.grid;
        assert_eq!(grid.basis(), Basis2d::BSpline { degree: W - 1 });
        let (cells, length) = (grid.cells_per_side(), grid.length());
        let kv = KnotVector::open_uniform(0.0, length, cells, W - 1).expect("knots");
        assert_eq!(kv.spans(), grid.axis().cells(), "the grid's knots");
        Self {
            knots: kv.knots().to_vec(),
            functions: kv.num_basis(),
            spans_per_length: cells as f64 / length,
        }
    }

    /// The triangle of `KnotVector::values_and_gradients_fixed`, x and y
    /// in paired lanes.
    #[inline(always)]
    fn evaluate(&self, x: Pair) -> ([usize; 2], [Pair; W], [Pair; W]) {
        let p = W - 1;
        let span = [self.span(x[0], p), self.span(x[1], p)];
        let t = &self.knots[..];
        let mut ndu = [[[0.0; 2]; W]; W];
        let (mut left, mut right) = ([[0.0; 2]; W], [[0.0; 2]; W]);
        ndu[0][0] = [1.0; 2];
        for j in 1..=p {
            left[j] = sub(x, [t[span[0] + 1 - j], t[span[1] + 1 - j]]);
            right[j] = sub([t[span[0] + j], t[span[1] + j]], x);
            let mut saved = [0.0; 2];
            for r in 0..j {
                ndu[j][r] = add(right[r + 1], left[j - r]);
                let temp = div(ndu[r][j - 1], ndu[j][r]);
                ndu[r][j] = add(saved, mul(right[r + 1], temp));
                saved = mul(left[j - r], temp);
            }
            ndu[j][j] = saved;
        }
        let mut values = [[0.0; 2]; W];
        for r in 0..W {
            values[r] = ndu[r][p];
        }
        let mut inverse = [[0.0; 2]; W];
        for r in 0..p {
            inverse[r] = div([1.0; 2], ndu[p][r]);
        }
        let mut gradients = [[0.0; 2]; W];
        for r in 0..W {
            let mut d = [0.0; 2];
            if r >= 1 {
                d = mul(inverse[r - 1], ndu[r - 1][p - 1]);
            }
            if r < p {
                d = add(d, mul(inverse[r].map(|v| -v), ndu[r][p - 1]));
            }
            gradients[r] = mul(d, splat(p as f64));
        }
        (span.map(|s| s - p), values, gradients)
    }
}

/// P1 Lagrange elements on [0, L].
pub struct BilinearAxis {
    h: f64,
    inverse_h: f64,
    last: usize,
}

impl Axis<2> for BilinearAxis {
    fn of(sim: &Simulation2d) -> Self {
        let grid = &sim.grid;
        assert_eq!(grid.basis(), Basis2d::Bilinear);
        assert_eq!(grid.axis().domain(), (0.0, grid.length()));
        let h = grid.length() / grid.cells_per_side() as f64;
        Self {
            h,
            inverse_h: 1.0 / h,
            last: grid.cells_per_side() - 1,
        }
    }

    /// `LagrangeBasis::evaluate_fixed` with a = 0 (x − 0 = x and 0 + kh = kh
    /// exactly), x and y in paired lanes.
    #[inline(always)]
    fn evaluate(&self, x: Pair) -> ([usize; 2], [Pair; 2], [Pair; 2]) {
        let h = splat(self.h);
        // Through i64 as `LagrangeBasis` converts (one instruction each way);
        // a negative quotient still gives element 0.
        let k = div(x, h).map(|q| ((q as i64).max(0) as usize).min(self.last));
        let start = [k[0] as i64 as f64 * self.h, k[1] as i64 as f64 * self.h];
        let xi = div(sub(x, start), h).map(|v| v.clamp(0.0, 1.0));
        let gradients = [splat(-self.inverse_h), splat(self.inverse_h)];
        (k, [sub([1.0; 2], xi), xi], gradients)
    }
}
