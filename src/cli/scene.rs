//! # `hompm run`: one MPM scene, watched by the stability monitor
//!
//! Builds a scene (`scenes`), runs MUSL (book §4.2.2) step by step under
//! [`StabilityMonitor`](crate::mpm::monitor::StabilityMonitor) (a diverged run is an error naming step, particle
//! and cause; a suspicious one warns), and prints the final particle state,
//! the diagnostics, the RMS errors against the analytic solution where one
//! exists, and the warnings. The 2D scene `aligned-vibration` runs in
//! [`aligned`].
//!
//! The setup comes from [`SetupArgs`] (shared with `trace` and `check`)
//! and runs through `oracle::run`; the JSON's `time` is steps × Δt.
//!
//! Items: [`RunArgs`], [`run_scene`].

use super::args::name;
use super::limits::Limits;
use super::setup_args::SetupArgs;
use super::{json, Output};
use crate::error::{Error, Result};
use crate::mpm::conventions::Conventions;
use crate::mpm::diagnostics::rms_error;
use crate::mpm::grid::NodeIntegrals;
use crate::mpm::monitor::Warning;
use crate::mpm::musl::{NoObserver, Simulation};
use crate::oracle::exact::{exact_1d, formulas_1d, reference_kind};
use crate::oracle::run::run_1d;
use crate::oracle::setup::{parameter_sets, to_json, Scene1d, Setup, Setup1d};
use serde::Serialize;

mod aligned;

/// Arguments of `hompm run`.
#[derive(clap::Args, Debug)]
pub struct RunArgs {
    /// The run's setup.
    #[command(flatten)]
    pub setup: SetupArgs,
    /// Print every named parameter set of every scene with its values, and
    /// nothing else.
    #[arg(long)]
    pub list_params: bool,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct ParticleJson {
    x0: Vec<f64>,
    x: Vec<f64>,
    u: Vec<f64>,
    v: Vec<f64>,
    stress: Vec<f64>,
    volume: Vec<f64>,
    density: Vec<f64>,
}

#[derive(Serialize)]
struct RunJson {
    scene: String,
    params: serde_json::Value,
    /// The physical parameters the command line overrode.
    overridden: Vec<&'static str>,
    method: String,
    /// DDMPM's node-integral rule (ddmpm only).
    #[serde(skip_serializing_if = "Option::is_none")]
    node_integrals: Option<NodeIntegrals>,
    mapping: String,
    mass: String,
    /// Another code's conventions (scheme, transfer, positions, body
    /// force), when not the book's.
    #[serde(skip_serializing_if = "Option::is_none")]
    conventions: Option<Conventions>,
    /// The consistent solver and its stopping rule.
    solver: serde_json::Value,
    cells: usize,
    ppc: usize,
    dt: f64,
    steps: usize,
    /// steps × dt.
    time: f64,
    /// The exact solution the RMS errors use, and its formulas.
    exact_solution: serde_json::Value,
    particles: ParticleJson,
    diagnostics: serde_json::Value,
    warnings: Vec<Warning>,
}

/// The scene's parameters as JSON.
fn params_json(scene: &Scene1d) -> Result<serde_json::Value> {
    match scene {
        Scene1d::VibratingBar(p) => to_json(p),
        Scene1d::Column(p) => to_json(p),
        Scene1d::ManufacturedStrip(p) => to_json(p),
    }
}

/// `run` with a progress callback: a bar on stderr when it is a terminal
/// and the run has at least 10 000 steps, nothing otherwise. The 1D and
/// the 2D run show the same bar.
pub(super) fn with_progress<T>(
    steps: usize,
    run: impl FnOnce(&mut dyn FnMut(usize)) -> Result<T>,
) -> Result<T> {
    use std::io::IsTerminal;
    let bar = indicatif::ProgressBar::new(steps as u64);
    if !(std::io::stderr().is_terminal() && steps >= 10_000) {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let out = run(&mut |_| bar.inc(1));
    bar.finish_and_clear();
    out
}

/// The steps, each followed by the monitor's check, with progress.
fn advance(setup: &Setup1d) -> Result<(Simulation, Vec<Warning>)> {
    let run = with_progress(setup.steps, |progress| {
        run_1d(setup, &mut NoObserver, progress)
    })?;
    Ok((run.simulation, run.warnings))
}

/// `hompm run`.
pub fn run_scene(a: RunArgs, limits: &Limits) -> Result<Output> {
    if a.list_params {
        return Ok(Output {
            stdout: json::strict(&parameter_sets()?)?,
            ..Output::default()
        });
    }
    let setup = a.setup.setup()?;
    a.setup.check_limits(&setup, limits, 0.0)?;
    let s = match setup {
        Setup::TwoD(s) => return aligned::run_aligned(&a, &s),
        Setup::OneD(s) => s,
    };
    let (sim, warnings) = advance(&s)?;
    let diagnostics = diagnostics_with_errors(&s, &sim)?;
    let pt = &sim.particles;
    let d = &s.discretisation;
    let doc = RunJson {
        scene: name(&a.setup.scene()?),
        params: params_json(&s.scene)?,
        overridden: a.setup.overrides().names(),
        method: name(&a.setup.method),
        node_integrals: d.method.node_integrals(),
        mapping: name(&a.setup.mapping),
        mass: name(&a.setup.mass),
        conventions: (!d.conventions.is_book()).then_some(d.conventions),
        solver: to_json(&d.mass)?,
        cells: d.cells,
        ppc: d.ppc,
        dt: s.dt,
        steps: s.steps,
        time: Setup::OneD(s).end_time(),
        exact_solution: serde_json::json!({
            "kind": reference_kind(&s.scene),
            "formulas": formulas_1d(&s.scene),
        }),
        particles: ParticleJson {
            x0: pt.x0.clone(),
            x: pt.x.clone(),
            u: pt.displacement.clone(),
            v: pt.velocity.clone(),
            stress: pt.stress.clone(),
            volume: pt.volume.clone(),
            density: pt.density.clone(),
        },
        diagnostics,
        warnings,
    };
    let warnings = doc.warnings.iter().map(ToString::to_string).collect();
    let stdout = if a.json {
        json::strict(&doc)?
    } else {
        format!(
            "{} (E = {}), {} with {} mapping and {} mass{}, {} cells × {} PPC, {} steps of {:e} s (t = {:e} s)\ndiagnostics: {}\n",
            doc.scene, sim.settings.young, doc.method, doc.mapping, doc.mass, conventions_words(&d.conventions, 1), doc.cells, doc.ppc, doc.steps, doc.dt, doc.time, doc.diagnostics
        )
    };
    Ok(Output {
        stdout,
        warnings,
        failure: None,
    })
}

/// The run's diagnostics with the RMS errors (thesis §4.3) of u, v and σ
/// at the particles' initial positions at t = steps × Δt, against the
/// exact solution `rms_reference` names (for a large-strain set, the
/// linear solution).
fn diagnostics_with_errors(s: &Setup1d, sim: &Simulation) -> Result<serde_json::Value> {
    let mut diagnostics = serde_json::to_value(&sim.diagnostics)
        .map_err(|e| Error::InvalidArgument(e.to_string()))?;
    let pt = &sim.particles;
    let t = Setup::OneD(*s).end_time();
    let exact: Vec<_> = pt.x0.iter().map(|&x| exact_1d(&s.scene, x, t)).collect();
    type Pick = fn(&crate::oracle::exact::Exact1d) -> f64;
    let fields: [(&str, &[f64], Pick); 3] = [
        ("rms_displacement", &pt.displacement, |e| e.u),
        ("rms_velocity", &pt.velocity, |e| e.v),
        ("rms_stress", &pt.stress, |e| e.stress),
    ];
    if let Some(obj) = diagnostics.as_object_mut() {
        for (field_name, field, pick) in fields {
            let reference: Vec<f64> = exact.iter().map(pick).collect();
            obj.insert(
                field_name.into(),
                serde_json::json!(rms_error(field, &reference)?),
            );
        }
        obj.insert(
            "rms_reference".into(),
            serde_json::json!(reference_kind(&s.scene)),
        );
    }
    Ok(diagnostics)
}

/// ", --scheme usl --positions grid" for conventions other than the
/// dimension's default; empty for the default.
pub(crate) fn conventions_words(c: &Conventions, dimension: usize) -> String {
    c.flags(dimension)
        .iter()
        .map(|f| format!(", {f}"))
        .collect()
}
