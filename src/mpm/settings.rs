//! # What a 1D run is set up with
//!
//! Everything a run needs besides the grid and the particles: the mappings
//! of the internal force and the velocity (book §4.4, thesis ch. 7), the
//! mass matrix of the projection, the constitutive update of step 7 (book
//! Eqs. 4.15–4.16), E, gravity and its ramp (TLS paper §6.2), the Dirichlet
//! DOFs, the consistent acceleration of the CFL study and the TLS density
//! fit's cell average, and the conventions of other codes
//! ([`super::conventions`]).
//!
//! Items: [`Constitutive`], [`Settings`].

use super::conventions::Conventions;
use super::mapping::{Mapping, MassMatrix};
use crate::reconstruct::taylor::CellAverage;
use serde::Serialize;

/// The constitutive update of step 7.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Constitutive {
    /// σ ← σ + E Δε (book Eq. 4.15).
    SmallStrain,
    /// σ ← σ + (E − σ) Δε (book Eq. 4.16).
    LargeStrain,
}

/// Everything a run needs besides the grid and the particles.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Settings {
    /// Mapping of the internal force.
    pub force_mapping: Mapping,
    /// Mapping of the nodal velocity.
    pub velocity_mapping: Mapping,
    /// Mass matrix of the velocity projection.
    pub mass: MassMatrix,
    /// Constitutive update.
    pub constitutive: Constitutive,
    /// Young's modulus E.
    pub young: f64,
    /// Gravitational acceleration g (signed: −9.81 points down the axis).
    pub gravity: f64,
    /// If set, gravity ramps linearly from 0 to `gravity` over this time and
    /// then stays (the body force of the column compaction, TLS paper §6.2).
    pub gravity_ramp: Option<f64>,
    /// DOFs with homogeneous Dirichlet conditions.
    pub dirichlet: Vec<usize>,
    /// Solve step 2 with the material-point consistent mass M^C = Σ m_p φφᵀ
    /// (sparse Cholesky) instead of the lumped mass (CFL study; book Eq. 4.1).
    pub consistent_acceleration: bool,
    /// How the TLS density fit averages (x − x_c)² in ψ_3 (book Eq. 4.30):
    /// exact, or with the TLS author's rounding (docs/conventions.md, "The
    /// TLS author's cell average"). Not printed when exact.
    #[serde(skip_serializing_if = "CellAverage::is_exact")]
    pub tls_density_average: CellAverage,
    /// Scheme, transfer, positions and body force ([`Conventions::BOOK`]
    /// unless another code's are asked for). Not printed when the book's.
    #[serde(skip_serializing_if = "Conventions::is_book")]
    pub conventions: Conventions,
}
