//! # Tensor-product B-splines in 2D
//!
//! MLS paper Eq. (4): N_{(i,j),(p,q)}(ξ, η) = N_{i,p}(ξ) N_{j,q}(η), and
//! Eq. (5): ∇N = (N'_{i,p}(ξ) N_{j,q}(η), N_{i,p}(ξ) N'_{j,q}(η)).
//!
//! Global numbering: function (i, j) has index `i + n_x · j` (x runs fastest),
//! which matches the Kronecker ordering M_2D = M_y ⊗ M_x used in `mass`.
//!
//! Items: [`TensorBasis2d`], [`TensorLocalBasis`].

use crate::error::Result;
use crate::spline::knots::KnotVector;

/// The tensor product of two univariate B-spline bases.
#[derive(Debug, Clone, PartialEq)]
pub struct TensorBasis2d {
    /// Basis in the x (ξ) direction.
    pub x: KnotVector,
    /// Basis in the y (η) direction.
    pub y: KnotVector,
}

/// The (p+1)(q+1) non-zero 2D functions at one point, with their gradients.
#[derive(Debug, Clone, PartialEq)]
pub struct TensorLocalBasis {
    /// Global indices `i + n_x · j` of the non-zero functions.
    pub indices: Vec<usize>,
    /// N_{(i,j)}(x, y), MLS paper Eq. (4).
    pub values: Vec<f64>,
    /// ∇N_{(i,j)}(x, y) = [∂/∂x, ∂/∂y], MLS paper Eq. (5).
    pub gradients: Vec<[f64; 2]>,
}

impl TensorBasis2d {
    /// Pairs two knot vectors.
    pub fn new(x: KnotVector, y: KnotVector) -> Self {
        Self { x, y }
    }

    /// Number of 2D functions n_x · n_y.
    pub fn num_basis(&self) -> usize {
        self.x.num_basis() * self.y.num_basis()
    }

    /// Values and gradients of the non-zero functions at (x, y), MLS paper Eqs. (4)–(5).
    pub fn local_basis(&self, x: f64, y: f64) -> Result<TensorLocalBasis> {
        let bx = self.x.local_basis(x, 1)?;
        let by = self.y.local_basis(y, 1)?;
        let nx = self.x.num_basis();
        let mut out = TensorLocalBasis {
            indices: Vec::new(),
            values: Vec::new(),
            gradients: Vec::new(),
        };
        for (b, (&ny_val, &ny_der)) in by.values().iter().zip(by.gradients()).enumerate() {
            for (a, (&nx_val, &nx_der)) in bx.values().iter().zip(bx.gradients()).enumerate() {
                out.indices.push((bx.first + a) + nx * (by.first + b));
                out.values.push(nx_val * ny_val);
                out.gradients.push([nx_der * ny_val, nx_val * ny_der]);
            }
        }
        Ok(out)
    }
}
