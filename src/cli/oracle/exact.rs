//! # `hompm exact`
//!
//! The exact fields of a setup (`oracle::exact::exact_table`), printed as
//! a table, CSV or JSON.
//!
//! Items: [`exact`].

use super::super::args::SceneArg;
use super::super::limits::Limits;
use super::super::{json, Output};
use super::{as_usage, ExactArgs};
use crate::error::Result;
use crate::oracle::exact::{exact_table, ExactTable};
use crate::oracle::setup::Setup;

/// `hompm exact`: every failure is in its arguments (exit 2) but a
/// refusal by the limits.
pub fn exact(a: ExactArgs, limits: &Limits) -> Result<Output> {
    exact_fields(a, limits).map_err(as_usage)
}

fn exact_fields(a: ExactArgs, limits: &Limits) -> Result<Output> {
    crate::error::finite("--time", a.time)?;
    let scene = a.setup.scene()?;
    let mut setup = a.setup.clone();
    // The method options do not matter for the exact solution; a 2D scene
    // builds its layout with any method.
    setup.method = if scene == SceneArg::AlignedVibration {
        super::super::args::MethodArg::MPM
    } else {
        setup.method
    };
    let s = setup.setup()?;
    let points = match &s {
        Setup::OneD(_) => a.at.len(),
        Setup::TwoD(_) => a.at.len() / 2,
    };
    let n = if a.at.is_empty() {
        let c = setup.cells()? as f64;
        match &s {
            Setup::OneD(_) => c * setup.ppc() as f64,
            Setup::TwoD(_) => c * c * setup.ppc() as f64,
        }
    } else {
        points as f64
    };
    limits.check_memory(
        || format!("the exact fields at {n:.0} points"),
        n * 400.0,
        "columns",
    )?;
    let at = (!a.at.is_empty()).then_some(a.at.as_slice());
    let ExactTable { columns, meta } = exact_table(&s, at, a.time, a.as_printed)?;
    if a.json {
        let mut doc = serde_json::Map::new();
        doc.insert("time".into(), serde_json::json!(a.time));
        doc.insert("exact_solution".into(), meta);
        let cols: serde_json::Map<String, serde_json::Value> = columns
            .into_iter()
            .map(|(k, v)| (k, serde_json::json!(v)))
            .collect();
        doc.insert("fields".into(), serde_json::Value::Object(cols));
        return Ok(Output::text(json::strict(&doc)?));
    }
    let mut out = format!(
        "# time: {:e}\n# kind: {}\n",
        a.time,
        meta["kind"].as_str().unwrap_or("")
    );
    if !a.csv {
        if let Some(f) = meta["formulas"].as_object() {
            for (k, v) in f {
                out.push_str(&format!("# {k}: {}\n", v.as_str().unwrap_or("")));
            }
        }
    }
    out.push_str(
        &columns
            .iter()
            .map(|(k, _)| k.as_str())
            .collect::<Vec<_>>()
            .join(","),
    );
    out.push('\n');
    let rows = columns.first().map_or(0, |(_, c)| c.len());
    for r in 0..rows {
        let line: Vec<String> = columns.iter().map(|(_, c)| format!("{:e}", c[r])).collect();
        out.push_str(&line.join(","));
        out.push('\n');
    }
    Ok(Output::text(out))
}
