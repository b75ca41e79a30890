//! # Partition-of-unity Taylor least squares in 2D, at the Gauss points
//!
//! A conservative reconstruction that is continuous in the particle
//! positions. 2D TLS ([`super::tls`]) fits each cell on its own, so its
//! φ_gp jump when a particle crosses a cell edge; MLS ([`super::mls`]) is
//! continuous but not conservative. This module blends constrained linear
//! (or quadratic) fits, one per function of the grid's quadratic B-spline
//! basis, by that basis. **The blend is hompm's construction, not a paper's**: its pieces
//! are the TLS paper's conservative fit (§5.2–5.5, Eqs. 13–14: a
//! least-squares fit whose first coefficient is fixed by the particles'
//! integral) and the MLS paper's route to the grid (Eqs. 18–25: values at
//! the 2×2 Gauss points of every cell, integrated with ω_g = (h/2)²).
//!
//! **Patches.** N_e = N_a(x) N_b(y), e = (a, b), are the open-uniform
//! quadratic B-splines of the grid's cells ([`open_quadratic_on_cell`], the
//! grid's own basis at `--degree 2` with open knots): C¹, non-negative,
//! Σ_e N_e = 1. With X = x/h, Y = y/h and the N_e-weighted Gauss centroid
//! (X̄_a, Ȳ_b) = Σ_g ω_g N_e(x_g)(X_g, Y_g) / m_e, m_e = Σ_g ω_g N_e(x_g),
//! the patch basis is ψ₁ = 1, ψ₂ = X − X̄_a, ψ₃ = Y − Ȳ_b: the linear
//! Taylor basis scaled by h, shifted so that Σ_g ω_g N_e(x_g) ψ_i = m_e δ_i1
//! (the counterpart of TLS paper Eq. 12 with the weight N_e). The
//! quadratic option ([`TaylorOrder2d::Quadratic`], `--method
//! bsmpm-pu-tls-quadratic`) adds ψ₄ = (dx² − ⟨dx²⟩)/2, ψ₅ = dx dy − ⟨dx⟩⟨dy⟩,
//! ψ₆ = (dy² − ⟨dy²⟩)/2 with dx = X − a, dy = Y − b and ⟨·⟩ the
//! N_e-weighted Gauss means, as 2D TLS's ψ₄ … ψ₆ on a cell.
//!
//! **The fit on patch e** (weights w_p = N_e(x_p), particle volumes V_p):
//! f_e = α₁ + α₂ψ₂ + α₃ψ₃ (+ α₄ψ₄ + α₅ψ₅ + α₆ψ₆) with the constraint
//! Σ_g ω_g N_e(x_g) f_e(x_g) = Σ_p N_e(x_p) V_p f_p, i.e.
//! α₁ = Σ_p N_e(x_p) V_p f_p / m_e (TLS paper Eq. 14 with V_p/|Ω_e|
//! replaced by N_e(x_p)V_p/m_e), and the rest the weighted least squares of
//! ψ̂ = (ψ₂, ψ₃, …) to f_p − α₁ (Eq. 13): D = Σ_p w_p ψ̂_pψ̂_pᵀ,
//! U = D⁻¹ Σ_p w_p ψ̂_p. Per particle, with c_pe = N_e(x_p)V_p/m_e,
//!
//! f_e(x) = Σ_p f_p [c_pe + (w_p D⁻¹ψ̂_p − c_pe U)·ψ̂(x)].
//!
//! **The reconstruction** f̃(x_g) = Σ_e N_e(x_g) f_e(x_g) = Σ_p φ_gp f_p, so
//! φ_gp = Σ_e N_e(x_g)[c_pe + (w_p D⁻¹ψ̂_p − c_pe U)·ψ̂(x_g)]: a
//! [`GaussReconstruction`] whose Gauss point in cell (c_x, c_y) reaches the
//! particles of the 5×5 cells around it.
//!
//! **Conservation.** Σ_g ω_g φ_gp = Σ_e [c_pe m_e + (…)·Σ_g ω_g N_e ψ̂] =
//! Σ_e N_e(x_p) V_p + 0 = V_p, by the constraint, the shift of ψ̂ and the
//! partition of unity at x_p. So Σ_g ω_g f̃_g = Σ_p V_p f_p to rounding:
//! mass and momentum are mapped exactly, at every step, as in the TLS
//! paper's §5.5 (the proof uses the discrete Gauss sums themselves, no
//! quadrature exactness).
//!
//! **Continuity.** w_p = N_e(x_p) vanishes with its first derivative at the
//! edge of supp N_e, so a particle enters and leaves a patch's sums
//! continuously, and the cell it is binned in changes only where the
//! functions it drops and gains are zero: φ_gp is continuous in the
//! positions while every patch keeps its basis.
//!
//! **Degenerate patches** (TLS paper §5.3, as 2D TLS). A patch whose D has
//! κ₁(D) = ‖D‖₁‖D⁻¹‖₁ above 2D TLS's limit
//! ([`super::tls::TLS_2D_MAX_CONDITION`], 1e10) or is singular (a linear fit with fewer than two particles
//! of w_p > 0, or all on a line through the centroid) is reduced,
//! quadratic → linear → constant, under [`DegenerateCells::ReduceBasis`]
//! (the engine's choice, as 2D TLS; the reduction keeps the constraint, so
//! it still conserves, and counts in [`Reconstruction::repaired`]), or is
//! `Error::SingularCell` naming the patch and its support under
//! [`DegenerateCells::Error`]. A patch without particles has f_e = 0,
//! exactly its particles' sum. The reduction is the one place φ_gp may
//! jump. The aligned vibration's full square meets it only once its
//! particles have drifted from the exact motion and left a wall row of
//! cells nearly empty (8 and 32 cells, docs/reproduction-notes.md "A
//! conservative reconstruction that is continuous"); κ₁ and the reduced
//! patches are reported.
//!
//! Items: [`open_quadratic_on_cell`], [`PuTlsShapes`].

use super::particles::Particles2d;
use super::reconstruction::{
    GaussGrid, GaussReconstruction, Reconstruction, ShapeBuffers, ShapeLists,
};
use super::tls::{TaylorOrder2d, TLS_2D_MAX_CONDITION};
use crate::error::{Error, Result};
use crate::reconstruct::taylor::DegenerateCells;
use nalgebra::SMatrix;

mod emit;

/// The three open-uniform quadratic B-splines N_c, N_{c+1}, N_{c+2} that are
/// non-zero on cell c of `cells` unit cells, at t = X − c ∈ [0, 1] (clamped):
/// the knots 0, 0, 0, 1, …, cells − 1, cells, cells, cells (book Eqs.
/// 4.19–4.20 for p = 2; MLS paper Eqs. 4–5 take their tensor product).
/// Interior cells carry the uniform pieces (1 − t)²/2, 1/2 + t − t², t²/2;
/// the first and last cells the pieces of the repeated knots.
pub fn open_quadratic_on_cell(cells: usize, cell: usize, t: f64) -> [f64; 3] {
    let t = t.clamp(0.0, 1.0);
    let s = 1.0 - t;
    if cells == 1 {
        return [s * s, 2.0 * t * s, t * t];
    }
    let first = if cell == 0 { s * s } else { 0.5 * s * s };
    let last = if cell + 1 == cells {
        t * t
    } else {
        0.5 * t * t
    };
    [first, 1.0 - first - last, last]
}

/// The most fitted functions of a patch: ψ₂ … ψ₆ of the quadratic basis.
const FITTED: usize = 5;

/// X − a, exact for a ≥ 4 (Sterbenz) on supp N_a = [a − 2, a + 1]: ψ then
/// rounds at the size of ψ, not of X (with X, Σ_g ω_g N_e ψ₂ = 0 held only
/// to ε·X and the mapped mass drifted by ~ε·cells, 1e-13 on 32 cells).
fn local(big_x: f64, a: usize) -> f64 {
    big_x - a as f64
}

/// The 1D Gauss moments of N_a: its mass Σ_g ½N_a(X_g) and the N_a-weighted
/// means of (X − a) and (X − a)².
#[derive(Debug, Clone, Copy, Default)]
struct AxisMoments {
    mass: f64,
    mean: f64,
    mean_square: f64,
}

/// ψ₂ … ψ₆ of patch (a, b) at offsets dx = X − a, dy = Y − b, each minus its
/// N_e-weighted Gauss mean (the means of a product are products, N_e and the
/// Gauss grid being tensor products).
fn fitted_functions(dx: f64, dy: f64, a: &AxisMoments, b: &AxisMoments) -> [f64; FITTED] {
    [
        dx - a.mean,
        dy - b.mean,
        0.5 * (dx * dx - a.mean_square),
        dx * dy - a.mean * b.mean,
        0.5 * (dy * dy - b.mean_square),
    ]
}

/// One patch's sums and solution: D = Σ w ψ̂ψ̂ᵀ and Σ w ψ̂ over the
/// fitted functions, the particles with w > 0, the fitted functions kept
/// (5, 2 or 0), D⁻¹ and U = D⁻¹Σ w ψ̂ on them.
#[derive(Debug, Clone, Copy, Default)]
struct Patch {
    d: [[f64; FITTED]; FITTED],
    g: [f64; FITTED],
    count: usize,
    fitted: usize,
    inverse: [[f64; FITTED]; FITTED],
    u: [f64; FITTED],
}

impl Patch {
    /// κ₁(D) of the leading `M` functions (∞ if D is singular); keeps
    /// D⁻¹ and U = D⁻¹Σ w ψ̂ on them if κ₁ is at most `limit`.
    fn fit<const M: usize>(&mut self, limit: f64) -> f64 {
        let d = SMatrix::<f64, M, M>::from_fn(|i, j| self.d[i][j]);
        let Some(inverse) = d.try_inverse() else {
            return f64::INFINITY;
        };
        let norm1 = |m: &SMatrix<f64, M, M>| {
            (0..M)
                .map(|j| (0..M).map(|i| m[(i, j)].abs()).sum::<f64>())
                .fold(0.0, f64::max)
        };
        let kappa = norm1(&d) * norm1(&inverse);
        if kappa <= limit {
            self.fitted = M;
            for i in 0..M {
                self.u[i] = (0..M).map(|j| inverse[(i, j)] * self.g[j]).sum();
                for j in 0..M {
                    self.inverse[i][j] = inverse[(i, j)];
                }
            }
        }
        if kappa.is_finite() {
            kappa
        } else {
            f64::INFINITY
        }
    }

    /// B = w D⁻¹ψ̂ − share·U on the leading `M` fitted functions (the `M`
    /// kept), into `out[1..=M]`.
    fn coefficients<const M: usize>(
        &self,
        psi: &[f64; FITTED],
        w: f64,
        share: f64,
        out: &mut [f64; FITTED + 1],
    ) {
        for r in 0..M {
            let q: f64 = (0..M).map(|t| self.inverse[r][t] * psi[t]).sum();
            out[1 + r] = w * q - share * self.u[r];
        }
    }
}

/// The PU-TLS shape functions at the Gauss points (module doc), with every
/// buffer of their evaluation, allocated in [`PuTlsShapes::new`].
#[derive(Debug, Clone)]
pub struct PuTlsShapes {
    cells: usize,
    order: TaylorOrder2d,
    degenerate: DegenerateCells,
    /// The lists; `phi` keeps the length of the longest lists so far (its
    /// first `particle.len()` entries are the lists', module `emit`).
    shapes: ShapeBuffers,
    largest_condition: f64,
    repaired: usize,
    /// Counting sort of the particles by cell: slots `bin_start[c] ..
    /// bin_start[c + 1]` of `bin_particles`.
    bin_start: Vec<usize>,
    bin_particles: Vec<u32>,
    /// The 1D functions at each Gauss abscissa (X units), three per point.
    gauss_values: Vec<[f64; 3]>,
    /// The Gauss moments of every 1D function.
    axis: Vec<AxisMoments>,
    patches: Vec<Patch>,
    /// Per slot: the 1D values along x and y.
    slot_values: Vec<[[f64; 3]; 2]>,
    /// Per slot and patch i + 3j of its cell: [c_pe, B₂, …, B₆].
    coefficients: Vec<[[f64; FITTED + 1]; 9]>,
}

impl PuTlsShapes {
    /// Buffers for `particles` particles on `cells`² cells, with the patch
    /// basis `order` (linear: ψ₁ … ψ₃; quadratic: ψ₁ … ψ₆; constant: ψ₁
    /// alone) under the degenerate-patch policy `degenerate` (`Error` or
    /// `ReduceBasis`; virtual points have no 2D form, as in 2D TLS, and are
    /// refused).
    pub fn new(
        order: TaylorOrder2d,
        degenerate: DegenerateCells,
        cells: usize,
        particles: usize,
    ) -> Result<Self> {
        if degenerate == DegenerateCells::VirtualPoints {
            return Err(Error::InvalidArgument(
                "PU-TLS repairs degenerate patches by reducing the basis or refuses them; virtual points are 1D only".into(),
            ));
        }
        if cells == 0 {
            return Err(Error::InvalidArgument(
                "PU-TLS needs at least one cell".into(),
            ));
        }
        if particles > u32::MAX as usize {
            return Err(Error::InvalidArgument(format!(
                "{particles} particles is more than the PU-TLS lists index"
            )));
        }
        let (gauss_points, functions) = (4 * cells * cells, cells + 2);
        // Each particle reaches the four Gauss points of the (at most) 5×5
        // cells around its own: the lists never outgrow this.
        let entries = 100 * particles;
        Ok(Self {
            cells,
            order,
            degenerate,
            shapes: ShapeBuffers {
                start: vec![0; gauss_points],
                end: vec![0; gauss_points],
                particle: Vec::with_capacity(entries),
                phi: Vec::with_capacity(entries),
            },
            largest_condition: 0.0,
            repaired: 0,
            bin_start: vec![0; cells * cells + 2],
            bin_particles: vec![0; particles],
            gauss_values: vec![[0.0; 3]; 2 * cells],
            axis: vec![AxisMoments::default(); functions],
            patches: vec![Patch::default(); functions * functions],
            slot_values: vec![[[0.0; 3]; 2]; particles],
            coefficients: vec![[[0.0; FITTED + 1]; 9]; particles],
        })
    }

    /// The engine's PU-TLS: linear patches, reduced-basis repair.
    pub fn for_engine(cells: usize, particles: usize) -> Result<Self> {
        Self::new(
            TaylorOrder2d::Linear,
            DegenerateCells::ReduceBasis,
            cells,
            particles,
        )
    }

    /// Bins the particles by cell (a counting sort into preallocated
    /// buffers, particles in order within a cell), refusing a cell index
    /// outside the grid. Afterwards cell c holds the slots
    /// `bin_start[c] .. bin_start[c + 1]`.
    fn bin(&mut self, cell_x: &[usize], cell_y: &[usize]) -> Result<()> {
        let n = self.cells;
        let start = &mut self.bin_start;
        start.iter_mut().for_each(|s| *s = 0);
        for (k, (&cx, &cy)) in cell_x.iter().zip(cell_y).enumerate() {
            if cx >= n || cy >= n {
                return Err(Error::InvalidArgument(format!(
                    "particle {k} is in cell ({cx}, {cy}) of a {n}×{n} grid"
                )));
            }
            start[cx + n * cy + 2] += 1;
        }
        for c in 2..n * n + 2 {
            start[c] += start[c - 1];
        }
        // start[c + 1] is the next free slot of cell c; once filled it is
        // the end of cell c, the start of cell c + 1.
        for (k, (&cx, &cy)) in cell_x.iter().zip(cell_y).enumerate() {
            let c = cx + n * cy;
            self.bin_particles[start[c + 1]] = k as u32;
            start[c + 1] += 1;
        }
        Ok(())
    }

    /// The 1D functions at the Gauss abscissae and their Gauss moments
    /// (module doc, "Patches").
    fn axis_moments(&mut self, gauss: &GaussGrid) {
        let (n, h) = (self.cells, gauss.cell_size);
        self.axis
            .iter_mut()
            .for_each(|m| *m = AxisMoments::default());
        for (gx, &x) in gauss.abscissae.iter().enumerate() {
            let (c, big_x) = (gx / 2, x / h);
            let v = open_quadratic_on_cell(n, c, big_x - c as f64);
            self.gauss_values[gx] = v;
            for (i, vi) in v.iter().enumerate() {
                let (m, dx) = (&mut self.axis[c + i], local(big_x, c + i));
                m.mass += 0.5 * vi;
                m.mean += 0.5 * vi * dx;
                m.mean_square += 0.5 * vi * dx * dx;
            }
        }
        for m in self.axis.iter_mut() {
            m.mean /= m.mass;
            m.mean_square /= m.mass;
        }
    }

    /// The sums D and Σ w ψ̂ of every patch, then its D⁻¹ and U, or its
    /// reduction (module doc, "Degenerate patches").
    fn fit_patches(&mut self, particles: &Particles2d, h: f64) -> Result<()> {
        let m = self.order.functions() - 1;
        self.patches.iter_mut().for_each(|p| *p = Patch::default());
        match m {
            0 => self.patch_sums::<0>(particles, h),
            2 => self.patch_sums::<2>(particles, h),
            _ => self.patch_sums::<FITTED>(particles, h),
        }
        for e in 0..self.patches.len() {
            let p = &mut self.patches[e];
            if p.count == 0 {
                continue;
            }
            for r in 0..m {
                for q in 0..r {
                    p.d[r][q] = p.d[q][r];
                }
            }
            let mut order = self.order;
            let kappa = loop {
                let kappa = match order {
                    TaylorOrder2d::Quadratic => p.fit::<FITTED>(TLS_2D_MAX_CONDITION),
                    TaylorOrder2d::Linear => p.fit::<2>(TLS_2D_MAX_CONDITION),
                    TaylorOrder2d::Constant => 1.0,
                };
                if kappa <= TLS_2D_MAX_CONDITION {
                    break kappa;
                }
                match (self.degenerate, order.reduced()) {
                    (DegenerateCells::ReduceBasis, Some(lower)) => order = lower,
                    _ => return Err(self.singular_patch(e, order, kappa, h)),
                }
            };
            self.largest_condition = self.largest_condition.max(kappa);
            self.repaired += usize::from(order < self.order);
        }
        Ok(())
    }

    /// The sums D and Σ w ψ̂ of every patch over its particles, on the
    /// leading `M` fitted functions, and each slot's 1D values.
    fn patch_sums<const M: usize>(&mut self, particles: &Particles2d, h: f64) {
        let n = self.cells;
        let nf = n + 2;
        for c in 0..n * n {
            let (cx, cy) = (c % n, c / n);
            for s in self.bin_start[c]..self.bin_start[c + 1] {
                let [x, y] = particles.x[self.bin_particles[s] as usize];
                let (big_x, big_y) = (x / h, y / h);
                let vx = open_quadratic_on_cell(n, cx, big_x - cx as f64);
                let vy = open_quadratic_on_cell(n, cy, big_y - cy as f64);
                self.slot_values[s] = [vx, vy];
                for (j, wy) in vy.iter().enumerate() {
                    for (i, wx) in vx.iter().enumerate() {
                        let (a, b) = (cx + i, cy + j);
                        let w = wx * wy;
                        let psi = fitted_functions(
                            local(big_x, a),
                            local(big_y, b),
                            &self.axis[a],
                            &self.axis[b],
                        );
                        let p = &mut self.patches[a + nf * b];
                        for r in 0..M {
                            p.g[r] += w * psi[r];
                            for q in r..M {
                                p.d[r][q] += w * psi[r] * psi[q];
                            }
                        }
                        p.count += usize::from(w > 0.0);
                    }
                }
            }
        }
    }

    /// `Error::SingularCell` for patch e: the B-spline's indices and its
    /// support.
    fn singular_patch(&self, e: usize, order: TaylorOrder2d, kappa: f64, h: f64) -> Error {
        let (n, nf) = (self.cells, self.cells + 2);
        let (a, b) = (e % nf, e / nf);
        let support = |i: usize| (i.saturating_sub(2) as f64 * h, (i + 1).min(n) as f64 * h);
        let ((x0, x1), (y0, y1)) = (support(a), support(b));
        Error::SingularCell {
            cell: vec![a, b],
            lower: vec![x0, y0],
            upper: vec![x1, y1],
            detail: format!(
                "the PU-TLS patch of B-spline ({a}, {b}) has {} particles with a positive weight for the {order:?} basis, κ₁(D) = {kappa:e} > {:e}",
                self.patches[e].count,
                TLS_2D_MAX_CONDITION
            ),
        }
    }

    /// Per slot and patch, [c_pe, B] with B = w_p D⁻¹ψ̂_p − c_pe U on the
    /// fitted functions kept (zero beyond them).
    fn particle_coefficients(&mut self, particles: &Particles2d, h: f64) {
        let n = self.cells;
        let nf = n + 2;
        for c in 0..n * n {
            let (cx, cy) = (c % n, c / n);
            for s in self.bin_start[c]..self.bin_start[c + 1] {
                let k = self.bin_particles[s] as usize;
                let [x, y] = particles.x[k];
                let (big_x, big_y) = (x / h, y / h);
                let [vx, vy] = self.slot_values[s];
                let volume = particles.volume[k];
                for (j, wy) in vy.iter().enumerate() {
                    for (i, wx) in vx.iter().enumerate() {
                        let (a, b) = (cx + i, cy + j);
                        let p = &self.patches[a + nf * b];
                        let w = wx * wy;
                        let m = h * h * self.axis[a].mass * self.axis[b].mass;
                        let share = w * volume / m;
                        let mut out = [0.0; FITTED + 1];
                        out[0] = share;
                        if p.fitted > 0 {
                            let psi = fitted_functions(
                                local(big_x, a),
                                local(big_y, b),
                                &self.axis[a],
                                &self.axis[b],
                            );
                            match p.fitted {
                                2 => p.coefficients::<2>(&psi, w, share, &mut out),
                                _ => p.coefficients::<FITTED>(&psi, w, share, &mut out),
                            }
                        }
                        self.coefficients[s][i + 3 * j] = out;
                    }
                }
            }
        }
    }
}

impl Reconstruction for PuTlsShapes {
    fn name(&self) -> &'static str {
        "PU-TLS"
    }

    fn largest_condition(&self) -> f64 {
        self.largest_condition
    }

    fn repaired(&self) -> usize {
        self.repaired
    }
}

impl GaussReconstruction for PuTlsShapes {
    /// The constrained fits of every patch (TLS paper Eqs. 13–14 with the
    /// weights N_e, module doc) blended by N_e at the Gauss points of
    /// MLS paper Eqs. 18–21.
    fn evaluate(
        &mut self,
        gauss: &GaussGrid,
        particles: &Particles2d,
        cell_x: &[usize],
        cell_y: &[usize],
    ) -> Result<()> {
        let (n, h) = (self.cells, gauss.cell_size);
        if gauss.cells != n || gauss.abscissae.len() != 2 * n || !(h.is_finite() && h > 0.0) {
            return Err(Error::InvalidArgument(format!(
                "PU-TLS was built for {n}×{n} cells, evaluated on {} cells of size {h} with {} abscissae",
                gauss.cells,
                gauss.abscissae.len()
            )));
        }
        let count = particles.len();
        if cell_x.len() != count || cell_y.len() != count {
            return Err(Error::InvalidArgument(format!(
                "{count} particles with {} and {} cell indices",
                cell_x.len(),
                cell_y.len()
            )));
        }
        // Allocates only when the particle count changed since `new`.
        self.bin_particles.resize(count, 0);
        self.slot_values.resize(count, [[0.0; 3]; 2]);
        self.coefficients.resize(count, [[0.0; FITTED + 1]; 9]);
        self.largest_condition = 0.0;
        self.repaired = 0;
        self.bin(cell_x, cell_y)?;
        self.axis_moments(gauss);
        self.fit_patches(particles, h)?;
        self.particle_coefficients(particles, h);
        // `phi` keeps its length (module `emit`): no zeros written again.
        self.shapes.particle.clear();
        let k = self.order.functions();
        for cy in 0..n {
            for cx in 0..n {
                match k {
                    1 => self.emit_cell::<1>(gauss, cx, cy),
                    3 => self.emit_cell::<3>(gauss, cx, cy),
                    _ => self.emit_cell::<{ FITTED + 1 }>(gauss, cx, cy),
                }
            }
        }
        Ok(())
    }

    fn lists(&self) -> ShapeLists<'_> {
        let entries = self.shapes.particle.len();
        ShapeLists {
            phi: &self.shapes.phi[..entries],
            ..self.shapes.lists()
        }
    }
}
