//! # The MLS paper's claims under the setup of its own code
//!
//! The strip of the paper's code (`Vibration.m`, f30bc24;
//! [`crate::scenes::manufactured_strip`]) run by hompm as the code runs it
//! (issue #40): MPM with MUSL and the particles moved by the updated grid
//! momentum (`--positions grid`, `Update_Particle_Position.m`), BSMPM with
//! quadratic B-splines and USL (`BSMPM_solvertest.m`), 5 PPC, Δt = 0.4h/c
//! and the code's loop to just past t = 0.02 s. The RMS errors are MLS
//! paper Eq. (43) at the particles' initial positions and the run's end
//! time, as `Vibration.m` computes them. The code's third solver,
//! MLS_BSMPM (cubic splines, consistent mass, a 1D MLS with the code's
//! mass-weight mismatch, `MLS_BSMPM_solvertest1.m` lines 322–332 against
//! 363), has no hompm counterpart yet.
//!
//! Items: [`StripErrors`], [`StripStudy`], [`strip_study`], [`STRIP_SIZES`].

use crate::error::Result;
use crate::mpm::conventions::{Conventions, Positions, Scheme};
use crate::mpm::grid::Method;
use crate::mpm::mapping::{Mapping, MassMatrix};
use crate::scenes::manufactured_strip::{parameters, StripParameters};
use crate::scenes::Discretisation;

/// The sizes the code's `Paper.m` runs: 8, 16, 32 and 64 cells.
pub const STRIP_SIZES: [usize; 4] = [8, 16, 32, 64];

/// The RMS errors of one run (MLS paper Eq. 43 in 1D).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StripErrors {
    /// Cells.
    pub cells: usize,
    /// End time, steps × Δt.
    pub time: f64,
    /// RMS of u_p − u(X_p, t).
    pub displacement: f64,
    /// RMS of v_p − v(X_p, t).
    pub velocity: f64,
    /// RMS of σ_p − σ(X_p, t).
    pub stress: f64,
}

/// The study: MPM's and BSMPM's errors at every size.
#[derive(Debug, Clone, PartialEq)]
pub struct StripStudy {
    /// The parameter set (mls-paper-code).
    pub parameters: StripParameters,
    /// MPM, by size.
    pub mpm: Vec<StripErrors>,
    /// BSMPM (p = 2), by size.
    pub bsmpm: Vec<StripErrors>,
}

/// One run of the strip on `cells` cells, as the code runs `method`.
fn run(p: &StripParameters, method: Method, cells: usize) -> Result<StripErrors> {
    let mut d = Discretisation::new(method, Mapping::Direct, MassMatrix::Lumped, cells, p.ppc);
    let mut conventions = Conventions::default_for(1);
    conventions.positions = Positions::Grid;
    if matches!(method, Method::Bsmpm { .. }) {
        conventions.scheme = Scheme::Usl;
    }
    d.conventions = conventions;
    let placed = p.placed(cells);
    let (dt, steps) = placed.code_time_steps(cells);
    let mut sim = placed.simulation(&d)?;
    sim.run(dt, steps)?;
    let t = steps as f64 * dt;
    let q = &sim.particles;
    let rms = |f: &dyn Fn(usize) -> f64| {
        let n = q.len();
        ((0..n).map(|k| f(k).powi(2)).sum::<f64>() / n as f64).sqrt()
    };
    Ok(StripErrors {
        cells,
        time: t,
        displacement: rms(&|k| q.displacement[k] - placed.displacement(q.x0[k], t)),
        velocity: rms(&|k| q.velocity[k] - placed.velocity(q.x0[k], t)),
        stress: rms(&|k| q.stress[k] - placed.stress(q.x0[k], t)),
    })
}

/// Runs MPM and BSMPM on `sizes` with the set `mls-paper-code`.
pub fn strip_study(sizes: &[usize]) -> Result<StripStudy> {
    let parameters = parameters("mls-paper-code")?;
    let each = |method: Method| -> Result<Vec<StripErrors>> {
        sizes.iter().map(|&c| run(&parameters, method, c)).collect()
    };
    Ok(StripStudy {
        parameters,
        mpm: each(Method::Mpm)?,
        bsmpm: each(Method::Bsmpm { degree: 2 })?,
    })
}
