//! # The manufactured strip: the MLS paper's code's 1D vibration
//!
//! The MLS paper's figures come from a strip, not from the 2D square of its
//! §4 (issue #40): `Paper.m` of the paper's own code
//! (QuocAnh90/CPLS-least-squares-for-Material-Point-Method, first commit
//! f30bc24; read, not copied) calls `Vibration.m`, a 2D code run on one row
//! of cells with the y velocity fixed, which is a 1D bar in x. hompm runs it
//! in 1D, in the code's own coordinates, so that its particle files check
//! without editing:
//!
//! - the body X ∈ [a, a + L] with a = 2h, two empty ghost cells to the
//!   left (`x_min = 2*le(1)`), L = 1; both end DOFs fixed;
//! - 5 particles per cell at a + (j + ½)h/5, V_p⁰ = h/5;
//! - the neo-Hookean law of MLS paper Eq. (37) in 1D,
//!   σ = (λ ln F + μ(F² − 1))/F, with E = 1e7, ν = 0, ρ₀ = 1000;
//! - the manufactured displacement, the Wallstedt–Guilkey form with one
//!   half-wave (not Eq. 38's 2πX/L):
//!
//!   u = A sin(π(X − a)/L) sin(cπt/L),  c = √(E/ρ₀),  A = 1e-4,
//!
//!   v = ∂u/∂t, F = 1 + ∂u/∂X, and the body force that makes it exact,
//!   b = ü − (1/ρ₀) ∂P/∂X with P = λ ln F/F + μ(F − 1/F):
//!
//!   b = (π²u/(ρ₀L²)) (λ(1 − ln F)/F² + μ(F² + 1)/F² − E),
//!
//!   evaluated at X_p and the time at the start of each step, as the code
//!   does (the expression in the code's order of operations);
//! - Δt = 0.4 h/c and steps while t < 0.02 + 1e-7 ([`StripParameters::code_time_steps`]).
//!
//! Items: [`StripParameters`], [`PARAMETER_SETS`], [`parameters`].

use super::Discretisation;
use crate::error::{Error, Result};
use crate::mpm::grid::Grid;
use crate::mpm::musl::{neo_hookean_1d, BodyForceField, Constitutive, Simulation};
use crate::mpm::particles::Particles;
use serde::Serialize;
use std::f64::consts::PI;

/// One named parameter set of the strip; every value cites the code's
/// `Vibration.m` (f30bc24) by line (line numbers of `git show
/// f30bc24:Vibration.m`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StripParameters {
    /// Name: `mls-paper-code`.
    pub name: &'static str,
    /// Young's modulus E (`E = 10000000`, line 23).
    pub young: f64,
    /// Density ρ₀ (`psp = 1000.0`, line 24).
    pub density: f64,
    /// Poisson's ratio ν (`nu = 0.0`, line 25).
    pub poisson: f64,
    /// Amplitude A (`A = 0.0001`, line 19).
    pub amplitude: f64,
    /// Length L of the body (`le(1) = 1/resolution`, line 35; the particles fill
    /// `resolution*particle_per_cell` slots of le(1)/5, lines 107–122).
    pub length: f64,
    /// Empty cells left of the body (`x_min = 2*le(1)`, line 96).
    pub offset_cells: usize,
    /// Δt = courant·h/c (`dt = 0.4*le(1)/C`, line 90).
    pub courant: f64,
    /// The loop runs while t < end_time + 1e-7 (`ftime = 0.02`, line 89;
    /// `while t<ft+0.0000001`, line 189).
    pub end_time: f64,
    /// Particles per cell (`particle_per_cell = 5`, line 107).
    pub ppc: usize,
    /// The body's left end a = offset·h for the run's cells
    /// ([`StripParameters::placed`]); 0 in the named set.
    pub left_end: f64,
}

/// Every parameter set of the strip.
pub const PARAMETER_SETS: [StripParameters; 1] = [StripParameters {
    name: "mls-paper-code",
    young: 1.0e7,
    density: 1000.0,
    poisson: 0.0,
    amplitude: 1.0e-4,
    length: 1.0,
    offset_cells: 2,
    courant: 0.4,
    end_time: 0.02,
    ppc: 5,
    left_end: 0.0,
}];

/// Looks up a parameter set by name.
pub fn parameters(name: &str) -> Result<StripParameters> {
    super::find_set(&PARAMETER_SETS, |p| p.name, name, "manufactured-strip")
}

impl StripParameters {
    /// Wave speed c = √(E/ρ₀) (`C = sqrt(E/psp)`).
    pub fn wave_speed(&self) -> f64 {
        (self.young / self.density).sqrt()
    }

    /// Lamé's λ and μ (`Lambda`, `Mu`, lines 27–28).
    pub fn lame(&self) -> (f64, f64) {
        let (e, nu) = (self.young, self.poisson);
        (e * nu / (1.0 + nu) / (1.0 - 2.0 * nu), e / 2.0 / (1.0 + nu))
    }

    /// The set placed for a run on `cells` cells: a = offset·h with
    /// h = L/cells (the code's `2*le(1)`).
    pub fn placed(mut self, cells: usize) -> Self {
        self.left_end = self.offset_cells as f64 * (self.length / cells as f64);
        self
    }

    /// sin(π(X − a)/L) and cos(π(X − a)/L).
    fn mode(&self, x0: f64) -> (f64, f64) {
        (PI * (x0 - self.left_end) / self.length).sin_cos()
    }

    /// The exact displacement u(X, t).
    pub fn displacement(&self, x0: f64, t: f64) -> f64 {
        let c = self.wave_speed();
        self.amplitude * self.mode(x0).0 * (c * PI * t / self.length).sin()
    }

    /// The exact velocity v = ∂u/∂t.
    pub fn velocity(&self, x0: f64, t: f64) -> f64 {
        let c = self.wave_speed();
        self.amplitude * c * PI / self.length * self.mode(x0).0 * (c * PI * t / self.length).cos()
    }

    /// The exact deformation gradient F = 1 + ∂u/∂X.
    pub fn deformation(&self, x0: f64, t: f64) -> f64 {
        let c = self.wave_speed();
        1.0 + self.amplitude * PI / self.length * self.mode(x0).1 * (c * PI * t / self.length).sin()
    }

    /// The exact Cauchy stress σ = (λ ln F + μ(F² − 1))/F.
    pub fn stress(&self, x0: f64, t: f64) -> f64 {
        let (lambda, mu) = self.lame();
        neo_hookean_1d(lambda, mu, self.deformation(x0, t))
    }

    /// The body force b(X, t) of the module docs.
    pub fn body_force(&self, x0: f64, t: f64) -> f64 {
        let (lambda, mu) = self.lame();
        let (u, f) = (self.displacement(x0, t), self.deformation(x0, t));
        let l2 = self.length * self.length;
        PI * PI * u / self.density / l2
            * (lambda / (f * f) * (1.0 - f.ln()) + mu / (f * f) * (f * f + 1.0) - self.young)
    }

    /// An upper bound of |b(X, t)| over every X and t (the stability
    /// monitor's loads): |u| ≤ A and F ∈ [1 − Aπ/L, 1 + Aπ/L], and
    /// g(F) = λ(1 − ln F)/F² + μ(F² + 1)/F² − E has
    /// g′(F) = −(λ(3 − 2 ln F) + 2μ)/F³ < 0 there (3λ + 2μ > 0 for
    /// −1 < ν < ½, and |ln F| small), so |g| is largest at an end:
    /// π²A/(ρ₀L²) · max(|g(F_min)|, |g(F_max)|). Infinite when
    /// Aπ/L ≥ 1 (F may reach 0).
    pub fn body_force_bound(&self) -> f64 {
        let (lambda, mu) = self.lame();
        let spread = self.amplitude.abs() * PI / self.length;
        if spread >= 1.0 {
            return f64::INFINITY;
        }
        let g =
            |f: f64| lambda / (f * f) * (1.0 - f.ln()) + mu / (f * f) * (f * f + 1.0) - self.young;
        let largest = g(1.0 - spread).abs().max(g(1.0 + spread).abs());
        PI * PI * self.amplitude.abs() / self.density / (self.length * self.length) * largest
    }

    /// The code's Δt = courant·h/c and its number of steps: the loop
    /// `t = 0; while t < end_time + 1e-7: t += Δt`, counted with the same
    /// floating-point sums (41 steps to t = 0.0205 on 8 cells).
    pub fn code_time_steps(&self, cells: usize) -> (f64, usize) {
        let dt = self.courant * (self.length / cells as f64) / self.wave_speed();
        let (mut t, mut steps) = (0.0, 0usize);
        while t < self.end_time + 1e-7 && steps < usize::MAX {
            t += dt;
            steps += 1;
        }
        (dt, steps)
    }

    /// The initial positions: a + (j + ½)h/ppc, j = 0 … cells·ppc − 1
    /// (the code's `2*le(2)+0.5*lp(1,1)+(j-1)*lp(1,1)`).
    pub fn initial_positions(&self, cells: usize, ppc: usize) -> Vec<f64> {
        let h = self.length / cells as f64;
        let lp = h / ppc as f64;
        let a = self.placed(cells).left_end;
        (0..cells * ppc)
            .map(|j| a + 0.5 * lp + j as f64 * lp)
            .collect()
    }

    /// The simulation on the body [a, a + L]: `cells` elements or spans,
    /// both end DOFs fixed, v_p = v(X_p, 0), σ_p = 0, F_p = 1, the
    /// neo-Hookean law and the manufactured body force.
    pub fn simulation(&self, d: &Discretisation) -> Result<Simulation> {
        if d.ppc == 0 || d.cells == 0 {
            return Err(Error::InvalidArgument(
                "cells and particles per cell must be positive".into(),
            ));
        }
        let me = self.placed(d.cells);
        if me.left_end != self.left_end {
            return Err(Error::InvalidArgument(format!(
                "the strip is placed for other cells than {} (left end {}, not {})",
                d.cells, self.left_end, me.left_end
            )));
        }
        let a = me.left_end;
        let grid = Grid::with_knots(d.method, a, a + self.length, d.cells, d.conventions.knots)?;
        let x0 = self.initial_positions(d.cells, d.ppc);
        let n = x0.len();
        let volume = self.length / d.cells as f64 / d.ppc as f64;
        let velocity = x0.iter().map(|&x| me.velocity(x, 0.0)).collect();
        let particles = Particles::new(
            x0,
            vec![volume; n],
            vec![self.density; n],
            velocity,
            vec![0.0; n],
        )?;
        let last = grid.num_dofs() - 1;
        let mut settings = d.settings(
            Constitutive::NeoHookean,
            self.young,
            0.0,
            None,
            vec![0, last],
        );
        settings.poisson = self.poisson;
        settings.body_force = Some(BodyForceField {
            name: "manufactured strip: b = (π²u/(ρ₀L²))(λ(1 − ln F)/F² + μ(F² + 1)/F² − E)",
            at: std::sync::Arc::new(move |x0, t| me.body_force(x0, t)),
            bound: me.body_force_bound(),
        });
        Simulation::new(grid, particles, settings)
    }
}
