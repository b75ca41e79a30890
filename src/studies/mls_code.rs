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
//! MLS_BSMPM (`MLS_BSMPM_solvertest1.m`), runs as [`MLS_BSMPM`] says:
//! cubic B-splines (`choice = 2`, line 6; `deg = 3`, line 66), USL (its
//! remap is commented out, lines 425-458), the code's 1D MLS at two Gauss
//! points per cell (`crate::mpm::mapping::mls`) and the consistent mass
//! (`lump = 0`, line 9), once with the code's weights (forces at h²/4,
//! mass at ρh/2, lines 322–332 against 363) and once with the consistent
//! weights h/2 (the fix; docs/conventions.md, "The MLS paper's code's 1D
//! MLS").
//!
//! Items: [`StripErrors`], [`StripStudy`], [`strip_study`], [`STRIP_SIZES`],
//! [`CodeSolver`], [`MLS_BSMPM`].

use crate::error::Result;
use crate::mpm::conventions::{Conventions, Positions, Scheme};
use crate::mpm::grid::Method;
use crate::mpm::mapping::{ConsistentSolver, Mapping, MassMatrix, MlsWeights};
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

/// The study: each of the code's solvers' errors at every size.
#[derive(Debug, Clone, PartialEq)]
pub struct StripStudy {
    /// The parameter set (mls-paper-code).
    pub parameters: StripParameters,
    /// MPM, by size.
    pub mpm: Vec<StripErrors>,
    /// BSMPM (p = 2), by size.
    pub bsmpm: Vec<StripErrors>,
    /// MLS_BSMPM with the code's weights, by size.
    pub mls: Vec<StripErrors>,
    /// MLS_BSMPM with the consistent weights (the fix), by size.
    pub mls_fixed: Vec<StripErrors>,
}

/// One of the code's three solvers, as `Vibration.m:205-232` calls them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CodeSolver {
    /// `MPM_solver.m`: P1, MUSL, particles moved by the updated grid
    /// momentum (`--positions grid`).
    Mpm,
    /// `BSMPM_solvertest.m`: quadratic B-splines, USL, lumped mass.
    Bsmpm,
    /// `MLS_BSMPM_solvertest1.m`: [`MLS_BSMPM`] with these weights.
    MlsBsmpm(MlsWeights),
}

/// The code's MLS_BSMPM as hompm runs it: cubic B-splines
/// (`MLS_BSMPM_solvertest1.m:6, 66`), the MLS mapping for forces, mass and
/// momentum, and the consistent mass (`lump = 0`, line 9; `nacc =
/// MASS\nforce`, line 394), under USL with the particles moved by the
/// updated grid velocity (lines 396-420).
pub const MLS_BSMPM: (Method, MassMatrix) = (
    Method::Bsmpm { degree: 3 },
    MassMatrix::Consistent(ConsistentSolver::Cholesky),
);

impl CodeSolver {
    /// hompm's discretisation of this solver on `cells` cells with `ppc`
    /// particles per cell: method, mapping, mass and conventions.
    pub fn discretisation(self, cells: usize, ppc: usize) -> Discretisation {
        let (method, mapping, mass) = match self {
            CodeSolver::Mpm => (Method::Mpm, Mapping::Direct, MassMatrix::Lumped),
            CodeSolver::Bsmpm => (
                Method::Bsmpm { degree: 2 },
                Mapping::Direct,
                MassMatrix::Lumped,
            ),
            CodeSolver::MlsBsmpm(weights) => (
                MLS_BSMPM.0,
                match weights {
                    MlsWeights::Code => Mapping::MlsCodeWeights,
                    MlsWeights::Consistent => Mapping::Mls,
                },
                MLS_BSMPM.1,
            ),
        };
        let mut d = Discretisation::new(method, mapping, mass, cells, ppc);
        let mut conventions = Conventions::default_for(1);
        conventions.positions = Positions::Grid;
        if self != CodeSolver::Mpm {
            conventions.scheme = Scheme::Usl;
        }
        d.conventions = conventions;
        d
    }
}

/// One run of the strip on `cells` cells, as the code runs `solver`.
fn run(p: &StripParameters, solver: CodeSolver, cells: usize) -> Result<StripErrors> {
    let d = solver.discretisation(cells, p.ppc);
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

/// Runs the code's three solvers (MLS_BSMPM with both weights) on
/// `sizes` with the set `mls-paper-code`.
pub fn strip_study(sizes: &[usize]) -> Result<StripStudy> {
    let parameters = parameters("mls-paper-code")?;
    let each = |solver: CodeSolver| -> Result<Vec<StripErrors>> {
        sizes.iter().map(|&c| run(&parameters, solver, c)).collect()
    };
    Ok(StripStudy {
        parameters,
        mpm: each(CodeSolver::Mpm)?,
        bsmpm: each(CodeSolver::Bsmpm)?,
        mls: each(CodeSolver::MlsBsmpm(MlsWeights::Code))?,
        mls_fixed: each(CodeSolver::MlsBsmpm(MlsWeights::Consistent))?,
    })
}
