//! # Conjugate gradients
//!
//! Book §4.6: CG for the SPD system M^C a = f from the zero initial guess,
//! stopped by Eq. (4.53), ‖r_k‖₂/‖r_0‖₂ < ε. The error obeys Eq. (4.57),
//! ‖a − a_k‖_M ≤ 2((√κ − 1)/(√κ + 1))^k ‖a − a_0‖_M, in the energy norm.
//!
//! Three variants that are identical in exact arithmetic are offered, because
//! book Table 4.3's counts depend on rounding (docs/reproduction.md):
//! [`CgVariant::Recursive`] (Hestenes–Stiefel, residual updated r ← r − αAp),
//! [`CgVariant::TrueResidual`] (r = b − A x recomputed each step) and
//! [`CgVariant::PolakRibiere`] (β = r_{k+1}ᵀ(r_{k+1} − r_k)/r_kᵀr_k).
//!
//! Items: [`CgVariant`], [`conjugate_gradient`],
//! [`conjugate_gradient_observed`].

use super::richardson::ResidualNorm;
use super::{check_rhs, dot, norm, IterativeResult, LinearOperator};
use crate::error::{Error, Result};

/// Which algebraically-equivalent CG recurrence to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CgVariant {
    /// Recursive residual, Fletcher–Reeves β (the textbook method).
    Recursive,
    /// The residual recomputed as b − A x at every iteration.
    TrueResidual,
    /// Recursive residual with the Polak–Ribière β.
    PolakRibiere,
}

/// Plain CG from x₀ = 0 until ‖r_k‖/‖r_0‖ < `tol` (book Eq. 4.53). Returns
/// `Error::NotConverged` after `max_iter` iterations, `Error::Singular` if a
/// search direction has non-positive curvature (A not SPD).
pub fn conjugate_gradient(
    op: &dyn LinearOperator,
    b: &[f64],
    tol: f64,
    max_iter: usize,
    variant: CgVariant,
) -> Result<IterativeResult> {
    let rule = ResidualNorm::Rhs;
    conjugate_gradient_observed(op, b, tol, rule, max_iter, variant, &mut |_, _| {})
}

/// [`conjugate_gradient`] with a choice of stopping rule, handing every
/// iterate x_k (k = 0, 1, …) to `observe` (the test of the error bound of
/// book Eq. 4.57 reads them). The residual is divided by ‖r_0‖ = ‖b‖
/// ([`ResidualNorm::Rhs`], Eq. 4.53) or by the iterate's ‖x_k‖
/// ([`ResidualNorm::Solution`], the rule of the thesis author's Richardson
/// code, offered so that another code's CG can be matched); both stop at
/// the first ratio below `tol`.
pub fn conjugate_gradient_observed(
    op: &dyn LinearOperator,
    b: &[f64],
    tol: f64,
    residual: ResidualNorm,
    max_iter: usize,
    variant: CgVariant,
    observe: &mut dyn FnMut(usize, &[f64]),
) -> Result<IterativeResult> {
    let n = op.size();
    check_rhs(n, b, tol)?;
    let mut x = vec![0.0; n];
    let mut r = b.to_vec();
    let r0 = norm(&r);
    let mut residuals = vec![1.0];
    observe(0, &x);
    if r0 == 0.0 {
        return Ok(IterativeResult {
            solution: x,
            iterations: 0,
            residuals: vec![0.0],
        });
    }
    let mut p = r.clone();
    let mut ap = vec![0.0; n];
    let mut rr = dot(&r, &r);
    for k in 1..=max_iter {
        let alpha = step_length(op, &p, &mut ap, rr, k)?;
        for i in 0..n {
            x[i] += alpha * p[i];
        }
        let r_old = (variant == CgVariant::PolakRibiere).then(|| r.clone());
        update_residual(variant, op, b, &x, alpha, &mut ap, &mut r);
        observe(k, &x);
        let rr_new = dot(&r, &r);
        let rel = match residual {
            ResidualNorm::Rhs => rr_new.sqrt() / r0,
            ResidualNorm::Solution => rr_new.sqrt() / norm(&x),
        };
        residuals.push(rel);
        if !rel.is_finite() {
            return Err(Error::BlowUp(format!(
                "CG residual became {rel} at iteration {k}"
            )));
        }
        if rel < tol {
            return Ok(IterativeResult {
                solution: x,
                iterations: k,
                residuals,
            });
        }
        let beta = match r_old {
            Some(ro) => r.iter().zip(&ro).map(|(a, b)| a * (a - b)).sum::<f64>() / rr,
            None => rr_new / rr,
        };
        for i in 0..n {
            p[i] = r[i] + beta * p[i];
        }
        rr = rr_new;
    }
    Err(Error::NotConverged(format!(
        "CG reached {max_iter} iterations with relative residual {:e} (tolerance {tol:e})",
        residuals.last().copied().unwrap_or(f64::NAN)
    )))
}

/// α_k = r_kᵀr_k / p_kᵀAp_k, leaving Ap_k in `ap`; a direction with
/// pᵀAp ≤ 0 means A is not SPD (or too ill-conditioned to tell).
fn step_length(
    op: &dyn LinearOperator,
    p: &[f64],
    ap: &mut [f64],
    rr: f64,
    k: usize,
) -> Result<f64> {
    op.apply(p, ap);
    let pap = dot(p, ap);
    if pap.is_nan() || pap <= 0.0 {
        return Err(Error::Singular(format!(
            "CG met a direction with pᵀAp = {pap:e} at iteration {k}: the matrix is not SPD, or its condition number exceeds what double precision resolves"
        )));
    }
    Ok(rr / pap)
}

/// r_{k+1} = r_k − α Ap_k (recursive), or b − A x_{k+1} (true residual; it
/// overwrites `ap` with A x_{k+1}).
fn update_residual(
    variant: CgVariant,
    op: &dyn LinearOperator,
    b: &[f64],
    x: &[f64],
    alpha: f64,
    ap: &mut [f64],
    r: &mut [f64],
) {
    match variant {
        CgVariant::TrueResidual => {
            op.apply(x, ap);
            for i in 0..r.len() {
                r[i] = b[i] - ap[i];
            }
        }
        _ => {
            for i in 0..r.len() {
                r[i] -= alpha * ap[i];
            }
        }
    }
}
