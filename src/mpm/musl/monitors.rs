//! # The run monitors of a 1D step
//!
//! The switch that turns every recorder of [`super::Simulation::step`]
//! off for timing ([`Simulation::without_diagnostics`], issue #39), and
//! the step that reports what the stability monitor reads
//! ([`Simulation::step_summarised`], [`StepSummary`]). The recorders
//! themselves are called where their quantities are computed (steps 2, 4
//! and 8 of the parent module, or the fused loops).

use super::Simulation;
use crate::error::Result;

/// One particle's kinetic plus strain energy ½ m v² + ½ σ ε V.
#[inline(always)]
pub(super) fn particle_energy(
    mass: f64,
    velocity: f64,
    stress: f64,
    strain: f64,
    volume: f64,
) -> f64 {
    0.5 * mass * velocity * velocity + 0.5 * stress * strain * volume
}

/// What a step reports of the particles it leaves, for the stability
/// monitor ([`Simulation::step_summarised`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepSummary {
    /// [`Simulation::energy`] after the step.
    pub energy: f64,
    /// max_p |ε_p| after the step (NaN strains ignored, as `f64::max` does).
    pub max_abs_strain: f64,
}

impl Simulation {
    /// The same simulation with its run monitors off: the steps skip every
    /// update of [`RunDiagnostics`](crate::mpm::diagnostics::RunDiagnostics) (the lumped-mass extremes, the
    /// projection's conservation errors and speeds, the strain extreme and
    /// the grid crossings), so `diagnostics` keeps its initial values. The
    /// particles and the grid evolve bit for bit as with them on, and the
    /// check that every particle stays physical still runs; the stability
    /// monitor's energy and strain checks read the particles and still
    /// work, its negative-mass warning reads the diagnostics and stays
    /// silent. For timing what the monitors cost (benches/lean_p1.rs,
    /// issue #39).
    pub fn without_diagnostics(mut self) -> Self {
        self.records_diagnostics = false;
        self
    }

    /// Whether the steps record [`RunDiagnostics`](crate::mpm::diagnostics::RunDiagnostics).
    pub fn records_diagnostics(&self) -> bool {
        self.records_diagnostics
    }

    /// One step of size dt ([`Simulation::step`]) and what it leaves for
    /// the stability monitor: the energy and the largest strain, found by
    /// the fused step in its last particle loop (else by a pass each).
    /// [`StabilityMonitor::check_step`](crate::mpm::monitor::StabilityMonitor::check_step)
    /// reads it.
    pub fn step_summarised(&mut self, dt: f64) -> Result<StepSummary> {
        crate::mpm::check_time_step(dt)?;
        if self.step_is_fused() {
            return self.step_fused(dt, true);
        }
        self.step(dt)?;
        let strain = &self.particles.strain;
        Ok(StepSummary {
            energy: self.energy(),
            max_abs_strain: strain.iter().map(|e| e.abs()).fold(0.0, f64::max),
        })
    }
}
