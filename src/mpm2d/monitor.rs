//! # The 2D run under the stability monitor
//!
//! The monitor of the 1D run ([`crate::mpm::monitor`]) watches the 2D run
//! through [`Watched`]: after each step, the kinetic energy
//! Σ_p ½ m_p |v_p|² must stay within [`ENERGY_GROWTH_BOUND`] × its budget.
//! A 2D step already refuses det F ≤ 0 (MLS paper Eq. 41) and a particle
//! that left the square; in every diverging case tried those came first
//! (docs/conventions.md, "The stability monitor"), so the energy rule is
//! the 1D rule carried over, loose in 2D. There is no strain limit in 2D
//! (see [`Watched::strain_at_limit`] for `Simulation2d`).
//!
//! The budget is [`ENERGY_GROWTH_BOUND`] × the sum of the kinetic energy
//! at the start and the most work the loads can do, as in 1D. The loads' share comes from
//! the scene (the aligned vibration's manufactured body force,
//! `scenes::aligned_vibration::AlignedVibration::work_bound`): a coarse
//! run departs from the exact solution, and the prescribed body force then
//! does work on it. BSMPM on 8 × 8 cells with Δt = 1e-5 reaches 10 × its
//! initial kinetic energy at t = 0.091 and still ends at t = 0.2 with an
//! RMS error in u of 0.10 (A = 0.1): inaccurate, not diverging. A budget
//! without the loads' work would stop it.
//!
//! Items: [`stability_monitor`], [`kinetic_energy`].

use super::step::Simulation2d;
use crate::error::DivergenceCause;
use crate::mpm::monitor::{StabilityMonitor, Watched, ENERGY_GROWTH_BOUND};

/// Σ_p ½ m_p |v_p|².
pub fn kinetic_energy(sim: &Simulation2d) -> f64 {
    let p = &sim.particles;
    p.mass
        .iter()
        .zip(&p.velocity)
        .map(|(m, v)| 0.5 * m * (v[0] * v[0] + v[1] * v[1]))
        .sum()
}

/// The monitor of a 2D run that starts from `sim`, whose loads can do at
/// most `work_of_loads`: a budget of [`ENERGY_GROWTH_BOUND`] × (the kinetic
/// energy at the start + `work_of_loads`), as 1D's; no warnings (no 2D
/// critical Courant number is measured).
pub fn stability_monitor(sim: &Simulation2d, work_of_loads: f64) -> StabilityMonitor {
    StabilityMonitor::with_budget(
        ENERGY_GROWTH_BOUND * (kinetic_energy(sim) + work_of_loads),
        Vec::new(),
    )
}

impl Watched for Simulation2d {
    fn steps_done(&self) -> usize {
        self.steps
    }

    fn time(&self) -> f64 {
        self.time
    }

    fn energy(&self) -> f64 {
        kinetic_energy(self)
    }

    fn fastest_particle(&self) -> Option<usize> {
        let v = &self.particles.velocity;
        let speed2 = |k: usize| v[k][0] * v[k][0] + v[k][1] * v[k][1];
        (0..v.len()).max_by(|&i, &j| speed2(i).total_cmp(&speed2(j)))
    }

    /// None: the neo-Hookean solid is a finite-strain model, and a step
    /// already refuses det F ≤ 0 (MLS paper Eq. 41). A bound on F − I like
    /// 1D's |ε| ≥ 1 stopped runs that do not diverge: BSMPM on 8 × 8 cells
    /// reaches |F − I| ≥ 1 at t ≈ 0.0126 for every Δt from 1e-3 to 1e-5
    /// (1.067 … 1.0004), the method's spatial error on 8 cells
    /// (docs/conventions.md).
    fn strain_at_limit(&self) -> Option<(usize, DivergenceCause)> {
        None
    }
}
