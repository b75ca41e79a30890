//! # The quadrature of a 1D mapping, and what the projection sums over it
//!
//! Every 1D mapping integrates with the grid's basis over a set of
//! quadrature points: the particles for the direct mapping (book Eqs. 4.6,
//! 4.10), the Gauss points of the cells that hold particles for TLS (book
//! Eq. 4.38, Eqs. 4.42–4.43), the half-span Gauss points inside Ω_t for the
//! cubic splines (thesis §7.2). This module holds what they share: a
//! reconstruction's quadrature points with the basis evaluated at them
//! (`QuadratureStencils`, private to the mapping), and the velocity
//! projection's nodal sums over the points, p_i = Σ_q (ρvw)_q φ_i(x_q) and
//! M_ij = Σ_q (ρw)_q φ_i(x_q) φ_j(x_q) ([`Accumulator`]), with the direct
//! mapping's loop over the particles (`accumulate_particles`, book
//! Eq. 4.10).
//!
//! Items: [`Accumulator`].

use crate::basis::Stencils;
use crate::error::Result;
use crate::mpm::grid::Grid;
use crate::mpm::particles::Particles;
use crate::quadrature::QuadraturePoint;
use crate::sparse::BandAssembly;
use crate::spline::bspline::SpanScratch;

/// Quadrature points with the basis evaluated at them.
#[derive(Debug, Clone, Default)]
pub(super) struct QuadratureStencils {
    pub(super) points: Vec<QuadraturePoint>,
    /// The cell of each point (TLS evaluates that cell's fit).
    pub(super) cell: Vec<usize>,
    pub(super) stencils: Stencils,
}

impl QuadratureStencils {
    pub(super) fn clear(&mut self) {
        self.points.clear();
        self.cell.clear();
    }

    pub(super) fn push(&mut self, q: QuadraturePoint, cell: usize) {
        self.points.push(q);
        self.cell.push(cell);
    }

    /// φ_i(x_q) and ∇φ_i(x_q) at every point.
    pub(super) fn evaluate(&mut self, grid: &Grid, scratch: &mut SpanScratch) -> Result<()> {
        if self.stencils.width() != grid.stencil_width() {
            self.stencils = grid.stencils(0);
        }
        let xs = &self.points;
        self.stencils.resize(xs.len());
        for (k, q) in xs.iter().enumerate() {
            let (v, g) = self.stencils.slots_mut(k);
            self.stencils.first[k] = grid.evaluate(q.x, scratch, v, g)?;
        }
        Ok(())
    }
}

/// The nodal sums of the velocity projection over its quadrature points
/// (book Eq. 4.10; Eqs. 4.42–4.43 with TLS; thesis §7.2 with splines): the
/// momentum p_i, the row sums and the diagonal of the mass matrix M_ij,
/// and M's entries when the consistent system is solved. A mapping adds
/// its points with [`Accumulator::add`].
#[derive(Debug)]
pub struct Accumulator<'a> {
    pub(super) momentum: &'a mut [f64],
    pub(super) lumped: &'a mut [f64],
    pub(super) diagonal: &'a mut [f64],
    pub(super) band: &'a mut BandAssembly,
    pub(super) consistent: bool,
}

impl Accumulator<'_> {
    /// Adds quadrature point `k` of `s` (a particle, or a Gauss point) with
    /// the weights ρw (mass) and ρvw (momentum): p_i += ρvw φ_i and
    /// M_ij += ρw φ_i φ_j (book Eqs. 4.42–4.43). Partition of unity,
    /// Σ_b φ_b = 1, makes the row sum of ρw φ_a φ_b equal to ρw φ_a.
    pub fn add(&mut self, s: &Stencils, k: usize, rho_w: f64, mom_w: f64) {
        accumulate::<0>(self, s, k, rho_w, mom_w);
    }
}

/// [`Accumulator::add`] with the stencil width `W` known at compile time
/// (0: read it from the stencils).
pub(super) fn accumulate<const W: usize>(
    acc: &mut Accumulator,
    s: &Stencils,
    k: usize,
    rho_w: f64,
    mom_w: f64,
) {
    let w = if W == 0 { s.width() } else { W };
    let first = s.first[k];
    let values = &s.values[k * w..k * w + w];
    let sum: f64 = values.iter().sum();
    for (a, &fa) in values.iter().enumerate() {
        acc.momentum[first + a] += mom_w * fa;
        acc.lumped[first + a] += rho_w * fa * sum;
        acc.diagonal[first + a] += rho_w * fa * fa;
        if acc.consistent {
            for (b, &fb) in values.iter().enumerate() {
                acc.band.add(first + a, first + b, rho_w * fa * fb);
            }
        }
    }
}

/// The direct mapping of book Eq. (4.10): every particle is a quadrature
/// point with mass m_p and momentum m_p v_p.
///
/// With a lumped mass and a known width, the sums of the current stencil are
/// held in registers while consecutive particles share it (as in
/// `basis::Stencils::scatter_values`): the same additions in the same order,
/// without a store between them.
pub(super) fn accumulate_particles<const W: usize>(
    acc: &mut Accumulator,
    s: &Stencils,
    p: &Particles,
) {
    if W == 0 || acc.consistent || p.is_empty() {
        for k in 0..p.len() {
            let m = p.mass[k];
            accumulate::<W>(acc, s, k, m, m * p.velocity[k]);
        }
        return;
    }
    let load = |v: &[f64], f: usize| -> [f64; W] { v[f..f + W].try_into().expect("W entries") };
    let mut current = s.first[0];
    let mut momentum = load(acc.momentum, current);
    let mut lumped = load(acc.lumped, current);
    let mut diagonal = load(acc.diagonal, current);
    for k in 0..p.len() {
        let f = s.first[k];
        if f != current {
            acc.momentum[current..current + W].copy_from_slice(&momentum);
            acc.lumped[current..current + W].copy_from_slice(&lumped);
            acc.diagonal[current..current + W].copy_from_slice(&diagonal);
            current = f;
            momentum = load(acc.momentum, current);
            lumped = load(acc.lumped, current);
            diagonal = load(acc.diagonal, current);
        }
        let (rho_w, mom_w) = (p.mass[k], p.mass[k] * p.velocity[k]);
        let values = &s.values[k * W..(k + 1) * W];
        let sums = [&mut momentum, &mut lumped, &mut diagonal];
        accumulate_lumped_row(sums, values.try_into().expect("W entries"), rho_w, mom_w);
    }
    acc.momentum[current..current + W].copy_from_slice(&momentum);
    acc.lumped[current..current + W].copy_from_slice(&lumped);
    acc.diagonal[current..current + W].copy_from_slice(&diagonal);
}

/// One particle's share of the lumped projection (book Eq. 4.10 with the
/// row-sum mass): p_i += (m_p v_p) φ_i, M^L_i += m_p φ_i Σ_j φ_j and
/// M_ii += m_p φ_i², over its stencil `values` with `rho_w` = m_p and
/// `mom_w` = m_p v_p; `sums` = [momentum, lumped, diagonal] at the
/// stencil. The loop of the direct mapping's assembly and of the fused
/// 1D step (`mpm::musl`).
#[inline(always)]
pub(crate) fn accumulate_lumped_row<const W: usize>(
    sums: [&mut [f64; W]; 3],
    values: &[f64; W],
    rho_w: f64,
    mom_w: f64,
) {
    let [momentum, lumped, diagonal] = sums;
    let sum: f64 = values.iter().sum();
    for (a, &fa) in values.iter().enumerate() {
        momentum[a] += mom_w * fa;
        lumped[a] += rho_w * fa * sum;
        diagonal[a] += rho_w * fa * fa;
    }
}

/// [`accumulate_lumped_row`] without the lumped mass, for a basis whose
/// M^L_i is the nodal mass bit for bit (P1, the fused 1D step):
/// p_i += (m_p v_p) φ_i and M_ii += m_p φ_i² (book Eq. 4.10).
#[inline(always)]
pub(crate) fn accumulate_momentum_and_diagonal_row<const W: usize>(
    sums: [&mut [f64; W]; 2],
    values: &[f64; W],
    rho_w: f64,
    mom_w: f64,
) {
    let [momentum, diagonal] = sums;
    for (a, &fa) in values.iter().enumerate() {
        momentum[a] += mom_w * fa;
        diagonal[a] += rho_w * fa * fa;
    }
}
