//! Tests of one part of the specification; see tests/spec/main.rs.

mod properties_bspline;
mod properties_lagrange;
mod properties_mass;
mod properties_mpm;
mod properties_quadrature;
mod properties_reconstruct;
mod properties_ulfem;
mod stability;
