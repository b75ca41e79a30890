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
    /// ([`Error::InvertedDeformation`], with no particle or step). Inlined
    /// into the step's particle loops, with the error built out of line.
    #[inline(always)]
    pub fn jacobian(f: &Matrix2<f64>) -> Result<f64> {
        let j = f.determinant();
        if j.is_finite() && j > 0.0 {
            Ok(j)
        } else {
            Err(Self::inverted(f, j))
        }
    }

    /// The error of [`NeoHookean::jacobian`] for det F = j.
    #[cold]
    #[inline(never)]
    fn inverted(f: &Matrix2<f64>, j: f64) -> Error {
        Error::InvertedDeformation {
            particle: None,
            step: None,
            time: None,
            jacobian: j,
            deformation: [f[(0, 0)], f[(0, 1)], f[(1, 0)], f[(1, 1)]],
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
    ///
    /// Entry by entry, with the operands and order of the matrix form
    /// (λ ln J / J) I + (B − I)(μ / J), B = F Fᵀ, as nalgebra evaluates it
    /// (an entry of a 2×2 product is A_{i0} B_{0j} + A_{i1} B_{1j}; the off
    /// diagonal keeps its 0·(λ ln J / J) and B_{01} − 0, which can turn a
    /// −0 into +0): the same bits, with B_{01} = F₀₀F₁₀ + F₀₁F₁₁ formed once,
    /// since B_{10} = F₁₀F₀₀ + F₁₁F₀₁ is the same two products in the same
    /// order, so σ is symmetric bit for bit.
    #[inline(always)]
    pub fn cauchy_stress_given_jacobian(&self, f: &Matrix2<f64>, j: f64) -> Matrix2<f64> {
        let (c, d) = (self.lambda * j.ln() / j, self.mu / j);
        let b00 = f[(0, 0)] * f[(0, 0)] + f[(0, 1)] * f[(0, 1)];
        let b01 = f[(0, 0)] * f[(1, 0)] + f[(0, 1)] * f[(1, 1)];
        let b11 = f[(1, 0)] * f[(1, 0)] + f[(1, 1)] * f[(1, 1)];
        let off = 0.0 * c + (b01 - 0.0) * d;
        Matrix2::new(c + (b00 - 1.0) * d, off, off, c + (b11 - 1.0) * d)
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
