//! # Running a setup under the stability monitor
//!
//! One function per dimension runs a [`Setup1d`] or [`Setup2d`] the way
//! `hompm run` does: each step, 1D or 2D, is followed by the stability
//! monitor's check (`mpm::monitor`, which `mpm2d::monitor` gives the 2D
//! run), and a run that failed with Δt above the measured
//! critical step names that cause ([`Error::Diverged`]). `hompm run`,
//! `trace` and `check` all call these, so they run the same steps.
//!
//! [`trace_1d`] runs a 1D setup with the trace recorder inside, and
//! [`reference`](fn@reference) gives hompm's final state (and trace) that `hompm check`
//! compares with.
//!
//! Items: [`run_1d`], [`run_2d`], [`run_2d_observed`], [`Run1d`], [`Run2d`],
//! [`trace_1d`], [`trace_2d`], [`reference`](fn@reference).

use super::setup::{Setup, Setup1d, Setup2d};
use super::state::{state_1d, state_2d, State};
use super::trace::{header_1d, header_2d, Recorder, Trace, TraceObserver, TraceObserver2d};
use crate::error::{DivergenceCause, Error, Result};
use crate::mpm::monitor::{StabilityMonitor, Warning};
use crate::mpm::musl::NoObserver;
use crate::mpm::musl::{Simulation, StepObserver};
use crate::mpm2d::monitor::stability_monitor;
use crate::mpm2d::step::{NoObserver2d, Simulation2d, StepObserver2d};
use std::collections::BTreeSet;

/// A finished 1D run: the simulation at its end and the monitor's warnings.
#[derive(Debug)]
pub struct Run1d {
    /// The simulation after the last step.
    pub simulation: Simulation,
    /// What the monitor found suspicious.
    pub warnings: Vec<Warning>,
}

/// Runs `setup` with `observer` called inside every step; `progress` is
/// called after each step with the number of steps done.
pub fn run_1d<O: StepObserver>(
    setup: &Setup1d,
    observer: &mut O,
    progress: &mut dyn FnMut(usize),
) -> Result<Run1d> {
    let mut sim = setup.scene.simulation(&setup.discretisation)?;
    let mut monitor = StabilityMonitor::new(&sim, setup.dt)?;
    for k in 0..setup.steps {
        let checked = if O::OBSERVES {
            sim.step_observed(setup.dt, observer)
                .and_then(|()| monitor.check(&sim))
        } else {
            sim.step_summarised(setup.dt)
                .and_then(|summary| monitor.check_step(&sim, &summary))
        };
        checked.map_err(|e| with_time_step_cause(e, &monitor, sim.time))?;
        progress(k + 1);
    }
    sim.diagnostics.final_energy = sim.energy();
    Ok(Run1d {
        warnings: monitor.warnings().to_vec(),
        simulation: sim,
    })
}

/// A finished 2D run: the simulation at its end and the monitor's warnings
/// (as [`Run1d`]).
pub struct Run2d {
    /// The simulation after the last step.
    pub simulation: Simulation2d,
    /// What the monitor found suspicious.
    pub warnings: Vec<Warning>,
}

/// Runs a 2D setup (MLS paper Eqs. 18–37) to its end under the stability
/// monitor (`mpm2d::monitor`).
pub fn run_2d(setup: &Setup2d) -> Result<Simulation2d> {
    Ok(run_2d_observed(setup, &mut NoObserver2d, &mut |_| {})?.simulation)
}

/// [`run_2d`] with `observer` called inside every step and `progress`
/// after each step with the number of steps done, as [`run_1d`].
pub fn run_2d_observed<O: StepObserver2d>(
    setup: &Setup2d,
    observer: &mut O,
    progress: &mut dyn FnMut(usize),
) -> Result<Run2d> {
    let mut sim = setup.scene.simulation_with(
        setup.method,
        setup.cells,
        setup.per_side,
        1.0,
        setup.conventions,
    )?;
    let work = setup.scene.work_bound(sim.particles.total_mass())?;
    let mut monitor = stability_monitor(&sim, work);
    for k in 0..setup.steps {
        sim.step_observed(setup.dt, observer)?;
        monitor.check_watched(&sim)?;
        progress(k + 1);
    }
    Ok(Run2d {
        warnings: monitor.warnings().to_vec(),
        simulation: sim,
    })
}

/// hompm's trace of a 2D setup (MLS paper Eqs. 18–41), as [`trace_1d`].
pub fn trace_2d(
    s: &Setup2d,
    every: usize,
    only: Option<BTreeSet<usize>>,
) -> Result<(Trace, Simulation2d)> {
    let recorder = match only {
        Some(steps) => Recorder::for_steps(s.dt, steps),
        None => Recorder::new(s.dt, every, s.steps),
    };
    let mut observer = TraceObserver2d { recorder };
    let sim = run_2d_observed(s, &mut observer, &mut |_| {})?.simulation;
    let mut header = header_2d(s)?;
    header.insert("every".into(), serde_json::json!(every));
    Ok((observer.recorder.into_trace(header), sim))
}

/// A run that failed with Δt above the measured critical step failed
/// because of it: the error becomes [`Error::Diverged`] naming that cause,
/// keeping the step and particle of the original error.
fn with_time_step_cause(e: Error, monitor: &StabilityMonitor, time: f64) -> Error {
    let Some(&Warning::TimeStepAboveCritical {
        dt,
        critical_dt,
        critical_courant,
    }) = monitor
        .warnings()
        .iter()
        .find(|w| matches!(w, Warning::TimeStepAboveCritical { .. }))
    else {
        return e;
    };
    let (step, particle) = match &e {
        Error::NonPhysicalParticle { step, particle, .. } => (*step, Some(*particle)),
        Error::ParticleLeftGrid { step, particle, .. } => (*step, Some(*particle)),
        Error::Diverged { step, particle, .. } => (*step, *particle),
        _ => return e,
    };
    Error::Diverged {
        step,
        time,
        particle,
        cause: DivergenceCause::TimeStepAboveCritical {
            dt,
            critical_dt,
            critical_courant,
            failure: Box::new(e.clone()),
        },
    }
}

/// hompm's trace of a 1D setup, of steps 1, 1 + `every`, … and the last,
/// or of exactly the steps `only`; with the run itself.
pub fn trace_1d(
    s: &Setup1d,
    every: usize,
    only: Option<BTreeSet<usize>>,
) -> Result<(Trace, Run1d)> {
    let constitutive = s.scene.constitutive();
    let mut observer = match only {
        Some(steps) => TraceObserver::for_steps(s.dt, steps, constitutive),
        None => TraceObserver::new(s.dt, every, s.steps, constitutive),
    };
    let run = run_1d(s, &mut observer, &mut |_| {})?;
    let mut header = header_1d(s)?;
    header.insert("every".into(), serde_json::json!(every));
    Ok((observer.into_trace(header), run))
}

/// hompm's final state for a setup, as `hompm check` compares it, and its
/// trace of the steps `only` if given (1D only).
pub fn reference(setup: &Setup, only: Option<BTreeSet<usize>>) -> Result<(State, Option<Trace>)> {
    match setup {
        Setup::OneD(s) => match only {
            Some(steps) => {
                let (trace, run) = trace_1d(s, 1, Some(steps))?;
                Ok((state_1d(s, &run.simulation), Some(trace)))
            }
            None => {
                let run = run_1d(s, &mut NoObserver, &mut |_| {})?;
                Ok((state_1d(s, &run.simulation), None))
            }
        },
        Setup::TwoD(s) => match only {
            Some(steps) => {
                let (trace, sim) = trace_2d(s, 1, Some(steps))?;
                Ok((state_2d(s, &sim), Some(trace)))
            }
            None => Ok((state_2d(s, &run_2d(s)?), None)),
        },
    }
}
