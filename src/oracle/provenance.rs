//! # Is the file of this run? Header, metadata and steps
//!
//! Before `hompm check` compares a number it makes sure the other code's
//! file is of the run it is compared with (issue #35): a trace's header
//! names the same settings, a file's metadata (`scene`, `cells`, `ppc`,
//! `steps`, `dt`, `time`, and the conventions `scheme`, `transfer`,
//! `positions`, `body-force`, `solution`) are the setup's, and a trace's steps lie in
//! 1..=steps, in order, once each, ending at the last. A file that is not
//! is [`Error::Input`] (exit 2), never compared.
//!
//! Items: [`check_header`], [`check_metadata`], [`check_steps`].

use super::setup::Setup;
use super::table::short;
use super::trace::{Trace, TraceStep};
use crate::error::{Error, Result};
use std::collections::BTreeMap;

/// Checks a trace's header against hompm's: every setting both name must
/// agree (numbers to 1e-12 relative).
pub fn check_header(
    theirs: &BTreeMap<String, serde_json::Value>,
    ours: &BTreeMap<String, serde_json::Value>,
) -> Result<()> {
    fn same(
        a: &serde_json::Value,
        b: &serde_json::Value,
        path: &str,
    ) -> std::result::Result<(), String> {
        use serde_json::Value as V;
        match (a, b) {
            (V::Number(x), V::Number(y)) => {
                let (x, y) = (
                    x.as_f64().unwrap_or(f64::NAN),
                    y.as_f64().unwrap_or(f64::NAN),
                );
                if (x - y).abs() <= 1e-12 * x.abs().max(y.abs()) {
                    Ok(())
                } else {
                    Err(format!("{path}: yours {x}, hompm's {y}"))
                }
            }
            (V::Object(x), V::Object(y)) => {
                for (k, v) in x {
                    if let Some(w) = y.get(k) {
                        same(v, w, &format!("{path}.{k}"))?;
                    }
                }
                Ok(())
            }
            _ if a == b => Ok(()),
            _ => Err(format!("{path}: yours {a}, hompm's {b}")),
        }
    }
    for (k, v) in theirs {
        if k == "every" || k == "hompm" {
            continue;
        }
        if let Some(w) = ours.get(k) {
            same(v, w, k).map_err(|m| {
                Error::Input(format!(
                    "the trace's header names other settings than this check's ({m}); give the same options"
                ))
            })?;
        }
    }
    Ok(())
}

/// Checks the metadata a file names (`# key: value` lines, or a JSON
/// document's top-level scalars) against the setup: `scene`, `cells`,
/// `ppc`, `steps`, `dt` and `time`, where given, must be the setup's
/// (numbers to 1e-12 relative). A file of another run is refused, not
/// compared.
pub fn check_metadata(metadata: &BTreeMap<String, String>, setup: &Setup) -> Result<()> {
    let refuse = |key: &str, theirs: &str, ours: String| {
        Error::Input(format!(
            "the file says {key} = {}, this check's setup has {ours}; give the options of the run that wrote it",
            short(theirs)
        ))
    };
    if let Some(scene) = metadata.get("scene") {
        let names = setup.scene_names();
        if !names.contains(&scene.trim_matches('"')) {
            return Err(refuse("scene", scene, names.join(" or ")));
        }
    }
    let c = setup.conventions();
    let mut words = vec![
        ("scheme", c.scheme.name().to_string()),
        ("transfer", c.transfer.name()),
        ("positions", c.positions.name().to_string()),
        ("body-force", c.body_force.name().to_string()),
        ("knots", c.knots.name().to_string()),
        ("gradient", c.gradient.name().to_string()),
    ];
    if let Setup::TwoD(s) = setup {
        words.push(("solution", s.scene.solution.name().to_string()));
    }
    for (key, ours) in words {
        if let Some(theirs) = metadata.get(key) {
            let t = theirs.trim_matches('"').trim();
            let same = match key {
                "transfer" => {
                    crate::mpm::conventions::Transfer::from_name(t).is_ok_and(|x| x == c.transfer)
                }
                _ => t == ours,
            };
            if !same {
                return Err(refuse(key, theirs, ours));
            }
        }
    }
    let (cells, ppc) = setup.cells_and_ppc();
    let numbers = [
        ("cells", cells as f64),
        ("ppc", ppc as f64),
        ("steps", setup.steps() as f64),
        ("dt", setup.dt()),
        ("time", setup.end_time()),
    ];
    for (key, ours) in numbers {
        let Some(text) = metadata.get(key) else {
            continue;
        };
        let theirs: f64 = text.trim_matches('"').trim().parse().map_err(|_| {
            Error::Input(format!(
                "the file's {key} '{}' is not a number",
                short(text)
            ))
        })?;
        if (theirs - ours).abs() > 1e-12 * ours.abs().max(theirs.abs()) || theirs.is_nan() {
            return Err(refuse(key, text, format!("{ours}")));
        }
    }
    Ok(())
}

/// A trace's steps checked against a run of `steps` steps: each in
/// 1..=steps, in order, none twice, the last one the run's last.
pub fn check_steps(trace: &Trace, steps: usize) -> Result<&TraceStep> {
    let mut previous = 0;
    for s in &trace.steps {
        if s.step == 0 || s.step > steps {
            return Err(Error::Input(format!(
                "the trace has step {}; the run has steps 1 to {steps}",
                s.step
            )));
        }
        if s.step <= previous {
            return Err(Error::Input(format!(
                "the trace has step {} after step {previous}; steps are ordered by number and given once",
                s.step
            )));
        }
        previous = s.step;
    }
    match trace.steps.last() {
        Some(last) if last.step == steps => Ok(last),
        Some(last) => Err(Error::Input(format!(
            "the trace ends at step {}; its last step must be the run's last, {steps}, whose particles are compared as the final state",
            last.step
        ))),
        None => Err(Error::Input("the trace has no steps".into())),
    }
}
