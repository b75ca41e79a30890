//! Tests of one part of the specification; see tests/spec/main.rs.

mod golden_compaction;
mod golden_tls_conservation;
mod golden_tls_example;
mod spec_ddmpm;
