//! # The TLS mapping in 1D
//!
//! Taylor least squares on every cell that holds particles, integrated
//! with two Gauss points per cell (book §4.4.3, Eqs. 4.36–4.44; TLS paper
//! §5.4): the stress unconstrained (Eq. 4.38), the density and the momentum
//! density conservative, with the cell mass Σ m_p and momentum Σ m_p v_p
//! as their prescribed integrals (Eqs. 4.39–4.44). The particles are
//! binned by cell once per step (a counting sort, so a step costs
//! O(particles + cells)); the fits themselves allocate their coefficients,
//! the same amount every step (tests/allocations.rs).
//!
//! Items: [`TLS_GAUSS_POINTS`], [`TlsWorkspace`].

use super::quadrature::{Accumulator, QuadratureStencils};
use super::reconstruction::{Reconstruction, Reconstruction1d};
use crate::error::Result;
use crate::mpm::grid::Grid;
use crate::mpm::particles::Particles;
use crate::quadrature::GaussLegendre;
use crate::reconstruct::taylor::{
    reconstruct_binned, CellAverage, CellBins, TlsOptions, TlsReconstruction, TlsScratch,
};
use crate::spline::bspline::SpanScratch;

/// Gauss points per cell for TLS: n_b ≤ 2 N_g/N_e (TLS paper §5.5), i.e. two
/// for quadratic TLS, as the paper uses.
pub const TLS_GAUSS_POINTS: usize = 2;

/// The buffers of the TLS mapping (book §4.4.3, TLS paper §5.4), allocated
/// once per simulation: the particles binned by cell, the Gauss points of
/// the cells that hold particles with the basis at them, and the cell
/// integrals the conservative fits prescribe (book Eq. 4.36).
#[derive(Debug, Clone)]
pub struct TlsWorkspace {
    fits: CellFits,
    rule: GaussLegendre,
    scratch: SpanScratch,
    quadrature: QuadratureStencils,
    /// ρ_p v_p, the data of the momentum fit.
    product: Vec<f64>,
    cell_mass: Vec<f64>,
    cell_momentum: Vec<f64>,
    /// How this step's density fit averages (x − x_c)² in ψ_3.
    density_average: CellAverage,
}

/// The particles binned by cell, the fits' scratch, and what the fits of
/// this step met.
#[derive(Debug, Clone)]
struct CellFits {
    cells: Vec<(f64, f64)>,
    bins: CellBins,
    scratch: TlsScratch,
    largest_condition: f64,
    repaired: usize,
}

impl CellFits {
    /// TLS of particle `values` over the binned particles (book Eqs.
    /// 4.33–4.37), conservative when cell integrals are given. The bins are
    /// half-open ([`Grid::cell_of`]), so a particle on a cell boundary
    /// belongs to the cell on its right; the default options are quadratic
    /// TLS with virtual points and a κ limit of 1e10. Records the fit's
    /// largest κ and its repaired cells.
    fn fit(
        &mut self,
        particles: &Particles,
        values: &[f64],
        integrals: Option<&[f64]>,
        average: CellAverage,
    ) -> Result<TlsReconstruction> {
        let options = TlsOptions {
            average,
            ..TlsOptions::default()
        };
        let tls = reconstruct_binned(
            &self.cells,
            &self.bins,
            &particles.x,
            values,
            integrals,
            options,
            &mut self.scratch,
        )?;
        let mut repaired = 0;
        for fit in tls.cells.iter().flatten() {
            self.largest_condition = self.largest_condition.max(fit.condition_number);
            repaired += usize::from(fit.virtual_points > 0);
        }
        self.repaired = self.repaired.max(repaired);
        Ok(tls)
    }
}

impl TlsWorkspace {
    /// Buffers for `grid` and `particles` particles.
    pub fn new(grid: &Grid, particles: usize) -> Result<Self> {
        Ok(Self {
            fits: CellFits {
                cells: grid.cells(),
                bins: CellBins::default(),
                scratch: TlsScratch::default(),
                largest_condition: 0.0,
                repaired: 0,
            },
            rule: GaussLegendre::new(2)?,
            scratch: SpanScratch::default(),
            quadrature: QuadratureStencils::default(),
            product: Vec::with_capacity(particles),
            cell_mass: vec![0.0; grid.num_cells()],
            cell_momentum: vec![0.0; grid.num_cells()],
            density_average: CellAverage::Exact,
        })
    }
}

/// The TLS reconstruction in cell e at x (a Gauss point of that cell).
fn cell_value(tls: &TlsReconstruction, e: usize, x: f64) -> f64 {
    tls.cells[e].as_ref().map_or(0.0, |fit| fit.evaluate(x))
}

impl Reconstruction for TlsWorkspace {
    fn name(&self) -> &'static str {
        "TLS"
    }

    fn largest_condition(&self) -> f64 {
        self.fits.largest_condition
    }

    fn repaired(&self) -> usize {
        self.fits.repaired
    }
}

impl Reconstruction1d for TlsWorkspace {
    /// Bins the particles by cell and puts two Gauss points on every cell
    /// that holds a particle (book Eq. 4.38).
    fn begin_step(
        &mut self,
        grid: &Grid,
        particles: &Particles,
        density_average: CellAverage,
    ) -> Result<()> {
        self.density_average = density_average;
        self.fits.largest_condition = 0.0;
        self.fits.repaired = 0;
        let x = &particles.x;
        let bins = &mut self.fits.bins;
        bins.fill(grid.num_cells(), x.len(), |k| {
            Ok((grid.cell_of(x[k])?, None))
        })?;
        let q = &mut self.quadrature;
        q.clear();
        for e in 0..grid.num_cells() {
            if bins.count(e) == 0 {
                continue;
            }
            let (a, b) = grid.cell_bounds(e);
            for i in 0..TLS_GAUSS_POINTS {
                q.push(self.rule.point(i, a, b), e);
            }
        }
        q.evaluate(grid, &mut self.scratch)
    }

    /// Book Eq. (4.38): the unconstrained TLS of σ, integrated against ∇φ_i.
    fn internal_force(&mut self, particles: &Particles, force: &mut [f64]) -> Result<()> {
        let tls = self
            .fits
            .fit(particles, &particles.stress, None, CellAverage::Exact)?;
        let q = &self.quadrature;
        q.stencils.scatter_gradients(
            |k| q.points[k].weight * cell_value(&tls, q.cell[k], q.points[k].x),
            force,
        );
        Ok(())
    }

    /// Book Eqs. (4.39)–(4.44), TLS paper §5.4: conservative TLS fits of ρ
    /// and ρv per cell, whose prescribed integrals are the cell mass Σ m_p
    /// and momentum Σ m_p v_p, integrated at the Gauss points of every cell.
    fn accumulate_projection(
        &mut self,
        particles: &Particles,
        acc: &mut Accumulator,
    ) -> Result<()> {
        let (cell_mass, cell_momentum) = (&mut self.cell_mass, &mut self.cell_momentum);
        cell_mass.fill(0.0);
        cell_momentum.fill(0.0);
        for e in 0..self.fits.cells.len() {
            for &k in self.fits.bins.points_of(e) {
                cell_mass[e] += particles.mass[k];
                cell_momentum[e] += particles.mass[k] * particles.velocity[k];
            }
        }
        self.product.clear();
        self.product.extend(
            particles
                .density
                .iter()
                .zip(&particles.velocity)
                .map(|(r, v)| r * v),
        );
        let fits = &mut self.fits;
        let density = &particles.density;
        let rho = fits.fit(particles, density, Some(cell_mass), self.density_average)?;
        let mom = fits.fit(
            particles,
            &self.product,
            Some(cell_momentum),
            CellAverage::Exact,
        )?;
        let q = &self.quadrature;
        for k in 0..q.points.len() {
            let (x, w, e) = (q.points[k].x, q.points[k].weight, q.cell[k]);
            acc.add(
                &q.stencils,
                k,
                w * cell_value(&rho, e, x),
                w * cell_value(&mom, e, x),
            );
        }
        Ok(())
    }
}
