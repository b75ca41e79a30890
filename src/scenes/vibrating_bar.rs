//! # The vibrating bar with fixed ends
//!
//! Thesis §4.1, TLS paper §6.1, book §4.5. A bar [0, L] fixed at both ends
//! starts with u = 0, σ = 0 and v(x, 0) = v₀ sin(πx/L). For small strains the
//! analytic solution is (thesis Eq. 4.1, book Eqs. 4.50–4.52)
//!
//! u = v₀/ω sin(ωt) sin(πx/L),  v = v₀ cos(ωt) sin(πx/L),
//! σ = v₀ √(Eρ) sin(ωt) cos(πx/L),  ω = π√(E/ρ)/L.
//!
//! The TLS paper prints σ = v₀√(E/ρ)…; the dimensionally right factor is
//! √(Eρ) = E/c (book Eq. 4.52), which hompm uses (docs/conventions.md).
//!
//! Items: [`BarParameters`], [`PARAMETER_SETS`], [`parameters`].

use super::Discretisation;
use crate::error::{Error, Result};
use crate::mpm::grid::Grid;
use crate::mpm::musl::{Constitutive, Simulation};
use crate::mpm::particles::Particles;
use serde::Serialize;
use std::f64::consts::PI;

/// One named parameter set of the bar.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BarParameters {
    /// Name, e.g. `thesis-table-4.1`.
    pub name: &'static str,
    /// Length L (or H).
    pub length: f64,
    /// Density ρ.
    pub density: f64,
    /// Young's modulus E.
    pub young: f64,
    /// Maximal initial velocity v₀.
    pub v0: f64,
    /// Small- or large-strain update.
    pub constitutive: Constitutive,
}

/// Every parameter set of the seeds.
pub const PARAMETER_SETS: [BarParameters; 6] = [
    BarParameters {
        name: "thesis-table-4.1",
        length: 25.0,
        density: 1.0,
        young: 100.0,
        v0: 0.1,
        constitutive: Constitutive::SmallStrain,
    },
    BarParameters {
        name: "thesis-table-4.2",
        length: 1.0,
        density: 25.0,
        young: 50.0,
        v0: 0.1,
        constitutive: Constitutive::LargeStrain,
    },
    BarParameters {
        name: "tls-table-2",
        length: 1.0,
        density: 2.0e3,
        young: 7.0e6,
        v0: 0.28,
        constitutive: Constitutive::SmallStrain,
    },
    BarParameters {
        name: "tls-table-4",
        length: 1.0,
        density: 2.0e3,
        young: 4.0e4,
        v0: 0.8,
        constitutive: Constitutive::LargeStrain,
    },
    BarParameters {
        name: "book-table-4.1",
        length: 1.0,
        density: 2.0e3,
        young: 7.0e6,
        v0: 0.28,
        constitutive: Constitutive::SmallStrain,
    },
    BarParameters {
        name: "book-table-4.1-large",
        length: 1.0,
        density: 2.0e3,
        young: 7.0e6,
        v0: 0.8,
        constitutive: Constitutive::LargeStrain,
    },
];

/// Looks up a parameter set by name.
pub fn parameters(name: &str) -> Result<BarParameters> {
    super::find_set(&PARAMETER_SETS, |p| p.name, name, "vibrating-bar")
}

impl BarParameters {
    /// Wave speed c = √(E/ρ).
    pub fn wave_speed(&self) -> f64 {
        (self.young / self.density).sqrt()
    }

    /// ω = π c / L.
    pub fn omega(&self) -> f64 {
        PI * self.wave_speed() / self.length
    }

    /// Analytic displacement, thesis Eq. (4.1) / book Eq. (4.50).
    pub fn displacement(&self, x: f64, t: f64) -> f64 {
        self.v0 / self.omega() * (self.omega() * t).sin() * (PI * x / self.length).sin()
    }

    /// Analytic velocity, book Eq. (4.51).
    pub fn velocity(&self, x: f64, t: f64) -> f64 {
        self.v0 * (self.omega() * t).cos() * (PI * x / self.length).sin()
    }

    /// Analytic stress, book Eq. (4.52), with √(Eρ).
    pub fn stress(&self, x: f64, t: f64) -> f64 {
        self.v0
            * (self.young * self.density).sqrt()
            * (self.omega() * t).sin()
            * (PI * x / self.length).cos()
    }

    /// The simulation: particles at the centres of `cells·ppc` equal
    /// sub-intervals (V_p = L/n_p, v_p = v₀ sin(πx_p/L)), both end DOFs fixed.
    pub fn simulation(&self, d: &Discretisation) -> Result<Simulation> {
        if d.ppc == 0 || d.cells == 0 {
            return Err(Error::InvalidArgument(
                "cells and particles per cell must be positive".into(),
            ));
        }
        let grid = Grid::with_knots(d.method, 0.0, self.length, d.cells, d.conventions.knots)?;
        let mut particles = Particles::uniform(0.0, self.length, d.cells * d.ppc, self.density)?;
        for k in 0..particles.len() {
            particles.velocity[k] = self.velocity(particles.x0[k], 0.0);
        }
        let last = grid.num_dofs() - 1;
        let settings = d.settings(self.constitutive, self.young, 0.0, None, vec![0, last]);
        Simulation::new(grid, particles, settings)
    }
}
