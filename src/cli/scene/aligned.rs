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

use super::super::args::{name, MethodArg};
use super::super::limits::Limits;
use super::super::{json, Output};
use super::RunArgs;
use crate::error::{Error, Result};
use crate::scenes::aligned_vibration::{parameters, AlignedMethod, AlignedVibration};
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
    method: String,
    mapping: String,
    mass: String,
    degree: usize,
    cells: usize,
    ppc: usize,
    dt: f64,
    steps: usize,
    time: f64,
    particles: Particles2dJson,
    diagnostics: serde_json::Value,
    warnings: Vec<String>,
}

fn method(a: &RunArgs) -> Result<AlignedMethod> {
    if a.degree == 0 && a.method != MethodArg::Mpm {
        return Err(Error::InvalidDegree(format!(
            "{} needs --degree ≥ 1, got 0",
            name(&a.method)
        )));
    }
    match a.method {
        MethodArg::Mpm => Ok(AlignedMethod::Mpm),
        MethodArg::Bsmpm => Ok(AlignedMethod::Bsmpm { degree: a.degree }),
        MethodArg::BsmpmMls => Ok(AlignedMethod::BsmpmMls { degree: a.degree }),
        MethodArg::TlFe => Ok(AlignedMethod::TotalLagrangian { degree: a.degree }),
        other => Err(Error::InvalidArgument(format!(
            "aligned-vibration runs mpm, bsmpm, bsmpm-mls or tl-fe, not {}",
            name(&other)
        ))),
    }
}

/// 9 PPC is 3 per side; a PPC that is not a square has no layout.
fn per_side(ppc: usize) -> Result<usize> {
    let side = (ppc as f64).sqrt().round() as usize;
    if side * side == ppc {
        Ok(side)
    } else {
        Err(Error::InvalidArgument(format!(
            "aligned-vibration places --ppc particles on a square lattice in each cell, so --ppc must be a square (4, 9, 16, …), got {ppc}"
        )))
    }
}

/// Memory: about 400 bytes per particle, 100 per node, and for MLS 12
/// bytes per (Gauss point, particle) pair, about 40 per particle (up to 7
/// times that where the material is compressed); 250 bytes of JSON per
/// particle. Time: the divan benchmark's 60 (MPM), 110 (BSMPM p = 2) and
/// 500 (MLS) ns per particle-step, doubled for the compressed states and
/// scaled by (p + 1)²/9 for other degrees.
fn check_limits(a: &RunArgs, m: AlignedMethod, limits: &Limits) -> Result<()> {
    let particles = (a.cells as f64).powi(2) * a.ppc() as f64;
    let nodes = (a.cells as f64 + a.degree as f64).powi(2);
    let mls = matches!(m, AlignedMethod::BsmpmMls { .. });
    let what = || format!("a 2D run of {particles:.0} particles × {} steps", a.steps);
    let bytes = particles * (650.0 + if mls { 7.0 * 40.0 * 12.0 } else { 0.0 }) + nodes * 100.0;
    limits.check_memory(what, bytes, "particle, grid and MLS storage")?;
    let width2 = (a.degree as f64 + 1.0).powi(2) / 9.0;
    let ns = match m {
        AlignedMethod::Mpm => 60.0,
        AlignedMethod::BsmpmMls { .. } => 500.0 * width2,
        _ => 110.0 * width2,
    };
    limits.check_time(what, 2.0 * ns * 1e-9 * particles * a.steps as f64)
}

fn rows(m: &[nalgebra::Matrix2<f64>]) -> Vec<[f64; 4]> {
    m.iter()
        .map(|t| [t[(0, 0)], t[(0, 1)], t[(1, 0)], t[(1, 1)]])
        .collect()
}

/// `hompm run aligned-vibration`.
pub fn run_aligned(a: &RunArgs, limits: &Limits) -> Result<Output> {
    let m = method(a)?;
    let side = per_side(a.ppc())?;
    check_limits(a, m, limits)?;
    let scene = parameters(a.params.as_deref().unwrap_or("mls-paper-e1e7"))?;
    let mut sim = scene.simulation(m, a.cells, side, 1.0)?;
    sim.run(a.dt, a.steps)?;
    let errors = scene.errors(&sim)?;
    let p = &sim.particles;
    let diagnostics = serde_json::json!({
        "rms_displacement": errors.displacement,
        "rms_velocity": errors.velocity,
        "rms_stress": errors.stress,
        "mapping_mass_error": sim.conservation.mass,
        "mapping_momentum_error": sim.conservation.momentum,
    });
    let doc = Run2dJson {
        scene: "aligned-vibration".into(),
        params: scene,
        method: name(&a.method),
        mapping: if matches!(m, AlignedMethod::BsmpmMls { .. }) {
            "mls"
        } else {
            "direct"
        }
        .into(),
        mass: "lumped".into(),
        degree: if m == AlignedMethod::Mpm { 1 } else { a.degree },
        cells: a.cells,
        ppc: a.ppc(),
        dt: a.dt,
        steps: a.steps,
        time: sim.time,
        particles: Particles2dJson {
            x0: p.x0.clone(),
            x: p.x.iter().zip(&p.y).map(|(&x, &y)| [x, y]).collect(),
            u: p.displacement.clone(),
            v: p.velocity.clone(),
            stress: rows(&p.stress),
            deformation_gradient: rows(&p.deformation),
            volume: p.volume.clone(),
            density: p.density.clone(),
        },
        diagnostics,
        warnings: Vec::new(),
    };
    let stdout = if a.json {
        json::strict(&doc)?
    } else {
        format!(
            "aligned-vibration (E = {}), {} ({}), {} × {} cells × {} PPC, {} steps of {:e} s (t = {:e} s)\ndiagnostics: {}\n",
            scene.young, m.label(), doc.mapping, a.cells, a.cells, doc.ppc, a.steps, a.dt, sim.time, doc.diagnostics
        )
    };
    Ok(Output {
        stdout,
        warnings: Vec::new(),
        failure: None,
    })
}
