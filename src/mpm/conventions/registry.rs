//! # The registry of the conventions of other codes
//!
//! One row per value of each flag (`--scheme`, `--transfer`, `--positions`,
//! `--body-force`, `--knots`, `--gradient`): its word, one line of help,
//! citation, the codes known to use it and the trace keys it adds. `--help`
//! and docs/conventions.md read it; a new value is one row here and one
//! arm in its enum (`super`).
//!
//! Items: [`ConventionInfo`], [`REGISTRY`], [`registered`].

use crate::error::{Error, Result};
use serde::Serialize;

/// One value of one convention flag, as `--help` and docs/conventions.md
/// list it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct ConventionInfo {
    /// The flag without dashes, e.g. `scheme`.
    pub flag: &'static str,
    /// The value as the command line spells it, e.g. `usl` (`flip:α` for
    /// the blend).
    pub value: &'static str,
    /// One line of `--help`.
    pub help: &'static str,
    /// Where the equations are stated.
    pub citation: &'static str,
    /// Codes known to use it.
    pub codes: &'static str,
    /// The trace keys it adds to the book's (1D) or the MLS paper's (2D).
    pub trace_keys: &'static [&'static str],
}

const GRID_VELOCITY_KEYS: &[&str] = &["nodal-momentum", "nodal-velocity", "nodal-velocity-updated"];

/// Every registered convention value, flag by flag, default first.
pub const REGISTRY: &[ConventionInfo] = &[
    ConventionInfo {
        flag: "scheme",
        value: "musl",
        help: "MUSL: project the updated particle velocities again, then strain and stress last",
        citation: "book §4.2.2, Eqs. (4.9)-(4.18); TLS paper §3.1; MLS paper Eqs. (31)-(37)",
        codes: "hompm, the thesis author's code, the TLS authors' code, Karamelo scheme(musl)",
        trace_keys: &[],
    },
    ConventionInfo {
        flag: "scheme",
        value: "usl",
        help: "USL: strain and stress last, from the updated grid velocity, without a second projection",
        citation: "Sulsky, Chen & Schreyer (1994); named in TLS paper §3",
        codes: "Karamelo scheme(usl), Taichi's mpm88/mpm99",
        trace_keys: GRID_VELOCITY_KEYS,
    },
    ConventionInfo {
        flag: "scheme",
        value: "usf",
        help: "USF: strain and stress first, from the grid velocity p_i/m_i, then forces and motion",
        citation: "Bardenhagen (2002)",
        codes: "Karamelo scheme(usf)",
        trace_keys: GRID_VELOCITY_KEYS,
    },
    ConventionInfo {
        flag: "transfer",
        value: "flip",
        help: "FLIP: v_p += Δt Σ N_i a_i",
        citation: "book Eq. (4.9); MLS paper Eq. (29)",
        codes: "hompm, the seeds' codes, Karamelo FLIP 1.0",
        trace_keys: &[],
    },
    ConventionInfo {
        flag: "transfer",
        value: "pic",
        help: "PIC: v_p = Σ N_i ṽ_i, the updated grid velocity",
        citation: "Harlow (1964); Brackbill & Ruppel (1986)",
        codes: "Karamelo FLIP 0.0",
        trace_keys: GRID_VELOCITY_KEYS,
    },
    ConventionInfo {
        flag: "transfer",
        value: "flip:α",
        help: "the blend v_p = α (v_p + Δt Σ N_i a_i) + (1 − α) Σ N_i ṽ_i, 0 ≤ α ≤ 1",
        citation: "Brackbill & Ruppel (1986); Stomakhin et al. (2013)",
        codes: "Karamelo's FLIP ratio (e.g. 0.99)",
        trace_keys: GRID_VELOCITY_KEYS,
    },
    ConventionInfo {
        flag: "transfer",
        value: "apic",
        help: "APIC: v_p = Σ N_i ṽ_i and the affine C_p = Σ N_i ṽ_i ⊗ (x_i − x_p) D_p⁻¹, carried to the grid as m_p C_p (x_i − x_p); 2D, with --scheme usl",
        citation: "Jiang, Schroeder, Selle, Teran & Stomakhin (2015)",
        codes: "Taichi's mpm88/mpm99 (MLS-MPM, Hu et al. 2018)",
        trace_keys: &[],
    },
    ConventionInfo {
        flag: "positions",
        value: "projected",
        help: "move particles with the projected nodal velocity: Δu_p = Δt Σ N_i v_i (the 1D default)",
        citation: "book Eqs. (4.11)-(4.13)",
        codes: "hompm 1D, the thesis author's code, the TLS authors' code",
        trace_keys: &[],
    },
    ConventionInfo {
        flag: "positions",
        value: "grid",
        help: "move particles with the updated grid velocity: Δu_p = Δt Σ N_i ṽ_i (the 2D default)",
        citation: "MLS paper Eq. (30)",
        codes: "hompm 2D, the MLS paper's code, Karamelo, Taichi",
        trace_keys: GRID_VELOCITY_KEYS,
    },
    ConventionInfo {
        flag: "body-force",
        value: "particles",
        help: "body force mapped from the particles: f_i = Σ_p N_i m_p b_p",
        citation: "MLS paper Eq. (24); thesis §3.2",
        codes: "hompm, the MLS paper's code",
        trace_keys: &[],
    },
    ConventionInfo {
        flag: "body-force",
        value: "nodes",
        help: "body force at the nodes: f_i = m_i b(X_i, t)",
        citation: "docs/conventions.md, \"Conventions of other codes\"",
        codes: "Karamelo",
        trace_keys: &[],
    },
    ConventionInfo {
        flag: "knots",
        value: "open",
        help: "open (clamped) uniform knot vectors on [0, L]: no basis function reaches past a wall",
        citation: "book §4.3; thesis §6.1; MLS paper §2",
        codes: "hompm, the seeds' codes",
        trace_keys: &[],
    },
    ConventionInfo {
        flag: "knots",
        value: "padded",
        help: "uniform node-centred quadratic B-splines with one node beyond each wall; the wall condition on the nodes at and beyond it; 2D",
        citation: "Steffen, Kirby & Berzins (2008); Hu et al. (2018)",
        codes: "Taichi's mpm88/mpm99",
        trace_keys: &[],
    },
    ConventionInfo {
        flag: "knots",
        value: "natural",
        help: "uniform node-centred B-splines of degree 2 or 3 on the nodes 0 … cells, the ghost function beyond each wall folded into the two nearest nodes (N_0 = B(ξ) + 2B(ξ+1), N_1 = B(ξ−1) − B(ξ+1); s'' = 0 at the walls); the wall condition on the wall node; 1D, with --method bsmpm --degree 2|3",
        citation: "Karamelo src/basis_functions.h (read, not copied); docs/conventions.md, \"Conventions of other codes\"",
        codes: "Karamelo quadratic-spline, cubic-spline",
        trace_keys: &[],
    },
    ConventionInfo {
        flag: "gradient",
        value: "basis",
        help: "velocity gradient Σ v_i ⊗ ∇N_i and internal force −Σ V_p σ_p ∇N_i",
        citation: "book Eqs. (4.6), (4.14); MLS paper Eqs. (25), (34)",
        codes: "hompm, the seeds' codes, Karamelo",
        trace_keys: &[],
    },
    ConventionInfo {
        flag: "gradient",
        value: "affine",
        help: "MLS-MPM: velocity gradient C_p and internal force −Σ V_p σ_p D_p⁻¹ (x_i − x_p) N_i; 2D, with --transfer apic",
        citation: "Hu, Fang, Ge, Qu, Zhu, Pradhana & Jiang (2018), MLS-MPM",
        codes: "Taichi's mpm88/mpm99",
        trace_keys: &[],
    },
];

/// The registered values of one flag.
pub fn registered(flag: &str) -> impl Iterator<Item = &'static ConventionInfo> + '_ {
    REGISTRY.iter().filter(move |c| c.flag == flag)
}

/// The registration of `value` under `flag`, or an error naming the known
/// values.
pub(super) fn lookup(flag: &str, value: &str) -> Result<&'static ConventionInfo> {
    registered(flag)
        .find(|c| c.value == value)
        .ok_or_else(|| unknown(flag, value))
}

pub(super) fn unknown(flag: &str, value: &str) -> Error {
    let known: Vec<&str> = registered(flag).map(|c| c.value).collect();
    Error::InvalidArgument(format!(
        "unknown --{flag} '{value}' (known: {})",
        known.join(", ")
    ))
}
