//! # `hompm exact`, `hompm trace`, `hompm check`
//!
//! The commands of the oracle (docs/oracle.md): they parse, call
//! [`crate::oracle`] and print. `check` exits 0 when the other code agrees,
//! 1 when it differs (the report is printed first), 2 when its input is
//! unusable. Bad arguments to `exact`, `trace` and `check` (a NaN time, an
//! unknown parameter set, an override a scene lacks, …) are usage errors:
//! one line, exit 2. A refusal by the limits and a run that fails exit 1.
//!
//! One file per command: [`exact`](mod@exact), [`trace`](mod@trace),
//! [`check`](mod@check); the arguments of all three are here.
//!
//! Items: [`ExactArgs`], [`TraceArgs`], [`CheckArgs`], [`MatchArg`],
//! [`exact()`], [`trace()`], [`check()`].

mod check;
mod exact;
mod trace;

pub use check::check;
pub use exact::exact;
pub use trace::trace;

use super::setup_args::SetupArgs;
use crate::error::Error;
use crate::oracle::input::Format;
use clap::ValueEnum;
use std::path::PathBuf;

/// Arguments of `hompm exact`.
#[derive(clap::Args, Debug)]
pub struct ExactArgs {
    /// The scene, its parameters and (with --cells and --ppc) its particle
    /// layout; the method options are ignored.
    #[command(flatten)]
    setup: SetupArgs,
    /// The time t.
    #[arg(long, allow_negative_numbers = true)]
    time: f64,
    /// Initial positions X (2D: x,y pairs, flattened); default: the
    /// particles of --cells and --ppc.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    at: Vec<f64>,
    /// The body force as MLS paper Eq. (42) prints it (π, not π²).
    #[arg(long)]
    as_printed: bool,
    /// Print JSON.
    #[arg(long, conflicts_with = "csv")]
    json: bool,
    /// Print CSV.
    #[arg(long)]
    csv: bool,
}

/// Arguments of `hompm trace`.
#[derive(clap::Args, Debug)]
pub struct TraceArgs {
    /// The run's setup (as `hompm run`); --steps is the number of steps run.
    #[command(flatten)]
    setup: SetupArgs,
    /// Trace steps 1, 1 + N, 1 + 2N, … and the last.
    #[arg(long, default_value_t = 1, value_parser = super::args::count)]
    every: usize,
    /// Print JSON.
    #[arg(long, conflicts_with = "csv")]
    json: bool,
    /// Print CSV (`step,time,equation,index,value`).
    #[arg(long)]
    csv: bool,
}

/// `--match`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MatchArg {
    /// By the `id` column if present, else by initial position.
    Auto,
    /// By the `id` column (0-based; 1..=n read as 1-based).
    Id,
    /// By initial position, nearest within a quarter spacing.
    X0,
    /// Row k is hompm's particle k (a file with neither id nor x0).
    Order,
}

/// Arguments of `hompm check`.
#[derive(clap::Args, Debug)]
pub struct CheckArgs {
    /// The run's setup, as the other code ran it.
    #[command(flatten)]
    setup: SetupArgs,
    /// The other code's particles at the end (CSV with a header, or JSON),
    /// or its trace in `hompm trace`'s schema.
    #[arg(long, required_unless_present = "convergence")]
    input: Option<PathBuf>,
    /// Several resolutions of the other code: the observed order per field
    /// (cells from each file's `# cells:` line or JSON `cells`, or --cells).
    #[arg(long, num_args = 1.., conflicts_with = "input")]
    convergence: Vec<PathBuf>,
    /// How --input is read: auto (binary formats by their first bytes,
    /// text ones by their first text), csv, json, lammps-dump, vtk,
    /// vtk-xml, npy or npz.
    #[arg(long, value_enum, default_value_t = Format::Auto)]
    format: Format,
    /// Where the other code's body starts: A (1D) or A,B (2D), subtracted
    /// from the file's x0 and x before matching (the MLS paper's code puts
    /// its body at 2h: --origin 0.25 on 8 cells).
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    origin: Vec<f64>,
    /// The timestep block of a LAMMPS dump file to read (default: the last).
    #[arg(long = "dump-step", value_parser = clap::value_parser!(u64))]
    dump_step: Option<u64>,
    /// Column names: ours=theirs,… (e.g. x0_x=X0,u_x=ux).
    #[arg(long, default_value = "")]
    columns: String,
    /// How particles are matched.
    #[arg(long = "match", value_enum, default_value_t = MatchArg::Auto)]
    match_by: MatchArg,
    /// Relative tolerance (a value fails only if both tolerances fail).
    #[arg(long, default_value_t = crate::oracle::check::DEFAULT_RTOL, allow_negative_numbers = true)]
    rtol: f64,
    /// Absolute tolerance.
    #[arg(long, default_value_t = crate::oracle::check::DEFAULT_ATOL, allow_negative_numbers = true)]
    atol: f64,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

/// An error in the arguments of an oracle command is a usage error (exit
/// 2, docs/oracle.md); a refusal by the limits, an input-file error and the
/// failures of a run keep their own kind.
fn as_usage(e: Error) -> Error {
    match e {
        Error::OverLimit { .. } | Error::Input(_) | Error::Usage(_) => e,
        other => Error::Usage(other.to_string()),
    }
}
