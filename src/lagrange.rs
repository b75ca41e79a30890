//! # Lagrange basis functions (P1 and P2)
//!
//! The classical MPM basis: piecewise-linear hat functions on `elements`
//! equal elements of [a, b] (thesis §5.1, TLS paper §3.2), and piecewise
//! quadratic functions with a mid-node per element (thesis §5.2).
//!
//! On the reference element ξ ∈ [0, 1] (thesis §5.1, T_{e_k}(ξ) = x_k + hξ):
//! - P1: N̂_1 = 1 − ξ, N̂_2 = ξ;
//! - P2: N̂_1 = 2ξ² − 3ξ + 1, N̂_2 = −4ξ² + 4ξ, N̂_3 = 2ξ² − ξ.
//!
//! The P2 end-node functions take negative values inside the element (minimum
//! −1/8 at ξ = 1/4 and 3/4), which is what makes lumped P2 masses negative
//! (thesis §5.2). Elements are half-open [x_k, x_{k+1}); the right end of the
//! domain belongs to the last element, as for knot spans.
//!
//! Items: [`LagrangeOrder`], [`reference_shape_functions`],
//! [`reference_shape_gradients`], [`LagrangeBasis`].

use crate::basis::{Basis1d, LocalBasis};
use crate::error::{finite, Error, Result};

/// Polynomial order of a Lagrange element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LagrangeOrder {
    /// Linear (P1), two nodes per element.
    Linear,
    /// Quadratic (P2), three nodes per element.
    Quadratic,
}

impl LagrangeOrder {
    /// The polynomial degree, 1 or 2.
    pub fn degree(self) -> usize {
        match self {
            LagrangeOrder::Linear => 1,
            LagrangeOrder::Quadratic => 2,
        }
    }
}

/// Reference shape functions N̂_i(ξ) on [0, 1], thesis §5.1 and §5.2.
pub fn reference_shape_functions(order: LagrangeOrder, xi: f64) -> Vec<f64> {
    match order {
        LagrangeOrder::Linear => vec![1.0 - xi, xi],
        LagrangeOrder::Quadratic => vec![
            2.0 * xi * xi - 3.0 * xi + 1.0,
            -4.0 * xi * xi + 4.0 * xi,
            2.0 * xi * xi - xi,
        ],
    }
}

/// Reference shape-function derivatives dN̂_i/dξ on [0, 1].
pub fn reference_shape_gradients(order: LagrangeOrder, xi: f64) -> Vec<f64> {
    match order {
        LagrangeOrder::Linear => vec![-1.0, 1.0],
        LagrangeOrder::Quadratic => vec![4.0 * xi - 3.0, -8.0 * xi + 4.0, 4.0 * xi - 1.0],
    }
}

/// A uniform mesh of P1 or P2 Lagrange elements on [a, b].
#[derive(Debug, Clone, PartialEq)]
pub struct LagrangeBasis {
    a: f64,
    b: f64,
    elements: usize,
    order: LagrangeOrder,
    /// h = (b − a)/elements and 1/h, computed once (the MPM step evaluates
    /// the basis at every particle in every step).
    h: f64,
    inverse_h: f64,
}

impl LagrangeBasis {
    /// `elements` equal elements of size h = (b − a)/elements (thesis §5.1).
    pub fn new(a: f64, b: f64, elements: usize, order: LagrangeOrder) -> Result<Self> {
        finite("left end a", a)?;
        finite("right end b", b)?;
        if b <= a {
            return Err(Error::NotPositive {
                what: format!("the length of the domain [{a}, {b}]"),
                value: b - a,
            });
        }
        if elements == 0 {
            return Err(Error::InvalidArgument(
                "a Lagrange mesh needs at least one element".into(),
            ));
        }
        let h = (b - a) / elements as f64;
        if !h.is_finite() || h < f64::MIN_POSITIVE {
            return Err(Error::InvalidArgument(format!(
                "{elements} elements on [{a:e}, {b:e}] have size {h:e}, which double precision cannot divide by"
            )));
        }
        Ok(Self {
            a,
            b,
            elements,
            order,
            h,
            inverse_h: 1.0 / h,
        })
    }

    /// The element order.
    pub fn order(&self) -> LagrangeOrder {
        self.order
    }

    /// Number of elements.
    pub fn elements(&self) -> usize {
        self.elements
    }

    /// Element size h.
    pub fn element_size(&self) -> f64 {
        self.h
    }

    /// Node positions: element ends, and for P2 also element mid-points.
    /// The last node is b itself (a + n·step can round past b).
    pub fn nodes(&self) -> Vec<f64> {
        let d = self.order.degree();
        let n = d * self.elements + 1;
        let step = self.element_size() / d as f64;
        (0..n)
            .map(|k| {
                if k + 1 == n {
                    self.b
                } else {
                    self.a + k as f64 * step
                }
            })
            .collect()
    }

    /// ξ = (x − x_k)/h of x in element k (thesis §5.1, the inverse of
    /// T: [0, 1] → [x_k, x_{k+1}]), clamped to [0, 1] against rounding.
    /// x_k = a + k h, with k converted through i64 (one instruction; the
    /// same value for every k below 2⁵³).
    #[inline(always)]
    fn local_coordinate(&self, x: f64, k: usize, h: f64) -> f64 {
        ((x - (self.a + k as i64 as f64 * h)) / h).clamp(0.0, 1.0)
    }

    /// The element k with x_k ≤ x < x_{k+1}; the right end belongs to the last.
    #[inline]
    pub fn element_of(&self, x: f64) -> Result<usize> {
        // One test on the way every point takes: a ≤ x ≤ b is false for a
        // NaN too; the reason is sorted out only for a point that fails.
        if !(x >= self.a && x <= self.b) {
            finite("evaluation point", x)?;
            return Err(Error::OutsideDomain {
                x,
                a: self.a,
                b: self.b,
            });
        }
        Ok(self.element_index(x))
    }

    /// [`LagrangeBasis::element_of`] for an x in [a, b] (not checked).
    /// x ≥ a, so truncation is the floor (and needs no libm call). The
    /// quotient is at most about the number of elements, so it converts
    /// through i64, one instruction, where a conversion to usize takes a
    /// dozen for the quotients of 2⁶³ and more that cannot occur (the same
    /// k; issue #39).
    #[inline(always)]
    fn element_index(&self, x: f64) -> usize {
        let k = ((x - self.a) / self.h) as i64 as usize;
        k.min(self.elements - 1)
    }
}

impl LagrangeBasis {
    /// The `degree + 1` shape functions of the element containing x and
    /// their gradients, written into the given slices (no allocation); the
    /// same numbers as [`Basis1d::local`] with order 1. Returns the global
    /// index of the first function. Thesis §5.1–5.2: N_i(x) = N̂_i(T⁻¹(x)),
    /// ∇N_i = N̂_i'(ξ)/h.
    #[inline]
    pub fn evaluate_into(
        &self,
        x: f64,
        values: &mut [f64],
        gradients: &mut [f64],
    ) -> Result<usize> {
        let k = self.element_of(x)?;
        let h = self.h;
        let xi = self.local_coordinate(x, k, h);
        match self.order {
            LagrangeOrder::Linear => {
                // −1/h = −(1/h) exactly: the same numbers as N̂'/h.
                values[..2].copy_from_slice(&[1.0 - xi, xi]);
                gradients[..2].copy_from_slice(&[-self.inverse_h, self.inverse_h]);
            }
            LagrangeOrder::Quadratic => {
                values[..3].copy_from_slice(&[
                    2.0 * xi * xi - 3.0 * xi + 1.0,
                    -4.0 * xi * xi + 4.0 * xi,
                    2.0 * xi * xi - xi,
                ]);
                gradients[..3].copy_from_slice(&[
                    (4.0 * xi - 3.0) / h,
                    (-8.0 * xi + 4.0) / h,
                    (4.0 * xi - 1.0) / h,
                ]);
            }
        }
        Ok(self.order.degree() * k)
    }
}

impl LagrangeBasis {
    /// [`LagrangeBasis::evaluate_into`] with the stencil width W = degree + 1
    /// known at compile time, for the step's batch fill
    /// (`mpm::grid::Grid::fill_stencils`): the same operations in the same
    /// order, so the same numbers bit for bit, without the width's slicing
    /// and the order's branch per point. `None` if W is not this basis'
    /// width (the caller then takes [`LagrangeBasis::evaluate_into`]).
    #[inline(always)]
    pub fn evaluate_fixed<const W: usize>(
        &self,
        x: f64,
        values: &mut [f64; W],
        gradients: &mut [f64; W],
    ) -> Option<Result<usize>> {
        if W != self.order.degree() + 1 {
            return None;
        }
        Some(self.evaluate_of_width::<W>(x, values, gradients))
    }

    /// [`LagrangeBasis::evaluate_fixed`] for a `W` the caller has checked
    /// is the basis' width (degree + 1): no check per point.
    #[inline(always)]
    pub fn evaluate_of_width<const W: usize>(
        &self,
        x: f64,
        values: &mut [f64; W],
        gradients: &mut [f64; W],
    ) -> Result<usize> {
        debug_assert_eq!(W, self.order.degree() + 1);
        let k = self.element_of(x)?;
        let h = self.h;
        let xi = self.local_coordinate(x, k, h);
        if W == 2 {
            values[0] = 1.0 - xi;
            values[1] = xi;
            gradients[0] = -self.inverse_h;
            gradients[1] = self.inverse_h;
        } else {
            values[0] = 2.0 * xi * xi - 3.0 * xi + 1.0;
            values[1] = -4.0 * xi * xi + 4.0 * xi;
            values[2] = 2.0 * xi * xi - xi;
            gradients[0] = (4.0 * xi - 3.0) / h;
            gradients[1] = (-8.0 * xi + 4.0) / h;
            gradients[2] = (4.0 * xi - 1.0) / h;
        }
        Ok((W - 1) * k)
    }

    /// [`LagrangeBasis::evaluate_of_width`] at the two coordinates of a 2D
    /// point (bilinear MPM's two axes, MLS paper Eqs. 4–5), the x axis
    /// into `values[0]`, `gradients[0]` and y into `[1]`. For P1 (W = 2)
    /// the two axes' operations sit side by side in the two lanes of SSE2
    /// registers (one packed division for both quotients (x − a)/h and one
    /// for both ξ, where two scalar divisions each were), so each lane
    /// computes what [`LagrangeBasis::evaluate_of_width`] computes, bit for
    /// bit. A coordinate outside [a, b] and the other widths take the
    /// point-by-point path, which names the point.
    #[inline(always)]
    pub fn evaluate_pair_of_width<const W: usize>(
        &self,
        x: [f64; 2],
        values: &mut [[f64; W]; 2],
        gradients: &mut [[f64; W]; 2],
    ) -> Result<[usize; 2]> {
        let inside = |x: f64| x >= self.a && x <= self.b;
        if W != 2 || !(inside(x[0]) && inside(x[1])) {
            let first_x = self.evaluate_of_width::<W>(x[0], &mut values[0], &mut gradients[0])?;
            let first_y = self.evaluate_of_width::<W>(x[1], &mut values[1], &mut gradients[1])?;
            return Ok([first_x, first_y]);
        }
        // The same functions per coordinate; the compiler pairs their lanes.
        let k = x.map(|x| self.element_index(x));
        let xi = [0, 1].map(|axis| self.local_coordinate(x[axis], k[axis], self.h));
        for axis in 0..2 {
            values[axis][0] = 1.0 - xi[axis];
            values[axis][1] = xi[axis];
            gradients[axis][0] = -self.inverse_h;
            gradients[axis][1] = self.inverse_h;
        }
        Ok(k)
    }
}

impl Basis1d for LagrangeBasis {
    fn num_basis(&self) -> usize {
        self.order.degree() * self.elements + 1
    }
    fn degree(&self) -> usize {
        self.order.degree()
    }
    fn domain(&self) -> (f64, f64) {
        (self.a, self.b)
    }
    /// Values via N_i(x) = N̂_i(T⁻¹(x)); derivatives via the chain rule, 1/h.
    /// Derivatives of order ≥ 2 are returned as zero for P1 and as the constant
    /// second derivative for P2.
    fn local(&self, x: f64, order: usize) -> Result<LocalBasis> {
        let k = self.element_of(x)?;
        let h = self.element_size();
        let xi = self.local_coordinate(x, k, h);
        let deg = self.order.degree();
        let mut derivatives = vec![reference_shape_functions(self.order, xi)];
        if order >= 1 {
            derivatives.push(
                reference_shape_gradients(self.order, xi)
                    .into_iter()
                    .map(|g| g / h)
                    .collect(),
            );
        }
        for m in 2..=order {
            let row = match (self.order, m) {
                (LagrangeOrder::Quadratic, 2) => vec![4.0, -8.0, 4.0]
                    .into_iter()
                    .map(|g| g / (h * h))
                    .collect(),
                _ => vec![0.0; deg + 1],
            };
            derivatives.push(row);
        }
        Ok(LocalBasis {
            first: deg * k,
            derivatives,
        })
    }
    /// Every interior element boundary (P1 and P2 gradients jump there).
    fn gradient_breaks(&self) -> Vec<f64> {
        let h = self.element_size();
        (1..self.elements).map(|k| self.a + k as f64 * h).collect()
    }
    fn cells(&self) -> Vec<(f64, f64)> {
        let h = self.element_size();
        (0..self.elements)
            .map(|k| (self.a + k as f64 * h, self.a + (k + 1) as f64 * h))
            .collect()
    }
}
