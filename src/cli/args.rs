//! # The vocabulary of the command line
//!
//! Every enumerated option is a [`ValueEnum`], so clap parses it and
//! `--help` lists its choices; each converts into the library's own type.
//! Counts go through [`count`], so that `--cells -1` reaches a range
//! message instead of clap's "unexpected argument".
//!
//! Items: [`MethodArg`], [`MappingArg`], [`MassArg`], [`SolverArg`], [`node_integrals`],
//! [`ReconstructionArg`], [`SceneArg`], [`count`], [`name`].

use crate::error::{Error, Result};
use crate::mpm::grid::{Method, NodeIntegrals};
use crate::mpm::mapping::{ConsistentSolver, Mapping, MassMatrix};
use clap::ValueEnum;

/// The MPM variant of `hompm run --method`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MethodArg {
    /// Linear Lagrange (P1) MPM.
    Mpm,
    /// Quadratic Lagrange (P2) MPM: negative masses (thesis §5.2).
    MpmP2,
    /// Dual-domain MPM (TLS paper §3.3).
    Ddmpm,
    /// B-spline MPM of degree --degree (book §4.3).
    Bsmpm,
    /// B-spline MPM with MLS to the Gauss points (MLS paper; aligned-vibration only).
    BsmpmMls,
    /// B-spline MPM with conservative Taylor least squares to the Gauss
    /// points (TLS paper §5 in 2D; aligned-vibration only).
    BsmpmTls,
    /// Total-Lagrangian FE with B-splines, no grid crossing (hompm's
    /// reference; aligned-vibration only).
    TlFe,
}

impl MethodArg {
    /// The library's [`Method`]; `degree` is used by `bsmpm` only and must
    /// be at least 1, `node_integrals` by `ddmpm` only.
    pub fn method(self, degree: usize, node_integrals: NodeIntegrals) -> Result<Method> {
        if self != MethodArg::Ddmpm && node_integrals != NodeIntegrals::Exact {
            return Err(Error::InvalidArgument(format!(
                "--node-integrals applies to --method ddmpm only, not {}",
                name(&self)
            )));
        }
        Ok(match self {
            MethodArg::Mpm => Method::Mpm,
            MethodArg::MpmP2 => Method::MpmP2,
            MethodArg::Ddmpm => Method::Ddmpm { node_integrals },
            MethodArg::Bsmpm if degree >= 1 => Method::Bsmpm { degree },
            MethodArg::Bsmpm => {
                return Err(Error::InvalidDegree(
                    "bsmpm needs --degree ≥ 1, got 0".into(),
                ))
            }
            MethodArg::BsmpmMls | MethodArg::BsmpmTls | MethodArg::TlFe => {
                return Err(Error::InvalidArgument(format!(
                    "--method {} runs only in the 2D scene aligned-vibration",
                    name(&self)
                )))
            }
        })
    }
}

/// How particle data reaches the grid (`--mapping`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MappingArg {
    /// Particles as quadrature points (book Eqs. 4.5–4.10).
    Direct,
    /// Taylor least squares (book §4.4.3, TLS paper §5.4).
    Tls,
    /// Cubic splines (thesis ch. 7), at the thesis' half-span Gauss points.
    CubicSpline,
    /// Cubic splines with every half span clipped to the continuum Ω_t.
    CubicSplineClipped,
}

impl From<MappingArg> for Mapping {
    fn from(m: MappingArg) -> Self {
        match m {
            MappingArg::Direct => Mapping::Direct,
            MappingArg::Tls => Mapping::Tls,
            MappingArg::CubicSpline => Mapping::CubicSpline,
            MappingArg::CubicSplineClipped => Mapping::CubicSplineClipped,
        }
    }
}

/// The mass matrix of the velocity projection (`--mass`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MassArg {
    /// Row-sum lumped mass (book Eq. 4.3).
    Lumped,
    /// Consistent mass, sparse Cholesky.
    Consistent,
    /// Consistent mass, the thesis' Richardson iteration (§7.2, tolerance 1e-9).
    Richardson,
}

impl From<MassArg> for MassMatrix {
    fn from(m: MassArg) -> Self {
        match m {
            MassArg::Lumped => MassMatrix::Lumped,
            MassArg::Consistent => MassMatrix::Consistent(ConsistentSolver::Cholesky),
            MassArg::Richardson => MassMatrix::Consistent(ConsistentSolver::richardson(1e-9)),
        }
    }
}

/// The solver of `hompm mass --solve`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SolverArg {
    /// Conjugate gradients (book Eq. 4.53).
    Cg,
    /// p-multigrid V-cycles (book Eqs. 4.59–4.62).
    Pmg,
    /// Lumped-preconditioned Richardson (thesis §7.2).
    Richardson,
    /// Sparse Cholesky.
    Direct,
}

/// The reconstruction of `hompm reconstruct --method`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ReconstructionArg {
    /// Taylor least squares per cell (book Eqs. 4.26–4.37).
    Tls,
    /// TLS conserving --integrals per cell (TLS paper §5.3).
    TlsConservative,
    /// Not-a-knot cubic spline through the data (thesis §7.1).
    CubicSpline,
    /// Natural cubic spline.
    CubicSplineNatural,
    /// Moving least squares, linear basis (MLS paper Eqs. 6–17).
    Mls,
}

/// The scene of `hompm run`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SceneArg {
    /// Thesis §4.1 / TLS paper §6.1: the vibrating bar.
    VibratingBar,
    /// Thesis §4.2: the column under its own weight.
    ColumnSelfWeight,
    /// Thesis §8.1: the column under a top load.
    ColumnTopLoad,
    /// MLS paper: the 2D manufactured neo-Hookean vibration (methods mpm,
    /// bsmpm, bsmpm-mls, bsmpm-tls, tl-fe).
    AlignedVibration,
}

/// The name clap knows a value by (`mpm-p2`, `cubic-spline`, …).
pub fn name<T: ValueEnum>(value: &T) -> String {
    value
        .to_possible_value()
        .map(|v| v.get_name().to_string())
        .unwrap_or_default()
}

/// Parses DDMPM's node-integral rule (`--node-integrals`): `exact`,
/// `particles`, `subpoints:N` with N ≥ 1, or `end-subpoints:N` with N ≥ 2
/// (TLS paper §3.3 and Table 8; [`NodeIntegrals`]).
pub fn node_integrals(text: &str) -> std::result::Result<NodeIntegrals, String> {
    let t = text.trim();
    let rules = "exact, particles, subpoints:N, end-subpoints:N";
    if let Some(rule) = [
        ("exact", NodeIntegrals::Exact),
        ("particles", NodeIntegrals::Particles),
    ]
    .into_iter()
    .find_map(|(name, rule)| (t == name).then_some(rule))
    {
        return Ok(rule);
    }
    let (prefix, least, make): (&str, usize, fn(usize) -> NodeIntegrals) =
        if t.starts_with("end-subpoints:") {
            ("end-subpoints:", 2, NodeIntegrals::EndSubpoints)
        } else if t.starts_with("subpoints:") {
            ("subpoints:", 1, NodeIntegrals::Subpoints)
        } else {
            return Err(format!("'{t}' is not a node-integral rule ({rules})"));
        };
    match count(&t[prefix.len()..]) {
        Ok(n) if n >= least => Ok(make(n)),
        Ok(_) => Err(format!("{prefix}N needs N ≥ {least}")),
        Err(e) => Err(format!("{prefix}N: {e}")),
    }
}

/// Parses a count (a non-negative whole number). Negative numbers,
/// fractions and numbers beyond the machine's word get a sentence naming
/// the range, not a parse error.
pub fn count(text: &str) -> std::result::Result<usize, String> {
    let t = text.trim();
    if let Ok(n) = t.parse::<usize>() {
        return Ok(n);
    }
    match t.parse::<i128>() {
        Ok(n) if n < 0 => Err(format!("{n} is negative; a count is 0 or more")),
        Ok(n) => Err(format!("{n} is above the largest count, {}", usize::MAX)),
        Err(_) if t.parse::<f64>().is_ok() => Err(format!("'{t}' is not a whole number")),
        Err(_) => Err(format!("'{t}' is not a number")),
    }
}
