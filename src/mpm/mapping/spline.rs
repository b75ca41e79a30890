//! # The cubic-spline mapping in 1D
//!
//! Not-a-knot cubic splines through the particle values, sorted by
//! position (thesis §7.1), evaluated at the thesis' half-span Gauss points
//! (thesis §7.2, `quadrature::half_span_points`) with the points outside
//! the continuum Ω_t ≈ [x_1 − V_1/2, x_N + V_N/2] deactivated and the pairs
//! that straddle its edge redefined (thesis Figs. 7.3–7.4). The stress
//! spline gives the internal force, the density and velocity splines the
//! projection's ρ̃ and ρ̃ṽ. The splines of the last step are refitted in
//! place, so a step allocates the same amount every time
//! (tests/allocations.rs).
//!
//! Items: [`SplineWorkspace`].

use super::quadrature::{Accumulator, QuadratureStencils};
use super::reconstruction::{Reconstruction, Reconstruction1d};
use crate::error::Result;
use crate::mpm::grid::Grid;
use crate::mpm::particles::Particles;
use crate::quadrature::{half_span_points, GaussLegendre};
use crate::reconstruct::cubic_spline::{CubicSpline, EndCondition};
use crate::reconstruct::taylor::CellAverage;
use crate::spline::bspline::SpanScratch;

/// The buffers of a cubic-spline mapping (thesis §7.1–7.2), allocated once
/// per simulation: the quadrature points inside Ω_t with the basis at
/// them, the particles' sorting permutation, and the splines of the last
/// step, whose buffers the next fits reuse.
#[derive(Debug, Clone)]
pub struct SplineWorkspace {
    /// Whether every half span that is not inside Ω_t is clipped to it
    /// (`Mapping::CubicSplineClipped`), rather than only those whose Gauss
    /// points leave it (thesis §7.2).
    clip_every_half_span: bool,
    rule: GaussLegendre,
    scratch: SpanScratch,
    quadrature: QuadratureStencils,
    /// Particle indices sorted by position.
    order: Vec<usize>,
    sorted: (Vec<f64>, Vec<f64>),
    /// Splines of the last step: [σ or ρ, v].
    spare: [Option<CubicSpline>; 2],
}

impl SplineWorkspace {
    /// Buffers for `particles` particles; `clip_every_half_span` chooses
    /// the clipped rule of `Mapping::CubicSplineClipped` over the thesis'.
    pub fn new(particles: usize, clip_every_half_span: bool) -> Result<Self> {
        Ok(Self {
            clip_every_half_span,
            rule: GaussLegendre::new(2)?,
            scratch: SpanScratch::default(),
            quadrature: QuadratureStencils::default(),
            order: (0..particles).collect(),
            sorted: (Vec::with_capacity(particles), Vec::with_capacity(particles)),
            spare: [None, None],
        })
    }

    /// A not-a-knot cubic spline of particle values over the particle
    /// positions (thesis §7.1), refitted into the buffers of spare spline
    /// `slot` when there is one. `order` keeps the sorting permutation
    /// between steps: it is already sorted unless particles overtook each
    /// other.
    fn spline(
        &mut self,
        particles: &Particles,
        values: &[f64],
        slot: usize,
    ) -> Result<CubicSpline> {
        let (order, sorted) = (&mut self.order, &mut self.sorted);
        let x = &particles.x;
        if order.len() != x.len() {
            *order = (0..x.len()).collect();
        }
        order.sort_unstable_by(|&a, &b| x[a].total_cmp(&x[b]));
        sorted.0.clear();
        sorted.1.clear();
        for &k in order.iter() {
            sorted.0.push(x[k]);
            sorted.1.push(values[k]);
        }
        match self.spare[slot].take() {
            Some(s) => s.refit(&sorted.0, &sorted.1, EndCondition::NotAKnot),
            None => CubicSpline::new(&sorted.0, &sorted.1, EndCondition::NotAKnot),
        }
    }
}

/// The continuum Ω_t ≈ [x_1 − V_1/2, x_N + V_N/2] spanned by the particles
/// (thesis §7.2), from the leftmost and rightmost particle.
fn continuum(p: &Particles) -> (f64, f64) {
    let mut lo = 0;
    let mut hi = 0;
    for k in 0..p.len() {
        if p.x[k] < p.x[lo] {
            lo = k;
        }
        if p.x[k] > p.x[hi] {
            hi = k;
        }
    }
    (p.x[lo] - 0.5 * p.volume[lo], p.x[hi] + 0.5 * p.volume[hi])
}

impl Reconstruction for SplineWorkspace {
    fn name(&self) -> &'static str {
        if self.clip_every_half_span {
            "CS (clipped)"
        } else {
            "CS"
        }
    }

    fn largest_condition(&self) -> f64 {
        0.0
    }
}

impl Reconstruction1d for SplineWorkspace {
    /// The thesis' half-span Gauss points (quadrature::half_span_points)
    /// restricted to the continuum Ω_t (thesis §7.2, Figs. 7.3–7.4): on
    /// each half span, both points are kept if both lie inside; otherwise
    /// the 2-point rule is redefined on the part of the half span inside
    /// Ω_t, and the half span is dropped if it misses Ω_t. With
    /// `clip_every_half_span`, a half span is kept whole only if it lies
    /// inside Ω_t.
    fn begin_step(&mut self, grid: &Grid, particles: &Particles, _: CellAverage) -> Result<()> {
        let (left, right) = continuum(particles);
        let q = &mut self.quadrature;
        q.clear();
        for e in 0..grid.num_cells() {
            let (a, b) = grid.cell_bounds(e);
            let m = 0.5 * (a + b);
            for (pair, (c, d)) in half_span_points(&self.rule, a, b)
                .into_iter()
                .zip([(a, m), (m, b)])
            {
                let keep_whole = if self.clip_every_half_span {
                    c >= left && d <= right
                } else {
                    pair.iter().all(|q| q.x >= left && q.x <= right)
                };
                if keep_whole {
                    pair.into_iter().for_each(|p| q.push(p, e));
                } else {
                    let (c2, d2) = (c.max(left), d.min(right));
                    if d2 > c2 {
                        for i in 0..2 {
                            q.push(self.rule.point(i, c2, d2), e);
                        }
                    }
                }
            }
        }
        q.evaluate(grid, &mut self.scratch)
    }

    /// Thesis §7.2: the stress spline integrated against ∇φ_i.
    fn internal_force(&mut self, particles: &Particles, force: &mut [f64]) -> Result<()> {
        let spline = self.spline(particles, &particles.stress, 0)?;
        let q = &self.quadrature;
        let cursor = std::cell::Cell::new(0);
        q.stencils.scatter_gradients(
            |k| {
                let mut c = cursor.get();
                let value = spline.evaluate_from(q.points[k].x, &mut c);
                cursor.set(c);
                q.points[k].weight * value
            },
            force,
        );
        self.spare[0] = Some(spline);
        Ok(())
    }

    /// Thesis §7.1–7.2: splines of ρ and v, with ρ̃ṽ integrated at the
    /// half-span points.
    fn accumulate_projection(
        &mut self,
        particles: &Particles,
        acc: &mut Accumulator,
    ) -> Result<()> {
        let rho = self.spline(particles, &particles.density, 0)?;
        let vel = self.spline(particles, &particles.velocity, 1)?;
        let q = &self.quadrature;
        let (mut cursor_rho, mut cursor_vel) = (0, 0);
        for k in 0..q.points.len() {
            let (x, w) = (q.points[k].x, q.points[k].weight);
            let r = rho.evaluate_from(x, &mut cursor_rho);
            let v = vel.evaluate_from(x, &mut cursor_vel);
            acc.add(&q.stencils, k, w * r, w * r * v);
        }
        self.spare = [Some(rho), Some(vel)];
        Ok(())
    }
}
