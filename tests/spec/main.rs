//! # The executable specification
//!
//! One test binary, read by seed: `cargo test book::`, `cargo test thesis::`,
//! `cargo test tls::` and `cargo test mls::` run what each document states;
//! `properties::` the property tests that hold for every input; `cli::` the
//! command line as its users meet it; `meta::` the checks that keep the
//! house true (the layers, the module docs, the equation map, the table
//! registry and the recorded causes of every deviation). One binary instead
//! of 31 keeps a clean build short (issue #26); the allocation test stays
//! its own binary (tests/allocations.rs) because it installs a counting
//! global allocator.

mod common;

/// Book (Wobbes, Tielen, Möller, Vuik, Galavi 2019): MUSL, B-splines,
/// condition numbers, CG and p-multigrid, Tables 4.2–4.4.
mod book;
/// Command line: JSON schemas, one-line errors, the oracle and its guide.
mod cli;
/// The house: layers, module docs, equation map, registry, causes.
mod meta;
/// MLS paper (Tran et al.): the 2D engine on the aligned vibration.
mod mls;
/// Properties that hold for every input: bases, quadrature, mass,
/// reconstruction, mappings, the FEM reference, and stability at failure.
mod properties;
/// Speed (issue #39): the lean steps hompm is timed against compute what
/// hompm computes.
mod speed;
/// Thesis (Tielen 2016): Tables 5.1–7.2, Richardson, the text's facts.
mod thesis;
/// TLS paper (Wobbes et al. 2019): TLS, DDMPM, conservation, compaction.
mod tls;
