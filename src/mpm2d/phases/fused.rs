//! # Phase 3 and the end-of-step scatter in one particle loop
//!
//! MLS paper Eqs. (29)–(31) with the particles as the quadrature points:
//! phase 3 gathers a_i and v_i^{t+1} over a particle's stencil and moves
//! it (Eqs. 29–30), and Eq. (31) then scatters m_p v_p^{t+1} over the same
//! stencil. [`super::update_particles`] and [`super::end_of_step_velocity`]
//! do this in two passes; a step that nobody observes
//! (`StepObserver2d::OBSERVES`, issue #39) does it in one, while the
//! stencil is at hand. The particles are visited in the same order and
//! every number is formed from the same operands in the same order, so
//! both ways give the same bits (tests/spec/speed/step_2d.rs). Each nodal
//! array is read and written a stencil row at a time (`for_each_row`).
//!
//! A reconstructed end of step (MLS, TLS, PU-TLS) scatters through the Gauss
//! points instead, which need every particle moved first; what one loop
//! can do there is gather each moved particle's [ρ_p, v_p^{t+1}] for
//! Eq. (31) while it is at hand ([`update_particles_and_end_values`]),
//! instead of in a pass of its own.
//!
//! Items: [`update_particles_and_end_momentum`], [`fuses_end_of_step`],
//! [`update_particles_and_end_values`], [`fuses_end_values`].

use super::{end_value, particle_stencils, update_particles_with};
use crate::basis::with_width;
use crate::mpm::conventions::{Conventions, Positions, Scheme, Transfer};
use crate::mpm2d::grid::Grid2d;
use crate::mpm2d::mapping::Mapping2d;
use crate::mpm2d::particles::Particles2d;
use crate::mpm2d::workspace::StepWorkspace2d;

/// Whether a step with these conventions and mapping may run
/// [`update_particles_and_end_momentum`]: the paper's phase 3 (FLIP with
/// the grid's positions), the MUSL end of step (Eqs. 31–33) and a direct
/// end-of-step mapping.
pub fn fuses_end_of_step(conventions: Conventions, mapping: Mapping2d) -> bool {
    conventions.transfer == Transfer::Flip
        && conventions.positions == Positions::Grid
        && conventions.scheme != Scheme::Usl
        && !mapping.reconstructs_end_of_step()
}

/// Whether a step with these conventions and mapping may run
/// [`update_particles_and_end_values`]: the paper's phase 3 (FLIP with the
/// grid's positions), the MUSL end of step and a reconstructed end-of-step
/// mapping.
pub fn fuses_end_values(conventions: Conventions, mapping: Mapping2d) -> bool {
    conventions.transfer == Transfer::Flip
        && conventions.positions == Positions::Grid
        && conventions.scheme != Scheme::Usl
        && mapping.reconstructs_end_of_step()
}

/// Eqs. (29)–(30) of [`super::update_particles`] and, for each particle as
/// it moves, its [ρ_p, v_p^{t+1}] into `end_values`, which
/// [`super::end_of_step_velocity_from_values`] maps (Eqs. 31–33).
pub fn update_particles_and_end_values(
    grid: &Grid2d,
    p: &mut Particles2d,
    ws: &mut StepWorkspace2d,
    dt: f64,
) {
    // Taken out of the workspace for the loop (a move, not a copy), so the
    // loop reads the nodal arrays while it writes these.
    let mut values = std::mem::take(&mut ws.end_values);
    if values.len() == p.len() {
        let gather = |k: usize, p: &Particles2d| values[k] = end_value(p, k);
        with_width!(
            grid.stencil_width(),
            update_particles_with::<W>(grid, p, ws, dt, gather)
        );
    } else {
        // No reconstruction reserved them: phase 3 alone.
        with_width!(
            grid.stencil_width(),
            update_particles_with::<W>(grid, p, ws, dt, |_, _| {})
        );
    }
    ws.end_values = values;
}

/// Eqs. (29)–(30) of [`super::update_particles`] and then, for the same
/// particle, Eq. (31)'s (mv)_i^L += N_i m_p v_p^{t+1} into `momentum_end`
/// (zeroed first). [`super::end_of_step_velocity_from_momentum`] finishes
/// Eqs. (32)–(33).
pub fn update_particles_and_end_momentum(
    grid: &Grid2d,
    p: &mut Particles2d,
    ws: &mut StepWorkspace2d,
    dt: f64,
) {
    ws.momentum_end.iter_mut().for_each(|m| *m = [0.0; 2]);
    with_width!(
        grid.stencil_width(),
        update_particles_and_end_momentum_with::<W>(grid, p, ws, dt)
    );
}

/// [`update_particles_and_end_momentum`] for stencil width `W` (0: any
/// width).
fn update_particles_and_end_momentum_with<const W: usize>(
    grid: &Grid2d,
    p: &mut Particles2d,
    ws: &mut StepWorkspace2d,
    dt: f64,
) {
    let n = grid.nodes_per_side();
    let w = if W == 0 { grid.stencil_width() } else { W };
    let StepWorkspace2d {
        stencils_x,
        stencils_y,
        acceleration,
        velocity_next,
        momentum_end,
        ..
    } = ws;
    let particles = p.x.iter_mut().zip(&p.x0).zip(&mut p.displacement);
    let particles = particles.zip(&mut p.velocity).zip(&p.mass);
    let stencils = particle_stencils(stencils_x, stencils_y, w, n);
    for (((((x, x0), u), v), &m), stencil) in particles.zip(stencils) {
        let (mut a, mut vn) = ([0.0; 2], [0.0; 2]);
        stencil.for_each_row(|start, row| {
            let acceleration = &acceleration[start..][..row.len()];
            let velocity_next = &velocity_next[start..][..row.len()];
            row.for_each(|j, nn, _| {
                a[0] += nn * acceleration[j][0];
                a[1] += nn * acceleration[j][1];
                vn[0] += nn * velocity_next[j][0];
                vn[1] += nn * velocity_next[j][1];
            });
        });
        v[0] += dt * a[0];
        v[1] += dt * a[1];
        x[0] += dt * vn[0];
        x[1] += dt * vn[1];
        *u = [x[0] - x0[0], x[1] - x0[1]];
        let mv = [m * v[0], m * v[1]];
        stencil.for_each_row(|start, row| {
            let momentum_end = &mut momentum_end[start..][..row.len()];
            row.for_each(|a, nn, _| {
                momentum_end[a][0] += nn * mv[0];
                momentum_end[a][1] += nn * mv[1];
            });
        });
    }
}
