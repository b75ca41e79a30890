//! # Studies: many runs of one scene
//!
//! Parameter sweeps that the tables and the report share:
//! - [`critical_courant`]: the largest stable time step of Euler–Cromer MUSL,
//!   as a Courant number C = c Δt/h (thesis Eq. 3.5), by bisection;
//! - [`bar_errors`]: displacement, velocity and stress errors of the vibrating
//!   bar for a method at one resolution, with the wall time of the run
//!   (convergence and work-precision charts).
//!
//! Items: [`BarExtremes`], [`bar_extremes`], [`TRANSITS`], [`ENERGY_BOUND`], [`is_stable`],
//! [`critical_courant`], [`BarErrors`], [`bar_errors`], [`Variant`],
//! [`work_precision_variants`], [`WorkPoint`], [`work_precision`],
//! [`speed_variants`], [`SpeedPoint`], [`speed`], [`SolverPoint`],
//! [`solver_study`], [`StabilityPoint`], [`stability_map`], [`tls_example`],
//! [`tls_paper`], [`mls_paper`], [`mls_code`], [`mls_convergence`], [`failures`], [`report`], [`thesis`], [`book`].

pub mod book;
pub mod failures;
pub mod mls_code;
pub mod mls_convergence;
pub mod mls_paper;
pub mod report;
pub mod thesis;
pub mod tls_example;
pub mod tls_paper;

use crate::error::{Error, Result};
use crate::mpm::diagnostics::rms_error;
use crate::mpm::grid::Method;
use crate::mpm::mapping::{ConsistentSolver, Mapping, MassMatrix};
use crate::scenes::{vibrating_bar, Discretisation};
use crate::solve::cg::{conjugate_gradient, CgVariant};
use crate::solve::direct::cholesky_solve;
use crate::solve::pmultigrid::{PMultigrid, PMultigridOptions};
use crate::solve::spectrum::spectrum_kronecker;
use serde::Serialize;

/// The extremes of a standard-MPM run of the vibrating bar: the largest
/// |u_p| over all steps and the grid crossings (TLS paper §6.1, book §4.5).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BarExtremes {
    /// max over steps and particles of |u_p| \[m\].
    pub max_displacement: f64,
    /// Grid crossings counted by the run's diagnostics.
    pub crossings: usize,
}

/// Runs the bar `params` (a parameter set of [`vibrating_bar::parameters`])
/// with standard MPM, direct mapping and lumped mass, on `cells` cells with
/// `ppc` particles each, for `steps` steps of `dt`, and reports its
/// [`BarExtremes`].
pub fn bar_extremes(
    params: &str,
    cells: usize,
    ppc: usize,
    dt: f64,
    steps: usize,
) -> Result<BarExtremes> {
    let p = vibrating_bar::parameters(params)?;
    let mut sim = p.simulation(&Discretisation::direct(Method::Mpm, cells, ppc))?;
    let mut max_displacement: f64 = 0.0;
    for _ in 0..steps {
        sim.step(dt)?;
        max_displacement = sim
            .particles
            .displacement
            .iter()
            .fold(max_displacement, |a, u| a.max(u.abs()));
    }
    Ok(BarExtremes {
        max_displacement,
        crossings: sim.diagnostics.grid_crossings,
    })
}

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
    let d = Discretisation::direct(method, cells, ppc);
    let mut sim = p.simulation(&d)?;
    sim.settings.consistent_acceleration = consistent_acceleration;
    let h = p.length / cells as f64;
    let dt = courant * h / p.wave_speed();
    let steps = (TRANSITS * p.length / p.wave_speed() / dt).ceil() as usize;
    match sim.run(dt, steps) {
        Ok(()) => Ok(sim.diagnostics.final_energy <= ENERGY_BOUND * sim.diagnostics.initial_energy),
        Err(Error::BlowUp(_))
        | Err(Error::NonPhysicalParticle { .. })
        | Err(Error::ParticleLeftGrid { .. })
        | Err(Error::Singular(_))
        | Err(Error::OutsideDomain { .. }) => Ok(false),
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
    let (grid, particles) = (&sim.grid, &sim.particles);
    let stencils = grid.stencils_at(&particles.x)?;
    let mut ws = crate::mpm::mapping::MappingWorkspace::new(grid, particles.len())?;
    ws.begin_step(grid, particles, &[d.velocity_mapping])?;
    crate::mpm::mapping::project_velocity(
        grid,
        particles,
        &stencils,
        d.velocity_mapping,
        d.mass,
        &mut ws,
    )?;
    let nodal = &ws.velocity;
    let mut vg: Vec<f64> = (0..particles.len())
        .map(|k| stencils.interpolate(k, nodal))
        .collect();
    // Dirichlet DOFs carry zero velocity: their terms are taken out again.
    let last = grid.num_dofs() - 1;
    for (k, vg) in vg.iter_mut().enumerate() {
        let first = stencils.first[k];
        for (j, phi) in stencils.values_of(k).iter().enumerate() {
            if first + j == 0 || first + j == last {
                *vg -= phi * nodal[first + j];
            }
        }
    }
    Ok(BarErrors {
        cells: d.cells,
        h: p.length / d.cells as f64,
        displacement: rms_error(&sim.particles.displacement, &u)?,
        velocity: rms_error(&sim.particles.velocity, &v)?,
        velocity_half_step: rms_error(&sim.particles.velocity, &vh)?,
        grid_velocity: rms_error(&vg, &v)?,
        grid_velocity_half_step: rms_error(&vg, &vh)?,
        stress: rms_error(&sim.particles.stress, &s)?,
        seconds,
        particle_steps_per_second: (sim.particles.len() * steps) as f64 / seconds.max(1e-12),
    })
}

/// A method of the work-precision chart: label and discretisation maker.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Variant {
    /// Legend label.
    pub label: &'static str,
    /// Basis.
    pub method: Method,
    /// Mapping of force and velocity.
    pub mapping: Mapping,
    /// Mass of the velocity projection.
    pub mass: MassMatrix,
}

/// The variants compared in the work-precision chart.
pub fn work_precision_variants() -> Vec<Variant> {
    let chol = MassMatrix::Consistent(ConsistentSolver::Cholesky);
    let rich = MassMatrix::Consistent(ConsistentSolver::richardson(1e-9));
    vec![
        Variant {
            label: "MPM",
            method: Method::Mpm,
            mapping: Mapping::Direct,
            mass: MassMatrix::Lumped,
        },
        Variant {
            label: "MPM + TLS (consistent)",
            method: Method::Mpm,
            mapping: Mapping::Tls,
            mass: chol,
        },
        Variant {
            label: "DDMPM",
            method: Method::DDMPM,
            mapping: Mapping::Direct,
            mass: MassMatrix::Lumped,
        },
        Variant {
            label: "DDMPM + TLS (consistent)",
            method: Method::DDMPM,
            mapping: Mapping::Tls,
            mass: chol,
        },
        Variant {
            label: "BSMPM",
            method: Method::Bsmpm { degree: 2 },
            mapping: Mapping::Direct,
            mass: MassMatrix::Lumped,
        },
        Variant {
            label: "BSMPM + TLS (lumped)",
            method: Method::Bsmpm { degree: 2 },
            mapping: Mapping::Tls,
            mass: MassMatrix::Lumped,
        },
        Variant {
            label: "BSMPM + TLS (consistent)",
            method: Method::Bsmpm { degree: 2 },
            mapping: Mapping::Tls,
            mass: chol,
        },
        Variant {
            label: "BSMPM + CS (Richardson)",
            method: Method::Bsmpm { degree: 2 },
            mapping: Mapping::CubicSpline,
            mass: rich,
        },
    ]
}

/// One point of the work-precision chart.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WorkPoint {
    /// Variant label.
    pub label: &'static str,
    /// Cells.
    pub cells: usize,
    /// RMS displacement error at t = 1999·1e-5 s.
    pub error: f64,
    /// Wall time of the run, seconds.
    pub seconds: f64,
}

/// Error against wall time for every variant on the thesis' bar (Table 4.1,
/// 4 PPC, 1999 steps of 1e-5 s), one point per resolution. Runs are timed
/// one after the other (no parallel runs distort the clock).
pub fn work_precision(resolutions: &[usize]) -> Result<Vec<WorkPoint>> {
    let mut out = Vec::new();
    for v in work_precision_variants() {
        for &cells in resolutions {
            let d = Discretisation {
                method: v.method,
                force_mapping: v.mapping,
                velocity_mapping: v.mapping,
                mass: v.mass,
                cells,
                ppc: 4,
                conventions: Default::default(),
            };
            let e = bar_errors("thesis-table-4.1", &d, 1e-5, 1999)?;
            out.push(WorkPoint {
                label: v.label,
                cells,
                error: e.displacement,
                seconds: e.seconds,
            });
        }
    }
    Ok(out)
}

/// The variants of the speed study: every basis with the direct mapping and
/// a lumped mass, and quadratic B-splines with each reconstruction.
pub fn speed_variants() -> Vec<Variant> {
    let chol = MassMatrix::Consistent(ConsistentSolver::Cholesky);
    let rich = MassMatrix::Consistent(ConsistentSolver::richardson(1e-9));
    let bs2 = Method::Bsmpm { degree: 2 };
    let variant = |label, method, mapping, mass| Variant {
        label,
        method,
        mapping,
        mass,
    };
    vec![
        variant("MPM", Method::Mpm, Mapping::Direct, MassMatrix::Lumped),
        variant("DDMPM", Method::DDMPM, Mapping::Direct, MassMatrix::Lumped),
        variant("BSMPM p=2", bs2, Mapping::Direct, MassMatrix::Lumped),
        variant(
            "BSMPM p=3",
            Method::Bsmpm { degree: 3 },
            Mapping::Direct,
            MassMatrix::Lumped,
        ),
        variant(
            "BSMPM p=2 + TLS (lumped)",
            bs2,
            Mapping::Tls,
            MassMatrix::Lumped,
        ),
        variant("BSMPM p=2 + TLS (consistent)", bs2, Mapping::Tls, chol),
        variant("BSMPM p=2 + CS (Cholesky)", bs2, Mapping::CubicSpline, chol),
        variant(
            "BSMPM p=2 + CS (Richardson)",
            bs2,
            Mapping::CubicSpline,
            rich,
        ),
    ]
}

/// One point of the speed study.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpeedPoint {
    /// Variant label.
    pub label: &'static str,
    /// Number of particles (8 per cell).
    pub particles: usize,
    /// Steps timed per repetition.
    pub steps: usize,
    /// Best of the repetitions, nanoseconds per particle-step.
    pub ns_per_particle_step: f64,
}

/// Cost of a MUSL step against the number of particles, on the thesis' bar
/// (Table 4.1) with 8 PPC: for each variant and cell count, about 65 536
/// particle-steps timed `repetitions` times after one warm-up step; the best
/// time counts. Runs one after the other on one thread, so that nothing else
/// shares the clock.
pub fn speed(cells: &[usize], repetitions: usize) -> Result<Vec<SpeedPoint>> {
    let p = vibrating_bar::parameters("thesis-table-4.1")?;
    let mut out = Vec::new();
    for v in speed_variants() {
        for &c in cells {
            let d = Discretisation::new(v.method, v.mapping, v.mass, c, 8);
            let particles = c * d.ppc;
            let steps = (65_536 / particles).max(2);
            let mut best = f64::INFINITY;
            for _ in 0..repetitions.max(1) {
                let mut sim = p.simulation(&d)?;
                sim.step(1e-5)?;
                let start = std::time::Instant::now();
                sim.run(1e-5, steps)?;
                best = best.min(start.elapsed().as_secs_f64());
            }
            out.push(SpeedPoint {
                label: v.label,
                particles,
                steps,
                ns_per_particle_step: best * 1e9 / (particles * steps) as f64,
            });
        }
    }
    Ok(out)
}

/// One row of the solver study (book §4.6–4.7 beyond the published tables).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SolverPoint {
    /// Degree p.
    pub degree: usize,
    /// 1/h.
    pub spans: usize,
    /// 2D DOFs (n + p − 2)².
    pub dofs: usize,
    /// κ of the 2D Dirichlet mass matrix.
    pub condition_number: f64,
    /// CG iterations to 1e-8 (None if not run).
    pub cg_iterations: Option<usize>,
    /// CG wall time, seconds.
    pub cg_seconds: Option<f64>,
    /// p-multigrid V-cycles (book setting).
    pub pmg_cycles: Option<usize>,
    /// p-multigrid wall time including the hierarchy set-up, seconds.
    pub pmg_seconds: Option<f64>,
    /// Sparse Cholesky wall time (factor and solve), seconds.
    pub cholesky_seconds: Option<f64>,
}

/// κ, CG, p-multigrid and Cholesky for the book's 2D mass matrix at each
/// (p, 1/h); iterative solves up to `max_iterative_dofs` DOFs, Cholesky up to
/// `max_direct_dofs`.
pub fn solver_study(
    degrees: &[usize],
    spans: &[usize],
    max_iterative_dofs: usize,
    max_direct_dofs: usize,
) -> Result<Vec<SolverPoint>> {
    let mut out = Vec::new();
    for &p in degrees {
        for &n in spans {
            let k = crate::mass::unit_density_mass_2d(n, p, true)?;
            let dofs = k.rows();
            let kappa = spectrum_kronecker(&k)?.condition_number();
            let mut pt = SolverPoint {
                degree: p,
                spans: n,
                dofs,
                condition_number: kappa,
                cg_iterations: None,
                cg_seconds: None,
                pmg_cycles: None,
                pmg_seconds: None,
                cholesky_seconds: None,
            };
            if dofs <= max_iterative_dofs {
                let a = k.assemble();
                let ones = vec![-9.81; dofs];
                let mut f = vec![0.0; dofs];
                a.mul_vec(&ones, &mut f);
                let t = std::time::Instant::now();
                let cg = conjugate_gradient(&a, &f, 1e-8, 100_000, CgVariant::Recursive)?;
                pt.cg_seconds = Some(t.elapsed().as_secs_f64());
                pt.cg_iterations = Some(cg.iterations);
                let t = std::time::Instant::now();
                let mg = PMultigrid::unit_mass(n, p, 2, true, PMultigridOptions::default())?;
                let r = mg.solve(&f, 1e-8, 10_000);
                pt.pmg_seconds = Some(t.elapsed().as_secs_f64());
                pt.pmg_cycles = r.ok().map(|r| r.iterations);
                if dofs <= max_direct_dofs {
                    let t = std::time::Instant::now();
                    cholesky_solve(&a, &f)?;
                    pt.cholesky_seconds = Some(t.elapsed().as_secs_f64());
                }
            }
            out.push(pt);
        }
    }
    Ok(out)
}

/// One entry of the stability map.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StabilityPoint {
    /// Method label.
    pub method: String,
    /// Largest stable Courant number with lumped acceleration.
    pub lumped: f64,
    /// With consistent acceleration.
    pub consistent: f64,
}

/// Critical Courant numbers for the bases of the seeds (16 cells, 4 PPC).
pub fn stability_map(cells: usize) -> Result<Vec<StabilityPoint>> {
    let methods = [
        Method::Mpm,
        Method::DDMPM,
        Method::MpmP2,
        Method::Bsmpm { degree: 2 },
        Method::Bsmpm { degree: 3 },
    ];
    methods
        .iter()
        .map(|&m| {
            Ok(StabilityPoint {
                method: m.label(),
                lumped: critical_courant(m, false, cells, 4)?,
                consistent: critical_courant(m, true, cells, 4)?,
            })
        })
        .collect()
}
