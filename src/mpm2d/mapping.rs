//! # The registry of 2D mappings
//!
//! How particle data reach the grid in a 2D step (MLS paper, "phase 1"):
//! directly by the B-spline functions (Eqs. 22–26), or through a
//! Gauss-point reconstruction, MLS (Eqs. 10–21), TLS (TLS paper §5 in
//! 2D) or partition-of-unity TLS (hompm's blend of TLS paper Eqs. 13–14).
//! A new mapping is one [`Mapping2d`] variant, one [`Mapping2d::info`] arm
//! and one [`Mapping2d::reconstruction`] arm.
//!
//! Items: [`Mapping2d`], [`MappingInfo`].

use super::mls::MlsShapes;
use super::pu_tls::PuTlsShapes;
use super::reconstruction::GaussReconstruction;
use super::tls::{BasisRule, TaylorOrder2d, TlsShapes};
use crate::error::Result;
use crate::reconstruct::taylor::DegenerateCells;
use serde::{Deserialize, Serialize};

/// How particle data reach the grid (MLS paper, "phase 1").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mapping2d {
    /// Particles as the quadrature points (standard MPM, BSMPM).
    Direct,
    /// MLS to the 2×2 Gauss points of each cell, then Gauss quadrature,
    /// in both mappings of a step (Eqs. 18–25 and 31–33).
    Mls,
    /// hompm's diagnostic variant: MLS in phase 1 (Eqs. 18–25) and the
    /// direct mapping for the end-of-step velocity (Eqs. 31–33), to tell
    /// which of the two MLS mappings drives the errors.
    MlsPhase1,
    /// Conservative Taylor least squares (TLS paper §5.2–5.5 on the cells,
    /// [`super::tls`]) in place of MLS, in both mappings of a step.
    Tls,
    /// [`Mapping2d::Tls`] with the basis chosen by each cell's particle
    /// count, as the 2D TLS of QuocAnh90/MPM2D_basic (cc01c1b,
    /// `SubFunctions/TLS2D.m:56-76`): [`super::tls::BasisRule::ParticleCount`].
    TlsByCount,
    /// Partition-of-unity TLS ([`super::pu_tls`], hompm's construction):
    /// conservative linear fits on the supports of the quadratic B-splines
    /// (TLS paper Eqs. 13–14 with the weights N_e), blended by them at the
    /// Gauss points; conservative and continuous, in both mappings of a step.
    PuTls,
    /// [`Mapping2d::PuTls`] with quadratic patches (ψ₁ … ψ₆, TLS paper §5.2
    /// in 2D as [`super::tls`]), reduced to linear, then constant, where
    /// degenerate.
    PuTlsQuadratic,
}

/// What the rest of hompm knows of a mapping: its names and its cost. One
/// [`Mapping2d::info`] arm per mapping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MappingInfo {
    /// The name in JSON (serde's) and on the command line, where the
    /// aligned vibration offers `bsmpm-<name>` (`direct` is plain `bsmpm`).
    pub name: &'static str,
    /// What a method label appends: `BSMPM-p2-<label>` (empty for direct).
    pub label: &'static str,
    /// One line for `--help`.
    pub summary: &'static str,
    /// The divan benchmark's cost of a step at degree 2, in ns per
    /// particle-step (benches/mpm2d.rs, rounded up): the command line's
    /// run-time estimate.
    pub ns_per_particle_step: f64,
    /// Bytes per particle that the reconstruction keeps besides the
    /// particles and the grid (the memory estimate).
    pub bytes_per_particle: f64,
}

impl Mapping2d {
    /// Every mapping, in the order the command line lists them.
    pub const ALL: [Mapping2d; 7] = [
        Mapping2d::Direct,
        Mapping2d::Mls,
        Mapping2d::MlsPhase1,
        Mapping2d::Tls,
        Mapping2d::TlsByCount,
        Mapping2d::PuTls,
        Mapping2d::PuTlsQuadratic,
    ];

    /// The registration of a mapping's names and cost.
    pub fn info(self) -> MappingInfo {
        match self {
            Mapping2d::Direct => MappingInfo {
                name: "direct",
                label: "",
                summary: "B-spline MPM of degree --degree (MLS paper Figs. 2-4)",
                ns_per_particle_step: 110.0,
                bytes_per_particle: 0.0,
            },
            Mapping2d::Mls => MappingInfo {
                name: "mls",
                label: "MLS",
                summary: "B-spline MPM with MLS to the Gauss points (MLS paper; aligned-vibration only)",
                ns_per_particle_step: 500.0,
                bytes_per_particle: 7.0 * 40.0 * 12.0,
            },
            Mapping2d::MlsPhase1 => MappingInfo {
                name: "mls-phase1",
                label: "MLS-phase-1",
                summary: "B-spline MPM with MLS in phase 1 only, hompm's diagnostic (aligned-vibration only)",
                ns_per_particle_step: 500.0,
                bytes_per_particle: 7.0 * 40.0 * 12.0,
            },
            Mapping2d::Tls => MappingInfo {
                name: "tls",
                label: "TLS",
                summary: "B-spline MPM with conservative Taylor least squares to the Gauss points (TLS paper §5 in 2D; aligned-vibration only)",
                ns_per_particle_step: 250.0,
                bytes_per_particle: 0.0,
            },
            Mapping2d::TlsByCount => MappingInfo {
                name: "tls-by-count",
                label: "TLS-by-count",
                summary: "B-spline MPM with conservative TLS whose basis follows each cell's particle count, as MPM2D_basic's TLS2D.m (aligned-vibration only)",
                ns_per_particle_step: 250.0,
                bytes_per_particle: 0.0,
            },
            Mapping2d::PuTls => MappingInfo {
                name: "pu-tls",
                label: "PU-TLS",
                summary: "B-spline MPM with partition-of-unity TLS to the Gauss points, conservative and continuous (hompm's construction; aligned-vibration only)",
                // Not benchmarked with divan: MLS's 500 ns scaled by the
                // instructions per particle-step (callgrind, 16 cells, 9
                // PPC: 14 100 against MLS's 7 500), rounded up.
                ns_per_particle_step: 1000.0,
                // 100 list entries (u32 + f64) per particle, 54 coefficients
                // and 6 basis values.
                bytes_per_particle: 100.0 * 12.0 + 60.0 * 8.0,
            },
            Mapping2d::PuTlsQuadratic => MappingInfo {
                name: "pu-tls-quadratic",
                label: "PU-TLS-quadratic",
                summary: "B-spline MPM with partition-of-unity TLS on quadratic patches (hompm's construction; aligned-vibration only)",
                // As PU-TLS: 18 300 instructions per particle-step.
                ns_per_particle_step: 1300.0,
                bytes_per_particle: 100.0 * 12.0 + 60.0 * 8.0,
            },
        }
    }

    /// The registration of the Gauss-point reconstructions: the
    /// [`GaussReconstruction`] of this mapping for `particles` particles on
    /// `cells`² cells (MLS with support scale `mls_support`), or `None` for
    /// the direct mapping.
    pub fn reconstruction(
        self,
        mls_support: f64,
        cells: usize,
        particles: usize,
    ) -> Result<Option<Box<dyn GaussReconstruction>>> {
        Ok(match self {
            Mapping2d::Direct => None,
            Mapping2d::Mls | Mapping2d::MlsPhase1 => {
                Some(Box::new(MlsShapes::new(mls_support, cells, particles)?))
            }
            Mapping2d::Tls => Some(Box::new(TlsShapes::for_engine(cells, particles)?)),
            Mapping2d::TlsByCount => Some(Box::new(
                TlsShapes::for_engine(cells, particles)?.with_basis_rule(BasisRule::ParticleCount),
            )),
            Mapping2d::PuTls => Some(Box::new(PuTlsShapes::for_engine(cells, particles)?)),
            Mapping2d::PuTlsQuadratic => Some(Box::new(PuTlsShapes::new(
                TaylorOrder2d::Quadratic,
                DegenerateCells::ReduceBasis,
                cells,
                particles,
            )?)),
        })
    }

    /// The mapping's name in JSON and on the command line:
    /// [`MappingInfo::name`].
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// The mapping of a name, if one is registered under it.
    pub fn from_name(name: &str) -> Option<Mapping2d> {
        Mapping2d::ALL.into_iter().find(|m| m.name() == name)
    }

    /// Whether the end-of-step velocity (Eqs. 31–33) is mapped through the
    /// reconstruction too (every reconstruction but the phase-1 diagnostic).
    pub fn reconstructs_end_of_step(self) -> bool {
        !matches!(self, Mapping2d::Direct | Mapping2d::MlsPhase1)
    }
}
