//! # The column: self-weight and top load
//!
//! Thesis §4.2: a column [0, H] fixed at the bottom, free (or loaded by p₀) at
//! the top, suddenly loaded by gravity. For small strains (thesis Eq. 4.2),
//!
//! u(y,t) = ρ g y²/(2E) + (p₀ − ρ g H) y/E
//!          + Σ_n u_n cos(c(2n−1)πt/(2H)) sin((2n−1)πy/(2H)),
//! u_n = 8H(2πp₀n(−1)ⁿ + 2ρgH − πp₀(−1)ⁿ) / ((4n²−4n+1)(2n−1)π³E),
//!
//! The column compaction of TLS paper §6.2 (Table 6) ramps the body force
//! linearly to b_f over the run; its stress is compared with the equilibrium
//! stress ρ₀ b(t)(H − X) ([`ColumnParameters::equilibrium_stress`]).
//!
//! where g is the *magnitude* 9.81 and the body force points down (the
//! thesis' tables write g = −9.81 for the vector; docs/conventions.md).
//!
//! Items: [`ColumnParameters`], [`PARAMETER_SETS`], [`parameters`].

use super::Discretisation;
use crate::error::{Error, Result};
use crate::mpm::grid::Grid;
use crate::mpm::musl::{Constitutive, Simulation};
use crate::mpm::particles::Particles;
use serde::Serialize;
use std::f64::consts::PI;

/// One named parameter set of the column.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ColumnParameters {
    /// Name, e.g. `thesis-table-4.3`.
    pub name: &'static str,
    /// Height H.
    pub height: f64,
    /// Density ρ.
    pub density: f64,
    /// Young's modulus E.
    pub young: f64,
    /// Gravitational acceleration along the axis (−9.81: downwards).
    pub gravity: f64,
    /// Top load p₀ (negative: compression).
    pub top_load: f64,
    /// Small- or large-strain update.
    pub constitutive: Constitutive,
    /// If set, the body force ramps linearly from zero to `gravity` over this
    /// time (column compaction, TLS paper §6.2). Left out of JSON when unset.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ramp_time: Option<f64>,
}

/// Every parameter set of the seeds.
pub const PARAMETER_SETS: [ColumnParameters; 4] = [
    ColumnParameters {
        name: "thesis-table-4.3",
        height: 25.0,
        density: 1.0,
        young: 5.0e4,
        gravity: -9.81,
        top_load: 0.0,
        constitutive: Constitutive::SmallStrain,
        ramp_time: None,
    },
    ColumnParameters {
        name: "thesis-table-4.4",
        height: 1.0,
        density: 1.0e3,
        young: 1.0e5,
        gravity: -9.81,
        top_load: 0.0,
        constitutive: Constitutive::LargeStrain,
        ramp_time: None,
    },
    ColumnParameters {
        name: "thesis-table-8.1",
        height: 1.0,
        density: 1.0e3,
        young: 1.0e5,
        gravity: 0.0,
        top_load: -1.0e4,
        constitutive: Constitutive::LargeStrain,
        ramp_time: None,
    },
    ColumnParameters {
        name: "tls-table-6",
        height: 50.0,
        density: 1.0,
        young: 1.0e6,
        gravity: -200.0,
        top_load: 0.0,
        constitutive: Constitutive::LargeStrain,
        ramp_time: Some(0.5),
    },
];

/// Looks up a parameter set by name.
pub fn parameters(name: &str) -> Result<ColumnParameters> {
    super::find_set(&PARAMETER_SETS, |p| p.name, name, "column")
}

impl ColumnParameters {
    /// Wave speed √(E/ρ).
    pub fn wave_speed(&self) -> f64 {
        (self.young / self.density).sqrt()
    }

    /// The series solution of thesis Eq. (4.2), summed to `terms` terms.
    pub fn displacement(&self, y: f64, t: f64, terms: usize) -> f64 {
        let (h, e, rho, p0) = (self.height, self.young, self.density, self.top_load);
        let g = -self.gravity;
        let c = self.wave_speed();
        let mut u = 0.5 * rho * g * y * y / e + (p0 - rho * g * h) * y / e;
        for n in 1..=terms {
            let nf = n as f64;
            let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
            let un = 8.0 * h * (2.0 * PI * p0 * nf * sign + 2.0 * rho * g * h - PI * p0 * sign)
                / ((4.0 * nf * nf - 4.0 * nf + 1.0) * (2.0 * nf - 1.0) * PI.powi(3) * e);
            let k = (2.0 * nf - 1.0) * PI / (2.0 * h);
            u += un * (c * k * t).cos() * (k * y).sin();
        }
        u
    }

    /// The quasi-static equilibrium stress of a column under a body force:
    /// σ(X, t) = ρ₀ g(t) (H − X) in the reference configuration, g(t) ramped
    /// if the set has a ramp. In 1D the column is statically determinate, so
    /// this holds for any constitutive law once inertia is negligible (the
    /// compaction ramp lasts ten wave transits H/c). TLS paper §6.2, Fig. 10.
    pub fn equilibrium_stress(&self, x0: f64, t: f64) -> f64 {
        let g = match self.ramp_time {
            Some(tr) if tr > 0.0 => self.gravity * (t / tr).min(1.0),
            _ => self.gravity,
        };
        self.density * g * (self.height - x0) + self.top_load
    }

    /// The simulation: `cells·ppc` particles at centres of equal sub-intervals,
    /// bottom DOF fixed, the top load applied as a traction on the top particle
    /// (thesis §3.2: "particles initially located next to the boundary").
    pub fn simulation(&self, d: &Discretisation) -> Result<Simulation> {
        if d.ppc == 0 || d.cells == 0 {
            return Err(Error::InvalidArgument(
                "cells and particles per cell must be positive".into(),
            ));
        }
        let grid = Grid::with_knots(d.method, 0.0, self.height, d.cells, d.conventions.knots)?;
        let mut particles = Particles::uniform(0.0, self.height, d.cells * d.ppc, self.density)?;
        let top = particles.len() - 1;
        particles.traction[top] = self.top_load;
        let settings = d.settings(
            self.constitutive,
            self.young,
            self.gravity,
            self.ramp_time,
            vec![0],
        );
        Simulation::new(grid, particles, settings)
    }
}
