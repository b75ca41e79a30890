//! # `hompm run aligned-vibration`: the 2D scene of the MLS paper
//!
//! Runs one method on the aligned vibration (MLS paper Eqs. 18–42;
//! `scenes::aligned_vibration`) and prints the particle state with its
//! tensor fields, the RMS errors of Eq. (43) at the final time, and the
//! mapping errors of mass and momentum. The JSON has the keys of the 1D
//! run; positions, displacements and velocities are [x, y] pairs, and
//! `stress` and `deformation_gradient` are [xx, xy, yx, yy] rows.
//!
//! Items: [`run_aligned`].

use super::super::args::name;
use super::super::{json, Output};
use super::RunArgs;
use crate::error::Result;
use crate::mpm::conventions::Conventions;
use crate::mpm::monitor::Warning;
use crate::mpm2d::step::NoObserver2d;
use crate::oracle::exact::formulas_2d;
use crate::oracle::run::run_2d_observed;
use crate::oracle::setup::{Setup, Setup2d};
use crate::scenes::aligned_vibration::AlignedVibration;
use serde::Serialize;

#[derive(Serialize)]
struct Particles2dJson {
    x0: Vec<[f64; 2]>,
    x: Vec<[f64; 2]>,
    u: Vec<[f64; 2]>,
    v: Vec<[f64; 2]>,
    stress: Vec<[f64; 4]>,
    deformation_gradient: Vec<[f64; 4]>,
    volume: Vec<f64>,
    density: Vec<f64>,
}

#[derive(Serialize)]
struct Run2dJson {
    scene: String,
    params: AlignedVibration,
    /// The set the parameters started from (`custom` if overridden).
    params_set: String,
    /// The physical parameters the command line overrode.
    overridden: Vec<&'static str>,
    method: String,
    mapping: String,
    mass: String,
    /// Another code's conventions, when not the MLS paper's.
    #[serde(skip_serializing_if = "Option::is_none")]
    conventions: Option<Conventions>,
    degree: usize,
    cells: usize,
    ppc: usize,
    dt: f64,
    steps: usize,
    /// steps × dt.
    time: f64,
    /// The manufactured solution's formulas (MLS paper Eqs. 38–42).
    exact_solution: serde_json::Value,
    particles: Particles2dJson,
    diagnostics: serde_json::Value,
    warnings: Vec<Warning>,
}

fn rows(m: &[nalgebra::Matrix2<f64>]) -> Vec<[f64; 4]> {
    m.iter()
        .map(|t| [t[(0, 0)], t[(0, 1)], t[(1, 0)], t[(1, 1)]])
        .collect()
}

/// `hompm run aligned-vibration`, for a setup already checked against the
/// limits.
pub fn run_aligned(a: &RunArgs, s: &Setup2d) -> Result<Output> {
    let (scene, m) = (s.scene, s.method);
    let run = super::with_progress(s.steps, |progress| {
        run_2d_observed(s, &mut NoObserver2d, progress)
    })?;
    let sim = run.simulation;
    let errors = scene.errors(&sim)?;
    let p = &sim.particles;
    let mut diagnostics = serde_json::json!({
        "rms_displacement": errors.displacement,
        "rms_velocity": errors.velocity,
        "rms_stress": errors.stress,
        "mapping_mass_error": sim.conservation.mass,
        "mapping_momentum_error": sim.conservation.momentum,
    });
    if sim.workspace.reconstruction.is_some() {
        let r = sim.reconstruction_record;
        diagnostics["largest_condition_number"] = r.largest_condition.into();
        diagnostics["most_repaired_cells"] = r.most_repaired.into();
    }
    let doc = Run2dJson {
        scene: "aligned-vibration".into(),
        params: scene,
        params_set: s.set_name.into(),
        overridden: a.setup.overrides().names(),
        method: name(&a.setup.method),
        mapping: m.parts().1.name().into(),
        mass: "lumped".into(),
        conventions: (!s.conventions.is_mls_paper()).then_some(s.conventions),
        degree: m.degree(),
        cells: s.cells,
        ppc: s.per_side * s.per_side,
        dt: s.dt,
        steps: s.steps,
        time: Setup::TwoD(*s).end_time(),
        exact_solution: formulas_2d(false),
        particles: Particles2dJson {
            x0: p.x0.clone(),
            x: p.x.clone(),
            u: p.displacement.clone(),
            v: p.velocity.clone(),
            stress: rows(&p.stress),
            deformation_gradient: rows(&p.deformation),
            volume: p.volume.clone(),
            density: p.density.clone(),
        },
        diagnostics,
        warnings: run.warnings,
    };
    let warnings = doc.warnings.iter().map(ToString::to_string).collect();
    let stdout = if a.json {
        json::strict(&doc)?
    } else {
        format!(
            "aligned-vibration (E = {}{}), {} ({}{}), {} × {} cells × {} PPC, {} steps of {:e} s (t = {:e} s)\ndiagnostics: {}\n",
            scene.young, if scene.solution.is_mls_paper() { String::new() } else { format!(", --solution {}", scene.solution.name()) }, m.label(), doc.mapping, super::conventions_words(&s.conventions, 2), s.cells, s.cells, doc.ppc, s.steps, s.dt, doc.time, doc.diagnostics
        )
    };
    Ok(Output {
        stdout,
        warnings,
        failure: None,
    })
}
