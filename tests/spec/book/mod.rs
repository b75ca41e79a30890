//! Tests of one part of the specification; see tests/spec/main.rs.

mod golden_basis;
mod golden_book;
mod spec_conventions;
mod spec_musl_step;
mod spec_natural_knots;
mod spec_pmultigrid;
