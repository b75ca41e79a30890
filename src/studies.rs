//! # Studies: many runs of one scene
//!
//! Parameter sweeps that the tables and the report share:
//! - [`critical_courant`]: the largest stable time step of Euler–Cromer MUSL,
//!   as a Courant number C = c Δt/h (thesis Eq. 3.5), by bisection;
//! - [`bar_errors`]: displacement, velocity and stress errors of the vibrating
//!   bar for a method at one resolution, with the wall time of the run
//!   (convergence and work-precision charts).

use crate::error::{Error, Result};
use crate::mpm::diagnostics::rms_error;
use crate::mpm::grid::Method;
use crate::mpm::mapping::{Mapping, MassMatrix};
use crate::scenes::{vibrating_bar, Discretisation};
use serde::Serialize;

/// Wave transits L/c simulated by [`is_stable`].
pub const TRANSITS: f64 = 20.0;
/// Largest accepted growth of the energy in [`is_stable`].
pub const ENERGY_BOUND: f64 = 2.0;

/// Whether a vibrating-bar run (thesis Table 4.1) with Courant number
/// `courant` stays bounded for four wave transits: no typed failure and a
/// final energy within a factor 2 of the initial one.
pub fn is_stable(
    method: Method,
    consistent_acceleration: bool,
    cells: usize,
    ppc: usize,
    courant: f64,
) -> Result<bool> {
    let p = vibrating_bar::parameters("thesis-table-4.1")?;
    let d = Discretisation {
        method,
        force_mapping: Mapping::Direct,
        velocity_mapping: Mapping::Direct,
        mass: MassMatrix::Lumped,
        cells,
        ppc,
    };
    let mut sim = p.simulation(&d)?;
    sim.settings.consistent_acceleration = consistent_acceleration;
    let h = p.length / cells as f64;
    let dt = courant * h / p.wave_speed();
    let steps = (TRANSITS * p.length / p.wave_speed() / dt).ceil() as usize;
    match sim.run(dt, steps) {
        Ok(()) => Ok(sim.diagnostics.final_energy <= ENERGY_BOUND * sim.diagnostics.initial_energy),
        Err(Error::BlowUp(_)) | Err(Error::Singular(_)) | Err(Error::OutsideDomain { .. }) => {
            Ok(false)
        }
        Err(e) => Err(e),
    }
}

/// The largest Courant number below which every tested value is stable:
/// a scan C = 0.05, 0.10, … up to the first unstable value, then bisection
/// between it and the last stable one to ±0.005. (Stability need not be
/// monotone in C, so plain bisection could land on an island.)
pub fn critical_courant(
    method: Method,
    consistent_acceleration: bool,
    cells: usize,
    ppc: usize,
) -> Result<f64> {
    let step = 0.05;
    let mut lo = 0.0;
    let mut hi = f64::NAN;
    for k in 1..=80 {
        let c = step * k as f64;
        if is_stable(method, consistent_acceleration, cells, ppc, c)? {
            lo = c;
        } else {
            hi = c;
            break;
        }
    }
    if hi.is_nan() {
        return Ok(lo);
    }
    while hi - lo > 0.005 {
        let mid = 0.5 * (lo + hi);
        if is_stable(method, consistent_acceleration, cells, ppc, mid)? {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(lo)
}

/// RMS errors of one vibrating-bar run against the analytic solution, and
/// its wall time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BarErrors {
    /// Knot spans or elements.
    pub cells: usize,
    /// Element size h.
    pub h: f64,
    /// RMS displacement error.
    pub displacement: f64,
    /// RMS particle-velocity error at t.
    pub velocity: f64,
    /// RMS particle-velocity error against the analytic velocity at t − Δt/2
    /// (Euler–Cromer's velocity is second-order accurate at the half step).
    pub velocity_half_step: f64,
    /// RMS error of the grid velocity interpolated to the particles, Σφ_i v_i.
    pub grid_velocity: f64,
    /// The same against the analytic velocity at t − Δt/2.
    pub grid_velocity_half_step: f64,
    /// RMS stress error.
    pub stress: f64,
    /// Wall time of the run in seconds.
    pub seconds: f64,
    /// Particle-steps per second.
    pub particle_steps_per_second: f64,
}

/// Runs the bar `params` with a discretisation for `steps` steps of `dt`
/// and measures the errors at the particles' initial positions.
pub fn bar_errors(params: &str, d: &Discretisation, dt: f64, steps: usize) -> Result<BarErrors> {
    let p = vibrating_bar::parameters(params)?;
    let start = std::time::Instant::now();
    let mut sim = p.simulation(d)?;
    sim.run(dt, steps)?;
    let seconds = start.elapsed().as_secs_f64();
    let t = sim.time;
    let x0 = &sim.particles.x0;
    let exact = |f: &dyn Fn(f64, f64) -> f64| -> Vec<f64> { x0.iter().map(|&x| f(x, t)).collect() };
    let u = exact(&|x, t| p.displacement(x, t));
    let v = exact(&|x, t| p.velocity(x, t));
    let vh = exact(&|x, t| p.velocity(x, t - 0.5 * dt));
    let s = exact(&|x, t| p.stress(x, t));
    // Grid velocity at the particles: re-project the final particle velocities.
    let shapes = crate::mpm::mapping::particle_shapes(&sim.grid, &sim.particles)?;
    let proj = crate::mpm::mapping::project_velocity(
        &sim.grid,
        &sim.particles,
        &shapes,
        d.velocity_mapping,
        d.mass,
    )?;
    let mut vg: Vec<f64> = shapes
        .iter()
        .map(|sh| {
            sh.values
                .iter()
                .enumerate()
                .map(|(j, phi)| phi * proj.velocity[sh.first + j])
                .sum()
        })
        .collect();
    let last = sim.grid.num_dofs() - 1;
    for (k, sh) in shapes.iter().enumerate() {
        // Dirichlet DOFs carry zero velocity.
        for (j, phi) in sh.values.iter().enumerate() {
            if sh.first + j == 0 || sh.first + j == last {
                vg[k] -= phi * proj.velocity[sh.first + j];
            }
        }
    }
    Ok(BarErrors {
        cells: d.cells,
        h: p.length / d.cells as f64,
        displacement: rms_error(&sim.particles.u, &u)?,
        velocity: rms_error(&sim.particles.v, &v)?,
        velocity_half_step: rms_error(&sim.particles.v, &vh)?,
        grid_velocity: rms_error(&vg, &v)?,
        grid_velocity_half_step: rms_error(&vg, &vh)?,
        stress: rms_error(&sim.particles.stress, &s)?,
        seconds,
        particle_steps_per_second: (sim.particles.len() * steps) as f64 / seconds.max(1e-12),
    })
}
