//! # `hompm check`
//!
//! Another code's output against hompm's run of the same setup
//! (`oracle::check`), or several resolutions' outputs against hompm's
//! observed orders (`oracle::convergence`). Exit 0 agrees, 1 differs (the
//! report is printed first), 2 unusable input.
//!
//! Items: [`check`].

use super::super::limits::Limits;
use super::super::{json, Output};
use super::{as_usage, CheckArgs, MatchArg};
use crate::error::{Error, Result};
use crate::oracle::check::{check as compare, CheckOptions, MatchBy};
use crate::oracle::compare::sci;
use crate::oracle::convergence::convergence;
use crate::oracle::input::{parse_input_as, read_input, ColumnMap, Input};
use crate::oracle::run::reference;
use crate::oracle::setup::Setup;
use crate::oracle::trace::{header_1d, header_2d};
use crate::oracle::visibility::time_resolution;

/// Reads and parses one input file.
fn read(path: &std::path::Path, a: &CheckArgs, limits: &Limits) -> Result<(Input, Vec<String>)> {
    let bytes = read_input(path, limits.max_memory)?;
    let (input, ignored) = parse_input_as(
        &bytes,
        a.format,
        a.dump_step,
        &ColumnMap::parse(&a.columns)?,
        a.setup.two_d(),
        limits.max_memory / crate::oracle::INPUT_MEMORY_FACTOR,
    )?;
    Ok((translated(input, &a.origin, a.setup.two_d())?, ignored))
}

/// `--origin`: the file's positions moved so that its body starts where
/// hompm's does (0, or the strip's 2h). The displacement, already derived
/// from the file's own coordinates, is unchanged.
fn translated(input: Input, origin: &[f64], two_d: bool) -> Result<Input> {
    if origin.is_empty() {
        return Ok(input);
    }
    let axes: &[(&[&str], usize)] = if two_d {
        &[(&["x0_x", "x_x"], 0), (&["x0_y", "x_y"], 1)]
    } else {
        &[(&["x0", "x"], 0)]
    };
    if origin.len() != axes.len() || origin.iter().any(|v| !v.is_finite()) {
        return Err(Error::Usage(format!(
            "--origin takes {} finite number{} in this dimension, got {origin:?}",
            axes.len(),
            if axes.len() == 1 { "" } else { "s" }
        )));
    }
    let Input::Particles(mut table) = input else {
        return Err(Error::Usage(
            "--origin applies to a file of particles, not to a trace".into(),
        ));
    };
    for (columns, axis) in axes {
        for (name, values) in table.columns.iter_mut() {
            if columns.contains(&name.as_str()) {
                values.iter_mut().for_each(|v| *v -= origin[*axis]);
            }
        }
    }
    Ok(Input::Particles(table))
}

/// `hompm check`.
pub fn check(a: CheckArgs, limits: &Limits) -> Result<Output> {
    let options = CheckOptions {
        rtol: a.rtol,
        atol: a.atol,
        match_by: match a.match_by {
            MatchArg::Auto => MatchBy::Auto,
            MatchArg::Id => MatchBy::Id,
            MatchArg::X0 => MatchBy::X0,
            MatchArg::Order => MatchBy::Order,
        },
    };
    for (name, v) in [("--rtol", a.rtol), ("--atol", a.atol)] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(Error::Usage(format!(
                "{name} must be finite and at least 0, got {v}"
            )));
        }
    }
    if !a.convergence.is_empty() {
        return check_convergence(&a, &options, limits);
    }
    let Some(path) = a.input.as_deref() else {
        return Err(Error::Usage(
            "--input FILE or --convergence FILE… is required".into(),
        ));
    };
    let setup = a.setup.setup().map_err(as_usage)?;
    a.setup.check_limits(&setup, limits, 0.0)?;
    let (input, ignored) = read(path, &a, limits)?;
    let only = match &input {
        Input::Trace(t) => {
            let mut ours = match &setup {
                Setup::OneD(s) => header_1d(s)?,
                Setup::TwoD(s) => header_2d(s)?,
            };
            name_default_conventions(&mut ours, &setup)?;
            crate::oracle::check::check_header(&t.header, &ours)?;
            Some(t.steps.iter().map(|s| s.step).collect())
        }
        Input::Particles(_) => None,
    };
    let (state, ours) = reference(&setup, only)?;
    let mut report = compare(&setup, &state, &input, ours.as_ref(), &options)?;
    if report.agrees && matches!(input, Input::Particles(_)) {
        let compared = report.compared_columns();
        if let Some(r) = time_resolution(&setup, &state, &compared, &options.tolerance())? {
            report = report.with_time_resolution(r);
        }
    }
    let mut warnings = Vec::new();
    if !ignored.is_empty() {
        let shown: Vec<&str> = ignored.iter().take(10).map(String::as_str).collect();
        let more = ignored.len().saturating_sub(shown.len());
        warnings.push(format!(
            "ignored columns that are not hompm's: {}{} (map them with --columns ours=theirs)",
            shown.join(", "),
            if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            }
        ));
    }
    let stdout = if a.json {
        json::strict(&report)?
    } else {
        report_text(&report)
    };
    let failure = (!report.agrees).then(|| {
        Error::Differs(
            report
                .verdict
                .lines()
                .next()
                .unwrap_or("differs from hompm")
                .to_string(),
        )
    });
    Ok(Output {
        stdout,
        warnings,
        failure,
    })
}

/// The report in words and a table of fields, in the order compared.
fn report_text(r: &crate::oracle::check::CheckReport) -> String {
    let mut out = format!(
        "{}\n\nhompm: {}; {} particles matched by {}; exact solution at t = {:e}\n",
        r.verdict, r.method, r.particles, r.matched_by, r.time
    );
    out.push_str(&format!(
        "{:<8} {:>10} {:>10} {:>10} {:>9} {:>9} {:>12} {:>12}\n",
        "field", "max abs", "max rel", "tol abs", "particle", "failures", "RMS yours", "RMS hompm"
    ));
    for name in &r.compared_fields {
        let Some(f) = r.fields.get(name) else {
            continue;
        };
        let (ry, rh) = f.rms_exact.map_or(("-".into(), "-".into()), |p| {
            (sci(p.yours, 4), sci(p.hompm, 4))
        });
        out.push_str(&format!(
            "{name:<8} {:>10} {:>10} {:>10} {:>9} {:>9} {ry:>12} {rh:>12}\n",
            sci(f.max_abs, 3),
            sci(f.max_rel, 3),
            sci(f.atol_abs, 3),
            f.worst_particle,
            f.failures
        ));
    }
    if let Some(d) = &r.first_difference {
        out.push_str(&format!(
            "first difference: step {}, {} ({}), {} {} (absolute tolerance there {:.3e})\n",
            d.step, d.equation, d.citation, d.index_kind, d.index, d.atol_abs
        ));
    }
    out
}

/// `hompm check --convergence`.
fn check_convergence(a: &CheckArgs, o: &CheckOptions, limits: &Limits) -> Result<Output> {
    let mut runs = Vec::new();
    let listed = &a.setup.cells;
    if listed.len() > 1 && listed.len() != a.convergence.len() {
        return Err(Error::Usage(format!(
            "--cells lists {} resolutions for {} files; give one per file, in the files' order",
            listed.len(),
            a.convergence.len()
        )));
    }
    let explicit = listed.len() == a.convergence.len() && listed.len() > 1;
    for (k, path) in a.convergence.iter().enumerate() {
        let (input, _) = read(path, a, limits)?;
        let Input::Particles(table) = &input else {
            return Err(Error::Input(format!(
                "{}: --convergence reads final particles, not traces",
                path.display()
            )));
        };
        let cells = if explicit {
            listed[k]
        } else {
            let text = table.metadata.get("cells").ok_or_else(|| {
                Error::Input(format!(
                    "{} names no cells (a '# cells: N' line or a JSON 'cells'); or list them with --cells N1,N2,…",
                    path.display()
                ))
            })?;
            super::super::args::count(text.trim_matches('"'))
                .map_err(|e| Error::Input(format!("{}: cells {e}", path.display())))?
        };
        let setup = a.setup.setup_with_cells(cells).map_err(as_usage)?;
        a.setup.check_limits(&setup, limits, 0.0)?;
        let length = match &setup {
            Setup::OneD(s) => s.scene.length(),
            Setup::TwoD(s) => s.scene.length,
        };
        let (state, _) = reference(&setup, None)?;
        runs.push((setup, state, input, cells, length));
    }
    runs.sort_by_key(|r| r.3);
    let report = convergence(&runs, o)?;
    let stdout = if a.json {
        json::strict(&report)?
    } else {
        format!("{}\n", report.verdict)
    };
    let not_held: Vec<String> = report
        .fields
        .iter()
        .filter(|(_, f)| f.verdict != crate::oracle::convergence::HOLDS)
        .map(|(name, f)| format!("{name} {}", f.verdict))
        .collect();
    Ok(Output {
        stdout,
        warnings: Vec::new(),
        failure: (!not_held.is_empty()).then(|| {
            Error::Differs(format!(
                "the observed order does not hold in every field: {}",
                not_held.join("; ")
            ))
        }),
    })
}

/// A trace header leaves out the dimension's default conventions (and the
/// aligned vibration's default solution); for the comparison of headers
/// hompm's names them, so that a trace that names others is refused, not
/// compared (issue #36's fuzz).
fn name_default_conventions(
    header: &mut std::collections::BTreeMap<String, serde_json::Value>,
    setup: &Setup,
) -> Result<()> {
    let value = crate::oracle::setup::to_json(&setup.conventions())?;
    match setup {
        Setup::OneD(_) => {
            if let Some(serde_json::Value::Object(d)) = header.get_mut("discretisation") {
                d.entry("conventions").or_insert(value);
            }
        }
        Setup::TwoD(s) => {
            header.entry("conventions".to_string()).or_insert(value);
            if let Some(serde_json::Value::Object(scene)) = header.get_mut("scene") {
                let form = serde_json::Value::String(s.scene.solution.name().into());
                scene.entry("solution").or_insert(form);
            }
        }
    }
    Ok(())
}
