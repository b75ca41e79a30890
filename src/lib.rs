//! # hompm — an executable specification of the high-order Material Point Method
//!
//! hompm implements the equations of four documents (cited by short name):
//! the **book** chapter of Wobbes, Tielen, Möller, Vuik & Galavi (2019), Tielen's
//! MSc **thesis** (2016), the **MLS paper** of Tran et al., and the **TLS paper**
//! of Wobbes et al. (2019). Every public item cites the equation it implements;
//! `docs/equations.md` maps each equation to its code and its test.
//!
//! ## Map of the crate, in data-flow order
//! A lower layer never imports a higher one, nor a module of its own layer;
//! tests/spec/meta/layers.rs holds this order and fails on any `crate::` path that
//! points up.
//!
//! | layer | module | what it holds |
//! |---|---|---|
//! | 0 | [`error`], [`rng`], [`dispatch`], [`placement`] | [`Error`]: every user-facing failure; the seeded generator behind every "random" layout; kernels compiled for the baseline and for AVX2; large arrays started at staggered offsets within the page |
//! | 1 | [`basis`], [`quadrature`] | the [`basis::Basis1d`] interface shared by all 1D bases; Gauss–Legendre rules and the thesis' half-span rule (§7.2) |
//! | 2 | [`spline`], [`lagrange`] | knot vectors, Cox–de Boor (book Eqs. 4.19–4.23), 2D tensor basis; P1 and P2 Lagrange shape functions (thesis §5.1–5.2) |
//! | 3 | [`sparse`] | CSR storage for banded and Kronecker mass matrices |
//! | 4 | [`mass`] | consistent and lumped mass, Kronecker 2D operators, the book's test problem (book Eqs. 4.2–4.4, thesis A.1–A.2) |
//! | 5 | [`solve`] | CG, Richardson, p-multigrid, condition numbers (book §4.6–4.7, thesis §7.2) |
//! | 6 | [`reconstruct`] | least squares, Taylor LS, cubic splines, MLS (book §4.4, TLS §5, thesis §7.1, MLS Eqs. 6–17) |
//! | 7 | [`mpm`] | particles, grid bases, mappings, the MUSL step, diagnostics (book §4.2, TLS §3–5, thesis §3) |
//! | 8 | [`mpm2d`], [`fem`] | 2D MPM, BSMPM and BSMPM with MLS (MLS Eqs. 4–5, 10–41); the updated-Lagrangian FEM reference (thesis §5.1.2, TLS §6.1) |
//! | 9 | [`scenes`] | benchmark problems with named parameter sets |
//! | 10 | [`studies`] | every run behind a table or a chart |
//! | 11 | [`tables`] | the registry of published tables: registrations that call studies |
//! | 12 | [`report`] | renders tables and studies: report.md/json, reproduction.md, charts |
//! | 13 | [`oracle`] | another code checks itself against hompm: exact fields, traces of each equation, `check` with a verdict |
//! | 14 | [`cli`] | the command line as a function, `cli::run(args)`; the binary prints what it returns |
//!

pub mod basis;
pub mod cli;
pub mod dispatch;
pub mod error;
pub mod fem;
pub mod lagrange;
pub mod mass;
pub mod mpm;
pub mod mpm2d;
pub mod oracle;
pub mod placement;
pub mod quadrature;
pub mod reconstruct;
pub mod report;
pub mod rng;
pub mod scenes;
pub mod solve;
pub mod sparse;
pub mod spline;
pub mod studies;
pub mod tables;

pub use error::{Error, Result};
