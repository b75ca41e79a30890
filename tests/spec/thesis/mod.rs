//! Tests of one part of the specification; see tests/spec/main.rs.

mod golden_facts_and_orders;
mod golden_thesis;
mod spec_richardson;
