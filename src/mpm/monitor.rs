//! # The stability monitor of a run
//!
//! MPM fails in known places: grid crossing, negative P2 masses, time steps
//! above the CFL limit (thesis Eq. 3.5). The step itself already refuses a
//! non-finite state or a particle that left the grid
//! ([`Error::NonPhysicalParticle`], [`Error::ParticleLeftGrid`]). This
//! monitor adds the checks that need a whole run in view, so that `hompm run`
//! never reports a diverged run as a success:
//!
//! - **diverged** (a typed [`Error::Diverged`] naming the step, the particle
//!   and the cause):
//!   - the energy Σ ½ m_p v_p² + ½ σ_p ε_p V_p grows beyond
//!     [`ENERGY_GROWTH_BOUND`] × (initial energy + the most work the loads
//!     can do), where the loads can do at most
//!     (Σ m_p (|g| + max|b|) + Σ |f_p^trac|) × L over a domain of length L,
//!     max|b| the bound of a body-force field (`BodyForceField::bound`);
//!   - a strain |ε_p| ≥ 1, i.e. a 1D Jacobian J = 1 + ε ≤ 0 or a doubled
//!     length: far outside the small-strain models of the seeds;
//! - **suspicious** (a [`Warning`], the run goes on): negative lumped masses
//!   (thesis §5.2), or a time step above the critical step that hompm's own
//!   CFL study measured for the basis ([`measured_critical_courant`]).
//!
//! One monitor watches the 1D and the 2D run ([`Watched`]): the energy
//! budget and the strain limit are checked the same way, and each run says
//! what its energy and its strain are. The 1D run adds the negative-mass
//! warning and the CFL warning, which 2D does not have yet (no 2D critical
//! Courant number is measured; docs/conventions.md, "The stability monitor").
//!
//! Items: [`StabilityMonitor`], [`Warning`], [`Watched`],
//! [`measured_critical_courant`], [`ENERGY_GROWTH_BOUND`], [`STRAIN_LIMIT`].

use super::grid::Method;
use super::musl::{Simulation, StepSummary};
use crate::error::{DivergenceCause, Error, Result};
use serde::Serialize;

/// Largest accepted ratio of the energy to (initial energy + the work the
/// loads can do). A stable Euler–Cromer run keeps its energy within a few
/// per cent of that budget; the reproducers of issue #13 grew it ×112 and
/// ×1485 (docs/conventions.md, "The stability monitor").
pub const ENERGY_GROWTH_BOUND: f64 = 10.0;

/// The strain |ε_p| at which a 1D run has diverged: a Jacobian 1 + ε ≤ 0
/// or a doubled length (module docs).
pub const STRAIN_LIMIT: f64 = 1.0;

/// The critical Courant number C = c Δt / h (thesis Eq. 3.5) that
/// `studies::stability_map(16)` measures for the vibrating bar with lumped
/// acceleration, 16 cells and 4 particles per cell, rounded down to two
/// digits. `None` where hompm has not measured it (B-splines of degree ≥ 4).
/// tests/spec/properties/stability.rs recomputes these values from the study.
pub fn measured_critical_courant(method: Method) -> Option<f64> {
    match method {
        Method::Mpm => Some(1.65),
        Method::MpmP2 => Some(0.55),
        Method::DDMPM => Some(2.41),
        Method::Bsmpm { degree: 1 } => Some(1.65),
        Method::Bsmpm { degree: 2 } => Some(1.94),
        Method::Bsmpm { degree: 3 } => Some(1.70),
        // Not measured: other DDMPM rules, higher degrees, and any basis
        // registered later (until the study measures it).
        _ => None,
    }
}

/// Something suspicious that does not stop a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Warning {
    /// Some active lumped mass was negative (P2 Lagrange, thesis §5.2).
    NegativeLumpedMass {
        /// The first step in which it happened.
        first_step: usize,
        /// Steps in which it happened.
        steps: usize,
        /// The most negative lumped mass seen.
        min_lumped_mass: f64,
    },
    /// Δt above the measured critical step c Δt_crit / h = C_crit.
    TimeStepAboveCritical {
        /// The time step of the run.
        dt: f64,
        /// C_crit h / c_max.
        critical_dt: f64,
        /// The measured critical Courant number C_crit.
        critical_courant: f64,
    },
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Warning::NegativeLumpedMass {
                first_step,
                steps,
                min_lumped_mass,
            } => write!(
                f,
                "negative lumped masses in {steps} steps from step {first_step} (min {min_lumped_mass:e}; thesis §5.2)"
            ),
            Warning::TimeStepAboveCritical {
                dt,
                critical_dt,
                critical_courant,
            } => write!(
                f,
                "dt = {dt:e} is above the critical step {critical_dt:e} (Courant number {critical_courant} measured by hompm's CFL study)"
            ),
        }
    }
}

/// What the monitor reads of a run after each step, in 1D or in 2D. Its
/// `steps_done` and `time` are also the one name of the step counter and
/// the clock that the trace and the command line read in both dimensions,
/// whatever field holds them (1D: `diagnostics.steps`, part of the run's
/// JSON record; 2D: `steps`).
pub trait Watched {
    /// Steps taken so far.
    fn steps_done(&self) -> usize;
    /// Time reached.
    fn time(&self) -> f64;
    /// The energy the budget bounds (1D: kinetic plus ½ σ ε V; 2D: kinetic).
    fn energy(&self) -> f64;
    /// The particle with the largest speed, if there is one.
    fn fastest_particle(&self) -> Option<usize>;
    /// The first particle whose strain reached the limit, with the cause.
    fn strain_at_limit(&self) -> Option<(usize, DivergenceCause)>;
}

impl Watched for Simulation {
    fn steps_done(&self) -> usize {
        self.diagnostics.steps
    }

    fn time(&self) -> f64 {
        self.time
    }

    fn energy(&self) -> f64 {
        Simulation::energy(self)
    }

    fn fastest_particle(&self) -> Option<usize> {
        let v = &self.particles.velocity;
        (0..v.len()).max_by(|&i, &j| v[i].abs().total_cmp(&v[j].abs()))
    }

    /// |ε_p| ≥ 1: a Jacobian 1 + ε ≤ 0 or a doubled length.
    fn strain_at_limit(&self) -> Option<(usize, DivergenceCause)> {
        let strain = &self.particles.strain;
        let k = strain.iter().position(|e| e.abs() >= STRAIN_LIMIT)?;
        Some((k, DivergenceCause::StrainLimit { strain: strain[k] }))
    }
}

/// Watches a run step by step: call [`StabilityMonitor::check`] (1D) or
/// [`StabilityMonitor::check_watched`] (any [`Watched`] run) after every
/// step.
#[derive(Debug, Clone)]
pub struct StabilityMonitor {
    energy_budget: f64,
    warnings: Vec<Warning>,
}

impl StabilityMonitor {
    /// Starts watching `sim`, which will run with steps of `dt`. Records the
    /// CFL warning at once if dt is above the measured critical step.
    pub fn new(sim: &Simulation, dt: f64) -> Result<Self> {
        let p = &sim.particles;
        let (a, b) = sim.grid.domain();
        let gravity = sim.settings.gravity.abs();
        let body = sim.settings.body_force.as_ref().map_or(0.0, |b| b.bound);
        let loads: f64 = (0..p.len())
            .map(|k| p.mass[k] * (gravity + body) + p.traction[k].abs())
            .sum();
        let energy_budget = ENERGY_GROWTH_BOUND * (sim.energy().abs() + loads * (b - a));
        let mut warnings = Vec::new();
        if let Some(critical_courant) = measured_critical_courant(sim.grid.method()) {
            let wave_speed = p
                .density
                .iter()
                .map(|&rho| (sim.settings.young / rho).sqrt())
                .fold(0.0, f64::max);
            let critical_dt = critical_courant * sim.grid.cell_size() / wave_speed;
            if dt > critical_dt {
                warnings.push(Warning::TimeStepAboveCritical {
                    dt,
                    critical_dt,
                    critical_courant,
                });
            }
        }
        Ok(Self::with_budget(energy_budget, warnings))
    }

    /// A monitor with a given energy budget (the run's [`ENERGY_GROWTH_BOUND`]
    /// × its largest admissible energy) and the warnings known before the
    /// first step.
    pub fn with_budget(energy_budget: f64, warnings: Vec<Warning>) -> Self {
        Self {
            energy_budget,
            warnings,
        }
    }

    /// Checks the state after a 1D step: [`StabilityMonitor::check_watched`],
    /// then records a negative-mass warning.
    pub fn check(&mut self, sim: &Simulation) -> Result<()> {
        self.check_watched(sim)?;
        self.record_negative_masses(sim);
        Ok(())
    }

    /// [`StabilityMonitor::check`] after `sim.step_summarised(dt)`, with
    /// the energy and the largest strain the step found: the same verdict,
    /// without a pass over the particles for each.
    pub fn check_step(&mut self, sim: &Simulation, summary: &StepSummary) -> Result<()> {
        self.check_energy(sim, summary.energy)?;
        // No strain reached the limit if the largest did not.
        if summary.max_abs_strain >= STRAIN_LIMIT {
            self.check_strain(sim)?;
        }
        self.record_negative_masses(sim);
        Ok(())
    }

    /// Checks the state after a step of any run: [`Error::Diverged`] if the
    /// energy left its budget (naming the fastest particle) or a strain
    /// reached its limit (naming that particle).
    pub fn check_watched(&mut self, run: &impl Watched) -> Result<()> {
        self.check_energy(run, run.energy())?;
        self.check_strain(run)
    }

    /// [`Error::Diverged`] if `energy`, the run's now, left the budget.
    fn check_energy(&self, run: &impl Watched, energy: f64) -> Result<()> {
        let (step, time) = (run.steps_done(), run.time());
        if energy > self.energy_budget {
            return Err(Error::Diverged {
                step,
                time,
                particle: run.fastest_particle(),
                cause: DivergenceCause::EnergyGrowth {
                    energy,
                    bound: ENERGY_GROWTH_BOUND,
                    budget: self.energy_budget,
                },
            });
        }
        Ok(())
    }

    /// [`Error::Diverged`] if a strain reached its limit.
    fn check_strain(&self, run: &impl Watched) -> Result<()> {
        let (step, time) = (run.steps_done(), run.time());
        if let Some((particle, cause)) = run.strain_at_limit() {
            return Err(Error::Diverged {
                step,
                time,
                particle: Some(particle),
                cause,
            });
        }
        Ok(())
    }

    fn record_negative_masses(&mut self, sim: &Simulation) {
        let d = &sim.diagnostics;
        if d.negative_mass_steps == 0 {
            return;
        }
        let existing = self
            .warnings
            .iter_mut()
            .find(|w| matches!(w, Warning::NegativeLumpedMass { .. }));
        match existing {
            Some(Warning::NegativeLumpedMass {
                steps,
                min_lumped_mass,
                ..
            }) => {
                *steps = d.negative_mass_steps;
                *min_lumped_mass = d.min_lumped_mass;
            }
            _ => self.warnings.push(Warning::NegativeLumpedMass {
                first_step: d.steps,
                steps: d.negative_mass_steps,
                min_lumped_mass: d.min_lumped_mass,
            }),
        }
    }

    /// The warnings recorded so far, in the order they first happened.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// The energy above which [`StabilityMonitor::check`] stops the run.
    pub fn energy_budget(&self) -> f64 {
        self.energy_budget
    }
}
