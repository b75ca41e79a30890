//! # The run monitors of a 1D step
//!
//! The switch that turns every recorder of [`super::Simulation::step`]
//! off for timing ([`Simulation::without_diagnostics`], issue #39). The
//! recorders themselves are called where their quantities are computed
//! (steps 2, 4 and 8 of the parent module).

use super::Simulation;

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
}
