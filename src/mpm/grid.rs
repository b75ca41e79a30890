//! # The background grid and its basis
//!
//! The MPM variants of the seeds differ in the basis of the background grid:
//!
//! | method | basis | gradient | seed |
//! |---|---|---|---|
//! | `mpm` | P1 Lagrange | ∇φ_i | thesis §5.1, TLS paper §3.2 |
//! | `mpm-p2` | P2 Lagrange | ∇φ_i | thesis §5.2 |
//! | `ddmpm` | P1 Lagrange | ∇̄φ_i = α∇φ_i + (1−α)∇̃φ_i | TLS paper §3.3 |
//! | `bsmpm` | B-splines, degree p, open uniform knots | ∇φ_i | book §4.3, thesis §6.2 |
//!
//! DDMPM (TLS paper §3.3): ∇̃φ_i(x) = Σ_j φ_j(x)/V_j ∫_Ω φ_j ∇φ_i dΩ with
//! V_j = ∫_Ω φ_j dΩ, blended by α(x) = 2 Σ_i φ_i(x) φ_{i+1}(x), which vanishes
//! on the element boundaries. The integrals are taken over the (fixed) grid
//! domain Ω, exactly by two Gauss points per element (docs/conventions.md).

use crate::basis::Basis1d;
use crate::error::{Error, Result};
use crate::lagrange::{LagrangeBasis, LagrangeOrder};
use crate::quadrature::GaussLegendre;
use crate::spline::KnotVector;
use serde::Serialize;

/// The MPM variant, i.e. the basis of the background grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Standard MPM with P1 Lagrange functions.
    Mpm,
    /// MPM with P2 Lagrange functions (unstable: negative masses).
    MpmP2,
    /// Dual-domain MPM.
    Ddmpm,
    /// B-spline MPM of the given degree.
    Bsmpm {
        /// Polynomial degree p ≥ 1.
        degree: usize,
    },
}

impl Method {
    /// Parses `mpm`, `mpm-p2`, `ddmpm` or `bsmpm` (with the degree).
    pub fn parse(name: &str, degree: usize) -> Result<Self> {
        match name {
            "mpm" => Ok(Method::Mpm),
            "mpm-p2" => Ok(Method::MpmP2),
            "ddmpm" => Ok(Method::Ddmpm),
            "bsmpm" if degree >= 1 => Ok(Method::Bsmpm { degree }),
            "bsmpm" => Err(Error::InvalidDegree("bsmpm needs --degree ≥ 1".into())),
            other => Err(Error::InvalidArgument(format!(
                "method must be mpm, mpm-p2, ddmpm or bsmpm, got '{other}'"
            ))),
        }
    }

    /// A short label for charts and tables.
    pub fn label(&self) -> String {
        match self {
            Method::Mpm => "MPM".into(),
            Method::MpmP2 => "MPM-P2".into(),
            Method::Ddmpm => "DDMPM".into(),
            Method::Bsmpm { degree } => format!("BSMPM-p{degree}"),
        }
    }
}

/// Values and (possibly modified) gradients of the basis at one point, over
/// the index range `first .. first + values.len()`.
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    /// First global index.
    pub first: usize,
    /// φ_i(x).
    pub values: Vec<f64>,
    /// ∇φ_i(x), or ∇̄φ_i(x) for DDMPM.
    pub gradients: Vec<f64>,
}

#[derive(Debug, Clone)]
struct DualDomain {
    /// V_j = ∫ φ_j.
    node_volume: Vec<f64>,
    /// g[j] = [∫ φ_j ∇φ_{j−1}, ∫ φ_j ∇φ_j, ∫ φ_j ∇φ_{j+1}].
    g: Vec<[f64; 3]>,
}

/// The background grid.
pub struct Grid {
    method: Method,
    basis: Box<dyn Basis1d + Send + Sync>,
    dual: Option<DualDomain>,
    cells: usize,
}

impl std::fmt::Debug for Grid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "Grid({:?}, {} cells on {:?})",
            self.method,
            self.cells,
            self.basis.domain()
        )
    }
}

impl Grid {
    /// A grid of `cells` equal elements (or knot spans) on [a, b].
    pub fn new(method: Method, a: f64, b: f64, cells: usize) -> Result<Self> {
        let basis: Box<dyn Basis1d + Send + Sync> = match method {
            Method::Mpm | Method::Ddmpm => {
                Box::new(LagrangeBasis::new(a, b, cells, LagrangeOrder::Linear)?)
            }
            Method::MpmP2 => Box::new(LagrangeBasis::new(a, b, cells, LagrangeOrder::Quadratic)?),
            Method::Bsmpm { degree } => Box::new(KnotVector::open_uniform(a, b, cells, degree)?),
        };
        let dual = if method == Method::Ddmpm {
            let n = basis.num_basis();
            let mut node_volume = vec![0.0; n];
            let mut g = vec![[0.0; 3]; n];
            let rule = GaussLegendre::new(2)?;
            for (c0, c1) in basis.cells() {
                for q in rule.on_interval(c0, c1) {
                    let loc = basis.local(q.x, 1)?;
                    for (a_, &phi_j) in loc.values().iter().enumerate() {
                        let j = loc.first + a_;
                        node_volume[j] += q.weight * phi_j;
                        for (b_, &grad_i) in loc.gradients().iter().enumerate() {
                            let i = loc.first + b_;
                            let slot = (i as isize - j as isize + 1) as usize;
                            g[j][slot] += q.weight * phi_j * grad_i;
                        }
                    }
                }
            }
            Some(DualDomain { node_volume, g })
        } else {
            None
        };
        Ok(Self {
            method,
            basis,
            dual,
            cells,
        })
    }

    /// The method.
    pub fn method(&self) -> Method {
        self.method
    }

    /// Number of degrees of freedom.
    pub fn num_dofs(&self) -> usize {
        self.basis.num_basis()
    }

    /// Number of elements or knot spans.
    pub fn num_cells(&self) -> usize {
        self.cells
    }

    /// The domain [a, b].
    pub fn domain(&self) -> (f64, f64) {
        self.basis.domain()
    }

    /// Element (or knot-span) size h.
    pub fn cell_size(&self) -> f64 {
        let (a, b) = self.domain();
        (b - a) / self.cells as f64
    }

    /// The cells (elements or non-empty knot spans).
    pub fn cells(&self) -> Vec<(f64, f64)> {
        self.basis.cells()
    }

    /// Polynomial degree of the basis.
    pub fn degree(&self) -> usize {
        self.basis.degree()
    }

    /// Points where a basis gradient is discontinuous (grid crossings).
    pub fn gradient_breaks(&self) -> Vec<f64> {
        self.basis.gradient_breaks()
    }

    /// The underlying basis (values and exact derivatives).
    pub fn basis(&self) -> &(dyn Basis1d + Send + Sync) {
        self.basis.as_ref()
    }

    /// φ and the method's gradient at x (book Eqs. 4.5–4.6, TLS paper §3.3).
    pub fn shape(&self, x: f64) -> Result<Shape> {
        let loc = self.basis.local(x, 1)?;
        let Some(dd) = &self.dual else {
            return Ok(Shape {
                first: loc.first,
                values: loc.values().to_vec(),
                gradients: loc.gradients().to_vec(),
            });
        };
        // P1: the element's two functions j = k, k+1; ∇̃φ_i non-zero for i = k−1..k+2.
        let n = self.num_dofs();
        let k = loc.first;
        let first = k.saturating_sub(1);
        let last = (k + 2).min(n - 1);
        let len = last - first + 1;
        let mut values = vec![0.0; len];
        let mut grads = vec![0.0; len];
        let (phi_k, phi_k1) = (loc.values()[0], loc.values()[1]);
        let alpha = 2.0 * phi_k * phi_k1;
        values[k - first] = phi_k;
        values[k + 1 - first] = phi_k1;
        for (a_, &phi_j) in loc.values().iter().enumerate() {
            let j = k + a_;
            for (slot, gji) in dd.g[j].iter().enumerate() {
                let i = j as isize + slot as isize - 1;
                if i < first as isize || i > last as isize {
                    continue;
                }
                grads[i as usize - first] += (1.0 - alpha) * phi_j / dd.node_volume[j] * gji;
            }
        }
        for (a_, &gr) in loc.gradients().iter().enumerate() {
            grads[k + a_ - first] += alpha * gr;
        }
        Ok(Shape {
            first,
            values,
            gradients: grads,
        })
    }
}
