//! # The 1D material point method
//!
//! One MUSL step with Euler–Cromer time integration, exactly as book §4.2.2
//! (Eqs. 4.5–4.18), TLS paper §3.1 and thesis §3.2 write it, for every variant
//! the seeds compare:
//!
//! - bases ([`grid`]): P1 and P2 Lagrange (thesis §5), dual-domain gradients
//!   (DDMPM, TLS paper §3.3), B-splines of any degree (book §4.3, thesis §6);
//! - mappings of particle data to the grid ([`mapping`]): the direct MPM
//!   mapping (Eqs. 4.5–4.10), Taylor least squares (book §4.4.3, TLS paper
//!   §5.4) and cubic splines (thesis ch. 7);
//! - mass: lumped, or consistent through a sparse Cholesky or the thesis'
//!   Richardson iteration.
//!
//! [`particles`] holds the material points (struct of arrays), [`method`]
//! the variants by their basis, [`settings`] what a run is set up with,
//! [`conventions`] the choices other codes make in the same step (scheme,
//! transfer, positions, body force),
//! [`musl`] the time step, [`workspace`] its buffers, [`diagnostics`] the error measures of the seeds and
//! [`monitor`] the stability monitor of `hompm run`. [`check_time_step`] is
//! the one check of Δt that the 1D step, the 2D step and the FE reference
//! share.

pub mod conventions;
pub mod diagnostics;
pub mod grid;
pub mod mapping;
pub mod method;
pub mod monitor;
pub mod musl;
pub mod particles;
pub mod settings;
pub mod workspace;

/// The time step of a step must be positive and finite: [`Error::NotPositive`](crate::error::Error::NotPositive)
/// naming "the time step" otherwise. The 1D step (`musl`), the 2D step
/// (`mpm2d::step`) and the updated-Lagrangian FE reference (`fem::ulfem`)
/// all check Δt here.
pub fn check_time_step(dt: f64) -> crate::error::Result<()> {
    if dt.is_nan() || dt <= 0.0 || dt.is_infinite() {
        return Err(crate::error::Error::NotPositive {
            what: "the time step".into(),
            value: dt,
        });
    }
    Ok(())
}
