//! # The trace: the quantities of each numbered equation at each step
//!
//! [`TraceObserver`] is a [`StepObserver`]: the 1D step (book §4.2.2)
//! hands it the simulation after each numbered function, and it copies
//! the quantities of the equations that function completed
//! ([`EQUATIONS_1D`]). A traced run is therefore the run itself, bit for
//! bit (tests/spec/cli/oracle.rs compares a traced run with an untraced one).
//!
//! The schema (docs/oracle.md): a header with the schema name, its
//! version and every setting of the run; then, per traced step, one array
//! of values per equation key. Keys are stable, and only ever added.
//! Steps are numbered from 1; `--every N` traces steps 1, 1 + N, 1 + 2N, …
//! and always the last.
//!
//! The 2D step (MLS paper Eqs. 18–41) is traced the same way by
//! [`TraceObserver2d`] ([`EQUATIONS_2D`]), vectors and tensors flattened
//! per node or particle.
//!
//! The traced quantities and their keys are `oracle::equations`'.
//!
//! Items: [`Trace`], [`TraceStep`], [`Recorder`], [`TraceObserver`],
//! [`TraceObserver2d`], [`header_1d`], [`header_2d`], [`TRACE_SCHEMA`],
//! [`TRACE_VERSION`].

pub use super::equations::{equation, Equation, IndexKind, EQUATIONS_1D, EQUATIONS_2D};
use super::setup::{Setup1d, Setup2d};
use crate::error::Result;
use crate::mpm::conventions::Positions;
use crate::mpm::monitor::Watched;
use crate::mpm::musl::{Constitutive, Simulation, StepObserver, StepPoint};
use crate::mpm2d::step::{Simulation2d, StepObserver2d, StepPoint2d};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The schema name a trace carries in its header.
pub const TRACE_SCHEMA: &str = "hompm-trace";
/// The version of the trace schema.
pub const TRACE_VERSION: u32 = 1;

/// The stress key that applies to an update.
fn stress_key(c: Constitutive) -> &'static str {
    match c {
        Constitutive::SmallStrain => "book-4.15",
        Constitutive::LargeStrain => "book-4.16",
        Constitutive::NeoHookean => "mls-37-1d",
    }
}

/// The values of every traced equation at one step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TraceStep {
    /// The step, from 1.
    pub step: usize,
    /// Its end time, step × Δt.
    pub time: f64,
    /// Values by equation key.
    pub equations: BTreeMap<String, Vec<f64>>,
}

/// A whole trace: header and traced steps.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Trace {
    /// `hompm-trace`.
    pub schema: String,
    /// [`TRACE_VERSION`].
    pub version: u32,
    /// Every setting of the run, as `hompm run --json` prints them.
    pub header: BTreeMap<String, serde_json::Value>,
    /// The traced steps, in order.
    pub steps: Vec<TraceStep>,
}

/// Which steps are traced, and the steps recorded so far: shared by the
/// 1D and 2D recorders.
#[derive(Debug, Clone)]
pub struct Recorder {
    dt: f64,
    every: usize,
    last: usize,
    only: Option<std::collections::BTreeSet<usize>>,
    current: Option<TraceStep>,
    /// The steps recorded so far.
    pub steps: Vec<TraceStep>,
}

impl Recorder {
    /// Steps 1, 1 + every, … and `last` of Δt.
    pub fn new(dt: f64, every: usize, last: usize) -> Self {
        Self {
            dt,
            every: every.max(1),
            last,
            only: None,
            current: None,
            steps: Vec::new(),
        }
    }

    /// Exactly the steps `only` (those of another code's trace).
    pub fn for_steps(dt: f64, only: std::collections::BTreeSet<usize>) -> Self {
        let mut r = Self::new(dt, 1, 0);
        r.only = Some(only);
        r
    }

    /// Whether step `s` (from 1) is traced.
    pub fn traces(&self, s: usize) -> bool {
        match &self.only {
            Some(only) => only.contains(&s),
            None => (s - 1).is_multiple_of(self.every) || s == self.last,
        }
    }

    /// Starts step `step` (recording it if traced); whether it is.
    fn begin(&mut self, step: usize) -> bool {
        self.current = self.traces(step).then(|| TraceStep {
            step,
            time: step as f64 * self.dt,
            equations: BTreeMap::new(),
        });
        self.current.is_some()
    }

    fn recording(&self) -> bool {
        self.current.is_some()
    }

    fn put(&mut self, key: &str, values: Vec<f64>) {
        if let Some(c) = self.current.as_mut() {
            c.equations.insert(key.to_string(), values);
        }
    }

    fn finish(&mut self) {
        if let Some(done) = self.current.take() {
            self.steps.push(done);
        }
    }

    /// The recorded steps as a [`Trace`] with `header`.
    pub fn into_trace(self, header: BTreeMap<String, serde_json::Value>) -> Trace {
        Trace {
            schema: TRACE_SCHEMA.into(),
            version: TRACE_VERSION,
            header,
            steps: self.steps,
        }
    }
}

/// Records the quantities of [`EQUATIONS_1D`] at the traced steps.
#[derive(Debug, Clone)]
pub struct TraceObserver {
    stress_key: &'static str,
    dt: f64,
    /// The steps and what was recorded.
    pub recorder: Recorder,
}

impl TraceObserver {
    /// An observer that records steps 1, 1 + every, … and `last`.
    pub fn new(dt: f64, every: usize, last: usize, constitutive: Constitutive) -> Self {
        Self {
            stress_key: stress_key(constitutive),
            dt,
            recorder: Recorder::new(dt, every, last),
        }
    }

    /// An observer that records exactly the steps `only` (those of
    /// another code's trace).
    pub fn for_steps(
        dt: f64,
        only: std::collections::BTreeSet<usize>,
        constitutive: Constitutive,
    ) -> Self {
        Self {
            stress_key: stress_key(constitutive),
            dt,
            recorder: Recorder::for_steps(dt, only),
        }
    }

    /// The recorded steps as a [`Trace`] with `header`.
    pub fn into_trace(self, header: BTreeMap<String, serde_json::Value>) -> Trace {
        self.recorder.into_trace(header)
    }

    fn put(&mut self, key: &str, values: &[f64]) {
        self.recorder.put(key, values.to_vec());
    }
}

impl StepObserver for TraceObserver {
    fn observe(&mut self, point: StepPoint, sim: &mut Simulation) -> Result<()> {
        if point == StepPoint::MassAndLoads {
            self.recorder.begin(sim.steps_done() + 1);
        }
        if !self.recorder.recording() {
            return Ok(());
        }
        let ws = sim.workspace();
        let p = &sim.particles;
        match point {
            StepPoint::MassAndLoads => {
                let external: Vec<f64> = ws
                    .gravity_force
                    .iter()
                    .zip(&ws.traction_force)
                    .map(|(g, t)| g + t)
                    .collect();
                let mass = ws.mass.clone();
                self.put("book-4.5", &mass);
                self.put("thesis-3.2", &external);
            }
            StepPoint::GridVelocity => {
                let (p, v) = (ws.nodal_momentum.clone(), ws.nodal_velocity.clone());
                self.put("nodal-momentum", &p);
                self.put("nodal-velocity", &v);
            }
            StepPoint::UpdatedGridVelocity => {
                let v = ws.updated_velocity.clone();
                self.put("nodal-velocity-updated", &v);
            }
            StepPoint::InternalForce => {
                let f = ws.internal_force.clone();
                self.put("book-4.6", &f);
            }
            StepPoint::Acceleration => {
                let a = ws.acceleration.clone();
                self.put("book-4.8", &a);
            }
            StepPoint::AccelerationConditions => {
                let a = ws.acceleration.clone();
                self.put("book-4.8-bc", &a);
            }
            StepPoint::ParticleVelocity => {
                let v = p.velocity.clone();
                self.put("book-4.9", &v);
            }
            StepPoint::NodalVelocity => {
                let m = &ws.mapping;
                let (rhs, v) = (m.momentum.clone(), m.velocity.clone());
                let solver = [m.solver_iterations as f64, m.solver_residual];
                self.put("book-4.10-rhs", &rhs);
                self.put("book-4.10", &v);
                self.put("book-4.10-solver", &solver);
            }
            StepPoint::NodalVelocityConditions => {
                let v = ws.mapping.velocity.clone();
                self.put("book-4.10-bc", &v);
            }
            StepPoint::Positions => {
                let moved_by = match sim.settings.conventions.positions {
                    Positions::Projected => &ws.mapping.velocity,
                    Positions::Grid => &ws.updated_velocity,
                };
                let du: Vec<f64> = moved_by.iter().map(|v| self.dt * v).collect();
                let (u, x, de) = (
                    p.displacement.clone(),
                    p.x.clone(),
                    ws.strain_increment.clone(),
                );
                self.put("book-4.11", &du);
                self.put("book-4.12", &u);
                self.put("book-4.13", &x);
                self.put("book-4.14", &de);
            }
            StepPoint::Stress => {
                let s = p.stress.clone();
                let key = self.stress_key;
                self.put(key, &s);
            }
            StepPoint::VolumeAndDensity => {
                let (vol, rho, eps) = (p.volume.clone(), p.density.clone(), p.strain.clone());
                self.put("book-4.17", &vol);
                self.put("book-4.18", &rho);
                self.put("book-4.14-strain", &eps);
                self.recorder.finish();
            }
        }
        Ok(())
    }
}

/// Records the quantities of [`EQUATIONS_2D`] at the traced steps of the
/// 2D step.
#[derive(Debug, Clone)]
pub struct TraceObserver2d {
    /// The steps and what was recorded.
    pub recorder: Recorder,
}

/// x_p and u_p (MLS paper Eq. 30) into the trace.
fn put_positions(r: &mut Recorder, p: &crate::mpm2d::Particles2d) {
    let x: Vec<f64> = p.x.iter().flatten().copied().collect();
    r.put("mls-30", x);
    r.put("mls-30-u", flat2(&p.displacement));
}

fn flat2(v: &[[f64; 2]]) -> Vec<f64> {
    v.iter().flatten().copied().collect()
}

fn flat4(v: &[nalgebra::Matrix2<f64>]) -> Vec<f64> {
    v.iter()
        .flat_map(|m| [m[(0, 0)], m[(0, 1)], m[(1, 0)], m[(1, 1)]])
        .collect()
}

impl StepObserver2d for TraceObserver2d {
    fn observe(&mut self, point: StepPoint2d, sim: &mut Simulation2d) -> Result<()> {
        let r = &mut self.recorder;
        if point == StepPoint2d::GridMapping {
            r.begin(sim.steps_done() + 1);
        }
        if !r.recording() {
            return Ok(());
        }
        let (ws, p) = (&sim.workspace, &sim.particles);
        let projected = sim.settings.conventions.positions == Positions::Projected;
        match point {
            StepPoint2d::GridMapping => {
                if !ws.gauss_values.is_empty() {
                    r.put(
                        "mls-18-21",
                        ws.gauss_values.iter().flatten().copied().collect(),
                    );
                }
                if !ws.nodal_body_force.is_empty() {
                    r.put("nodal-body-force", flat2(&ws.nodal_body_force));
                }
                r.put("mls-22", ws.mass.clone());
                r.put("mls-23", flat2(&ws.momentum));
                r.put("mls-26", flat2(&ws.force));
            }
            StepPoint2d::NodalUpdate => {
                r.put("mls-27", flat2(&ws.acceleration));
                r.put("mls-28", flat2(&ws.momentum_next));
            }
            StepPoint2d::ParticleUpdate => {
                r.put("mls-29", flat2(&p.velocity));
                if !projected {
                    put_positions(r, p);
                }
                if sim.settings.conventions.transfer == crate::mpm::conventions::Transfer::Apic {
                    r.put("apic-c", flat4(&p.affine));
                }
            }
            StepPoint2d::EndOfStepVelocity => {
                r.put("mls-32", flat2(&ws.momentum_end));
                r.put("mls-33", flat2(&ws.velocity_end));
                // `--positions projected` moves the particles after
                // Eqs. (31)–(33): their positions are final only here.
                if projected {
                    put_positions(r, p);
                }
            }
            StepPoint2d::Deformation => {
                r.put("mls-35", flat4(&p.deformation));
                r.put("mls-36", p.volume.clone());
                r.put("mls-37", p.density.clone());
                r.put("mls-41", flat4(&p.stress));
                r.finish();
            }
        }
        Ok(())
    }
}

/// The header of a 2D setup's trace, as [`header_1d`].
pub fn header_2d(setup: &Setup2d) -> Result<BTreeMap<String, serde_json::Value>> {
    header_of(setup)
}

/// The header of a 1D setup's trace: the setup's settings as `hompm`
/// serialises them (`scene` with its parameters, `discretisation`, `dt`,
/// `steps`) and the hompm version.
pub fn header_1d(setup: &Setup1d) -> Result<BTreeMap<String, serde_json::Value>> {
    header_of(setup)
}

/// A setup's fields as a header, with the hompm version.
fn header_of<T: serde::Serialize>(setup: &T) -> Result<BTreeMap<String, serde_json::Value>> {
    let mut header: BTreeMap<String, serde_json::Value> = match super::setup::to_json(setup)? {
        serde_json::Value::Object(m) => m.into_iter().collect(),
        _ => BTreeMap::new(),
    };
    header.insert("hompm".into(), serde_json::json!(env!("CARGO_PKG_VERSION")));
    Ok(header)
}

impl Trace {
    /// The trace as CSV: `#` header lines (`# key: value`, values as JSON),
    /// then `step,time,equation,index,value` rows.
    pub fn to_csv(&self) -> String {
        let table: &[Equation] = if self
            .steps
            .iter()
            .any(|s| s.equations.contains_key("mls-22"))
        {
            &EQUATIONS_2D
        } else {
            &EQUATIONS_1D
        };
        let mut out = format!("# schema: {}\n# version: {}\n", self.schema, self.version);
        for (k, v) in &self.header {
            out.push_str(&format!("# {k}: {v}\n"));
        }
        out.push_str("step,time,equation,index,value\n");
        for s in &self.steps {
            for e in table {
                if let Some(values) = s.equations.get(e.key) {
                    for (i, v) in values.iter().enumerate() {
                        out.push_str(&format!("{},{:e},{},{i},{v:e}\n", s.step, s.time, e.key));
                    }
                }
            }
        }
        out
    }
}
