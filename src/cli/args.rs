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
use crate::mpm::grid::{Method, NodeIntegrals, METHOD_FAMILIES};
use crate::mpm::mapping::{ConsistentSolver, Mapping, MassMatrix};
use crate::mpm2d::step::Mapping2d;
use crate::scenes::aligned_vibration::AlignedMethod;
use clap::ValueEnum;

/// The MPM variant of `hompm run --method`, one of the registered names:
/// the 1D method families ([`METHOD_FAMILIES`]), `bsmpm-<mapping>` for
/// every registered 2D mapping but the direct one ([`Mapping2d::ALL`]), and
/// `tl-fe`. A new basis or mapping reaches the command line through its
/// registration; nothing here names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MethodArg {
    name: &'static str,
}

/// The 2D-only name of the total-Lagrangian reference.
const TL_FE: &str = "tl-fe";

/// Every choice of `--method` with its help line, built once from the
/// registrations.
fn method_choices() -> &'static (Vec<MethodArg>, Vec<&'static str>) {
    static CHOICES: std::sync::OnceLock<(Vec<MethodArg>, Vec<&'static str>)> =
        std::sync::OnceLock::new();
    CHOICES.get_or_init(|| {
        let mut choices: Vec<(&'static str, &'static str)> = METHOD_FAMILIES
            .iter()
            .map(|f| (f.name, f.summary))
            .collect();
        for mapping in Mapping2d::ALL {
            if mapping != Mapping2d::Direct {
                // The 2D method's own JSON tag, `bsmpm-<name>`.
                let name: &'static str = AlignedMethod::bsmpm_with(1, mapping).tag().leak();
                choices.push((name, mapping.info().summary));
            }
        }
        choices.push((
            TL_FE,
            "Total-Lagrangian FE with B-splines, no grid crossing (hompm's reference; aligned-vibration only)",
        ));
        choices
            .into_iter()
            .map(|(name, summary)| (MethodArg { name }, summary))
            .unzip()
    })
}

impl MethodArg {
    /// Linear Lagrange MPM, the default.
    pub const MPM: MethodArg = MethodArg { name: "mpm" };

    /// The library's 1D [`Method`]: the family of this name with `degree`
    /// and `node_integrals` (which only a method with node integrals takes).
    pub fn method(self, degree: usize, node_integrals: NodeIntegrals) -> Result<Method> {
        let method = METHOD_FAMILIES
            .iter()
            .find(|f| f.name == self.name)
            .map(|f| (f.method)(degree, node_integrals))
            .transpose()?;
        if node_integrals != NodeIntegrals::Exact
            && method.and_then(|m| m.node_integrals()).is_none()
        {
            return Err(Error::InvalidArgument(format!(
                "--node-integrals applies to --method ddmpm only, not {}",
                self.name
            )));
        }
        method.ok_or_else(|| {
            Error::InvalidArgument(format!(
                "--method {} runs only in the 2D scene aligned-vibration",
                self.name
            ))
        })
    }

    /// The 2D method of the aligned vibration: `mpm`, `bsmpm` (direct
    /// mapping), `bsmpm-<mapping>` or `tl-fe`, of `degree` ≥ 1.
    pub fn aligned(self, degree: usize) -> Result<AlignedMethod> {
        if degree == 0 && self != MethodArg::MPM {
            return Err(Error::InvalidDegree(format!(
                "{} needs --degree ≥ 1, got 0",
                self.name
            )));
        }
        let tag = if self.name == TL_FE {
            "total-lagrangian"
        } else {
            self.name
        };
        AlignedMethod::from_tag(tag, degree).ok_or_else(|| {
            let names: Vec<&str> = method_choices()
                .0
                .iter()
                .map(|c| c.name)
                .filter(|n| *n == TL_FE || AlignedMethod::from_tag(n, 1).is_some())
                .collect();
            Error::InvalidArgument(format!(
                "aligned-vibration runs {}, not {}",
                names.join(", "),
                self.name
            ))
        })
    }
}

impl ValueEnum for MethodArg {
    fn value_variants<'a>() -> &'a [Self] {
        &method_choices().0
    }

    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        let (choices, summaries) = method_choices();
        let i = choices.iter().position(|c| c == self)?;
        Some(clap::builder::PossibleValue::new(self.name).help(summaries[i]))
    }
}

/// How particle data reaches the grid (`--mapping`): any registered 1D
/// mapping, by its name ([`Mapping::ALL`], [`Mapping::info`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MappingArg(pub Mapping);

impl MappingArg {
    /// The default, particles as quadrature points.
    pub const DIRECT: MappingArg = MappingArg(Mapping::Direct);
}

impl ValueEnum for MappingArg {
    fn value_variants<'a>() -> &'a [Self] {
        static ALL: std::sync::OnceLock<Vec<MappingArg>> = std::sync::OnceLock::new();
        ALL.get_or_init(|| Mapping::ALL.into_iter().map(MappingArg).collect())
    }

    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        let info = self.0.info();
        Some(clap::builder::PossibleValue::new(info.name).help(info.summary))
    }
}

impl From<MappingArg> for Mapping {
    fn from(m: MappingArg) -> Self {
        m.0
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
    /// bsmpm, bsmpm-mls, bsmpm-tls, bsmpm-pu-tls, tl-fe).
    AlignedVibration,
    /// The MLS paper's code: its 1D manufactured neo-Hookean strip, in the
    /// code's coordinates (--params mls-paper-code; issue #40).
    ManufacturedStrip,
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
