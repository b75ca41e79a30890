//! # The traced equations: keys, quantities and citations
//!
//! One table per dimension lists every quantity `hompm trace` records, in
//! the order the step computes it (the order in which `hompm check` looks
//! for the first difference): [`EQUATIONS_1D`] for book Eqs. (4.5)–(4.18),
//! [`EQUATIONS_2D`] for MLS paper Eqs. (18)–(41). Keys are stable and only
//! ever added (docs/oracle.md lists them).
//!
//! Items: [`Equation`], [`IndexKind`], [`EQUATIONS_1D`], [`EQUATIONS_2D`],
//! [`equation`].

use crate::mpm::musl::StepPoint;
use serde::Serialize;

/// What one entry of an equation's values is indexed by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum IndexKind {
    /// A grid DOF (node), 0-based.
    Dof,
    /// A particle, 0-based in hompm's order.
    Particle,
    /// The solver's [iterations, final relative residual].
    Solver,
    /// A 2D grid node i = ix + n·iy, 0-based, with n = cells + p nodes per
    /// side; with `--knots padded` n = cells + 3 and ix = 0 is the node at
    /// x = −h beyond the wall (ix = i_x + 1 of Taichi's node i_x·h).
    Node,
    /// A 2D Gauss point g = gx + 2·cells·gy, 0-based.
    GaussPoint,
}

impl IndexKind {
    /// The word for an index of this kind in a sentence ("DOF 7").
    pub fn word(self) -> &'static str {
        match self {
            IndexKind::Dof => "DOF",
            IndexKind::Particle => "particle",
            IndexKind::Solver => "entry",
            IndexKind::Node => "node",
            IndexKind::GaussPoint => "Gauss point",
        }
    }
}

/// One traced equation: its key, what it is, and where the seeds state it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Equation {
    /// The stable key, e.g. `book-4.10`.
    pub key: &'static str,
    /// The symbol, e.g. `v_i`.
    pub symbol: &'static str,
    /// What the quantity is, in words.
    pub quantity: &'static str,
    /// The citation, e.g. `book Eq. (4.10)`.
    pub citation: &'static str,
    /// What the values are indexed by.
    pub index: IndexKind,
    /// Values per index, stored consecutively: 1, 2 (x, y), 4 (xx, xy,
    /// yx, yy) or 8 (the Gauss-point values of MLS Eqs. 18–21).
    pub components: usize,
}

impl Equation {
    /// The entity (DOF, node, particle, …) and component of a flat index.
    pub fn locate(&self, flat: usize) -> (usize, Option<&'static str>) {
        let names: &[&str] = match self.components {
            2 => &["x", "y"],
            4 => &["xx", "xy", "yx", "yy"],
            8 => &["ρ", "ρv_x", "ρv_y", "ρb_x", "ρb_y", "σ_xx", "σ_yy", "σ_xy"],
            _ => &[],
        };
        let c = self.components.max(1);
        (flat / c, names.get(flat % c).copied())
    }
}

/// A 1D equation: one value per index; `_point` documents where the step
/// makes it final.
const fn eq(
    key: &'static str,
    symbol: &'static str,
    quantity: &'static str,
    citation: &'static str,
    index: IndexKind,
    _point: StepPoint,
) -> Equation {
    eq2(key, symbol, quantity, citation, index, 1)
}

const fn eq2(
    key: &'static str,
    symbol: &'static str,
    quantity: &'static str,
    citation: &'static str,
    index: IndexKind,
    components: usize,
) -> Equation {
    Equation {
        key,
        symbol,
        quantity,
        citation,
        index,
        components,
    }
}

/// The traced equations of the 1D MUSL step, in the order the step
/// computes them (the order in which `hompm check` looks for the first
/// difference). The stress key is `book-4.15` for the small-strain update
/// `book-4.16` for the large-strain one and `mls-37-1d` for the
/// neo-Hookean one (the manufactured strip); all are listed.
pub const EQUATIONS_1D: [Equation; 23] = [
    eq(
        "book-4.5",
        "m_i",
        "the lumped nodal mass",
        "book Eq. (4.5)",
        IndexKind::Dof,
        StepPoint::MassAndLoads,
    ),
    eq(
        "thesis-3.2",
        "f_ext,i",
        "the external nodal force (gravity and traction)",
        "thesis §3.2",
        IndexKind::Dof,
        StepPoint::MassAndLoads,
    ),
    eq(
        "nodal-momentum",
        "p_i",
        "another code's grid momentum Σ m_p v_p φ_i at the start of the step",
        "MLS paper Eq. (19), 1D",
        IndexKind::Dof,
        StepPoint::GridVelocity,
    ),
    eq(
        "nodal-velocity",
        "v_i^n",
        "another code's grid velocity p_i/m_i, 0 on Dirichlet DOFs",
        "MLS paper Eq. (19), 1D",
        IndexKind::Dof,
        StepPoint::GridVelocity,
    ),
    eq(
        "book-4.6",
        "f_int,i",
        "the internal nodal force",
        "book Eq. (4.6)",
        IndexKind::Dof,
        StepPoint::InternalForce,
    ),
    eq(
        "book-4.8",
        "a_i",
        "the nodal acceleration before the boundary conditions",
        "book Eq. (4.8)",
        IndexKind::Dof,
        StepPoint::Acceleration,
    ),
    eq(
        "book-4.8-bc",
        "a_i",
        "the nodal acceleration with the boundary conditions",
        "book Eq. (4.8) and §4.2.2",
        IndexKind::Dof,
        StepPoint::AccelerationConditions,
    ),
    eq(
        "nodal-velocity-updated",
        "ṽ_i",
        "another code's updated grid velocity v_i^n + Δt a_i, 0 on Dirichlet DOFs",
        "MLS paper Eqs. (27)-(28), 1D",
        IndexKind::Dof,
        StepPoint::UpdatedGridVelocity,
    ),
    eq(
        "book-4.9",
        "v_p",
        "the updated particle velocity",
        "book Eq. (4.9)",
        IndexKind::Particle,
        StepPoint::ParticleVelocity,
    ),
    eq(
        "book-4.10-rhs",
        "p_i",
        "the projection's right-hand side (nodal momentum)",
        "book Eq. (4.10)",
        IndexKind::Dof,
        StepPoint::NodalVelocity,
    ),
    eq(
        "book-4.10",
        "v_i",
        "the projected nodal velocity before the boundary conditions",
        "book Eq. (4.10)",
        IndexKind::Dof,
        StepPoint::NodalVelocity,
    ),
    eq(
        "book-4.10-solver",
        "[iterations, residual]",
        "the projection solver's iterations and final relative residual",
        "thesis §7.2",
        IndexKind::Solver,
        StepPoint::NodalVelocity,
    ),
    eq(
        "book-4.10-bc",
        "v_i",
        "the projected nodal velocity with the boundary conditions",
        "book Eq. (4.10) and §4.2.2",
        IndexKind::Dof,
        StepPoint::NodalVelocityConditions,
    ),
    eq(
        "book-4.11",
        "Δu_i",
        "the nodal displacement increment",
        "book Eq. (4.11)",
        IndexKind::Dof,
        StepPoint::Positions,
    ),
    eq(
        "book-4.12",
        "u_p",
        "the particle displacement",
        "book Eq. (4.12)",
        IndexKind::Particle,
        StepPoint::Positions,
    ),
    eq(
        "book-4.13",
        "x_p",
        "the particle position",
        "book Eq. (4.13)",
        IndexKind::Particle,
        StepPoint::Positions,
    ),
    eq(
        "book-4.14",
        "Δε_p",
        "the particle strain increment",
        "book Eq. (4.14)",
        IndexKind::Particle,
        StepPoint::Positions,
    ),
    eq(
        "book-4.15",
        "σ_p",
        "the particle stress (small-strain update)",
        "book Eq. (4.15)",
        IndexKind::Particle,
        StepPoint::Stress,
    ),
    eq(
        "book-4.16",
        "σ_p",
        "the particle stress (large-strain update)",
        "book Eq. (4.16)",
        IndexKind::Particle,
        StepPoint::Stress,
    ),
    eq(
        "mls-37-1d",
        "σ_p",
        "the particle stress (neo-Hookean, F_p ← (1 + Δε_p) F_p)",
        "MLS paper Eq. (37) in 1D",
        IndexKind::Particle,
        StepPoint::Stress,
    ),
    eq(
        "book-4.17",
        "V_p",
        "the particle volume",
        "book Eq. (4.17)",
        IndexKind::Particle,
        StepPoint::VolumeAndDensity,
    ),
    eq(
        "book-4.18",
        "ρ_p",
        "the particle density",
        "book Eq. (4.18)",
        IndexKind::Particle,
        StepPoint::VolumeAndDensity,
    ),
    eq(
        "book-4.14-strain",
        "ε_p",
        "the accumulated particle strain Σ Δε_p",
        "book Eq. (4.14), summed",
        IndexKind::Particle,
        StepPoint::VolumeAndDensity,
    ),
];

/// The traced equations of the 2D step (MLS paper Eqs. 18–41), in the
/// order the step computes them. Vectors and tensors are flattened per
/// node or particle ([`Equation::components`]).
pub const EQUATIONS_2D: [Equation; 17] = [
    eq2(
        "mls-18-21",
        "[ρ, ρv, ρb, σ]_g",
        "the values at the Gauss points, by MLS or (bsmpm-tls) TLS",
        "MLS paper Eqs. (18)-(21)",
        IndexKind::GaussPoint,
        8,
    ),
    eq2(
        "mls-22",
        "m_i",
        "the lumped nodal mass",
        "MLS paper Eq. (22)",
        IndexKind::Node,
        1,
    ),
    eq2(
        "mls-23",
        "(mv)_i",
        "the nodal momentum",
        "MLS paper Eq. (23)",
        IndexKind::Node,
        2,
    ),
    eq2(
        "nodal-body-force",
        "b(X_i, t)",
        "the body force per unit mass at the nodes (--body-force nodes)",
        "docs/conventions.md, \"Conventions of other codes\"",
        IndexKind::Node,
        2,
    ),
    eq2(
        "mls-26",
        "f_i",
        "the nodal force f^b + f^int",
        "MLS paper Eqs. (24)-(26)",
        IndexKind::Node,
        2,
    ),
    eq2(
        "mls-27",
        "a_i",
        "the nodal acceleration with the wall conditions",
        "MLS paper Eq. (27)",
        IndexKind::Node,
        2,
    ),
    eq2(
        "mls-28",
        "(mv)_i^{t+1}",
        "the updated nodal momentum",
        "MLS paper Eq. (28)",
        IndexKind::Node,
        2,
    ),
    eq2(
        "mls-29",
        "v_p",
        "the updated particle velocity",
        "MLS paper Eq. (29)",
        IndexKind::Particle,
        2,
    ),
    eq2(
        "mls-30",
        "x_p",
        "the particle position",
        "MLS paper Eq. (30)",
        IndexKind::Particle,
        2,
    ),
    eq2(
        "mls-30-u",
        "u_p",
        "the particle displacement x_p − X_p",
        "MLS paper Eq. (30)",
        IndexKind::Particle,
        2,
    ),
    eq2(
        "apic-c",
        "C_p",
        "APIC's affine velocity (--transfer apic)",
        "Jiang et al. (2015); docs/conventions.md, \"Conventions of other codes\"",
        IndexKind::Particle,
        4,
    ),
    eq2(
        "mls-32",
        "(mv)_i^L",
        "the end-of-step nodal momentum",
        "MLS paper Eqs. (31)-(32)",
        IndexKind::Node,
        2,
    ),
    eq2(
        "mls-33",
        "v_i^L",
        "the end-of-step nodal velocity with the wall conditions",
        "MLS paper Eq. (33)",
        IndexKind::Node,
        2,
    ),
    eq2(
        "mls-35",
        "F_p",
        "the deformation gradient",
        "MLS paper Eqs. (34)-(35)",
        IndexKind::Particle,
        4,
    ),
    eq2(
        "mls-36",
        "V_p",
        "the particle volume",
        "MLS paper Eq. (36)",
        IndexKind::Particle,
        1,
    ),
    eq2(
        "mls-37",
        "ρ_p",
        "the particle density",
        "MLS paper Eq. (37)",
        IndexKind::Particle,
        1,
    ),
    eq2(
        "mls-41",
        "σ_p",
        "the Cauchy stress",
        "MLS paper Eq. (41)",
        IndexKind::Particle,
        4,
    ),
];

/// The traced equation with key `key`, 1D or 2D.
pub fn equation(key: &str) -> Option<&'static Equation> {
    EQUATIONS_1D
        .iter()
        .chain(EQUATIONS_2D.iter())
        .find(|e| e.key == key)
}
