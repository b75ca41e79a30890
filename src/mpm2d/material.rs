//! # The neo-Hookean material of the MLS paper
//!
//! MLS paper Eqs. (40)–(41). For a deformation gradient F with J = det F > 0
//! and Lamé constants λ, μ:
//!
//! - first Piola–Kirchhoff stress P = μ (F − F⁻ᵀ) + λ ln(J) F⁻ᵀ, which is
//!   the transpose of what Eq. (40) prints, λ ln(J) F⁻¹ + μ F⁻¹(F Fᵀ − I)
//!   (that is the nominal stress J F⁻¹ σ); the two agree whenever F is
//!   symmetric, as in the aligned vibration. hompm uses the P for which
//!   Eq. (41)'s σ = P Fᵀ / J holds (docs/conventions.md, "2D MPM");
//! - Cauchy stress σ = (λ ln J / J) I + (μ / J)(F Fᵀ − I), Eq. (41).
//!
//! J ≤ 0 or not finite (a particle turned inside out) is
//! `Error::InvertedDeformation`.
//!
//! Items: [`NeoHookean`].

use crate::error::{Error, Result};
use nalgebra::Matrix2;

/// A compressible neo-Hookean solid, MLS paper Eqs. (40)–(41).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NeoHookean {
    /// Lamé's first constant λ = E ν / ((1 + ν)(1 − 2ν)).
    pub lambda: f64,
    /// Shear modulus μ = E / (2(1 + ν)).
    pub mu: f64,
}

impl NeoHookean {
    /// From Young's modulus E > 0 and Poisson's ratio −1 < ν < ½.
    pub fn from_young_poisson(young: f64, poisson: f64) -> Result<Self> {
        if !(young.is_finite() && young > 0.0 && poisson > -1.0 && poisson < 0.5) {
            return Err(Error::InvalidArgument(format!(
                "a neo-Hookean solid needs E > 0 and −1 < ν < 0.5, got E = {young}, ν = {poisson}"
            )));
        }
        Ok(Self {
            lambda: young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson)),
            mu: young / (2.0 * (1.0 + poisson)),
        })
    }

    /// J = det F, refused unless positive and finite
    /// ([`Error::InvertedDeformation`], with no particle or step).
    pub fn jacobian(f: &Matrix2<f64>) -> Result<f64> {
        let j = f.determinant();
        if j.is_finite() && j > 0.0 {
            Ok(j)
        } else {
            Err(Error::InvertedDeformation {
                particle: None,
                step: None,
                time: None,
                jacobian: j,
                deformation: [f[(0, 0)], f[(0, 1)], f[(1, 0)], f[(1, 1)]],
            })
        }
    }

    /// Cauchy stress σ = (λ ln J / J) I + (μ / J)(F Fᵀ − I), MLS paper Eq. (41).
    pub fn cauchy_stress(&self, f: &Matrix2<f64>) -> Result<Matrix2<f64>> {
        let j = Self::jacobian(f)?;
        Ok(self.cauchy_stress_given_jacobian(f, j))
    }

    /// [`NeoHookean::cauchy_stress`] for a J = det F > 0 the caller has
    /// already checked with [`NeoHookean::jacobian`] (the step does, once
    /// per particle).
    pub fn cauchy_stress_given_jacobian(&self, f: &Matrix2<f64>, j: f64) -> Matrix2<f64> {
        let b = f * f.transpose();
        Matrix2::identity() * (self.lambda * j.ln() / j) + (b - Matrix2::identity()) * (self.mu / j)
    }

    /// First Piola–Kirchhoff stress P = μ (F − F⁻ᵀ) + λ ln(J) F⁻ᵀ = J σ F⁻ᵀ
    /// (MLS paper Eq. 40, transposed as the module doc explains).
    pub fn first_piola(&self, f: &Matrix2<f64>) -> Result<Matrix2<f64>> {
        let j = Self::jacobian(f)?;
        let f_inv_t = f
            .try_inverse()
            .ok_or_else(|| Error::Singular("F is not invertible".into()))?
            .transpose();
        Ok((f - f_inv_t) * self.mu + f_inv_t * (self.lambda * j.ln()))
    }

    /// Eq. (40) exactly as printed: λ ln(J) F⁻¹ + μ F⁻¹(F Fᵀ − I), the
    /// nominal stress J F⁻¹ σ = Pᵀ. Kept so that a test can show the
    /// difference.
    pub fn first_piola_as_printed(&self, f: &Matrix2<f64>) -> Result<Matrix2<f64>> {
        let j = Self::jacobian(f)?;
        let f_inv = f
            .try_inverse()
            .ok_or_else(|| Error::Singular("F is not invertible".into()))?;
        Ok(f_inv * (self.lambda * j.ln())
            + f_inv * (f * f.transpose() - Matrix2::identity()) * self.mu)
    }
}
