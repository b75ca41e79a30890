//! # The hompm command line
//!
//! Reviewers check published numbers (`hompm table <id>`, `hompm reproduce`);
//! authors of faster MPM codes use the oracle commands (`hompm basis`, …) with
//! `--json`. Bad input gives one line on stderr and a non-zero exit code.

use clap::{Parser, Subcommand};
use hompm::error::{Error, Result};
use hompm::spline::KnotVector;
use hompm::tables::{self, RunOptions};
use serde::Serialize;
use std::io::Write;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "hompm",
    version,
    about = "An executable specification of the high-order Material Point Method"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// B-spline basis values (and derivatives) at points: book Eqs. (4.19)-(4.23).
    Basis {
        /// Polynomial degree p.
        #[arg(long)]
        degree: usize,
        /// Comma-separated knots, non-decreasing.
        #[arg(long, allow_hyphen_values = true)]
        knots: String,
        /// Comma-separated evaluation points inside the domain.
        #[arg(long, allow_hyphen_values = true)]
        at: String,
        /// Also print first derivatives.
        #[arg(long)]
        derivatives: bool,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Published and computed values of one table, with deviation and status.
    Table {
        /// Table id (see --list).
        id: Option<String>,
        /// List the registered table ids.
        #[arg(long)]
        list: bool,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Run every registered table and print how many published numbers reproduce.
    Reproduce {
        /// Only these table ids.
        #[arg(long, num_args = 1..)]
        only: Vec<String>,
        /// Reduced sizes (smoke test).
        #[arg(long)]
        quick: bool,
    },
}

fn parse_list(what: &str, text: &str) -> Result<Vec<f64>> {
    text.split(',')
        .map(|s| {
            let s = s.trim();
            s.parse::<f64>()
                .map_err(|_| Error::InvalidArgument(format!("{what}: '{s}' is not a number")))
        })
        .collect()
}

#[derive(Serialize)]
struct BasisJson {
    degree: usize,
    knots: Vec<f64>,
    points: Vec<f64>,
    values: Vec<Vec<f64>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    derivatives: Option<Vec<Vec<f64>>>,
}

fn print(out: &str) {
    let mut stdout = std::io::stdout().lock();
    let _ = stdout.write_all(out.as_bytes());
    let _ = stdout.flush();
}

fn to_json<T: Serialize>(value: &T) -> Result<String> {
    serde_json::to_string_pretty(value)
        .map(|s| s + "\n")
        .map_err(|e| Error::InvalidArgument(format!("cannot write JSON: {e}")))
}

fn basis(degree: usize, knots: &str, at: &str, derivatives: bool, json: bool) -> Result<String> {
    let knots = parse_list("--knots", knots)?;
    let points = parse_list("--at", at)?;
    let kv = KnotVector::new(knots.clone(), degree)?;
    let mut values = Vec::new();
    let mut ders = Vec::new();
    for &x in &points {
        values.push(kv.dense_values(x)?);
        if derivatives {
            ders.push(kv.dense_derivatives(x)?);
        }
    }
    let doc = BasisJson {
        degree,
        knots,
        points,
        values,
        derivatives: derivatives.then_some(ders),
    };
    if json {
        return to_json(&doc);
    }
    let mut s = format!(
        "degree {} on {} knots: {} basis functions, domain [{}, {}]\n",
        degree,
        doc.knots.len(),
        kv.num_basis(),
        kv.domain().0,
        kv.domain().1
    );
    for (k, x) in doc.points.iter().enumerate() {
        let row: Vec<String> = doc.values[k].iter().map(|v| format!("{v:.12}")).collect();
        s.push_str(&format!("x = {x}: phi = [{}]\n", row.join(", ")));
        if let Some(d) = &doc.derivatives {
            let row: Vec<String> = d[k].iter().map(|v| format!("{v:.12}")).collect();
            s.push_str(&format!("        dphi = [{}]\n", row.join(", ")));
        }
    }
    Ok(s)
}

fn table(id: Option<String>, list: bool, json: bool) -> Result<String> {
    if list || id.is_none() {
        let mut s = String::new();
        for spec in tables::registry() {
            let p = tables::Published::parse(spec.id, spec.published_json)?;
            s.push_str(&format!("{:<20} {}\n", spec.id, p.title));
        }
        return Ok(s);
    }
    let id = id.unwrap_or_default();
    let spec = tables::find(&id)?;
    let report = tables::run(&spec, &RunOptions::default())?;
    if json {
        to_json(&report)
    } else {
        Ok(report.render_text())
    }
}

fn reproduce(only: Vec<String>, quick: bool) -> Result<String> {
    let options = RunOptions { quick };
    let mut s = String::new();
    let (mut rep, mut total) = (0, 0);
    for spec in tables::registry() {
        if !only.is_empty() && !only.iter().any(|o| o == spec.id) {
            continue;
        }
        let report = tables::run(&spec, &options)?;
        let (r, t) = report.counts();
        s.push_str(&format!("{:<20} {r:>4} of {t:>4} reproduced\n", spec.id));
        rep += r;
        total += t;
    }
    for o in &only {
        tables::find(o)?;
    }
    s.push_str(&format!("{rep} of {total} published numbers reproduced\n"));
    Ok(s)
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(
                e.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            ) {
                print(&e.to_string());
                return if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
                    ExitCode::from(2)
                } else {
                    ExitCode::SUCCESS
                };
            }
            let text = e.to_string();
            let first = text.lines().next().unwrap_or("error: invalid arguments");
            eprintln!("{first}");
            return ExitCode::from(2);
        }
    };
    let result = match cli.command {
        Command::Basis {
            degree,
            knots,
            at,
            derivatives,
            json,
        } => basis(degree, &knots, &at, derivatives, json),
        Command::Table { id, list, json } => table(id, list, json),
        Command::Reproduce { only, quick } => reproduce(only, quick),
    };
    match result {
        Ok(out) => {
            print(&out);
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
