//! # One time step of 2D MPM, BSMPM and BSMPM with MLS or TLS
//!
//! The algorithm of the MLS paper (Eqs. 18–37), phase by phase. Each phase is
//! one function of [`super::phases`] (re-exported here), called in this
//! order by [`Simulation2d::step`]:
//!
//! 1. [`evaluate_basis`]: N_i(x_p) and ∇N_i(x_p) at the particles (Eqs. 4–5),
//!    as two 1D stencils per particle;
//! 2. phase 1, the mapping to the grid: [`map_direct`] (particles as the
//!    quadrature points: m_i = Σ_p N_i m_p, (mv)_i = Σ_p N_i m_p v_p,
//!    f_i^b = Σ_p N_i m_p b_p, f_i^int = −Σ_p ∇N_i σ_p V_p) or
//!    [`map_reconstructed`] (Eqs. 18–21 by a reconstruction to the Gauss
//!    points, MLS or TLS, [`super::reconstruction`]; then Eqs. 22–25 by 2×2
//!    Gauss quadrature);
//! 3. phase 2, [`nodal_update`]: f = f^int + f^b (Eq. 26), a = f/m (27),
//!    (mv)^{t+1} = (mv)^t + f Δt (28), with zero normal velocity on the walls;
//! 4. phase 3, [`update_particles`]: v_p and x_p (Eqs. 29–30);
//! 5. [`end_of_step_velocity`]: the second mapping (Eqs. 31–33), direct or by
//!    the reconstruction with the same φ_gp;
//! 6. [`update_deformation`]: ∇v_p (34), F_p (35), V_p (36), ρ_p (37) and the
//!    neo-Hookean stress (Eq. 41).
//!
//! Conventions (docs/conventions.md, "2D MPM"): every basis function and
//! every φ_gp of a step is evaluated at the positions x_p^t of its start;
//! the body force b is per unit mass (Eq. 42 has units of acceleration), so
//! Eqs. (20) and (24) map ρ_p b_p; the mass is lumped, as in the paper; a
//! node without mass (m_i ≤ 0, possible only where no particle reaches) is
//! inactive: a_i = v_i = 0.
//!
//! [`Simulation2d::step_observed`] calls a [`StepObserver2d`] after each
//! phase ([`StepPoint2d`]) with the simulation as the phase left it; the
//! trace of `hompm trace aligned-vibration` is recorded so, from the step
//! that runs. [`Simulation2d::step`] passes [`NoObserver2d`].
//!
//! A step allocates nothing: the stencils, nodal arrays and MLS lists live
//! in a [`Workspace2d`] made once (the MLS lists grow only if a Gauss point
//! gathers more particles than the reserve).
//!
//! Items: [`Mapping2d`], [`MappingInfo`], [`ReconstructionRecord`], [`Formulation`], [`BodyForce2d`], [`Settings2d`], [`Workspace2d`],
//! [`Conservation2d`], [`Simulation2d`], [`StepPoint2d`], [`StepObserver2d`],
//! [`NoObserver2d`].
//!
//! Re-exported from [`super::phases`]: the phase functions above and the
//! total-Lagrangian reference's `map_direct_reference` and
//! `update_deformation_reference`.

use super::grid::Grid2d;
use super::material::NeoHookean;
use super::mls::MlsShapes;
use super::particles::Particles2d;
use super::phases::{evaluate_basis_at_reference, record_conservation};
use super::reconstruction::GaussReconstruction;
use super::tls::TlsShapes;
use crate::basis::Stencils;
use crate::error::{Error, Result};
use crate::spline::bspline::SpanScratch;
use serde::{Deserialize, Serialize};

pub use super::phases::{
    end_of_step_velocity, evaluate_basis, map_direct, map_direct_reference, map_reconstructed,
    nodal_update, update_deformation, update_deformation_reference, update_particles,
};

/// How particle data reach the grid (MLS paper, "phase 1").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mapping2d {
    /// Particles as the quadrature points (standard MPM, BSMPM).
    Direct,
    /// MLS to the 2×2 Gauss points of each cell, then Gauss quadrature,
    /// in both mappings of a step (Eqs. 18–25 and 31–33).
    Mls,
    /// hompm's diagnostic variant: MLS in phase 1 (Eqs. 18–25) and the
    /// direct mapping for the end-of-step velocity (Eqs. 31–33), to tell
    /// which of the two MLS mappings drives the errors.
    MlsPhase1,
    /// Conservative Taylor least squares (TLS paper §5.2–5.5 on the cells,
    /// [`super::tls`]) in place of MLS, in both mappings of a step.
    Tls,
}

/// What the rest of hompm knows of a mapping: its names and its cost. One
/// [`Mapping2d::info`] arm per mapping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MappingInfo {
    /// The name in JSON (serde's) and on the command line, where the
    /// aligned vibration offers `bsmpm-<name>` (`direct` is plain `bsmpm`).
    pub name: &'static str,
    /// What a method label appends: `BSMPM-p2-<label>` (empty for direct).
    pub label: &'static str,
    /// One line for `--help`.
    pub summary: &'static str,
    /// The divan benchmark's cost of a step at degree 2, in ns per
    /// particle-step (benches/mpm2d.rs, rounded up): the command line's
    /// run-time estimate.
    pub ns_per_particle_step: f64,
    /// Bytes per particle that the reconstruction keeps besides the
    /// particles and the grid (the memory estimate).
    pub bytes_per_particle: f64,
}

impl Mapping2d {
    /// Every mapping, in the order the command line lists them.
    pub const ALL: [Mapping2d; 4] = [
        Mapping2d::Direct,
        Mapping2d::Mls,
        Mapping2d::MlsPhase1,
        Mapping2d::Tls,
    ];

    /// The registration of a mapping's names and cost.
    pub fn info(self) -> MappingInfo {
        match self {
            Mapping2d::Direct => MappingInfo {
                name: "direct",
                label: "",
                summary: "B-spline MPM of degree --degree (MLS paper Figs. 2-4)",
                ns_per_particle_step: 110.0,
                bytes_per_particle: 0.0,
            },
            Mapping2d::Mls => MappingInfo {
                name: "mls",
                label: "MLS",
                summary: "B-spline MPM with MLS to the Gauss points (MLS paper; aligned-vibration only)",
                ns_per_particle_step: 500.0,
                bytes_per_particle: 7.0 * 40.0 * 12.0,
            },
            Mapping2d::MlsPhase1 => MappingInfo {
                name: "mls-phase1",
                label: "MLS-phase-1",
                summary: "B-spline MPM with MLS in phase 1 only, hompm's diagnostic (aligned-vibration only)",
                ns_per_particle_step: 500.0,
                bytes_per_particle: 7.0 * 40.0 * 12.0,
            },
            Mapping2d::Tls => MappingInfo {
                name: "tls",
                label: "TLS",
                summary: "B-spline MPM with conservative Taylor least squares to the Gauss points (TLS paper §5 in 2D; aligned-vibration only)",
                ns_per_particle_step: 250.0,
                bytes_per_particle: 0.0,
            },
        }
    }

    /// The registration of the Gauss-point reconstructions: the
    /// [`GaussReconstruction`] of this mapping for `particles` particles on
    /// `cells`² cells (MLS with support scale `mls_support`), or `None` for
    /// the direct mapping.
    pub fn reconstruction(
        self,
        mls_support: f64,
        cells: usize,
        particles: usize,
    ) -> Result<Option<Box<dyn GaussReconstruction>>> {
        Ok(match self {
            Mapping2d::Direct => None,
            Mapping2d::Mls | Mapping2d::MlsPhase1 => {
                Some(Box::new(MlsShapes::new(mls_support, cells, particles)?))
            }
            Mapping2d::Tls => Some(Box::new(TlsShapes::for_engine(cells, particles)?)),
        })
    }

    /// The mapping's name in JSON and on the command line:
    /// [`MappingInfo::name`].
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// The mapping of a name, if one is registered under it.
    pub fn from_name(name: &str) -> Option<Mapping2d> {
        Mapping2d::ALL.into_iter().find(|m| m.name() == name)
    }

    /// Whether the end-of-step velocity (Eqs. 31–33) is mapped through the
    /// reconstruction too (every reconstruction but the phase-1 diagnostic).
    pub fn reconstructs_end_of_step(self) -> bool {
        !matches!(self, Mapping2d::Direct | Mapping2d::MlsPhase1)
    }
}

/// The points of a 2D step after which a [`StepObserver2d`] is called.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum StepPoint2d {
    /// Phase 1 (Eqs. 18–25): m_i, (mv)_i and f_i = f^b + f^int in the
    /// workspace (and, with MLS, the Gauss-point values of Eqs. 18–21).
    GridMapping,
    /// Phase 2 (Eqs. 26–28): `acceleration` holds a_i, `momentum_next`
    /// (mv)^{t+1}, `velocity_next` v^{t+1} = (mv)^{t+1}/m.
    NodalUpdate,
    /// Phase 3 (Eqs. 29–30): v_p, x_p and u_p.
    ParticleUpdate,
    /// Eqs. (31)–(33): `momentum_end` holds (mv)^L, `velocity_end` v^L.
    EndOfStepVelocity,
    /// Eqs. (34)–(37), (41): F_p, V_p, ρ_p, σ_p.
    Deformation,
}

/// Called by [`Simulation2d::step_observed`] after each phase.
pub trait StepObserver2d {
    /// The step has just passed `point`; `sim.steps` steps were completed
    /// before this one.
    fn observe(&mut self, point: StepPoint2d, sim: &mut Simulation2d) -> Result<()>;
}

/// The observer that does nothing ([`Simulation2d::step`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct NoObserver2d;

impl StepObserver2d for NoObserver2d {
    #[inline(always)]
    fn observe(&mut self, _: StepPoint2d, _: &mut Simulation2d) -> Result<()> {
        Ok(())
    }
}

/// A body force per unit mass given at the particles, b_p(t).
pub trait BodyForce2d: Send + Sync {
    /// Writes b(X_p, t) for every particle with initial position `x0[p]`.
    fn fill(&self, time: f64, x0: &[[f64; 2]], out: &mut [[f64; 2]]);
}

/// The configuration the grid is attached to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Formulation {
    /// The MLS paper's method: the basis is evaluated at the current
    /// positions x_p^t every step, so particles cross cells (Eqs. 29–37).
    UpdatedLagrangian,
    /// hompm's reference without grid crossing: the basis is evaluated once
    /// at the initial positions X_p and differentiated in X; the internal
    /// force is −Σ_p V_p⁰ P_p ∇_X N_i = −Σ_p V_p σ_p F_p⁻ᵀ ∇_X N_i and
    /// F_p ← F_p + Δt Σ_i v_i^L ⊗ ∇_X N_i (Ḟ = ∇_X v): a total-Lagrangian
    /// finite-element method with particle quadrature. Direct mapping only.
    TotalLagrangian,
}

/// What a 2D run needs besides its grid and particles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings2d {
    /// Updated (the paper) or total Lagrangian (the reference).
    pub formulation: Formulation,
    /// Direct or MLS mapping.
    pub mapping: Mapping2d,
    /// The material.
    pub material: NeoHookean,
    /// The MLS support scale s (r = |x − x_p|/(s·h)); unused for `Direct`.
    pub mls_support: f64,
}

/// The largest relative mapping errors of a run: mass |Σ_i m_i − Σ_p m_p| /
/// Σ_p m_p and momentum |Σ_i (mv)_i − Σ_p m_p v_p| / Σ_p m_p |v_p|, taken
/// over every phase-1 mapping (before the wall conditions).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Conservation2d {
    /// Largest relative mass error.
    pub mass: f64,
    /// Largest relative momentum error.
    pub momentum: f64,
}

/// Everything a step writes besides the particles, allocated once.
#[derive(Debug)]
pub struct Workspace2d {
    /// The x-axis basis at every particle.
    pub along_x: Stencils,
    /// The y-axis basis at every particle.
    pub along_y: Stencils,
    pub(super) scratch: SpanScratch,
    /// b_p(t) per unit mass.
    pub body_force: Vec<[f64; 2]>,
    /// Lumped nodal masses m_i (Eq. 22).
    pub mass: Vec<f64>,
    /// Nodal momenta (mv)_i^t of phase 1 (Eq. 23).
    pub momentum: Vec<[f64; 2]>,
    /// Nodal forces f_i = f_i^b + f_i^int of phase 1 (Eqs. 24–26), before
    /// the walls' conditions.
    pub force: Vec<[f64; 2]>,
    /// Nodal accelerations a_i = f_i/m_i (Eq. 27), zero normal to the walls.
    pub acceleration: Vec<[f64; 2]>,
    /// Updated nodal momenta (mv)_i^{t+1} = (mv)_i^t + f_i Δt (Eq. 28).
    pub momentum_next: Vec<[f64; 2]>,
    /// Updated nodal velocities v_i^{t+1} = (mv)_i^{t+1}/m_i, which move the
    /// particles (Eq. 30).
    pub velocity_next: Vec<[f64; 2]>,
    /// End-of-step nodal momenta (mv)_i^L (Eqs. 31–32).
    pub momentum_end: Vec<[f64; 2]>,
    /// End-of-step nodal velocities v_i^L = (mv)_i^L/m_i (Eq. 33), which
    /// update the deformation (Eq. 34).
    pub velocity_end: Vec<[f64; 2]>,
    /// The Gauss-point reconstruction (MLS or TLS) of a reconstructed
    /// mapping; `None` for the direct mapping.
    pub reconstruction: Option<Box<dyn GaussReconstruction>>,
    /// [ρ, ρv_x, ρv_y, ρb_x, ρb_y, σ_xx, σ_yy, σ_xy] per particle, the values
    /// a reconstruction carries to the Gauss points (Eqs. 18–21).
    pub particle_values: Vec<[f64; 8]>,
    /// The same eight values at every Gauss point g = gx + 2·cells·gy after
    /// the reconstruction of phase 1, Eqs. (18)–(21).
    pub gauss_values: Vec<[f64; 8]>,
}

/// A 2D simulation: grid, particles, settings, workspace and clock.
pub struct Simulation2d {
    /// The grid.
    pub grid: Grid2d,
    /// The particles.
    pub particles: Particles2d,
    /// The settings.
    pub settings: Settings2d,
    /// The workspace.
    pub workspace: Workspace2d,
    /// The body force, if any.
    pub body_force: Option<Box<dyn BodyForce2d>>,
    /// Time reached.
    pub time: f64,
    /// Steps taken.
    pub steps: usize,
    /// Mapping errors so far.
    pub conservation: Conservation2d,
    /// What the reconstruction (if any) met so far: the largest condition
    /// number of its small systems and the most cells repaired in one step.
    pub reconstruction_record: ReconstructionRecord,
}

/// The largest κ and the most repaired cells of a run's reconstructions
/// (MLS: κ₁ of the moment matrices; TLS: κ₁ of the cells' normal matrices
/// and the cells whose basis was reduced, TLS paper §5.3).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct ReconstructionRecord {
    /// Largest condition number over every step.
    pub largest_condition: f64,
    /// Most cells repaired in one step.
    pub most_repaired: usize,
}

impl Simulation2d {
    /// A simulation at t = 0. Errors if a particle lies outside the grid or
    /// the settings are out of range.
    pub fn new(
        grid: Grid2d,
        particles: Particles2d,
        settings: Settings2d,
        body_force: Option<Box<dyn BodyForce2d>>,
    ) -> Result<Self> {
        let n = particles.len();
        let nodes = grid.num_nodes();
        if settings.formulation == Formulation::TotalLagrangian
            && settings.mapping != Mapping2d::Direct
        {
            return Err(Error::InvalidArgument(
                "the total-Lagrangian reference uses the direct mapping only".into(),
            ));
        }
        let reconstruction =
            settings
                .mapping
                .reconstruction(settings.mls_support, grid.cells(), n)?;
        let workspace = Workspace2d {
            along_x: grid.axis().stencils(n),
            along_y: grid.axis().stencils(n),
            scratch: SpanScratch::default(),
            body_force: vec![[0.0; 2]; n],
            mass: vec![0.0; nodes],
            momentum: vec![[0.0; 2]; nodes],
            force: vec![[0.0; 2]; nodes],
            acceleration: vec![[0.0; 2]; nodes],
            momentum_next: vec![[0.0; 2]; nodes],
            velocity_next: vec![[0.0; 2]; nodes],
            momentum_end: vec![[0.0; 2]; nodes],
            velocity_end: vec![[0.0; 2]; nodes],
            particle_values: if reconstruction.is_some() {
                vec![[0.0; 8]; n]
            } else {
                Vec::new()
            },
            gauss_values: if reconstruction.is_some() {
                vec![[0.0; 8]; 4 * grid.cells() * grid.cells()]
            } else {
                Vec::new()
            },
            reconstruction,
        };
        let mut sim = Self {
            grid,
            particles,
            settings,
            workspace,
            body_force,
            time: 0.0,
            steps: 0,
            conservation: Conservation2d::default(),
            reconstruction_record: ReconstructionRecord::default(),
        };
        evaluate_basis(&sim.grid, &sim.particles, &mut sim.workspace, 0)?;
        if settings.formulation == Formulation::TotalLagrangian {
            evaluate_basis_at_reference(&sim.grid, &sim.particles, &mut sim.workspace)?;
        }
        Ok(sim)
    }

    /// One step of length Δt > 0, MLS paper Eqs. (18)–(37).
    pub fn step(&mut self, dt: f64) -> Result<()> {
        self.step_observed(dt, &mut NoObserver2d)
    }

    /// One step of length Δt > 0 that calls `observer` after each phase
    /// ([`StepPoint2d`]).
    pub fn step_observed<O: StepObserver2d>(&mut self, dt: f64, observer: &mut O) -> Result<()> {
        crate::mpm::musl::check_time_step(dt)?;
        let total = self.settings.formulation == Formulation::TotalLagrangian;
        // The step and time this step reaches, for its errors.
        let (next_step, next_time) = (self.steps + 1, self.time + dt);
        let failed = move |e| at_step(e, next_step, next_time);
        {
            let (grid, p, ws) = (&self.grid, &self.particles, &mut self.workspace);
            if !total {
                evaluate_basis(grid, p, ws, self.steps)?;
            }
            if let Some(b) = &self.body_force {
                b.fill(self.time, &p.x0, &mut ws.body_force);
            }
            match self.settings.mapping {
                Mapping2d::Direct if total => map_direct_reference(grid, p, ws).map_err(failed)?,
                Mapping2d::Direct => map_direct(grid, p, ws),
                // Every other mapping is a registered reconstruction.
                _ => map_reconstructed(grid, p, ws)?,
            }
            record_conservation(p, ws, &mut self.conservation);
            if let Some(shapes) = &ws.reconstruction {
                let r = &mut self.reconstruction_record;
                r.largest_condition = r.largest_condition.max(shapes.largest_condition());
                r.most_repaired = r.most_repaired.max(shapes.repaired());
            }
        }
        observer.observe(StepPoint2d::GridMapping, self)?;
        nodal_update(&self.grid, &mut self.workspace, dt);
        observer.observe(StepPoint2d::NodalUpdate, self)?;
        update_particles(&self.grid, &mut self.particles, &self.workspace, dt);
        observer.observe(StepPoint2d::ParticleUpdate, self)?;
        let mapping = self.settings.mapping;
        end_of_step_velocity(&self.grid, &self.particles, &mut self.workspace, mapping);
        observer.observe(StepPoint2d::EndOfStepVelocity, self)?;
        let (grid, p, ws) = (&self.grid, &mut self.particles, &self.workspace);
        let material = &self.settings.material;
        if total {
            update_deformation_reference(grid, p, ws, material, dt)
        } else {
            update_deformation(grid, p, ws, material, dt)
        }
        .map_err(failed)?;
        observer.observe(StepPoint2d::Deformation, self)?;
        self.steps += 1;
        self.time += dt;
        Ok(())
    }

    /// `steps` steps of Δt.
    pub fn run(&mut self, dt: f64, steps: usize) -> Result<()> {
        for _ in 0..steps {
            self.step(dt)?;
        }
        Ok(())
    }
}

/// Puts the step and time into the blow-up error of the step that failed.
fn at_step(mut e: Error, failed_step: usize, failed_time: f64) -> Error {
    if let Error::InvertedDeformation { step, time, .. }
    | Error::NonFiniteVelocity { step, time, .. } = &mut e
    {
        *step = Some(failed_step);
        *time = Some(failed_time);
    }
    e
}
