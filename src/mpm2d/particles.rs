//! # Material points in 2D
//!
//! The particle state of the MLS paper's algorithm (Eqs. 18–37), as a struct
//! of arrays in the 1D step's names (`x`, `x0`, `velocity`, …), each 2D
//! vector as `[f64; 2]`: current position x_p, initial
//! position X_p, displacement, velocity, deformation gradient F_p, Cauchy
//! stress σ_p, volume V_p, initial volume V_p⁰, density ρ_p and the fixed
//! mass m_p = ρ_p⁰ V_p⁰.
//!
//! Items: [`Particles2d`].

use crate::error::{finite_named, Error, Result};
use nalgebra::Matrix2;

/// Particles in the plane, struct of arrays.
#[derive(Debug, Clone, PartialEq)]
pub struct Particles2d {
    /// Current positions x_p = [x, y] (the 1D step's `x`; the tensor
    /// product's basis reads one axis at a time, `Grid::fill_stencils`).
    pub x: Vec<[f64; 2]>,
    /// Initial positions X_p.
    pub x0: Vec<[f64; 2]>,
    /// Displacements u_p = x_p − X_p.
    pub displacement: Vec<[f64; 2]>,
    /// Velocities v_p.
    pub velocity: Vec<[f64; 2]>,
    /// Deformation gradients F_p (MLS paper Eq. 35).
    pub deformation: Vec<Matrix2<f64>>,
    /// Cauchy stresses σ_p (symmetric; MLS paper Eq. 41).
    pub stress: Vec<Matrix2<f64>>,
    /// Volumes V_p (Eq. 36).
    pub volume: Vec<f64>,
    /// Initial volumes V_p⁰.
    pub volume0: Vec<f64>,
    /// Densities ρ_p (Eq. 37).
    pub density: Vec<f64>,
    /// Masses m_p = ρ_p⁰ V_p⁰ (constant).
    pub mass: Vec<f64>,
    /// APIC's affine velocity C_p (`--transfer apic`; Jiang et al. 2015),
    /// zero at the start and untouched by every other transfer.
    pub affine: Vec<Matrix2<f64>>,
}

impl Particles2d {
    /// Undeformed particles (F = I, σ = 0, u = 0) at `positions` with
    /// volumes, one density and initial velocities.
    pub fn new(
        positions: Vec<[f64; 2]>,
        volume: Vec<f64>,
        density: f64,
        velocity: Vec<[f64; 2]>,
    ) -> Result<Self> {
        let n = positions.len();
        if n == 0 {
            return Err(Error::Empty("particles".into()));
        }
        for (what, got) in [("volumes", volume.len()), ("velocities", velocity.len())] {
            if got != n {
                return Err(Error::LengthMismatch {
                    what: format!("particle {what} (one per position)"),
                    expected: n,
                    got,
                });
            }
        }
        if !(density.is_finite() && density > 0.0) {
            return Err(Error::NotPositive {
                what: "the density".into(),
                value: density,
            });
        }
        for k in 0..n {
            for c in 0..2 {
                finite_named(positions[k][c], || format!("position of particle {k}"))?;
                finite_named(velocity[k][c], || format!("velocity of particle {k}"))?;
            }
            if !(volume[k].is_finite() && volume[k] > 0.0) {
                return Err(Error::NotPositive {
                    what: format!("the volume of particle {k}"),
                    value: volume[k],
                });
            }
        }
        Ok(Self {
            x: positions.clone(),
            x0: positions,
            displacement: vec![[0.0; 2]; n],
            velocity,
            deformation: vec![Matrix2::identity(); n],
            stress: vec![Matrix2::zeros(); n],
            mass: volume.iter().map(|v| v * density).collect(),
            volume0: volume.clone(),
            volume,
            density: vec![density; n],
            affine: vec![Matrix2::zeros(); n],
        })
    }

    /// `per_side`² particles in every cell of an `cells`×`cells` grid on
    /// [0, L]², each at the centre of its sub-cell (MLS paper: "9 material
    /// points are distributed equally in a single cell"), with volume
    /// (L / (cells · per_side))² and velocity `velocity(X)`.
    pub fn cell_centred(
        length: f64,
        cells: usize,
        per_side: usize,
        density: f64,
        velocity: impl Fn([f64; 2]) -> [f64; 2],
    ) -> Result<Self> {
        if cells == 0 || per_side == 0 || !(length.is_finite() && length > 0.0) {
            return Err(Error::InvalidArgument(format!(
                "particles need cells ≥ 1, per side ≥ 1 and L > 0, got {cells}, {per_side}, {length}"
            )));
        }
        let n = cells * per_side;
        let d = length / n as f64;
        let mut positions = Vec::with_capacity(n * n);
        for j in 0..n {
            for i in 0..n {
                positions.push([(i as f64 + 0.5) * d, (j as f64 + 0.5) * d]);
            }
        }
        let velocity = positions.iter().map(|&p| velocity(p)).collect();
        Self::new(positions, vec![d * d; n * n], density, velocity)
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Always false: construction refuses zero particles.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Σ_p m_p.
    pub fn total_mass(&self) -> f64 {
        self.mass.iter().sum()
    }

    /// Σ_p m_p v_p.
    pub fn total_momentum(&self) -> [f64; 2] {
        let mut s = [0.0; 2];
        for (m, v) in self.mass.iter().zip(&self.velocity) {
            s[0] += m * v[0];
            s[1] += m * v[1];
        }
        s
    }
}
