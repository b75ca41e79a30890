//! # The gravity that loads a 1D step
//!
//! Step 1's gravity load Σ_p m_p g φ_i (thesis §3.2) takes g from here: the
//! constant g, or the ramp of the column compaction (TLS paper §6.2,
//! [`GravityRamp`](super::GravityRamp)) read at the time level its
//! settings name (TLS paper Eq. 10's tⁿ by default; docs/conventions.md,
//! "The time level of a ramped body force").

use super::Simulation;

impl Simulation {
    /// The gravitational acceleration at time t: g·min(t/t_ramp, 1) with a
    /// ramp time t_ramp > 0, else g (no ramp, or t_ramp ≤ 0).
    pub fn gravity_at(&self, t: f64) -> f64 {
        match self.settings.gravity_ramp {
            Some(ramp) => self.settings.gravity * ramp.fraction_at(t),
            None => self.settings.gravity,
        }
    }

    /// The gravity that loads the step of size Δt starting now: g(tⁿ), or
    /// g(tⁿ⁺¹) for a ramp read at the step's end ([`GravityRamp::read_time`](crate::mpm::settings::GravityRamp::read_time)).
    pub fn gravity_in_step(&self, dt: f64) -> f64 {
        match self.settings.gravity_ramp {
            Some(ramp) => self.gravity_at(ramp.read_time(self.time, dt)),
            None => self.settings.gravity,
        }
    }
}
