//! # Finite-element references
//!
//! [`ulfem`]: the updated-Lagrangian FEM (P1 elements that move with the
//! material) the seeds use as the reference for large deformations (thesis
//! §4, TLS paper §6.1, book §4.5).

pub mod ulfem;
