//! # The conventions of other codes: scheme, transfer, positions, body force
//!
//! The seeds write one step (book §4.2.2 in 1D, MLS paper Eqs. 18–37 in
//! 2D). Codes people run make other choices at four places of the same
//! step; each choice is a value of one flag, registered once in
//! [`REGISTRY`] with its one-line help, citation, the codes known to use it
//! and the trace keys it adds. `run`, `trace` and `check` take the flags in
//! 1D and 2D alike (docs/conventions.md, "Conventions of other codes"):
//!
//! - [`Scheme`] (`--scheme`): when the stress is updated and whether the
//!   velocity is projected again. MUSL (book §4.2.2, TLS paper §3.1: the
//!   default), USL (Sulsky et al. 1994, named in TLS paper §3), USF
//!   (Bardenhagen 2002).
//! - [`Transfer`] (`--transfer`): how the particle velocity is updated
//!   (book Eq. 4.9 is FLIP; PIC; Karamelo's blend α·FLIP + (1 − α)·PIC).
//! - [`Positions`] (`--positions`): the velocity that moves the particles:
//!   the projected v_i of book Eq. (4.11) (the 1D default) or the updated
//!   grid velocity ṽ_i = v_i^n + Δt a_i of MLS paper Eq. (30) (the 2D
//!   default; Karamelo, Taichi).
//! - [`BodyForceAt`] (`--body-force`): the body force mapped from the
//!   particles, Σ_p N_i m_p b_p (MLS paper Eq. 24; thesis §3.2), or taken at
//!   the nodes as m_i b(X_i) (Karamelo).
//!
//! The grid velocity at the start of a step, which USL, USF, PIC and the
//! grid positions need, is v_i^n = p_i / m_i with p_i = Σ_p m_p v_p N_i
//! (MLS paper Eq. 19 with the particles as quadrature points); on a
//! Dirichlet DOF it is 0. The updated grid velocity is ṽ_i = v_i^n + Δt a_i
//! (MLS paper Eqs. 27–28, written per unit mass), 0 on a Dirichlet DOF.
//!
//! - [`Knots`] (`--knots`) and [`Gradient`] (`--gradient`): Taichi's
//!   padded uniform quadratic B-splines and the MLS-MPM gradient from APIC's
//!   C_p (Hu et al. 2018), 2D only; Karamelo's boundary-modified uniform
//!   B-splines of degree 2 and 3 (`--knots natural`, 1D only).
//!
//! Items: [`Scheme`], [`Transfer`], [`Positions`], [`BodyForceAt`], [`Knots`], [`Gradient`],
//! [`Conventions`], [`ConventionInfo`], [`REGISTRY`], [`registered`].

use super::method::Method;
use crate::error::{Error, Result};
use serde::{Serialize, Serializer};

mod registry;
use registry::{lookup, unknown};
pub use registry::{registered, ConventionInfo, REGISTRY};

/// `--scheme`: when the stress is updated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Scheme {
    /// Modified update-stress-last (book §4.2.2).
    #[default]
    Musl,
    /// Update-stress-last (Sulsky et al. 1994).
    Usl,
    /// Update-stress-first (Bardenhagen 2002).
    Usf,
}

impl Scheme {
    /// The command line's word.
    pub fn name(self) -> &'static str {
        match self {
            Scheme::Musl => "musl",
            Scheme::Usl => "usl",
            Scheme::Usf => "usf",
        }
    }

    /// The scheme called `name`.
    pub fn from_name(name: &str) -> Result<Self> {
        let info = lookup("scheme", name)?;
        Ok(match info.value {
            "usl" => Scheme::Usl,
            "usf" => Scheme::Usf,
            _ => Scheme::Musl,
        })
    }
}

/// `--transfer`: how the particle velocity is updated (step 3).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Transfer {
    /// v_p ← v_p + Δt Σ N_i a_i (book Eq. 4.9).
    #[default]
    Flip,
    /// v_p ← Σ N_i ṽ_i.
    Pic,
    /// v_p ← α (v_p + Δt Σ N_i a_i) + (1 − α) Σ N_i ṽ_i, α in [0, 1].
    Blend(f64),
    /// v_p ← Σ N_i ṽ_i and C_p ← Σ N_i ṽ_i ⊗ (x_i − x_p) D_p⁻¹ (Jiang et
    /// al. 2015); the grid momentum gains m_p C_p (x_i − x_p).
    Apic,
}

impl Transfer {
    /// The command line's word: `flip`, `pic` or `flip:α`.
    pub fn name(self) -> String {
        match self {
            Transfer::Flip => "flip".into(),
            Transfer::Pic => "pic".into(),
            Transfer::Blend(a) => format!("flip:{a}"),
            Transfer::Apic => "apic".into(),
        }
    }

    /// `flip`, `pic` or `flip:α` with 0 ≤ α ≤ 1 (`flip:1` is `flip`,
    /// `flip:0` is `pic`).
    pub fn from_name(name: &str) -> Result<Self> {
        if let Some(alpha) = name.strip_prefix("flip:") {
            let a: f64 = alpha.parse().map_err(|_| {
                Error::InvalidArgument(format!(
                    "--transfer flip:α needs a number α in [0, 1], got '{alpha}'"
                ))
            })?;
            if !(0.0..=1.0).contains(&a) {
                return Err(Error::InvalidArgument(format!(
                    "--transfer flip:α needs 0 ≤ α ≤ 1, got {a}"
                )));
            }
            return Ok(if a == 1.0 {
                Transfer::Flip
            } else if a == 0.0 {
                Transfer::Pic
            } else {
                Transfer::Blend(a)
            });
        }
        let info = lookup("transfer", name)?;
        match info.value {
            "flip" => Ok(Transfer::Flip),
            "pic" => Ok(Transfer::Pic),
            "apic" => Ok(Transfer::Apic),
            _ => Err(unknown("transfer", name)),
        }
    }

    /// The weight α of the FLIP update (1 for FLIP, 0 for PIC and APIC).
    pub fn flip_weight(self) -> f64 {
        match self {
            Transfer::Flip => 1.0,
            Transfer::Pic | Transfer::Apic => 0.0,
            Transfer::Blend(a) => a,
        }
    }
}

/// `--positions`: the nodal velocity that moves the particles.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Positions {
    /// Δu_p = Δt Σ N_i v_i with the projected v_i (book Eq. 4.11).
    Projected,
    /// Δu_p = Δt Σ N_i ṽ_i with the updated grid velocity (MLS paper Eq. 30).
    Grid,
}

impl Positions {
    /// The command line's word.
    pub fn name(self) -> &'static str {
        match self {
            Positions::Projected => "projected",
            Positions::Grid => "grid",
        }
    }

    /// The positions rule called `name`.
    pub fn from_name(name: &str) -> Result<Self> {
        Ok(match lookup("positions", name)?.value {
            "grid" => Positions::Grid,
            _ => Positions::Projected,
        })
    }
}

/// `--body-force`: where the body force is evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum BodyForceAt {
    /// f_i = Σ_p N_i m_p b_p (MLS paper Eq. 24; thesis §3.2).
    #[default]
    Particles,
    /// f_i = m_i b(X_i, t), X_i the node's position.
    Nodes,
}

impl BodyForceAt {
    /// The command line's word.
    pub fn name(self) -> &'static str {
        match self {
            BodyForceAt::Particles => "particles",
            BodyForceAt::Nodes => "nodes",
        }
    }

    /// The body-force rule called `name`.
    pub fn from_name(name: &str) -> Result<Self> {
        Ok(match lookup("body-force", name)?.value {
            "nodes" => BodyForceAt::Nodes,
            _ => BodyForceAt::Particles,
        })
    }
}

/// `--knots`: the B-spline basis of the grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Knots {
    /// Open uniform knot vectors on [0, L] (book §4.3).
    #[default]
    Open,
    /// Uniform node-centred quadratic B-splines, nodes at i·h for
    /// i = −1 … cells + 1 (Taichi).
    Padded,
    /// Uniform node-centred B-splines of degree 2 or 3 on the nodes
    /// i·h, i = 0 … cells, the ghost function beyond each wall folded into
    /// the two nearest nodes (Karamelo src/basis_functions.h, read, not
    /// copied; `spline::natural`).
    Natural,
}

impl Knots {
    /// The command line's word.
    pub fn name(self) -> &'static str {
        match self {
            Knots::Open => "open",
            Knots::Padded => "padded",
            Knots::Natural => "natural",
        }
    }

    /// The knots called `name`.
    pub fn from_name(name: &str) -> Result<Self> {
        Ok(match lookup("knots", name)?.value {
            "padded" => Knots::Padded,
            "natural" => Knots::Natural,
            _ => Knots::Open,
        })
    }
}

/// `--gradient`: how the velocity gradient and the internal force are
/// formed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Gradient {
    /// From the basis gradient ∇N_i.
    #[default]
    Basis,
    /// From the affine C_p and D_p⁻¹ (x_i − x_p) N_i (MLS-MPM).
    Affine,
}

impl Gradient {
    /// The command line's word.
    pub fn name(self) -> &'static str {
        match self {
            Gradient::Basis => "basis",
            Gradient::Affine => "affine",
        }
    }

    /// The gradient rule called `name`.
    pub fn from_name(name: &str) -> Result<Self> {
        Ok(match lookup("gradient", name)?.value {
            "affine" => Gradient::Affine,
            _ => Gradient::Basis,
        })
    }
}

/// The four choices of a step. The defaults are the seeds': the book's
/// step in 1D ([`Conventions::BOOK`]) and the MLS paper's in 2D
/// ([`Conventions::MLS_PAPER`]), which differ only in [`Positions`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Conventions {
    /// `--scheme`.
    pub scheme: Scheme,
    /// `--transfer`.
    pub transfer: Transfer,
    /// `--positions`.
    pub positions: Positions,
    /// `--body-force`.
    pub body_force: BodyForceAt,
    /// `--knots`.
    pub knots: Knots,
    /// `--gradient`.
    pub gradient: Gradient,
}

impl Conventions {
    /// The book's 1D step (§4.2.2): MUSL, FLIP, projected positions, body
    /// force from the particles.
    pub const BOOK: Self = Self {
        scheme: Scheme::Musl,
        transfer: Transfer::Flip,
        positions: Positions::Projected,
        body_force: BodyForceAt::Particles,
        knots: Knots::Open,
        gradient: Gradient::Basis,
    };

    /// The MLS paper's 2D step (Eqs. 18–37): as [`Self::BOOK`] but with the
    /// positions of Eq. (30).
    pub const MLS_PAPER: Self = Self {
        positions: Positions::Grid,
        ..Self::BOOK
    };

    /// Whether these are the book's ([`Self::BOOK`]).
    pub fn is_book(&self) -> bool {
        *self == Self::BOOK
    }

    /// Whether these are the MLS paper's ([`Self::MLS_PAPER`]).
    pub fn is_mls_paper(&self) -> bool {
        *self == Self::MLS_PAPER
    }

    /// The default of a dimension (1 or 2).
    pub fn default_for(dimension: usize) -> Self {
        if dimension == 2 {
            Self::MLS_PAPER
        } else {
            Self::BOOK
        }
    }

    /// Whether the step needs the grid velocity v_i^n and its update ṽ_i
    /// (module doc): every non-default scheme, transfer or positions rule.
    pub fn needs_grid_velocity(&self) -> bool {
        self.scheme != Scheme::Musl
            || self.transfer != Transfer::Flip
            || self.positions == Positions::Grid
    }

    /// The non-default choices as `--flag value` words, for a header and a
    /// verdict; empty for the dimension's default.
    pub fn flags(&self, dimension: usize) -> Vec<String> {
        let d = Self::default_for(dimension);
        let mut out = Vec::new();
        if self.scheme != d.scheme {
            out.push(format!("--scheme {}", self.scheme.name()));
        }
        if self.transfer != d.transfer {
            out.push(format!("--transfer {}", self.transfer.name()));
        }
        if self.positions != d.positions {
            out.push(format!("--positions {}", self.positions.name()));
        }
        if self.body_force != d.body_force {
            out.push(format!("--body-force {}", self.body_force.name()));
        }
        if self.knots != d.knots {
            out.push(format!("--knots {}", self.knots.name()));
        }
        if self.gradient != d.gradient {
            out.push(format!("--gradient {}", self.gradient.name()));
        }
        out
    }

    /// Refuses the combinations that mean nothing: USL and USF project
    /// nothing, so they move the particles with the grid velocity.
    pub fn validate(&self) -> Result<()> {
        if self.scheme != Scheme::Musl && self.positions == Positions::Projected {
            return Err(Error::InvalidArgument(format!(
                "--scheme {} has no projected velocity to move the particles with; \
                 use --positions grid",
                self.scheme.name()
            )));
        }
        if self.transfer == Transfer::Apic && self.scheme != Scheme::Usl {
            return Err(Error::InvalidArgument(
                "--transfer apic runs with --scheme usl (Taichi's MLS-MPM step); a second projection of C_p is not defined here".into(),
            ));
        }
        if self.gradient == Gradient::Affine && self.transfer != Transfer::Apic {
            return Err(Error::InvalidArgument(
                "--gradient affine needs the C_p of --transfer apic".into(),
            ));
        }
        Ok(())
    }

    /// Where the 1D step takes these (`plain`: the direct mapping with a
    /// lumped mass) on a grid of `method`: [`Self::validate`], none of the
    /// 2D-only conventions, another code's step only with a plain mapping,
    /// and natural knots with a plain mapping of B-splines of degree 2 or 3
    /// (Karamelo's splines).
    pub fn check_1d(&self, plain: bool, method: Method) -> Result<()> {
        self.validate()?;
        if self.is_two_d_only() {
            return Err(Error::InvalidArgument(format!(
                "{} is 2D only: the 1D step has no APIC, affine gradient or padded knots",
                self.flags(1).join(" ")
            )));
        }
        let natural = self.knots == Knots::Natural;
        if (self.needs_grid_velocity() || natural) && !plain {
            return Err(Error::InvalidArgument(format!(
                "{} is defined for the direct mapping with a lumped mass, or a mapping that maps the loads too (--mapping mls or mls-code-weights)",
                self.flags(1).join(" ")
            )));
        }
        if natural && !matches!(method, Method::Bsmpm { degree: 2 | 3 }) {
            return Err(Error::InvalidArgument(format!(
                "--knots natural is Karamelo's quadratic and cubic splines only: use --method bsmpm --degree 2 or 3, not {}",
                method.label()
            )));
        }
        Ok(())
    }

    /// Where the 2D step takes these: [`Self::validate`]; no USF (its
    /// stress update would precede phase 1); APIC, the affine gradient and
    /// padded knots with the direct mapping of quadratic B-splines (APIC
    /// needs D_p > 0, which bilinear functions lose at the nodes); the
    /// total-Lagrangian reference with the MLS paper's conventions only.
    pub fn check_2d(&self, quadratic_bspline: bool, direct: bool, total: bool) -> Result<()> {
        self.validate()?;
        if self.scheme == Scheme::Usf {
            return Err(Error::InvalidArgument(
                "--scheme usf is 1D only; the 2D step has musl and usl".into(),
            ));
        }
        if self.knots == Knots::Natural {
            return Err(Error::InvalidArgument(
                "--knots natural is 1D only (Karamelo's 1D splines); the 2D grid has open and padded knots".into(),
            ));
        }
        if self.is_two_d_only() && !(direct && quadratic_bspline) {
            return Err(Error::InvalidArgument(
                "--transfer apic, --gradient affine and --knots padded run with the direct mapping of quadratic B-splines (--method bsmpm --degree 2)".into(),
            ));
        }
        if total && *self != Self::MLS_PAPER {
            return Err(Error::InvalidArgument(
                "the total-Lagrangian reference runs with the MLS paper's conventions only".into(),
            ));
        }
        Ok(())
    }

    /// Whether these use a convention the 1D step does not have (APIC,
    /// the affine gradient, padded knots).
    pub fn is_two_d_only(&self) -> bool {
        self.transfer == Transfer::Apic
            || self.gradient == Gradient::Affine
            || self.knots == Knots::Padded
    }
}

impl Default for Conventions {
    fn default() -> Self {
        Self::BOOK
    }
}

impl Serialize for Conventions {
    /// As `{"scheme": "usl", "transfer": "flip:0.99", …}`.
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(6))?;
        m.serialize_entry("scheme", self.scheme.name())?;
        m.serialize_entry("transfer", &self.transfer.name())?;
        m.serialize_entry("positions", self.positions.name())?;
        m.serialize_entry("body-force", self.body_force.name())?;
        m.serialize_entry("knots", self.knots.name())?;
        m.serialize_entry("gradient", self.gradient.name())?;
        m.end()
    }
}
