//! # Material points
//!
//! Each particle carries position x_p, displacement u_p, velocity v_p,
//! stress σ_p, volume V_p and density ρ_p, all time dependent, and a fixed
//! mass m_p = ρ_p⁰ V_p⁰ (book §4.2.2, thesis §3.2). The initial position X_p
//! is kept because the seeds compare with analytic solutions in the
//! reference configuration (thesis §2.2).
//!
//! Items: [`Particles`].

use crate::error::{finite_named, Error, Result};

/// Particles as a struct of arrays.
#[derive(Debug, Clone, PartialEq)]
pub struct Particles {
    /// Initial positions X_p.
    pub x0: Vec<f64>,
    /// Current positions x_p.
    pub x: Vec<f64>,
    /// Displacements u_p = x_p − X_p (accumulated by Eq. 4.12).
    pub displacement: Vec<f64>,
    /// Velocities v_p.
    pub velocity: Vec<f64>,
    /// Stresses σ_p.
    pub stress: Vec<f64>,
    /// Volumes V_p.
    pub volume: Vec<f64>,
    /// Densities ρ_p.
    pub density: Vec<f64>,
    /// Masses m_p (constant).
    pub mass: Vec<f64>,
    /// Traction forces f_p^trac applied to the particle (thesis §3.2).
    pub traction: Vec<f64>,
    /// Accumulated strain ε_p = Σ Δε_p (for the maximal-strain diagnostic).
    pub strain: Vec<f64>,
    /// Deformation gradients F_p ← (1 + Δε_p) F_p, kept by the neo-Hookean
    /// law only (1 otherwise; [`super::settings::Constitutive::NeoHookean`]).
    pub deformation: Vec<f64>,
    /// Initial volumes V_p⁰ (the neo-Hookean law's V_p = V_p⁰ F_p).
    pub initial_volume: Vec<f64>,
}

impl Particles {
    /// Particles at the given initial positions with volumes, densities,
    /// velocities and stresses; displacement zero, m_p = ρ_p V_p.
    pub fn new(
        x0: Vec<f64>,
        volume: Vec<f64>,
        density: Vec<f64>,
        velocity: Vec<f64>,
        stress: Vec<f64>,
    ) -> Result<Self> {
        let n = x0.len();
        let lengths = [
            ("volumes", volume.len()),
            ("densities", density.len()),
            ("velocities", velocity.len()),
            ("stresses", stress.len()),
        ];
        if let Some(&(what, got)) = lengths.iter().find(|&&(_, l)| l != n) {
            return Err(Error::LengthMismatch {
                what: format!("particle {what} (one per position)"),
                expected: n,
                got,
            });
        }
        if n == 0 {
            return Err(Error::Empty("particles".into()));
        }
        for k in 0..n {
            finite_named(x0[k], || format!("position of particle {k}"))?;
            finite_named(velocity[k], || format!("velocity of particle {k}"))?;
            finite_named(stress[k], || format!("stress of particle {k}"))?;
            if volume[k].is_nan() || volume[k] <= 0.0 || density[k].is_nan() || density[k] <= 0.0 {
                return Err(Error::InvalidArgument(format!(
                    "particle {k} needs positive volume and density, got V = {}, ρ = {}",
                    volume[k], density[k]
                )));
            }
        }
        let mass = volume.iter().zip(&density).map(|(v, r)| v * r).collect();
        Ok(Self {
            deformation: vec![1.0; n],
            initial_volume: volume.clone(),
            x: x0.clone(),
            x0,
            displacement: vec![0.0; n],
            velocity,
            stress,
            volume,
            density,
            mass,
            traction: vec![0.0; n],
            strain: vec![0.0; n],
        })
    }

    /// `count` particles at the centres of equal sub-intervals of [a, b]:
    /// x_p = a + (p − ½)(b − a)/count, V_p = (b − a)/count (thesis §3.2:
    /// "initially equally distributed", V_p⁰ = L/n_p; x_p = 12.4023 m for the
    /// bar of thesis §5.1.1).
    pub fn uniform(a: f64, b: f64, count: usize, density: f64) -> Result<Self> {
        if count == 0 {
            return Err(Error::Empty("particles".into()));
        }
        let dx = (b - a) / count as f64;
        let x0: Vec<f64> = (0..count).map(|p| a + (p as f64 + 0.5) * dx).collect();
        Self::new(
            x0,
            vec![dx; count],
            vec![density; count],
            vec![0.0; count],
            vec![0.0; count],
        )
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Always false: there is at least one particle.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Total mass Σ m_p.
    pub fn total_mass(&self) -> f64 {
        self.mass.iter().sum()
    }

    /// Total momentum Σ m_p v_p.
    pub fn total_momentum(&self) -> f64 {
        self.mass
            .iter()
            .zip(&self.velocity)
            .map(|(m, v)| m * v)
            .sum()
    }

    /// Whether some particle carries a traction force f_p^trac ≠ 0 (thesis
    /// §3.2), NaN included: the steps map the traction only then. One
    /// comparison per particle without an early exit, which the compiler
    /// turns into vector comparisons (the search that stopped at the first
    /// non-zero took 5 instructions per particle-step, all of them for the
    /// common all-zero case; issue #39).
    pub fn has_traction(&self) -> bool {
        self.traction.iter().fold(false, |any, &t| any | (t != 0.0))
    }
}
