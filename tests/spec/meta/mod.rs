//! Tests of one part of the specification; see tests/spec/main.rs.

mod deviation_causes;
mod equation_map;
mod extensions;
mod file_lengths;
mod golden_tables;
mod layers;
mod module_docs;
mod registry;
