//! # The phases of a 2D step, one function per group of equations
//!
//! The functions that [`super::step::Simulation2d::step`] calls in order
//! (MLS paper Eqs. 4–5 and 18–41; the step's module doc is the table of
//! contents):
//!
//! - [`evaluate_basis`]: Eqs. (4)–(5), two 1D stencils per particle;
//! - phase 1: [`map_direct`] (the particles as quadrature points) or
//!   [`map_reconstructed`] (Eqs. 18–25, through the Gauss-point
//!   reconstruction of [`super::reconstruction`]);
//! - phase 2: [`nodal_update`], Eqs. (26)–(28) with the walls' conditions;
//! - phase 3: [`update_particles`], Eqs. (29)–(30);
//! - [`end_of_step_velocity`]: Eqs. (31)–(33);
//! - [`update_deformation`]: Eqs. (34)–(37) and (41);
//! - the total-Lagrangian reference's [`map_direct_reference`] and
//!   [`update_deformation_reference`].
//!
//! Each loop over the particles is monomorphised on the stencil width
//! (`with_width!`), reads the workspace's two 1D stencils and writes its
//! nodal arrays; none allocates. Every scatter to the nodes and gather from
//! them, at the particles and at the Gauss points alike, walks the tensor
//! product of the two 1D stencils with one function, `TensorStencil::for_each`,
//! which hands each node i its N_i and ∇N_i (Eqs. 4–5).
//!
//! Items: [`evaluate_basis`], [`map_direct`], [`map_direct_reference`],
//! [`map_reconstructed`], [`nodal_update`], [`update_particles`],
//! [`end_of_step_velocity`], [`end_of_step_velocity_from_momentum`],
//! [`end_of_step_velocity_from_values`], [`update_deformation`] (and, from
//! submodules, the fused `update_particles_and_end_momentum` and
//! `update_particles_and_end_values`,
//! the total-Lagrangian `update_deformation_reference` and other codes'
//! phases).

use super::grid::Grid2d;
use super::mapping::Mapping2d;
use super::material::NeoHookean;
use super::particles::Particles2d;
use super::reconstruction::{GaussGrid, GaussReconstruction};
use super::workspace::StepWorkspace2d;
use crate::basis::{with_width, Stencils};
use crate::error::{Error, Result};
use crate::mpm::conventions::{Conventions, Positions, Transfer};

mod fused;
mod lists;
mod other_codes;
mod reference;
mod rows;
pub use fused::{
    fuses_end_of_step, fuses_end_values, update_particles_and_end_momentum,
    update_particles_and_end_values,
};
use lists::{gauss_point_momentum, gauss_point_values, storage_pairs};
use nalgebra::Matrix2;
pub use other_codes::{
    map_direct_apic, move_particles, update_deformation_affine, update_particles_apic,
};
pub(super) use reference::evaluate_basis_at_reference;
pub use reference::update_deformation_reference;
use rows::particle_stencils;

/// MLS paper Eqs. (4)–(5) at every particle: the two 1D stencils. A particle
/// outside [0, L]² is `Error::ParticleLeftGrid`.
pub fn evaluate_basis(
    grid: &Grid2d,
    p: &Particles2d,
    ws: &mut StepWorkspace2d,
    step: usize,
) -> Result<()> {
    let (sx, sy) = (&mut ws.stencils_x, &mut ws.stencils_y);
    if let Some(Ok(())) = grid.fill_stencils_paired(&p.x, sx, sy) {
        return Ok(());
    }
    let axis = grid.axis();
    for (c, stencils) in [(0, &mut ws.stencils_x), (1, &mut ws.stencils_y)] {
        if let Err(e) = axis.fill_stencils(&p.x, |x| x[c], stencils, &mut ws.scratch) {
            let k =
                p.x.iter()
                    .position(|x| !(x[c] >= 0.0 && x[c] <= grid.length()))
                    .unwrap_or(0);
            return Err(match e {
                Error::OutsideDomain { x, a, b } => Error::ParticleLeftGrid {
                    particle: k,
                    step,
                    x,
                    a,
                    b,
                },
                other => other,
            });
        }
    }
    Ok(())
}

/// The tensor-product stencil of one point, MLS paper Eqs. (4)–(5): from
/// the 1D stencils N_a(x) along x and N_b(y) along y, the functions
/// N_i = N_a(x) N_b(y) and gradients ∇N_i = (N_a'(x) N_b(y), N_a(x) N_b'(y))
/// of the nodes i = (first_y + b)·n + first_x + a. Every scatter and gather
/// of a 2D step goes through [`TensorStencil::for_each`], the 2D form of the
/// 1D [`Stencils`].
#[derive(Clone, Copy)]
struct TensorStencil<'a> {
    values_x: &'a [f64],
    gradients_x: &'a [f64],
    values_y: &'a [f64],
    gradients_y: &'a [f64],
    /// The node of (a, b) = (0, 0).
    first: usize,
    /// Nodes per side n.
    nodes_per_side: usize,
}

impl<'a> TensorStencil<'a> {
    /// The stencil of point `kx` of `sx` times point `ky` of `sy`, `w`
    /// functions per direction, on a grid of n nodes per side.
    #[inline(always)]
    fn of(sx: &'a Stencils, kx: usize, sy: &'a Stencils, ky: usize, w: usize, n: usize) -> Self {
        let (rx, ry) = (kx * w..(kx + 1) * w, ky * w..(ky + 1) * w);
        TensorStencil {
            values_x: &sx.values[rx.clone()],
            gradients_x: &sx.gradients[rx],
            values_y: &sy.values[ry.clone()],
            gradients_y: &sy.gradients[ry],
            first: sy.first[ky] * n + sx.first[kx],
            nodes_per_side: n,
        }
    }

    /// Calls `visit(i, N_i, ∇N_i)` for every node of the stencil, row by row
    /// (b outer, a inner, [`TensorStencil::for_each_row`]): the order, and
    /// so the rounding, of every sum over the stencil.
    #[inline(always)]
    fn for_each(&self, mut visit: impl FnMut(usize, f64, [f64; 2])) {
        self.for_each_row(|start, row| row.for_each(|a, nn, dn| visit(start + a, nn, dn)));
    }
}

fn clear_nodes(ws: &mut StepWorkspace2d) {
    ws.mass.iter_mut().for_each(|m| *m = 0.0);
    ws.momentum.iter_mut().for_each(|m| *m = [0.0; 2]);
    ws.force.iter_mut().for_each(|f| *f = [0.0; 2]);
}

/// Phase 1 with the particles as quadrature points: m_i = Σ_p N_i m_p,
/// (mv)_i = Σ_p N_i m_p v_p, f_i = Σ_p (N_i m_p b_p − V_p σ_p ∇N_i)
/// (MLS paper Eqs. 22–26 with ρ ω → m_p at x_p).
pub fn map_direct(grid: &Grid2d, p: &Particles2d, ws: &mut StepWorkspace2d) {
    clear_nodes(ws);
    let stress = |k: usize| p.stress[k] * p.volume[k];
    with_width!(
        grid.stencil_width(),
        map_direct_with::<W>(grid, p, ws, stress)
    );
}

/// [`map_direct`] of the total-Lagrangian reference
/// ([`Formulation`](super::step::Formulation)): the
/// stencils hold N_i(X_p) and ∇_X N_i(X_p), and the stress term is
/// V_p⁰ P_p = V_p σ_p F_p⁻ᵀ. A particle with det F ≤ 0, which has no such
/// P, is `Error::InvertedDeformation`.
pub fn map_direct_reference(
    grid: &Grid2d,
    p: &Particles2d,
    ws: &mut StepWorkspace2d,
) -> Result<()> {
    clear_nodes(ws);
    for (k, f) in p.deformation.iter().enumerate() {
        NeoHookean::jacobian(f).map_err(|e| particle_error(e, k))?;
    }
    let stress = |k: usize| {
        let f_inv_t = p.deformation[k]
            .try_inverse()
            .unwrap_or_else(Matrix2::zeros)
            .transpose();
        p.stress[k] * f_inv_t * p.volume[k]
    };
    with_width!(
        grid.stencil_width(),
        map_direct_with::<W>(grid, p, ws, stress)
    );
    Ok(())
}

/// [`map_direct`] for stencil width `W` (0: any width), with the stress
/// term V σ (or V⁰ P) of particle k given by `stress(k)`.
fn map_direct_with<const W: usize>(
    grid: &Grid2d,
    p: &Particles2d,
    ws: &mut StepWorkspace2d,
    stress: impl Fn(usize) -> Matrix2<f64>,
) {
    let n = grid.nodes_per_side();
    let w = if W == 0 { grid.stencil_width() } else { W };
    let (sx, sy) = (&ws.stencils_x, &ws.stencils_y);
    let particles = p.mass.iter().zip(&p.velocity).zip(&ws.body_force);
    for (k, (((&m, v), b), stencil)) in particles.zip(particle_stencils(sx, sy, w, n)).enumerate() {
        let mv = [m * v[0], m * v[1]];
        let mb = [m * b[0], m * b[1]];
        let s = stress(k);
        // Row by row, each nodal array's row one slice (`for_each_row`).
        stencil.for_each_row(|start, row| {
            let mass = &mut ws.mass[start..][..row.len()];
            let momentum = &mut ws.momentum[start..][..row.len()];
            let force = &mut ws.force[start..][..row.len()];
            row.for_each(|a, nn, dn| {
                mass[a] += nn * m;
                momentum[a][0] += nn * mv[0];
                momentum[a][1] += nn * mv[1];
                force[a][0] += nn * mb[0] - (s[(0, 0)] * dn[0] + s[(0, 1)] * dn[1]);
                force[a][1] += nn * mb[1] - (s[(1, 0)] * dn[0] + s[(1, 1)] * dn[1]);
            });
        });
    }
}

/// Phase 1 by a reconstruction (MLS or TLS): ρ_g, (ρv)_g, (ρb)_g and σ_g
/// at every Gauss point (MLS paper Eqs. 18–21, f̃_g = Σ_p φ_gp f_p), then
/// m_i = Σ_g N_i(x_g) ρ_g ω_g (22), (mv)_i = Σ_g N_i (ρv)_g ω_g (23),
/// f_i^b = Σ_g N_i (ρb)_g ω_g (24) and f_i^int = −Σ_g ∇N_i σ_g ω_g (25).
pub fn map_reconstructed(grid: &Grid2d, p: &Particles2d, ws: &mut StepWorkspace2d) -> Result<()> {
    clear_nodes(ws);
    // Taken out for the loop (a move, no allocation) and put back below.
    let Some(mut shapes) = ws.reconstruction.take() else {
        return Err(Error::InvalidArgument(
            "a reconstructed mapping needs its reconstruction (Mapping2d::Mls or Tls)".into(),
        ));
    };
    let result = map_reconstructed_with(grid, p, ws, shapes.as_mut());
    ws.reconstruction = Some(shapes);
    result
}

fn map_reconstructed_with(
    grid: &Grid2d,
    p: &Particles2d,
    ws: &mut StepWorkspace2d,
    shapes: &mut dyn GaussReconstruction,
) -> Result<()> {
    let gauss = GaussGrid {
        abscissae: grid.gauss_abscissae(),
        cells: grid.cells_per_side(),
        cell_size: grid.cell_size(),
    };
    shapes.evaluate(&gauss, p, &ws.stencils_x.first, &ws.stencils_y.first)?;
    let lists = shapes.lists();
    let omega = grid.gauss_weight();
    let ng = 2 * grid.cells_per_side();
    // The eight particle values of Eqs. (18)–(21), packed so that each
    // (Gauss point, particle) pair reads one record.
    for (k, d) in ws.particle_values.iter_mut().enumerate() {
        let (rho, v, b, s) = (p.density[k], p.velocity[k], ws.body_force[k], &p.stress[k]);
        *d = [
            rho,
            rho * v[0],
            rho * v[1],
            rho * b[0],
            rho * b[1],
            s[(0, 0)],
            s[(1, 1)],
            s[(0, 1)],
        ];
    }
    for pair in storage_pairs(grid.cells_per_side()) {
        let points = pair.map(|(gx, gy)| gx + ng * gy);
        let sums = gauss_point_values(lists, points, &ws.particle_values);
        for (((gx, gy), g), q) in pair.into_iter().zip(points).zip(sums) {
            ws.gauss_values[g] = q;
            scatter_gauss_point(grid, gx, gy, &q.map(|v| v * omega), ws);
        }
    }
    Ok(())
}

/// Eqs. (22)–(25) for one Gauss point (gx, gy) with ω-weighted values
/// q = ω [ρ, ρv_x, ρv_y, ρb_x, ρb_y, σ_xx, σ_yy, σ_xy].
fn scatter_gauss_point(
    grid: &Grid2d,
    gx: usize,
    gy: usize,
    q: &[f64; 8],
    ws: &mut StepWorkspace2d,
) {
    let s = grid.gauss_stencils();
    let stencil = TensorStencil::of(s, gx, s, gy, s.width(), grid.nodes_per_side());
    stencil.for_each_row(|start, row| {
        let mass = &mut ws.mass[start..][..row.len()];
        let momentum = &mut ws.momentum[start..][..row.len()];
        let force = &mut ws.force[start..][..row.len()];
        row.for_each(|a, nn, dn| {
            mass[a] += nn * q[0];
            momentum[a][0] += nn * q[1];
            momentum[a][1] += nn * q[2];
            force[a][0] += nn * q[3] - (q[5] * dn[0] + q[7] * dn[1]);
            force[a][1] += nn * q[4] - (q[7] * dn[0] + q[6] * dn[1]);
        });
    });
}

/// Zero normal velocity on the walls x = 0, L and y = 0, L: the x components
/// of the first and last column of nodes and the y components of the first
/// and last row vanish. With open knot vectors (and P1) those are the only
/// functions non-zero on the walls, so v·n = 0 along each wall.
///
/// With padded knots (`--knots padded`) the two outer rows at each wall
/// carry the condition ([`Grid2d::wall_rows`]), as Taichi's step does.
fn wall_conditions(n: usize, rows: usize, field: &mut [[f64; 2]]) {
    for r in 0..rows {
        for j in 0..n {
            field[j * n + r][0] = 0.0;
            field[j * n + n - 1 - r][0] = 0.0;
        }
        for i in 0..n {
            field[r * n + i][1] = 0.0;
            field[(n - 1 - r) * n + i][1] = 0.0;
        }
    }
}

/// Phase 2, MLS paper Eqs. (26)–(28), with the walls' conditions on f and
/// (mv): `momentum_next` = (mv)_i^{t+1} = (mv)_i^t + f_i Δt (28),
/// `acceleration` = a_i = f_i/m_i (27) and `velocity_next` =
/// (mv)_i^{t+1}/m_i, the velocity Eq. (30) moves the particles with. The
/// phase-1 buffers `force` and `momentum` keep f_i and (mv)_i^t.
pub fn nodal_update(grid: &Grid2d, ws: &mut StepWorkspace2d, dt: f64) {
    let (n, rows) = (grid.nodes_per_side(), grid.wall_rows());
    for i in 0..ws.mass.len() {
        let m = ws.mass[i];
        let (f, mv) = (ws.force[i], ws.momentum[i]);
        let next = [mv[0] + f[0] * dt, mv[1] + f[1] * dt];
        ws.momentum_next[i] = next;
        if m > 0.0 {
            ws.acceleration[i] = [f[0] / m, f[1] / m];
            ws.velocity_next[i] = [next[0] / m, next[1] / m];
        } else {
            ws.acceleration[i] = [0.0; 2];
            ws.velocity_next[i] = [0.0; 2];
        }
    }
    // A wall component of f and (mv)^t is zero, and so is every value
    // computed from it: zeroing the results is the same, bit for bit.
    wall_conditions(n, rows, &mut ws.momentum_next);
    wall_conditions(n, rows, &mut ws.acceleration);
    wall_conditions(n, rows, &mut ws.velocity_next);
}

/// Phase 3, MLS paper Eqs. (29)–(30): v_p += Δt Σ_i N_i a_i and
/// x_p += Δt Σ_i N_i (mv)_i^{t+1}/m_i; u_p = x_p − X_p.
///
/// Another code's conventions (`mpm::conventions`): `--transfer pic` sets
/// v_p = Σ_i N_i v_i^{t+1} and `flip:α` blends
/// v_p = α (v_p + Δt Σ_i N_i a_i) + (1 − α) Σ_i N_i v_i^{t+1};
/// `--positions projected` leaves x_p to [`move_particles`].
pub fn update_particles(
    grid: &Grid2d,
    p: &mut Particles2d,
    ws: &StepWorkspace2d,
    conventions: Conventions,
    dt: f64,
) {
    if conventions.transfer == Transfer::Flip && conventions.positions == Positions::Grid {
        with_width!(
            grid.stencil_width(),
            update_particles_with::<W>(grid, p, ws, dt, |_, _| {})
        );
        return;
    }
    other_codes::update_particles_blended(grid, p, ws, conventions, dt);
}

/// [`update_particles`] for stencil width `W` (0: any width): both sums
/// of Eqs. (29)–(30) in one pass over the stencil; `moved(k, p)` is called
/// once particle k has moved.
fn update_particles_with<const W: usize>(
    grid: &Grid2d,
    p: &mut Particles2d,
    ws: &StepWorkspace2d,
    dt: f64,
    mut moved: impl FnMut(usize, &Particles2d),
) {
    let n = grid.nodes_per_side();
    let w = if W == 0 { grid.stencil_width() } else { W };
    let (sx, sy) = (&ws.stencils_x, &ws.stencils_y);
    for (k, stencil) in particle_stencils(sx, sy, w, n).enumerate().take(p.len()) {
        let (mut a, mut v) = ([0.0; 2], [0.0; 2]);
        stencil.for_each(|i, nn, _| {
            a[0] += nn * ws.acceleration[i][0];
            a[1] += nn * ws.acceleration[i][1];
            v[0] += nn * ws.velocity_next[i][0];
            v[1] += nn * ws.velocity_next[i][1];
        });
        p.velocity[k][0] += dt * a[0];
        p.velocity[k][1] += dt * a[1];
        p.x[k][0] += dt * v[0];
        p.x[k][1] += dt * v[1];
        p.displacement[k] = [p.x[k][0] - p.x0[k][0], p.x[k][1] - p.x0[k][1]];
        moved(k, p);
    }
}

/// MLS paper Eqs. (31)–(33): the particles' new velocities mapped again,
/// (mv)_i^L = Σ_p N_i m_p v_p^{t+1} (direct) or Σ_g N_i (ρv)_g^L ω_g with
/// (ρv)_g^L = Σ_p φ_gp ρ_p v_p^{t+1} (MLS or TLS, the φ_gp of phase 1),
/// then v_i^L = (mv)_i^L / m_i with the walls' conditions. Writes (mv)^L
/// into `momentum_end` and v^L into `velocity_end`.
pub fn end_of_step_velocity(
    grid: &Grid2d,
    p: &Particles2d,
    ws: &mut StepWorkspace2d,
    mapping: Mapping2d,
) {
    match (mapping.reconstructs_end_of_step(), &ws.reconstruction) {
        (true, Some(_)) => {
            // ρ_p and v_p^{t+1} side by side, for one read per list entry.
            for (k, e) in ws.end_values.iter_mut().enumerate() {
                *e = end_value(p, k);
            }
            end_of_step_velocity_from_values(grid, ws);
        }
        _ => {
            ws.momentum_end.iter_mut().for_each(|m| *m = [0.0; 2]);
            with_width!(
                grid.stencil_width(),
                map_particle_momentum_with::<W>(grid, p, ws)
            );
            end_of_step_velocity_from_momentum(grid, ws);
        }
    }
}

/// [ρ_p, v_x, v_y] of particle k: what the reconstructed Eq. (31) reads
/// of it (`StepWorkspace2d::end_values`).
#[inline(always)]
fn end_value(p: &Particles2d, k: usize) -> [f64; 3] {
    let v = p.velocity[k];
    [p.density[k], v[0], v[1]]
}

/// The reconstructed Eqs. (31)–(33) from [ρ_p, v_p^{t+1}] in
/// `end_values`: (ρv)_g^L = Σ_p φ_gp ρ_p v_p^{t+1} with the φ_gp of phase
/// 1, (mv)_i^L = Σ_g N_i (ρv)_g^L ω_g into `momentum_end` (zeroed first),
/// then [`end_of_step_velocity_from_momentum`]. Without a reconstruction
/// in the workspace, `momentum_end` stays zero.
pub fn end_of_step_velocity_from_values(grid: &Grid2d, ws: &mut StepWorkspace2d) {
    ws.momentum_end.iter_mut().for_each(|m| *m = [0.0; 2]);
    if let Some(shapes) = &ws.reconstruction {
        let n = grid.nodes_per_side();
        let lists = shapes.lists();
        let s = grid.gauss_stencils();
        let ng = 2 * grid.cells_per_side();
        let omega = grid.gauss_weight();
        for pair in storage_pairs(grid.cells_per_side()) {
            let points = pair.map(|(gx, gy)| gx + ng * gy);
            let sums = gauss_point_momentum(lists, points, &ws.end_values);
            for ((gx, gy), q) in pair.into_iter().zip(sums) {
                let q = [q[0] * omega, q[1] * omega];
                scatter_vector(n, s, gx, s, gy, q, &mut ws.momentum_end);
            }
        }
    }
    end_of_step_velocity_from_momentum(grid, ws);
}

/// Eqs. (32)–(33) from (mv)^L in `momentum_end`: v_i^L = (mv)_i^L / m_i into
/// `velocity_end`, with the walls' conditions.
pub fn end_of_step_velocity_from_momentum(grid: &Grid2d, ws: &mut StepWorkspace2d) {
    let n = grid.nodes_per_side();
    for i in 0..ws.mass.len() {
        let m = ws.mass[i];
        ws.velocity_end[i] = if m > 0.0 {
            [ws.momentum_end[i][0] / m, ws.momentum_end[i][1] / m]
        } else {
            [0.0; 2]
        };
    }
    wall_conditions(n, grid.wall_rows(), &mut ws.velocity_end);
}

/// (mv)_i^L = Σ_p N_i m_p v_p^{t+1} (Eq. 31 with the particles as the
/// quadrature points) into `momentum_end`, for stencil width `W` (0: any
/// width).
fn map_particle_momentum_with<const W: usize>(
    grid: &Grid2d,
    p: &Particles2d,
    ws: &mut StepWorkspace2d,
) {
    let n = grid.nodes_per_side();
    let w = if W == 0 { grid.stencil_width() } else { W };
    let (sx, sy) = (&ws.stencils_x, &ws.stencils_y);
    let particles = p.mass.iter().zip(&p.velocity);
    for ((&m, v), stencil) in particles.zip(particle_stencils(sx, sy, w, n)) {
        let mv = [m * v[0], m * v[1]];
        stencil.for_each(|i, nn, _| {
            ws.momentum_end[i][0] += nn * mv[0];
            ws.momentum_end[i][1] += nn * mv[1];
        });
    }
}

/// out_i += N_i q over the tensor stencil of point kx of `sx` and ky of `sy`.
fn scatter_vector(
    n: usize,
    sx: &Stencils,
    kx: usize,
    sy: &Stencils,
    ky: usize,
    q: [f64; 2],
    out: &mut [[f64; 2]],
) {
    TensorStencil::of(sx, kx, sy, ky, sx.width(), n).for_each_row(|start, row| {
        let out = &mut out[start..][..row.len()];
        row.for_each(|a, nn, _| {
            out[a][0] += nn * q[0];
            out[a][1] += nn * q[1];
        });
    });
}

/// MLS paper Eqs. (34)–(37) and (41): ∇v_p = Σ_i v_i^L ⊗ ∇N_i(x_p),
/// F_p ← (I + ∇v_p Δt) F_p, V_p = det(F_p) V_p⁰, ρ_p = m_p / V_p, σ_p from
/// the neo-Hookean law. det F ≤ 0 is `Error::InvertedDeformation` and a
/// velocity that is not finite `Error::NonFiniteVelocity`, each naming the
/// particle.
pub fn update_deformation(
    grid: &Grid2d,
    p: &mut Particles2d,
    ws: &StepWorkspace2d,
    material: &NeoHookean,
    dt: f64,
) -> Result<()> {
    let rule = |l: Matrix2<f64>, f: Matrix2<f64>| (Matrix2::identity() + l * dt) * f;
    with_width!(
        grid.stencil_width(),
        update_deformation_with::<W>(grid, p, ws, material, rule)
    )
}

/// [`update_deformation`] for stencil width `W` (0: any width); `rule(L, F)`
/// is the new F from the interpolated gradient L = Σ_i v_i ⊗ ∇N_i.
pub(super) fn update_deformation_with<const W: usize>(
    grid: &Grid2d,
    p: &mut Particles2d,
    ws: &StepWorkspace2d,
    material: &NeoHookean,
    rule: impl Fn(Matrix2<f64>, Matrix2<f64>) -> Matrix2<f64>,
) -> Result<()> {
    let n = grid.nodes_per_side();
    let w = if W == 0 { grid.stencil_width() } else { W };
    let (sx, sy) = (&ws.stencils_x, &ws.stencils_y);
    for (k, stencil) in particle_stencils(sx, sy, w, n).enumerate().take(p.len()) {
        let mut l = [0.0; 4];
        stencil.for_each_row(|start, row| {
            let velocity_end = &ws.velocity_end[start..][..row.len()];
            row.for_each(|a, _, dn| {
                let v = velocity_end[a];
                l[0] += v[0] * dn[0];
                l[1] += v[0] * dn[1];
                l[2] += v[1] * dn[0];
                l[3] += v[1] * dn[1];
            });
        });
        let l = Matrix2::new(l[0], l[1], l[2], l[3]);
        set_deformation(p, k, rule(l, p.deformation[k]), material)?;
    }
    Ok(())
}

/// Eqs. (35)–(37) and (41) for particle k with its new F (errors as
/// [`update_deformation`]'s).
#[inline(always)]
pub(super) fn set_deformation(
    p: &mut Particles2d,
    k: usize,
    f: Matrix2<f64>,
    material: &NeoHookean,
) -> Result<()> {
    let j = NeoHookean::jacobian(&f).map_err(|e| particle_error(e, k))?;
    p.deformation[k] = f;
    p.volume[k] = j * p.volume0[k];
    p.density[k] = p.mass[k] / p.volume[k];
    p.stress[k] = material.cauchy_stress_given_jacobian(&f, j);
    if !(p.velocity[k][0].is_finite() && p.velocity[k][1].is_finite()) {
        return Err(Error::NonFiniteVelocity {
            particle: k,
            step: None,
            time: None,
            velocity: p.velocity[k],
        });
    }
    Ok(())
}

/// Names particle k in the error of its deformation update.
fn particle_error(mut e: Error, k: usize) -> Error {
    if let Error::InvertedDeformation { particle, .. } = &mut e {
        *particle = Some(k);
    }
    e
}
