//! # The oracle: another MPM code checks itself against the specification
//!
//! The floor between the studies and the command line. It holds what an
//! author of a faster MPM code needs to compare that code with hompm, the
//! command line only parsing and printing (docs/oracle.md is the guide):
//!
//! - [`setup`]: the run another code can match: named parameter sets with
//!   overrides of every physical parameter, the discretisation, the
//!   solver's stopping rule; `hompm run`, `trace` and `check` share it;
//! - [`exact`]: the exact and manufactured fields at any point and time
//!   (thesis Eqs. 4.1–4.2, book Eqs. 4.50–4.52, MLS paper Eqs. 38–42);
//! - [`run`]: a setup run under the stability monitor, with an observer
//!   inside each step;
//! - [`equations`]: the traced quantities' keys and citations;
//! - [`trace`]: the quantities of each numbered equation of the 1D step
//!   (book Eqs. 4.5–4.18), recorded by a [`StepObserver`](crate::mpm::musl::StepObserver);
//! - [`columns`]: the column schema of the particles, declared once;
//! - [`input`]: the other code's particles or trace, in CSV or JSON,
//!   read strictly ([`input_json`] for JSON, [`input_dump`] for LAMMPS-style
//!   dump files, [`input_vtk`] and [`input_vtk_xml`] for VTK, [`input_npy`]
//!   and [`npy_header`] for NumPy, [`binary`] for their raw numbers) into a [`table`] of named
//!   columns;
//! - [`provenance`]: whether a file is of the run it is compared with;
//! - [`state`]: hompm's particles as the check's table, and the matching
//!   of the other code's particles;
//! - [`check`](mod@check): the comparison, field by field and equation by
//!   equation, with a verdict, and the rule of when it may say "agrees";
//! - [`compare`]: the arithmetic of a comparison (tolerances scaled by
//!   each field's size, overflow-free errors, traces equation by equation);
//! - [`convergence`](mod@convergence): observed orders over resolutions;
//! - [`visibility`]: what the tolerance can see at a check's Δt.
//!
//! Items: [`columns`], [`setup`], [`exact`], [`run`], [`equations`], [`trace`], [`input`], [`input_json`], [`input_dump`], [`input_vtk`], [`input_vtk_xml`], [`input_npy`], [`npy_header`], [`binary`], [`table`], [`provenance`], [`state`],
//! [`check`](mod@check), [`compare`], [`convergence`](mod@convergence), [`visibility`],
//! [`method_label_1d`], [`conventions_suffix`], [`INPUT_MEMORY_FACTOR`].

pub mod binary;
pub mod check;
pub mod columns;
pub mod compare;
pub mod convergence;
pub mod equations;
pub mod exact;
pub mod input;
pub mod input_dump;
pub mod input_json;
pub mod input_npy;
pub mod input_vtk;
pub mod input_vtk_xml;
pub mod npy_header;
pub mod provenance;
pub mod run;
pub mod setup;
pub mod state;
pub mod table;
pub mod trace;
pub mod visibility;

use crate::mpm::mapping::{ConsistentSolver, MassMatrix};
use crate::scenes::Discretisation;

/// Bytes of memory per byte of an input file while it is parsed (the text,
/// the parsed columns and hompm's copy): a file larger than the memory
/// limit divided by this is refused before it is read.
pub const INPUT_MEMORY_FACTOR: u64 = 4;

/// A 1D discretisation in words: `BSMPM-p2 with direct mapping and lumped
/// mass`.
pub fn method_label_1d(d: &Discretisation) -> String {
    let mapping = d.velocity_mapping.info().label;
    let mass = match d.mass {
        MassMatrix::Lumped => "lumped mass".to_string(),
        MassMatrix::Consistent(ConsistentSolver::Cholesky) => "consistent mass (Cholesky)".into(),
        MassMatrix::Consistent(ConsistentSolver::Richardson {
            tolerance,
            residual,
        }) => format!(
            "consistent mass (Richardson to {tolerance:e}, residual over ‖{}‖)",
            residual.symbol()
        ),
    };
    format!(
        "{} with {mapping} and {mass}{}",
        d.method.label(),
        conventions_suffix(&d.conventions, 1)
    )
}

/// " (--scheme usl --positions grid)" for conventions other than the
/// dimension's default, so that a verdict names what it compared with;
/// empty for the default.
pub fn conventions_suffix(c: &crate::mpm::conventions::Conventions, dimension: usize) -> String {
    let flags = c.flags(dimension);
    if flags.is_empty() {
        String::new()
    } else {
        format!(" ({})", flags.join(" "))
    }
}
