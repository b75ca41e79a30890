//! Tests of one part of the specification; see tests/spec/main.rs.

mod spec_mls_convergence;
mod spec_mpm2d;
mod spec_pu_tls;
mod spec_strip;
mod spec_strip_mls;
mod spec_tls2d_count;
