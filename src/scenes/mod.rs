//! # Benchmark scenes
//!
//! Each scene has named parameter sets (one per seed table, kept separate
//! because the seeds' values differ), builds the grid and particles, and
//! provides the analytic solution where one exists.
//!
//! - [`vibrating_bar`]: thesis §4.1 (Tables 4.1/4.2), TLS paper §6.1
//!   (Tables 2/4), book §4.5 (Table 4.1);
//! - [`column`](mod@column): the column under self-weight (thesis §4.2, Tables 4.3/4.4,
//!   series solution Eq. 4.2) and with a top load (thesis Table 8.1).
//!
//! - [`aligned_vibration`]: the MLS paper's 2D manufactured neo-Hookean
//!   vibration (Eqs. 38–42).
//! - [`manufactured_strip`]: the 1D strip the MLS paper's own code runs
//!   for its figures (issue #40).
//!
//! Items: [`Discretisation`], [`aligned_vibration`], [`column`](mod@column), [`manufactured_strip`], [`vibrating_bar`].

pub mod aligned_vibration;
pub mod column;
pub mod manufactured_strip;
pub mod vibrating_bar;

use crate::mpm::conventions::Conventions;
use crate::mpm::grid::Method;
use crate::mpm::mapping::{Mapping, MassMatrix};
use serde::Serialize;

/// The discretisation and algorithm choices of a run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Discretisation {
    /// Method (basis).
    pub method: Method,
    /// Mapping of the internal force.
    pub force_mapping: Mapping,
    /// Mapping of the nodal velocity.
    pub velocity_mapping: Mapping,
    /// Mass matrix of the velocity projection.
    pub mass: MassMatrix,
    /// Elements or knot spans.
    pub cells: usize,
    /// Particles per cell.
    pub ppc: usize,
    /// The conventions of the step (scheme, transfer, positions, body
    /// force); the book's by default.
    #[serde(skip_serializing_if = "Conventions::is_book")]
    pub conventions: Conventions,
}

impl Discretisation {
    /// The same mapping for force and velocity.
    pub fn new(
        method: Method,
        mapping: Mapping,
        mass: MassMatrix,
        cells: usize,
        ppc: usize,
    ) -> Self {
        Self {
            method,
            force_mapping: mapping,
            velocity_mapping: mapping,
            mass,
            cells,
            ppc,
            conventions: Conventions::BOOK,
        }
    }

    /// Standard MPM mapping with lumped mass (book §4.2.2).
    pub fn direct(method: Method, cells: usize, ppc: usize) -> Self {
        Self::new(method, Mapping::Direct, MassMatrix::Lumped, cells, ppc)
    }

    /// The run settings of this discretisation for a scene's material and
    /// boundary conditions.
    pub fn settings(
        &self,
        constitutive: crate::mpm::musl::Constitutive,
        young: f64,
        gravity: f64,
        gravity_ramp: Option<f64>,
        dirichlet: Vec<usize>,
    ) -> crate::mpm::musl::Settings {
        crate::mpm::musl::Settings {
            force_mapping: self.force_mapping,
            velocity_mapping: self.velocity_mapping,
            mass: self.mass,
            constitutive,
            young,
            poisson: 0.0,
            gravity,
            body_force: None,
            gravity_ramp: gravity_ramp.map(crate::mpm::musl::GravityRamp::over),
            dirichlet,
            consistent_acceleration: false,
            tls_density_average: crate::reconstruct::taylor::CellAverage::Exact,
            conventions: self.conventions,
        }
    }
}

/// Finds the parameter set called `name` among `sets`, or names the known ones.
pub(crate) fn find_set<T: Copy>(
    sets: &[T],
    name_of: fn(&T) -> &'static str,
    name: &str,
    scene: &str,
) -> crate::Result<T> {
    sets.iter()
        .copied()
        .find(|p| name_of(p) == name)
        .ok_or_else(|| {
            let names: Vec<&str> = sets.iter().map(name_of).collect();
            crate::Error::InvalidArgument(format!(
                "unknown {scene} parameter set '{name}' (known: {})",
                names.join(", ")
            ))
        })
}
