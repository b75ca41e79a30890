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
//! Items: [`Constitutive`], [`BodyForceField`], [`GravityRamp`], [`RampTimeLevel`], [`Settings`].

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
    /// The neo-Hookean law in one dimension (F_yy = F_zz = 1):
    /// F_p ← (1 + Δε_p) F_p, V_p = V_p⁰ F_p, ρ_p = m_p/V_p and
    /// σ_p = (λ ln F_p + μ(F_p² − 1))/F_p, with λ and μ of
    /// [`Settings::young`] and [`Settings::poisson`] (MLS paper Eq. 37 with
    /// J = F; its code's `Update_Stress.m` and `Neo_Hookean_elastic.m`, as
    /// `BSMPM_solvertest.m` runs them on its strip; issue #40).
    NeoHookean,
}

/// A body force per unit mass b(X, t) given by a formula of the initial
/// position and the time, mapped as Σ_p m_p b(X_p, tⁿ) φ_i(x_p) at the
/// start of each step (a manufactured solution's source term; the MLS
/// paper's code evaluates it so in `Vibration.m` before each solver call).
#[derive(Clone)]
pub struct BodyForceField {
    /// What the formula is, for the run document.
    pub name: &'static str,
    /// b(X, t).
    pub at: std::sync::Arc<dyn Fn(f64, f64) -> f64 + Send + Sync>,
    /// An upper bound of |b(X, t)| over the body and the run: the
    /// stability monitor counts the work Σ_p m_p · bound · L among the
    /// loads' (`mpm::monitor`, as the 2D monitor counts its body force's).
    pub bound: f64,
}

impl std::fmt::Debug for BodyForceField {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "BodyForceField({})", self.name)
    }
}

impl PartialEq for BodyForceField {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name && std::sync::Arc::ptr_eq(&self.at, &other.at)
    }
}

impl Serialize for BodyForceField {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.name)
    }
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
    /// Poisson's ratio ν, read only by [`Constitutive::NeoHookean`]
    /// (λ = Eν/((1 + ν)(1 − 2ν)), μ = E/(2(1 + ν))). Not printed when 0.
    #[serde(skip_serializing_if = "is_zero")]
    pub poisson: f64,
    /// Gravitational acceleration g (signed: −9.81 points down the axis).
    pub gravity: f64,
    /// A body force b(X, t) per unit mass besides gravity (a manufactured
    /// solution's). Not printed when absent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub body_force: Option<BodyForceField>,
    /// If set, gravity ramps linearly from 0 to `gravity` over the ramp's
    /// duration and then stays (the body force of the column compaction,
    /// TLS paper §6.2).
    pub gravity_ramp: Option<GravityRamp>,
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

/// When in a step of size Δt from tⁿ a ramped gravity is evaluated. TLS
/// paper Eq. (10) writes the external force at tⁿ ([`RampTimeLevel::StepStart`],
/// hompm's default); a code that advances its clock before it loads the
/// grid evaluates it at tⁿ⁺¹ ([`RampTimeLevel::StepEnd`]). The two differ
/// by one step of the ramp, and the compaction's stress errors by up to
/// 11 % (docs/conventions.md, "The time level of a ramped body force").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RampTimeLevel {
    /// g(tⁿ): TLS paper Eq. (10), (f^ext)^t.
    #[default]
    StepStart,
    /// g(tⁿ + Δt).
    StepEnd,
}

impl RampTimeLevel {
    fn is_step_start(&self) -> bool {
        *self == RampTimeLevel::StepStart
    }
}

/// A gravity ramped linearly from 0 to its full value over `duration`, then
/// held: g(t) = g·min(t/duration, 1) (TLS paper §6.2, "the body force
/// increases linearly with time").
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GravityRamp {
    /// The ramp's duration (TLS paper Table 6: the run's 0.5 s).
    pub duration: f64,
    /// When in a step the ramp is read. Not printed when at the step's start.
    #[serde(skip_serializing_if = "RampTimeLevel::is_step_start")]
    pub time_level: RampTimeLevel,
}

impl GravityRamp {
    /// A ramp over `duration`, read at the start of each step (TLS paper
    /// Eq. 10).
    pub fn over(duration: f64) -> Self {
        Self {
            duration,
            time_level: RampTimeLevel::StepStart,
        }
    }

    /// The fraction min(t/duration, 1) of the full gravity at time t (1 for
    /// a duration ≤ 0: no ramp).
    pub fn fraction_at(&self, t: f64) -> f64 {
        if self.duration > 0.0 {
            (t / self.duration).min(1.0)
        } else {
            1.0
        }
    }

    /// The time at which a step of size Δt from tⁿ reads the ramp.
    pub fn read_time(&self, step_start: f64, dt: f64) -> f64 {
        match self.time_level {
            RampTimeLevel::StepStart => step_start,
            RampTimeLevel::StepEnd => step_start + dt,
        }
    }
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

impl Settings {
    /// Lamé's λ and μ of E and ν.
    pub fn lame(&self) -> (f64, f64) {
        let (e, nu) = (self.young, self.poisson);
        // In the order of the MLS paper's code (`Vibration.m`, lines 25–26).
        (e * nu / (1.0 + nu) / (1.0 - 2.0 * nu), e / 2.0 / (1.0 + nu))
    }
}
