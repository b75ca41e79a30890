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
//! that runs. [`Simulation2d::step`] passes [`NoObserver2d`], which does not
//! observe (`StepObserver2d::OBSERVES`): such a step runs phases 3 and the
//! end-of-step scatter (Eqs. 29–31) in one particle loop,
//! [`update_particles_and_end_momentum`], where the conventions allow
//! ([`fuses_end_of_step`]), the same bits as the two passes.
//!
//! A step allocates nothing: the stencils, nodal arrays and MLS lists live
//! in a [`StepWorkspace2d`] made once (the MLS lists grow only if a Gauss point
//! gathers more particles than the reserve).
//!
//! Items: [`ReconstructionRecord`], [`Formulation`], [`BodyForce2d`], [`Settings2d`], [`Simulation2d`], [`StepPoint2d`], [`StepObserver2d`],
//! [`NoObserver2d`].
//!
//! Re-exported from [`super::mapping`]: [`Mapping2d`], [`MappingInfo`]; from
//! [`super::workspace`]: [`StepWorkspace2d`], [`Conservation2d`]; from
//! [`super::phases`]: the phase functions above and the
//! total-Lagrangian reference's `map_direct_reference` and
//! `update_deformation_reference`.

use super::grid::{Basis2d, Grid2d};
use super::material::NeoHookean;
use super::particles::Particles2d;
use super::phases::evaluate_basis_at_reference;
use super::workspace::record_conservation;
use crate::error::{Error, Result};
use crate::mpm::conventions::{BodyForceAt, Conventions, Gradient, Positions, Scheme, Transfer};
use crate::spline::bspline::SpanScratch;
use serde::{Deserialize, Serialize};

pub use super::mapping::{Mapping2d, MappingInfo};
pub use super::phases::{
    end_of_step_velocity, end_of_step_velocity_from_momentum, end_of_step_velocity_from_values,
    evaluate_basis, fuses_end_of_step, fuses_end_values, map_direct, map_direct_apic,
    map_direct_reference, map_reconstructed, move_particles, nodal_update, update_deformation,
    update_deformation_affine, update_deformation_reference, update_particles,
    update_particles_and_end_momentum, update_particles_and_end_values, update_particles_apic,
};
pub use super::workspace::{Conservation2d, StepWorkspace2d};

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
    /// Whether the observer looks: a step nobody observes runs phase 3 and
    /// the end-of-step scatter in one particle loop where it can
    /// (`update_particles_and_end_momentum`), the same numbers without the
    /// [`StepPoint2d::ParticleUpdate`] between them.
    const OBSERVES: bool = true;

    /// The step has just passed `point`; `sim.steps` steps were completed
    /// before this one.
    fn observe(&mut self, point: StepPoint2d, sim: &mut Simulation2d) -> Result<()>;
}

/// The observer that does nothing ([`Simulation2d::step`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct NoObserver2d;

impl StepObserver2d for NoObserver2d {
    const OBSERVES: bool = false;

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
    /// Scheme, transfer, positions and body force
    /// ([`Conventions::MLS_PAPER`] unless another code's are asked for;
    /// `--scheme usf` is 1D only).
    pub conventions: Conventions,
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
    pub workspace: StepWorkspace2d,
    /// The body force, if any: evaluated at the particles' X_p, or with
    /// `--body-force nodes` at [`Grid2d::node_positions`].
    pub body_force: Option<Box<dyn BodyForce2d>>,
    /// The nodes' positions X_i (`--body-force nodes`; empty otherwise).
    pub node_positions: Vec<[f64; 2]>,
    /// Time reached.
    pub time: f64,
    /// Steps taken.
    pub steps: usize,
    /// Mapping errors so far.
    pub conservation: Conservation2d,
    /// What the reconstruction (if any) met so far: the largest condition
    /// number of its small systems and the most cells repaired in one step.
    pub reconstruction_record: ReconstructionRecord,
    /// Whether the steps record `conservation` and `reconstruction_record`
    /// (off with [`Simulation2d::without_diagnostics`]).
    records_diagnostics: bool,
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
        let nodes = grid.num_dofs();
        if settings.formulation == Formulation::TotalLagrangian
            && settings.mapping != Mapping2d::Direct
        {
            return Err(Error::InvalidArgument(
                "the total-Lagrangian reference uses the direct mapping only".into(),
            ));
        }
        settings.conventions.check_2d(
            grid.basis() == Basis2d::BSpline { degree: 2 },
            settings.mapping == Mapping2d::Direct,
            settings.formulation == Formulation::TotalLagrangian,
        )?;
        let reconstruction =
            settings
                .mapping
                .reconstruction(settings.mls_support, grid.cells_per_side(), n)?;
        let node_positions = match settings.conventions.body_force {
            BodyForceAt::Nodes => grid.node_positions(),
            BodyForceAt::Particles => Vec::new(),
        };
        let workspace = StepWorkspace2d {
            stencils_x: grid.axis().stencils(n),
            stencils_y: grid.axis().stencils(n),
            scratch: SpanScratch::default(),
            body_force: vec![[0.0; 2]; n],
            node_along: match settings.conventions.transfer {
                Transfer::Apic => grid.node_positions_along(),
                _ => Vec::new(),
            },
            nodal_body_force: match settings.conventions.body_force {
                BodyForceAt::Nodes => vec![[0.0; 2]; nodes],
                BodyForceAt::Particles => Vec::new(),
            },
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
            end_values: if reconstruction.is_some() {
                vec![[0.0; 3]; n]
            } else {
                Vec::new()
            },
            gauss_values: if reconstruction.is_some() {
                vec![[0.0; 8]; 4 * grid.cells_per_side() * grid.cells_per_side()]
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
            node_positions,
            time: 0.0,
            steps: 0,
            conservation: Conservation2d::default(),
            reconstruction_record: ReconstructionRecord::default(),
            records_diagnostics: true,
        };
        evaluate_basis(&sim.grid, &sim.particles, &mut sim.workspace, 0)?;
        if settings.formulation == Formulation::TotalLagrangian {
            evaluate_basis_at_reference(&sim.grid, &sim.particles, &mut sim.workspace)?;
        }
        Ok(sim)
    }

    /// The same simulation with its run monitors off: the steps skip the
    /// mapping errors ([`Simulation2d::conservation`], four compensated sums
    /// over the particles per step) and the reconstruction's record, which
    /// keep their initial values. The particles and the grid evolve bit for
    /// bit as with them on. For timing what the monitors cost, as the 1D
    /// `Simulation::without_diagnostics` (examples/mpm2d_step_cost.rs,
    /// issue #39).
    pub fn without_diagnostics(mut self) -> Self {
        self.records_diagnostics = false;
        self
    }

    /// Whether the steps record the mapping errors and the reconstruction's
    /// record ([`Simulation2d::without_diagnostics`]).
    pub fn records_diagnostics(&self) -> bool {
        self.records_diagnostics
    }

    /// One step of length Δt > 0, MLS paper Eqs. (18)–(37).
    pub fn step(&mut self, dt: f64) -> Result<()> {
        self.step_observed(dt, &mut NoObserver2d)
    }

    /// One step of length Δt > 0 that calls `observer` after each phase
    /// ([`StepPoint2d`]).
    pub fn step_observed<O: StepObserver2d>(&mut self, dt: f64, observer: &mut O) -> Result<()> {
        crate::mpm::check_time_step(dt)?;
        let total = self.settings.formulation == Formulation::TotalLagrangian;
        // The step and time this step reaches, for its errors.
        let (next_step, next_time) = (self.steps + 1, self.time + dt);
        let failed = move |e| at_step(e, next_step, next_time);
        {
            let (grid, p, ws) = (&self.grid, &self.particles, &mut self.workspace);
            if !total {
                evaluate_basis(grid, p, ws, self.steps)?;
            }
            let at_nodes = self.settings.conventions.body_force == BodyForceAt::Nodes;
            if let Some(b) = &self.body_force {
                if at_nodes {
                    b.fill(self.time, &self.node_positions, &mut ws.nodal_body_force);
                } else {
                    b.fill(self.time, &p.x0, &mut ws.body_force);
                }
            }
            let conventions = self.settings.conventions;
            match self.settings.mapping {
                Mapping2d::Direct if conventions.transfer == Transfer::Apic => {
                    map_direct_apic(grid, p, ws, conventions.gradient)
                }
                Mapping2d::Direct if total => map_direct_reference(grid, p, ws).map_err(failed)?,
                Mapping2d::Direct => map_direct(grid, p, ws),
                // Every other mapping is a registered reconstruction.
                _ => map_reconstructed(grid, p, ws)?,
            }
            if at_nodes && self.body_force.is_some() {
                add_nodal_body_force(ws);
            }
            if self.records_diagnostics {
                record_conservation(p, ws, &mut self.conservation);
            }
            if let (Some(shapes), true) = (&ws.reconstruction, self.records_diagnostics) {
                let r = &mut self.reconstruction_record;
                r.largest_condition = r.largest_condition.max(shapes.largest_condition());
                r.most_repaired = r.most_repaired.max(shapes.repaired());
            }
        }
        observer.observe(StepPoint2d::GridMapping, self)?;
        nodal_update(&self.grid, &mut self.workspace, dt);
        observer.observe(StepPoint2d::NodalUpdate, self)?;
        let (conventions, mapping) = (self.settings.conventions, self.settings.mapping);
        if !O::OBSERVES && fuses_end_of_step(conventions, mapping) {
            // Eqs. (29)–(31) in one particle loop, then (32)–(33).
            let (grid, p, ws) = (&self.grid, &mut self.particles, &mut self.workspace);
            update_particles_and_end_momentum(grid, p, ws, dt);
            end_of_step_velocity_from_momentum(grid, ws);
        } else if !O::OBSERVES && fuses_end_values(conventions, mapping) {
            // Eqs. (29)–(30) gathering [ρ_p, v_p] as they go, then (31)–(33).
            let (grid, p, ws) = (&self.grid, &mut self.particles, &mut self.workspace);
            update_particles_and_end_values(grid, p, ws, dt);
            end_of_step_velocity_from_values(grid, ws);
        } else {
            let (grid, p, ws) = (&self.grid, &mut self.particles, &self.workspace);
            if conventions.transfer == Transfer::Apic {
                update_particles_apic(grid, p, ws, dt);
            } else {
                update_particles(grid, p, ws, conventions, dt);
            }
            observer.observe(StepPoint2d::ParticleUpdate, self)?;
            match conventions.scheme {
                Scheme::Usl => {
                    let ws = &mut self.workspace;
                    ws.momentum_end.copy_from_slice(&ws.momentum_next);
                    ws.velocity_end.copy_from_slice(&ws.velocity_next);
                }
                _ => {
                    end_of_step_velocity(&self.grid, &self.particles, &mut self.workspace, mapping)
                }
            }
        }
        if conventions.positions == Positions::Projected {
            move_particles(&self.grid, &mut self.particles, &self.workspace, dt);
        }
        observer.observe(StepPoint2d::EndOfStepVelocity, self)?;
        let (grid, p, ws) = (&self.grid, &mut self.particles, &self.workspace);
        let material = &self.settings.material;
        if total {
            update_deformation_reference(grid, p, ws, material, dt)
        } else if conventions.gradient == Gradient::Affine {
            update_deformation_affine(p, material, dt)
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

/// `--body-force nodes`: f_i += m_i b(X_i, t) after phase 1, whose
/// particle body force was left zero.
fn add_nodal_body_force(ws: &mut StepWorkspace2d) {
    for ((f, &m), b) in ws.force.iter_mut().zip(&ws.mass).zip(&ws.nodal_body_force) {
        f[0] += m * b[0];
        f[1] += m * b[1];
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
