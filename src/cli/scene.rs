//! # `hompm run`: one MPM scene, watched by the stability monitor
//!
//! Builds a scene (`scenes`), runs MUSL (book §4.2.2) step by step under
//! [`StabilityMonitor`] (a diverged run is an error naming step, particle
//! and cause; a suspicious one warns), and prints the final particle state,
//! the diagnostics, the RMS errors against the analytic solution where one
//! exists, and the warnings. The 2D scene `aligned-vibration` runs in
//! [`aligned`].
//!
//! Items: [`RunArgs`], [`run_scene`].

use super::args::{count, name, node_integrals, MappingArg, MassArg, MethodArg, SceneArg};
use super::limits::Limits;
use super::{json, Output};
use crate::error::{DivergenceCause, Error, Result};
use crate::mpm::diagnostics::rms_error;
use crate::mpm::grid::NodeIntegrals;
use crate::mpm::mapping::Mapping;
use crate::mpm::monitor::{StabilityMonitor, Warning};
use crate::mpm::musl::{Constitutive, Simulation};
use crate::scenes::{column, vibrating_bar, Discretisation};
use serde::Serialize;

mod aligned;

/// Arguments of `hompm run`.
#[derive(clap::Args, Debug)]
pub struct RunArgs {
    /// The scene.
    #[arg(value_enum)]
    scene: SceneArg,
    /// Named parameter set (default: the thesis' set of the scene).
    #[arg(long)]
    params: Option<String>,
    /// The MPM variant.
    #[arg(long, value_enum, default_value_t = MethodArg::Mpm)]
    method: MethodArg,
    /// DDMPM's node integrals V_j and ∫φ_j∇φ_i: exact, particles (particle
    /// quadrature) or subpoints:N (N subpoints per particle).
    #[arg(long, default_value = "exact", value_parser = node_integrals)]
    node_integrals: NodeIntegrals,
    /// B-spline degree for bsmpm.
    #[arg(long, default_value_t = 2, value_parser = count, allow_negative_numbers = true)]
    degree: usize,
    /// How particle data reaches the grid.
    #[arg(long, value_enum, default_value_t = MappingArg::Direct)]
    mapping: MappingArg,
    /// The mass matrix of the velocity projection.
    #[arg(long, value_enum, default_value_t = MassArg::Lumped)]
    mass: MassArg,
    /// Elements or knot spans.
    #[arg(long, default_value_t = 16, value_parser = count, allow_negative_numbers = true)]
    cells: usize,
    /// Particles per cell [default: 4 in 1D, 9 (3 × 3) in aligned-vibration,
    /// where it must be a square].
    #[arg(long, value_parser = count, allow_negative_numbers = true)]
    ppc: Option<usize>,
    /// Time step.
    #[arg(long, default_value_t = 1e-5, allow_negative_numbers = true)]
    dt: f64,
    /// Number of steps.
    #[arg(long, default_value_t = 100, value_parser = count, allow_negative_numbers = true)]
    steps: usize,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

/// Analytic (u, v, σ) at (X, t), where known.
type Reference = Box<dyn Fn(f64, f64) -> [Option<f64>; 3]>;

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
    method: String,
    /// DDMPM's node-integral rule (ddmpm only).
    #[serde(skip_serializing_if = "Option::is_none")]
    node_integrals: Option<NodeIntegrals>,
    mapping: String,
    mass: String,
    cells: usize,
    ppc: usize,
    dt: f64,
    steps: usize,
    time: f64,
    particles: ParticleJson,
    diagnostics: serde_json::Value,
    warnings: Vec<Warning>,
}

impl RunArgs {
    /// --ppc, or its default: 4 in 1D, 9 in 2D.
    fn ppc(&self) -> usize {
        self.ppc
            .unwrap_or(if self.scene == SceneArg::AlignedVibration {
                9
            } else {
                4
            })
    }
}

fn validate(a: &RunArgs) -> Result<()> {
    if a.cells == 0 || a.ppc() == 0 {
        return Err(Error::InvalidArgument(format!(
            "--cells and --ppc must be at least 1, got {} and {}",
            a.cells,
            a.ppc()
        )));
    }
    if !(a.dt > 0.0 && a.dt.is_finite()) {
        return Err(Error::InvalidArgument(format!(
            "--dt must be positive and finite, got {}",
            a.dt
        )));
    }
    if !(a.dt * a.steps as f64).is_finite() {
        return Err(Error::InvalidArgument(format!(
            "--dt {:e} × --steps {} overflows the time t = n·Δt in double precision",
            a.dt, a.steps
        )));
    }
    if a.scene != SceneArg::AlignedVibration {
        a.method.method(a.degree, a.node_integrals)?;
    }
    Ok(())
}

/// Memory: about 200 bytes plus 16 per stencil entry for each particle,
/// the same per DOF, and 200 bytes of JSON per particle. Time: about
/// 45 + 4 w² ns per particle-step for a stencil of width w (the divan
/// benchmark measures 24–50 ns for w ≤ 3), 200 ns more for TLS or
/// cubic-spline mappings, and a banded solve per step for a consistent mass.
fn check_limits(a: &RunArgs, limits: &Limits) -> Result<()> {
    let particles = a.cells as f64 * a.ppc() as f64;
    let width = match a.method {
        MethodArg::Mpm | MethodArg::Ddmpm => 4.0,
        MethodArg::MpmP2 => 3.0,
        _ => a.degree as f64 + 1.0,
    };
    let dofs = 2.0 * a.cells as f64 + width;
    let what = || format!("a run of {particles:.0} particles × {} steps", a.steps);
    let bytes = (particles + dofs) * (200.0 + 16.0 * width) + particles * 200.0;
    limits.check_memory(what, bytes, "particle and grid storage")?;
    let mapping = if a.mapping == MappingArg::Direct {
        0.0
    } else {
        200.0
    };
    let solve = if a.mass == MassArg::Lumped {
        20.0
    } else {
        40.0 * width * width
    };
    let per_step = (particles * (45.0 + 4.0 * width * width + mapping) + dofs * solve) * 1e-9;
    limits.check_time(what, per_step * a.steps as f64)
}

fn build(a: &RunArgs) -> Result<(Simulation, serde_json::Value, Reference)> {
    let mapping = Mapping::from(a.mapping);
    let d = Discretisation::new(
        a.method.method(a.degree, a.node_integrals)?,
        mapping,
        a.mass.into(),
        a.cells,
        a.ppc(),
    );
    match a.scene {
        SceneArg::VibratingBar => {
            let p = vibrating_bar::parameters(a.params.as_deref().unwrap_or("thesis-table-4.1"))?;
            let small = p.constitutive == Constitutive::SmallStrain;
            let reference: Reference = Box::new(move |x, t| {
                if small {
                    [
                        Some(p.displacement(x, t)),
                        Some(p.velocity(x, t)),
                        Some(p.stress(x, t)),
                    ]
                } else {
                    [None; 3]
                }
            });
            Ok((p.simulation(&d)?, params_json(&p)?, reference))
        }
        SceneArg::ColumnSelfWeight | SceneArg::ColumnTopLoad => {
            let default = if a.scene == SceneArg::ColumnSelfWeight {
                "thesis-table-4.3"
            } else {
                "thesis-table-8.1"
            };
            let p = column::parameters(a.params.as_deref().unwrap_or(default))?;
            let small = p.constitutive == Constitutive::SmallStrain;
            let reference: Reference = Box::new(move |x, t| {
                if small {
                    [Some(p.displacement(x, t, 200)), None, None]
                } else {
                    [None; 3]
                }
            });
            Ok((p.simulation(&d)?, params_json(&p)?, reference))
        }
        SceneArg::AlignedVibration => Err(Error::InvalidArgument(
            "aligned-vibration is a 2D scene (cli::scene::aligned)".into(),
        )),
    }
}

/// A scene's parameter set as JSON.
fn params_json<T: Serialize>(p: &T) -> Result<serde_json::Value> {
    serde_json::to_value(p).map_err(|e| Error::InvalidArgument(format!("cannot write JSON: {e}")))
}

/// The steps, each followed by the monitor's check; a progress bar on a
/// terminal.
fn advance(sim: &mut Simulation, dt: f64, steps: usize) -> Result<Vec<Warning>> {
    use std::io::IsTerminal;
    let mut monitor = StabilityMonitor::new(sim, dt)?;
    let bar = indicatif::ProgressBar::new(steps as u64);
    if !(std::io::stderr().is_terminal() && steps >= 10_000) {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    for _ in 0..steps {
        sim.step(dt)
            .and_then(|()| monitor.check(sim))
            .map_err(|e| with_time_step_cause(e, &monitor, sim.time))?;
        bar.inc(1);
    }
    bar.finish_and_clear();
    sim.diagnostics.final_energy = sim.energy();
    Ok(monitor.warnings().to_vec())
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

/// `hompm run`.
pub fn run_scene(a: RunArgs, limits: &Limits) -> Result<Output> {
    validate(&a)?;
    if a.scene == SceneArg::AlignedVibration {
        return aligned::run_aligned(&a, limits);
    }
    check_limits(&a, limits)?;
    let (mut sim, params, reference) = build(&a)?;
    let warnings = advance(&mut sim, a.dt, a.steps)?;
    let diagnostics = diagnostics_with_errors(&sim, &reference)?;
    let pt = &sim.particles;
    let doc = RunJson {
        scene: name(&a.scene),
        params,
        method: name(&a.method),
        node_integrals: (a.method == MethodArg::Ddmpm).then_some(a.node_integrals),
        mapping: name(&a.mapping),
        mass: name(&a.mass),
        cells: a.cells,
        ppc: a.ppc(),
        dt: a.dt,
        steps: a.steps,
        time: sim.time,
        particles: ParticleJson {
            x0: pt.x0.clone(),
            x: pt.x.clone(),
            u: pt.u.clone(),
            v: pt.v.clone(),
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
            "{} (E = {}), {} with {} mapping and {} mass, {} cells × {} PPC, {} steps of {:e} s (t = {:e} s)\ndiagnostics: {}\n",
            doc.scene, sim.settings.young, doc.method, doc.mapping, doc.mass, doc.cells, doc.ppc, doc.steps, doc.dt, doc.time, doc.diagnostics
        )
    };
    Ok(Output {
        stdout,
        warnings,
        failure: None,
    })
}

/// The run's diagnostics with the RMS errors (thesis Eq. 4.3 style) of u,
/// v and σ at the particles' initial positions, where the scene knows them.
fn diagnostics_with_errors(sim: &Simulation, reference: &Reference) -> Result<serde_json::Value> {
    let mut diagnostics = serde_json::to_value(&sim.diagnostics)
        .map_err(|e| Error::InvalidArgument(e.to_string()))?;
    let pt = &sim.particles;
    let refs: Vec<[Option<f64>; 3]> = pt.x0.iter().map(|&x| reference(x, sim.time)).collect();
    let fields = [
        ("rms_displacement", &pt.u),
        ("rms_velocity", &pt.v),
        ("rms_stress", &pt.stress),
    ];
    for (k, (field_name, field)) in fields.into_iter().enumerate() {
        let exact: Option<Vec<f64>> = refs.iter().map(|r| r[k]).collect();
        if let (Some(exact), Some(obj)) = (exact, diagnostics.as_object_mut()) {
            obj.insert(
                field_name.into(),
                serde_json::json!(rms_error(field, &exact)?),
            );
        }
    }
    Ok(diagnostics)
}
