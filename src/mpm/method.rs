//! # The MPM variants of the seeds by their basis
//!
//! Which basis and gradient a 1D run uses ([`Method`]: P1 and P2 Lagrange,
//! DDMPM's blended gradient with its node-integral rule [`NodeIntegrals`],
//! B-splines of degree p; the table in [`super::grid`]), and the
//! registrations of their families on the command line
//! ([`METHOD_FAMILIES`]). The grid that evaluates them is
//! [`super::grid::Grid`].
//!
//! Items: [`NodeIntegrals`], [`Method`], [`MethodFamily`], [`METHOD_FAMILIES`].

use crate::error::{Error, Result};
use serde::Serialize;

/// How DDMPM evaluates its node integrals V_j = ∫_Ω φ_j dΩ and
/// ∫_Ω φ_j ∇φ_i dΩ (TLS paper §3.3, which does not say; module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum NodeIntegrals {
    /// Exactly over the fixed grid domain Ω (two Gauss points per element),
    /// once per run.
    Exact,
    /// Particle quadrature: V_j ≈ Σ_p V_p φ_j(x_p) and
    /// ∫φ_j∇φ_i ≈ Σ_p V_p φ_j(x_p)∇φ_i(x_p), every step.
    Particles,
    /// n ≥ 1 subpoints per particle, at the midpoints of n equal parts of
    /// [x_p − V_p/2, x_p + V_p/2], weight V_p/n each, every step (Dhakal and
    /// Zhang 2016; TLS paper Table 8). One subpoint is `Particles`.
    Subpoints(usize),
    /// n ≥ 2 equally spaced subpoints per particle from x_p − V_p/2 to
    /// x_p + V_p/2, both ends included, weight V_p/n each: the other
    /// placement the description allows (a sensitivity check of Table 8).
    EndSubpoints(usize),
}

impl NodeIntegrals {
    /// A short label: "exact integrals", "particle quadrature", "8 subpoints".
    pub fn label(&self) -> String {
        match self {
            NodeIntegrals::Exact => "exact integrals".into(),
            NodeIntegrals::Particles => "particle quadrature".into(),
            NodeIntegrals::Subpoints(n) => format!("{n} subpoints"),
            NodeIntegrals::EndSubpoints(n) => format!("{n} subpoints incl. ends"),
        }
    }
}

/// The MPM variant, i.e. the basis of the background grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Standard MPM with P1 Lagrange functions.
    Mpm,
    /// MPM with P2 Lagrange functions (unstable: negative masses).
    MpmP2,
    /// Dual-domain MPM (TLS paper §3.3) with a rule for its node integrals.
    Ddmpm {
        /// How V_j and ∫φ_j∇φ_i are evaluated.
        node_integrals: NodeIntegrals,
    },
    /// B-spline MPM of the given degree.
    Bsmpm {
        /// Polynomial degree p ≥ 1.
        degree: usize,
    },
}

impl Method {
    /// DDMPM with exactly integrated node integrals, hompm's default.
    pub const DDMPM: Method = Method::Ddmpm {
        node_integrals: NodeIntegrals::Exact,
    };

    /// DDMPM with particle-quadrature node integrals.
    pub const DDMPM_PARTICLES: Method = Method::Ddmpm {
        node_integrals: NodeIntegrals::Particles,
    };

    /// DDMPM with n subpoints per particle for its node integrals.
    pub fn ddmpm_subpoints(n: usize) -> Method {
        Method::Ddmpm {
            node_integrals: NodeIntegrals::Subpoints(n),
        }
    }

    /// DDMPM with n subpoints per particle, both ends of its domain included.
    pub fn ddmpm_end_subpoints(n: usize) -> Method {
        Method::Ddmpm {
            node_integrals: NodeIntegrals::EndSubpoints(n),
        }
    }

    /// A short label for charts and tables: "DDMPM" for the exact
    /// integrals, "DDMPM (particle quadrature)", "DDMPM (8 subpoints)".
    pub fn label(&self) -> String {
        match *self {
            Method::Mpm => "MPM".into(),
            Method::MpmP2 => "MPM-P2".into(),
            Method::DDMPM => "DDMPM".into(),
            Method::Ddmpm { node_integrals } => format!("DDMPM ({})", node_integrals.label()),
            Method::Bsmpm { degree } => format!("BSMPM-p{degree}"),
        }
    }

    /// Basis functions that can be non-zero at a particle: 2 for P1, 3 for
    /// P2, p+1 for B-splines, and 4 for DDMPM, whose modified gradient
    /// ∇̄φ_i reaches one node beyond the element on each side (TLS paper
    /// §3.3).
    pub fn functions_per_particle(&self) -> usize {
        match *self {
            Method::Mpm => 2,
            Method::MpmP2 => 3,
            Method::Ddmpm { .. } => 4,
            Method::Bsmpm { degree } => degree + 1,
        }
    }

    /// DDMPM's rule for its node integrals; `None` for the other methods.
    pub fn node_integrals(&self) -> Option<NodeIntegrals> {
        match *self {
            Method::Ddmpm { node_integrals } => Some(node_integrals),
            _ => None,
        }
    }
}

/// A family of 1D methods as the command line names it (`--method`), with
/// how `--degree` and `--node-integrals` choose its member.
#[derive(Debug, Clone, Copy)]
pub struct MethodFamily {
    /// The name after `--method`.
    pub name: &'static str,
    /// One line for `--help`.
    pub summary: &'static str,
    /// The member of `--degree` and `--node-integrals` (the caller refuses
    /// node integrals for a method without them, [`Method::node_integrals`]).
    pub method: fn(usize, NodeIntegrals) -> Result<Method>,
}

/// The registration of the 1D methods on the command line.
///
/// ## How to add a 1D basis
/// 1. Implement [`Basis1d`](crate::basis::Basis1d) (and `evaluate_into` for the batch evaluation)
///    in a module of the basis layer, declared in its `mod.rs`.
/// 2. Register it here: a [`Method`] variant, its arms in
///    [`Method::label`], [`Method::functions_per_particle`] and
///    [`Grid::new`](crate::mpm::grid::Grid::new), and its family in this list.
///
/// That is three files (the basis, its `mod.rs` and this one); the command
/// line, the run estimates, the stability monitor and the report take the
/// method from here.
pub const METHOD_FAMILIES: [MethodFamily; 4] = [
    MethodFamily {
        name: "mpm",
        summary: "Linear Lagrange (P1) MPM",
        method: |_, _| Ok(Method::Mpm),
    },
    MethodFamily {
        name: "mpm-p2",
        summary: "Quadratic Lagrange (P2) MPM: negative masses (thesis §5.2)",
        method: |_, _| Ok(Method::MpmP2),
    },
    MethodFamily {
        name: "ddmpm",
        summary: "Dual-domain MPM (TLS paper §3.3)",
        method: |_, node_integrals| Ok(Method::Ddmpm { node_integrals }),
    },
    MethodFamily {
        name: "bsmpm",
        summary: "B-spline MPM of degree --degree (book §4.3)",
        method: |degree, _| {
            if degree == 0 {
                return Err(Error::InvalidDegree(
                    "bsmpm needs --degree ≥ 1, got 0".into(),
                ));
            }
            Ok(Method::Bsmpm { degree })
        },
    },
];
