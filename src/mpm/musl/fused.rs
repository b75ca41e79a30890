//! # The step in three particle loops
//!
//! [`Simulation::step`] for the book's step (MUSL, FLIP and projected
//! positions: book §4.2.2, the body force from the particles or the nodes),
//! the direct mapping of forces and velocities, a lumped mass and the small-
//! or large-strain law, on a B-spline or Lagrange grid of stencil width 2
//! to 4 without DDMPM's dual domain: every 1D scene of the book and the
//! thesis that does not reconstruct. It computes bit for bit what the pass
//! per equation of [`Simulation::step_observed`] computes (the particles,
//! the workspace and every [`RunDiagnostics`] entry;
//! tests/spec/speed/fused_step.rs), because each sum is formed from the same
//! products in the same order, but it visits each particle three times
//! instead of fourteen (issue #39):
//!
//! 1. [`map_particles_to_grid`]: the basis at x_p, then the particle's
//!    mass m_p φ_i (book Eq. 4.5), internal force σ_p V_p ∇φ_i (Eq. 4.6) and
//!    loads (thesis §3.2) added to the nodes while the basis is in
//!    registers. Then on the grid: a_i (Eq. 4.8), a_i = 0 on Dirichlet DOFs.
//! 2. [`update_velocities_and_map_momentum`]: v_p (Eq. 4.9, FLIP), then its
//!    share of the projection p_i, M^L_i, M_ii (Eq. 4.10) and of the
//!    conservation monitor's particle totals. Then on the grid:
//!    v_i = p_i / M^L_i, the projection's record, v_i = 0 on Dirichlet DOFs.
//! 3. [`move_particles`]: u_p, x_p, Δε_p, σ_p, V_p, ρ_p, ε_p
//!    (Eqs. 4.11–4.18), with Δε_p in a register (the workspace's
//!    `strain_increment` is left empty), the strain and crossing monitors
//!    (thesis §3.3; the crossings counted from x_p^t and x_p^t+Δt) and
//!    the screen of the check that every particle is physical.
//!
//! The loops call the one-particle equations of
//! [`super::particle_equations`] (which the other path calls too) and keep
//! nodal sums in registers with [`StencilSums`]; the grid phases are the
//! same functions as the other path's. A step that an observer watches
//! (`hompm trace`, the planted defects of `hompm check`) takes the pass per
//! equation, so that every equation's quantity is there to be seen.
//!
//! Items: `Simulation::step_is_fused`, `Simulation::step_fused`.

use super::particle_equations::{
    displacement_and_strain_increment, flip_velocity, large_strain_stress, small_strain_stress,
    update_volume_density_strain,
};
use super::{particle_energy, BodyForceAt, Constitutive, Simulation, StepSummary};
use super::{Particles, StepWorkspace};
use crate::basis::{interpolate_row, StencilSums, Stencils};
use crate::error::{Error, Result};
use crate::mpm::grid::{fill::FixedWidthLoop, Grid};
use crate::mpm::mapping::{
    accumulate_lumped_row, accumulate_momentum_and_diagonal_row, both_finite, diagnose_projection,
    running_max, solve_projection, Mapping, MassMatrix,
};

impl Simulation {
    /// Whether [`Simulation::step`] takes the fused loops of this module:
    /// the book's conventions, the direct mapping for both transfers, a
    /// lumped mass (also in step 2), no manufactured body force field, the
    /// small- or large-strain law, and a grid that
    /// fills a fixed width (`Grid::fills_fixed_width`).
    pub fn step_is_fused(&self) -> bool {
        let s = &self.settings;
        !s.conventions.needs_grid_velocity()
            && s.force_mapping == Mapping::Direct
            && s.velocity_mapping == Mapping::Direct
            && s.mass == MassMatrix::Lumped
            && !s.consistent_acceleration
            && s.body_force.is_none()
            && matches!(
                s.constitutive,
                Constitutive::SmallStrain | Constitutive::LargeStrain
            )
            && self.grid.fills_fixed_width()
    }

    /// One step of size dt in three particle loops (module docs); the
    /// caller has checked dt and [`Simulation::step_is_fused`]. With `summarise`
    /// the last loop also sums the particles' energy for the
    /// [`StepSummary`] (else its energy is NaN).
    pub(super) fn step_fused(&mut self, dt: f64, summarise: bool) -> Result<StepSummary> {
        match (self.settings.constitutive, summarise) {
            (Constitutive::SmallStrain, false) => of_width::<false>(self, dt, small_strain_stress),
            (Constitutive::SmallStrain, true) => of_width::<true>(self, dt, small_strain_stress),
            (Constitutive::LargeStrain, false) => of_width::<false>(self, dt, large_strain_stress),
            (Constitutive::LargeStrain, true) => of_width::<true>(self, dt, large_strain_stress),
            (Constitutive::NeoHookean, _) => {
                Err(Error::Usage("the fused step has no neo-Hookean law".into()))
            }
        }
    }
}

/// [`step_fused_width`] at the simulation's stencil width.
fn of_width<const ENERGY: bool>(
    sim: &mut Simulation,
    dt: f64,
    law: impl Fn(f64, f64, f64) -> f64,
) -> Result<StepSummary> {
    match sim.workspace.stencils.width() {
        2 => step_fused_width::<2, ENERGY>(sim, dt, law),
        3 => step_fused_width::<3, ENERGY>(sim, dt, law),
        4 => step_fused_width::<4, ENERGY>(sim, dt, law),
        _ => step_fused_width::<0, ENERGY>(sim, dt, law),
    }
}

/// [`Simulation::step_fused`] with the stencil width `W` known at compile
/// time, the stress law (book Eq. 4.15 or 4.16) chosen, and whether to
/// sum the energy (`ENERGY`).
fn step_fused_width<const W: usize, const ENERGY: bool>(
    sim: &mut Simulation,
    dt: f64,
    law: impl Fn(f64, f64, f64) -> f64,
) -> Result<StepSummary> {
    if W == 0 {
        return Err(Error::Usage(
            "the fused step needs a stencil width of 2 to 4".into(),
        ));
    }
    // Δε_p stays in a register (module docs): no older step's values are
    // left to be read as this one's.
    let (n, ws) = (sim.particles.len(), &mut sim.workspace);
    ws.strain_increment.clear();
    ws.breaks_before.resize(n, 0);
    let g = sim.gravity_in_step(dt);
    let at_particles = sim.settings.conventions.body_force == BodyForceAt::Particles;
    let traction = sim.particles.has_traction();
    if traction || (at_particles && g != 0.0) {
        map_particles_to_grid::<W, true>(sim, g)?;
    } else {
        map_particles_to_grid::<W, false>(sim, g)?;
    }
    sim.nodal_acceleration()?;
    sim.apply_acceleration_conditions();
    let totals = if lumped_mass_is_nodal_mass(&sim.grid) {
        update_velocities_and_map_momentum::<W, true>(sim, dt)
    } else {
        update_velocities_and_map_momentum::<W, false>(sim, dt)
    };
    let mapping = &mut sim.workspace.mapping;
    let iterations = solve_projection(None, MassMatrix::Lumped, mapping)?;
    let projection = diagnose_projection(None, iterations, mapping);
    if let Some(t) = totals {
        sim.diagnostics.record_projection_totals(
            &projection,
            &mapping.velocity,
            t.fastest_particle_speed,
            t.mass,
            t.momentum,
        );
    }
    sim.apply_velocity_conditions();
    let screen = move_particles::<W, ENERGY>(sim, dt, law);
    if sim.records_diagnostics {
        sim.diagnostics
            .record_particle_extremes(screen.max_abs_strain, screen.crossings);
    }
    sim.time += dt;
    sim.diagnostics.steps += 1;
    if screen.suspect {
        sim.check_particles_are_physical()?;
    }
    Ok(StepSummary {
        energy: if ENERGY { screen.energy } else { f64::NAN },
        max_abs_strain: screen.max_abs_strain,
    })
}

/// Loop 1: φ_i(x_p), ∇φ_i(x_p) into the workspace's stencils and the
/// lumped mass m_i = Σ m_p φ_i (book Eq. 4.5), internal force
/// f_i = Σ σ_p V_p ∇φ_i (Eq. 4.6), gravity Σ m_p g φ_i and traction
/// Σ f_p φ_i (thesis §3.2; with the body force at the nodes, m_i g after
/// the loop). Without `LOADS` (no traction, no gravity at the particles)
/// the loads are not added: a load whose weights are all zero adds only ±0
/// to +0, and the other path skips it too. The loop itself is
/// [`MapParticlesToGrid`], compiled once per kind of basis.
fn map_particles_to_grid<const W: usize, const LOADS: bool>(
    sim: &mut Simulation,
    g: f64,
) -> Result<()> {
    let (grid, p, ws) = (&sim.grid, &sim.particles, &mut sim.workspace);
    let evaluator = grid
        .fixed_width_evaluator::<W>()
        .ok_or_else(|| Error::Usage("the fused step on a grid it does not serve".into()))?;
    let at_particles = sim.settings.conventions.body_force == BodyForceAt::Particles;
    for v in [
        &mut ws.mass,
        &mut ws.internal_force,
        &mut ws.gravity_force,
        &mut ws.traction_force,
    ] {
        v.fill(0.0);
    }
    evaluator.run(MapParticlesToGrid::<LOADS> {
        particles: p,
        workspace: &mut *ws,
        weight_per_mass: if at_particles { g } else { 0.0 },
    })?;
    if !at_particles && g != 0.0 {
        for (f, m) in ws.gravity_force.iter_mut().zip(&ws.mass) {
            *f = m * g;
        }
    }
    Ok(())
}

/// The particle loop of [`map_particles_to_grid`] and what it reads.
struct MapParticlesToGrid<'a, const LOADS: bool> {
    particles: &'a Particles,
    workspace: &'a mut StepWorkspace,
    /// g at the particles (the body force m_p g φ_i), else 0.
    weight_per_mass: f64,
}

impl<const W: usize, const LOADS: bool> FixedWidthLoop<W> for MapParticlesToGrid<'_, LOADS> {
    type Output = Result<()>;

    #[inline(always)]
    fn run(
        self,
        evaluate: impl Fn(f64, &mut [f64; W], &mut [f64; W]) -> Result<usize>,
    ) -> Result<()> {
        let Self {
            particles: p,
            workspace: ws,
            weight_per_mass,
        } = self;
        let n = p.len();
        ws.stencils.resize(n);
        let Stencils {
            first,
            values,
            gradients,
            ..
        } = &mut ws.stencils;
        let rows = values.as_chunks_mut::<W>().0.iter_mut();
        let rows = rows.zip(gradients.as_chunks_mut::<W>().0.iter_mut());
        let (x, mass, stress, volume) = (&p.x[..n], &p.mass[..n], &p.stress[..n], &p.volume[..n]);
        let traction = &p.traction[..n];
        // Mass and internal force in one pair of register sums, the loads
        // (when there are any) in another: each vector's additions in
        // particle order, as before.
        let mut forces = [&mut ws.mass[..], &mut ws.internal_force[..]];
        let mut loads = [&mut ws.gravity_force[..], &mut ws.traction_force[..]];
        let (mut force_sums, mut load_sums) = (
            StencilSums::<W, 2>::default(),
            StencilSums::<W, 2>::default(),
        );
        for (k, (first, (phi, dphi))) in first[..n].iter_mut().zip(rows).enumerate() {
            // Evaluated into locals, then stored: the sums below read the
            // basis from registers, not back from the rows just written.
            let (mut values, mut gradients) = ([0.0; W], [0.0; W]);
            *first = evaluate(x[k], &mut values, &mut gradients)?;
            (*phi, *dphi) = (values, gradients);
            let (phi, dphi) = (&values, &gradients);
            force_sums.move_to(*first, &mut forces);
            let [nodal_mass, force] = &mut force_sums.sums;
            let (m, stress_volume) = (mass[k], stress[k] * volume[k]);
            for a in 0..W {
                nodal_mass[a] += m * phi[a];
                force[a] += stress_volume * dphi[a];
            }
            if LOADS {
                load_sums.move_to(*first, &mut loads);
                let [gravity, trac] = &mut load_sums.sums;
                let (weight, t) = (m * weight_per_mass, traction[k]);
                for a in 0..W {
                    gravity[a] += weight * phi[a];
                    trac[a] += t * phi[a];
                }
            }
        }
        force_sums.store(&mut forces);
        load_sums.store(&mut loads);
        Ok(())
    }
}

/// What loop 2 sums over the particles for the projection's record
/// (present when the run records its diagnostics).
struct ParticleTotals {
    /// Σ m_p.
    mass: f64,
    /// Σ m_p v_p with the updated velocities.
    momentum: f64,
    /// max_p |v_p|.
    fastest_particle_speed: f64,
}

/// Whether the lumped mass of the projection, M^L_i = Σ_p m_p φ_i Σ_j φ_j
/// (book Eq. 4.10), is loop 1's nodal mass m_i = Σ_p m_p φ_i bit for bit:
/// on P1 elements φ = (fl(1 − ξ), ξ), and fl(fl(1 − ξ) + ξ) = 1 for every
/// ξ in [0, 1] (for ξ ≥ ½, 1 − ξ is exact; for ξ < ½, fl(1 − ξ) = 1 − ξ + δ
/// with |δ| ≤ 2⁻⁵⁴, and 1 + δ rounds to 1, a tie going to the even 1), so
/// each m_p φ_i · 1 is m_p φ_i, added in the same particle order from +0.
/// B-splines of degree 1 sum their Cox–de Boor values, which need not give
/// exactly 1, and keep the sum.
fn lumped_mass_is_nodal_mass(grid: &Grid) -> bool {
    grid.plain_lagrange()
        .is_some_and(|l| l.order().degree() == 1)
}

/// Loop 2: v_p ← v_p + Δt Σ φ_i a_i (book Eq. 4.9), then the projection's
/// momentum p_i = Σ m_p v_p φ_i, lumped mass M^L_i = Σ m_p φ_i Σ_j φ_j and
/// diagonal Σ m_p φ_i² (Eq. 4.10), and the particles' totals. With
/// `MASS_IS_LUMPED` ([`lumped_mass_is_nodal_mass`]) M^L is loop 1's nodal
/// mass, copied, and only p_i and the diagonal are summed.
fn update_velocities_and_map_momentum<const W: usize, const MASS_IS_LUMPED: bool>(
    sim: &mut Simulation,
    dt: f64,
) -> Option<ParticleTotals> {
    let (p, ws) = (&mut sim.particles, &mut sim.workspace);
    let n = sim.grid.num_dofs();
    let mapping = &mut ws.mapping;
    for v in [&mut mapping.momentum, &mut mapping.diagonal] {
        v.clear();
        v.resize(n, 0.0);
    }
    mapping.lumped.clear();
    let (velocity, mass) = (&mut p.velocity[..], &p.mass[..]);
    let on_grid = (&ws.stencils, &ws.acceleration[..]);
    let totals = if MASS_IS_LUMPED {
        mapping.lumped.extend_from_slice(&ws.mass);
        let vectors = [&mut mapping.momentum[..], &mut mapping.diagonal[..]];
        velocity_loop::<W, 2>(
            velocity,
            mass,
            on_grid,
            dt,
            vectors,
            accumulate_momentum_and_diagonal_row::<W>,
        )
    } else {
        mapping.lumped.resize(n, 0.0);
        let vectors = [
            &mut mapping.momentum[..],
            &mut mapping.lumped[..],
            &mut mapping.diagonal[..],
        ];
        velocity_loop::<W, 3>(
            velocity,
            mass,
            on_grid,
            dt,
            vectors,
            accumulate_lumped_row::<W>,
        )
    };
    sim.records_diagnostics.then_some(totals)
}

/// The particle loop of [`update_velocities_and_map_momentum`]: Eq. 4.9
/// for each particle, then `row` adds its share of Eq. 4.10 to the `N`
/// nodal sums of its stencil, and the totals are summed.
#[inline(always)]
fn velocity_loop<const W: usize, const N: usize>(
    velocities: &mut [f64],
    masses: &[f64],
    (stencils, acceleration): (&Stencils, &[f64]),
    dt: f64,
    mut vectors: [&mut [f64]; N],
    row: impl Fn([&mut [f64; W]; N], &[f64; W], f64, f64),
) -> ParticleTotals {
    let Stencils { first, values, .. } = stencils;
    let mut sums = StencilSums::<W, N>::default();
    // Rust's f64 sums start from −0.0 (Particles::total_mass, total_momentum).
    let (mut mass, mut momentum, mut fastest) = (-0.0, -0.0, 0.0f64);
    let rows = values.as_chunks::<W>().0.iter();
    let particles = velocities.iter_mut().zip(masses);
    for ((velocity, &m), (&f, phi)) in particles.zip(first.iter().zip(rows)) {
        let v = flip_velocity(*velocity, dt, interpolate_row(phi, &acceleration[f..f + W]));
        *velocity = v;
        sums.move_to(f, &mut vectors);
        row(sums.sums.each_mut(), phi, m, m * v);
        mass += m;
        momentum += m * v;
        fastest = running_max(fastest, v.abs());
    }
    sums.store(&mut vectors);
    ParticleTotals {
        mass,
        momentum,
        fastest_particle_speed: fastest,
    }
}

/// What loop 3 finds for the monitors and the physical check.
struct ParticleScreen {
    /// max_p |ε_p| after the step.
    max_abs_strain: f64,
    /// Gradient breaks crossed in the step.
    crossings: usize,
    /// Σ_p ½ m_p v_p² + ½ σ_p ε_p V_p after the step (when summed).
    energy: f64,
    /// Whether some particle is non-finite, has a non-positive volume or
    /// left the grid (then [`Simulation::check_particles_are_physical`]
    /// names the first).
    suspect: bool,
}

/// Loop 3: with Δu_i = Δt v_i, u_p and x_p grow by Σ φ_i Δu_i and
/// Δε_p = Σ ∇φ_i Δu_i (book Eqs. 4.11–4.14); σ_p by `law` (Eq. 4.15 or
/// 4.16); V_p, ρ_p, ε_p (Eqs. 4.17–4.18); then the particle's strain and
/// crossings for the monitors, its physical screen and (`ENERGY`) its
/// energy ½ m_p v_p² + ½ σ_p ε_p V_p ([`Simulation::energy`]'s terms, in
/// its order). Δε_p is not stored: each array written here is one more
/// stream to memory per particle-step, and at 16384 cells the two that
/// used to be written (Δε_p, the position the breaks were counted at)
/// cost between an eighth and a third of the step on session 12's host
/// (docs/conventions.md, "Session 12"). The crossings
/// are |N(x_p^t+Δt) − N(x_p^t)| from the break count kept from the last
/// step, checked against x_p^t ([`Grid::crossings_between`]).
fn move_particles<const W: usize, const ENERGY: bool>(
    sim: &mut Simulation,
    dt: f64,
    law: impl Fn(f64, f64, f64) -> f64,
) -> ParticleScreen {
    let (grid, p, ws) = (&sim.grid, &mut sim.particles, &mut sim.workspace);
    let (young, monitors) = (sim.settings.young, sim.records_diagnostics);
    let (lo, hi) = grid.domain();
    let Stencils {
        first,
        values,
        gradients,
        ..
    } = &ws.stencils;
    let v = &ws.mapping.velocity;
    let mut screen = ParticleScreen {
        max_abs_strain: 0.0,
        crossings: 0,
        energy: -0.0,
        suspect: false,
    };
    let n = p.len();
    let mass = &p.mass[..n];
    let (x, displacement, velocity) = (&mut p.x[..n], &mut p.displacement[..n], &p.velocity[..n]);
    let (stress, volume) = (&mut p.stress[..n], &mut p.volume[..n]);
    let (density, strain) = (&mut p.density[..n], &mut p.strain[..n]);
    let (first, breaks_before) = (&first[..n], &mut ws.breaks_before[..n]);
    let (values, gradients) = (
        &values.as_chunks::<W>().0[..n],
        &gradients.as_chunks::<W>().0[..n],
    );
    for k in 0..n {
        // Each field is read once and written once: the values that the
        // monitors and the screen read stay in registers, not read back
        // from the arrays just written (which the compiler cannot tell
        // apart from the ones it would read).
        let (du, deps) = displacement_and_strain_increment(
            &values[k],
            &gradients[k],
            &v[first[k]..first[k] + W],
            dt,
        );
        let moved_from = x[k];
        let xk = moved_from + du;
        displacement[k] += du;
        x[k] = xk;
        let sigma = law(stress[k], young, deps);
        stress[k] = sigma;
        let (mut vol, mut rho, mut eps) = (volume[k], density[k], strain[k]);
        update_volume_density_strain(&mut vol, &mut rho, &mut eps, deps);
        (volume[k], density[k], strain[k]) = (vol, rho, eps);
        let vk = velocity[k];
        screen.max_abs_strain = running_max(screen.max_abs_strain, eps.abs());
        if ENERGY {
            screen.energy += particle_energy(mass[k], vk, sigma, eps, vol);
        }
        if monitors {
            screen.crossings += grid.crossings_between(&mut breaks_before[k], moved_from, xk);
        }
        // A screen, not the check: false for a NaN anywhere or a particle
        // outside [lo, hi]; the check itself names the first culprit.
        let inside = (xk >= lo) & (xk <= hi) & (vol > 0.0);
        screen.suspect |= !(inside & both_finite(vk, sigma));
    }
    screen
}
