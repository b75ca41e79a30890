//! # Function reconstruction from scattered data
//!
//! MPM knows its fields only at the material points. The seeds reconstruct
//! them before integrating on the grid:
//! - [`least_squares`]: the normal equations D α = B F (book Eqs. 4.26–4.29,
//!   TLS paper Eqs. 10–11) with the condition number of D;
//! - [`taylor`]: the Taylor basis (book Eqs. 4.30–4.32) and Taylor least
//!   squares, conservative or not (book Eqs. 4.33–4.37, TLS paper §5.2–5.3),
//!   with virtual data points or a reduced basis for degenerate cells;
//! - [`cubic_spline`]: natural and not-a-knot cubic-spline interpolation
//!   (thesis §7.1);
//! - [`mls`]: moving least squares shape functions in 1D and 2D (MLS paper
//!   Eqs. 6–17).

pub mod cubic_spline;
pub mod least_squares;
pub mod mls;
pub mod taylor;
