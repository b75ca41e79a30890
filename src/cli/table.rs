//! # `hompm table`: published and computed values side by side
//!
//! Items: [`TableArgs`], [`table`].

use super::{json, Output};
use crate::error::Result;
use crate::tables::{self, RunOptions};
use serde::Serialize;

/// Arguments of `hompm table`.
#[derive(clap::Args, Debug)]
pub struct TableArgs {
    /// Table id (see --list).
    id: Option<String>,
    /// List the registered table ids.
    #[arg(long)]
    list: bool,
    /// Print JSON.
    #[arg(long)]
    json: bool,
    /// The largest sizes, as `hompm reproduce --full` runs them (the tables
    /// whose setup it changes: mls-aligned, mls-convergence-study).
    #[arg(long)]
    full: bool,
}

#[derive(Serialize)]
struct Listed {
    id: &'static str,
    title: String,
}

/// `hompm table [ID] [--list] [--json] [--full]`: without an id, or with --list, the
/// registered ids and titles. In table JSON, `null` means "not published"
/// or "not computed" (DESIGN.md); a computed number that is not finite is
/// an error, never a `null`.
pub fn table(a: TableArgs) -> Result<Output> {
    let id = match (&a.id, a.list) {
        (Some(id), false) => id,
        _ => return list(a.json),
    };
    let spec = tables::find(id)?;
    let options = RunOptions {
        quick: false,
        full: a.full,
    };
    let report = tables::run(&spec, &options)?;
    for (r, row) in report.computed.iter().enumerate() {
        for (c, v) in row.iter().enumerate() {
            if let Some(v) = v {
                crate::error::finite_named(*v, || format!("{id} computed value ({r}, {c})"))?;
            }
        }
    }
    let stdout = if a.json {
        json::pretty(&report)?
    } else {
        report.render_text()
    };
    Ok(Output::text(stdout))
}

fn list(as_json: bool) -> Result<Output> {
    let mut listed = Vec::new();
    for spec in tables::registry() {
        let p = tables::Published::parse(spec.id, spec.published_json)?;
        listed.push(Listed {
            id: spec.id,
            title: p.title,
        });
    }
    if as_json {
        return Ok(Output::text(json::strict(&listed)?));
    }
    let lines: String = listed
        .iter()
        .map(|l| format!("{:<20} {}\n", l.id, l.title))
        .collect();
    Ok(Output::text(lines))
}
