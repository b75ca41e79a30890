//! # The command line, as a library function
//!
//! `hompm::cli::run(args)` is the whole of `hompm`: the binary only prints
//! what it returns. Reviewers check published numbers (`hompm table <id>`,
//! `hompm reproduce`); authors of faster MPM codes use the oracle commands
//! (`basis`, `mass`, `reconstruct`, `run`) with `--json`.
//!
//! The contract (issue #13, docs/conventions.md "The command line"):
//! - clap parses every argument: enumerated options are [`clap::ValueEnum`]s
//!   (`--help` lists the choices), lists are comma-delimited, and negative
//!   numbers reach the range checks;
//! - every command validates its arguments and estimates its memory and run
//!   time ([`limits`]) before it does any work, and refuses what exceeds
//!   `--max-memory` or `--max-seconds` in one line;
//! - a failure is an [`Error`] (exit code 1; [`Error::Usage`] exits 2), and
//!   [`one_line`] renders it with control characters escaped;
//! - JSON never carries `null` for a number (`json`).
//!
//! Items: [`run`], [`Output`], [`one_line`], [`exit_code`], [`Cli`], and one
//! module per command: `basis`, `mass`, `reconstruct`, `scene` (`hompm
//! run`), `oracle` (`exact`, `trace`, `check`), `table`, `reproduce`;
//! `setup_args` holds the options `run`, `trace` and `check` share.

mod args;
mod basis;
mod json;
pub mod limits;
mod mass;
mod oracle;
mod reconstruct;
mod reproduce;
mod scene;
mod setup_args;
mod table;

pub use args::{MappingArg, MassArg, MethodArg, ReconstructionArg, SceneArg, SolverArg};

use crate::error::{Error, Result};
use clap::{Parser, Subcommand};
use std::ffi::OsString;

/// What a successful command hands back.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Output {
    /// Text (or JSON) for stdout.
    pub stdout: String,
    /// Warnings for stderr, one line each (also recorded in `--json`
    /// output where the command has a warnings field).
    pub warnings: Vec<String>,
    /// A command that wrote its output and still failed (`reproduce` when a
    /// number marked reproduced no longer reproduces): print `stdout`, then
    /// this error, and exit non-zero.
    pub failure: Option<Error>,
}

impl Output {
    fn text(stdout: String) -> Self {
        Self {
            stdout,
            ..Self::default()
        }
    }
}

/// The command line of `hompm`.
#[derive(Parser, Debug)]
#[command(
    name = "hompm",
    version,
    about = "An executable specification of the high-order Material Point Method"
)]
pub struct Cli {
    /// Refuse commands whose estimated memory exceeds this (e.g. 512MiB,
    /// 4GiB, 16GB, or bytes).
    #[arg(long, global = true, default_value = "4GiB", value_parser = limits::parse_bytes)]
    pub max_memory: u64,
    /// Refuse commands whose estimated run time exceeds this many seconds.
    #[arg(long, global = true, default_value_t = 3600.0, value_parser = limits::parse_seconds)]
    pub max_seconds: f64,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// B-spline basis values (and derivatives) at points: book Eqs. (4.19)-(4.23).
    Basis(basis::BasisArgs),
    /// Mass matrix of degree p on N uniform spans of [0,1] (ρ = 1): size, spectrum and a
    /// solve of M a = M·(−9.81·1). Book Eqs. (4.2), (4.53)–(4.62); thesis §7.2.
    Mass(mass::MassArgs),
    /// Reconstruct a function from scattered data: TLS (book Eqs. 4.26-4.37), cubic splines
    /// (thesis §7.1) or MLS (MLS paper Eqs. 6-17). Prints values at --at, cell integrals and κ(D).
    Reconstruct(reconstruct::ReconstructArgs),
    /// Run a 1D MPM scene and print the final particle state and diagnostics (MUSL,
    /// book §4.2.2), watched by the stability monitor (mpm::monitor).
    Run(scene::RunArgs),
    /// The exact or manufactured fields of a scene at points and a time (thesis
    /// Eqs. 4.1-4.2, MLS paper Eqs. 38-42), for another code to compare with.
    Exact(oracle::ExactArgs),
    /// Run a 1D scene and print the quantities of each numbered equation of the
    /// step (book Eqs. 4.5-4.18) at the traced steps (docs/oracle.md).
    Trace(oracle::TraceArgs),
    /// Check another code's particles (or trace) against hompm's run of the same
    /// setup: differences per field, errors against the exact solution, the
    /// first equation that differs, a verdict. Exit 0 agree, 1 differ, 2 bad input.
    Check(oracle::CheckArgs),
    /// Published and computed values of one table, with deviation and status.
    Table(table::TableArgs),
    /// Run every registered table and the studies; write report.md, report.json,
    /// reproduction.md and charts; fail if a number marked reproduced in
    /// golden/reproduced.json no longer reproduces.
    Reproduce(reproduce::ReproduceArgs),
}

/// Runs `hompm` on `args` (without the program name): the whole command
/// line as a function. Never panics on any input; see the module docs for
/// the contract.
pub fn run<I, T>(args: I) -> Result<Output>
where
    I: IntoIterator<Item = T>,
    T: Into<OsString>,
{
    let argv = std::iter::once(OsString::from("hompm")).chain(args.into_iter().map(Into::into));
    let cli = match Cli::try_parse_from(argv) {
        Ok(cli) => cli,
        Err(e) => return clap_outcome(e),
    };
    let limits = limits::Limits {
        max_memory: cli.max_memory,
        max_seconds: cli.max_seconds,
    };
    match cli.command {
        Command::Basis(a) => basis::basis(a, &limits),
        Command::Mass(a) => mass::mass(a, &limits),
        Command::Reconstruct(a) => reconstruct::reconstruct(a, &limits),
        Command::Run(a) => scene::run_scene(a, &limits),
        Command::Exact(a) => oracle::exact(a, &limits),
        Command::Trace(a) => oracle::trace(a, &limits),
        Command::Check(a) => oracle::check(a, &limits),
        Command::Table(a) => table::table(a),
        Command::Reproduce(a) => reproduce::reproduce(a),
    }
}

/// Help and version are successes; every other clap outcome is
/// [`Error::Usage`] with clap's first paragraph (its message, without the
/// usage block), or a plain sentence when no subcommand was given.
fn clap_outcome(e: clap::Error) -> Result<Output> {
    use clap::error::ErrorKind;
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => Ok(Output::text(e.to_string())),
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand | ErrorKind::MissingSubcommand => {
            Err(Error::Usage(
                "a command is required: basis, mass, reconstruct, run, exact, trace, check, table or reproduce (see hompm --help)"
                    .into(),
            ))
        }
        _ => {
            let text = e.to_string();
            let message = text.split("\n\n").next().unwrap_or(&text);
            let message = message.strip_prefix("error: ").unwrap_or(message);
            // clap indents its own continuation lines ("\n  [possible
            // values: …]"); a newline inside a user's value stays, and is
            // escaped by `one_line`.
            Err(Error::Usage(message.trim_end().replace("\n  ", " ")))
        }
    }
}

/// `s` on one line: every control character (newline, tab, escape, …)
/// written as its Rust escape (`\n`, `\t`, `\u{1b}`), so an error never
/// spans lines or drives a terminal.
pub fn one_line(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        // Control characters, and the Unicode line and paragraph
        // separators a terminal also breaks at (U+2028, U+2029).
        if c.is_control() || (c.is_whitespace() && c != ' ') {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

/// The process exit code for an error: 2 for a usage error (as clap), 1
/// for everything else.
pub fn exit_code(e: &Error) -> u8 {
    match e {
        Error::Usage(_) | Error::Input(_) => 2,
        _ => 1,
    }
}
