//! # Comparing another code's output with hompm's
//!
//! [`check`] takes the other code's particles (or trace) and hompm's run of
//! the same [`Setup`], and reports:
//!
//! - per field (x, u, v, stress, F, volume, density): the largest absolute
//!   and relative difference and the particle of each;
//! - both codes' RMS and L∞ errors against the exact solution, the RMS of
//!   MLS paper Eq. (43) with the Euclidean norm per particle (Frobenius for
//!   tensors; a symmetric stress given as xx, yy, xy counts xy twice),
//!   evaluated at the particles' initial positions at t = steps × Δt;
//! - with a trace: the first step, equation and index where the two
//!   differ, both values and the equation's citation;
//! - a verdict in plain words.
//!
//! **The tolerance rule** (after Uintah's regression tester): a value
//! fails only when both |yours − hompm| > atol and |yours − hompm| >
//! rtol·|hompm|. The defaults, [`DEFAULT_RTOL`] and [`DEFAULT_ATOL`], come
//! from measurement (docs/oracle.md): the same method run with the
//! Cholesky and the Richardson (1e-9) solve of a consistent mass differs by
//! up to about 1e-9 relative; rounding alone (another summation order)
//! stays below 1e-12. The relative difference is |yours − hompm|/|hompm|,
//! left out where hompm's value is 0.
//!
//! **Matching particles** is `oracle::state`'s: by `id`, or by initial
//! position.
//!
//! Items: [`check`], [`CheckOptions`], [`MatchBy`], [`CheckReport`],
//! [`FieldReport`], [`Pair`], [`FirstDifference`], [`first_difference`],
//! [`check_header`], [`DEFAULT_RTOL`], [`DEFAULT_ATOL`],
//! [`field_columns`].

use super::exact::{exact_1d, exact_2d};
use super::input::{Input, ParticleTable};
use super::setup::Setup;
use super::state::{match_particles, state_of_trace, x0_columns, State};
use super::trace::{Equation, Trace, EQUATIONS_1D, EQUATIONS_2D};
use crate::error::{Error, Result};
use serde::Serialize;
use std::collections::BTreeMap;

/// The default relative tolerance (module docs).
pub const DEFAULT_RTOL: f64 = 1e-9;
/// The default absolute tolerance (module docs).
pub const DEFAULT_ATOL: f64 = 1e-12;

/// How the other code's particles are matched with hompm's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum MatchBy {
    /// By `id` if the file has it, else by initial position.
    #[default]
    Auto,
    /// By the `id` column.
    Id,
    /// By the initial position (x0, or x0_x and x0_y).
    X0,
}

/// What a check is asked to do.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CheckOptions {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// Particle matching.
    pub match_by: MatchBy,
}

impl Default for CheckOptions {
    fn default() -> Self {
        Self {
            rtol: DEFAULT_RTOL,
            atol: DEFAULT_ATOL,
            match_by: MatchBy::Auto,
        }
    }
}

/// A quantity of both codes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Pair {
    /// The other code's.
    pub yours: f64,
    /// hompm's.
    pub hompm: f64,
}

/// The comparison of one field.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FieldReport {
    /// The columns compared.
    pub columns: Vec<String>,
    /// Largest |yours − hompm| over particles and components.
    pub max_abs: f64,
    /// Largest |yours − hompm|/|hompm| (where hompm's value is not 0).
    pub max_rel: f64,
    /// hompm's index of the particle with the largest absolute difference.
    pub worst_particle: usize,
    /// hompm's index of the particle with the largest relative difference.
    pub worst_particle_rel: usize,
    /// The values at the worst particle (largest absolute difference).
    pub at_worst: Pair,
    /// Values that fail the tolerance rule.
    pub failures: usize,
    /// RMS error against the exact solution (Eq. 43), where one exists.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rms_exact: Option<Pair>,
    /// L∞ error against the exact solution (largest per-particle norm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub linf_exact: Option<Pair>,
}

/// Where two traces first part.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FirstDifference {
    /// The step, from 1.
    pub step: usize,
    /// The equation key, e.g. `book-4.10`.
    pub equation: String,
    /// The citation, e.g. `book Eq. (4.10)`.
    pub citation: String,
    /// What the quantity is.
    pub quantity: String,
    /// `dof`, `particle` or `solver`.
    pub index_kind: String,
    /// The DOF, node, particle, Gauss point or entry.
    pub index: usize,
    /// The component (x, y, xx, …) of a vector or tensor quantity.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub component: Option<String>,
    /// Both values (NaN never: a missing value is reported by `count`).
    pub values: Pair,
    /// Both codes' number of values, when they differ.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub count: Option<[usize; 2]>,
}

/// The whole report of `hompm check`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CheckReport {
    /// The verdict in plain words (several sentences, one per line).
    pub verdict: String,
    /// Whether every compared value is within the tolerance.
    pub agrees: bool,
    /// hompm's method, e.g. `BSMPM-p2 with direct mapping and lumped mass`.
    pub method: String,
    /// The tolerances.
    pub tolerance: CheckOptions,
    /// Particles compared.
    pub particles: usize,
    /// How they were matched: `id`, `id (1-based)`, `x0` or `order`.
    pub matched_by: String,
    /// Per field.
    pub fields: BTreeMap<String, FieldReport>,
    /// Where the traces first differ (with a trace).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub first_difference: Option<FirstDifference>,
    /// The equation keys compared in the trace (with a trace).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub compared_equations: Vec<String>,
    /// The ratio of your RMS error of u to hompm's, where both exist.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error_ratio: Option<f64>,
    /// The time the exact solution is evaluated at, steps × Δt.
    pub time: f64,
}

/// The fields and their columns.
pub fn field_columns(two_d: bool) -> &'static [(&'static str, &'static [&'static str])] {
    if two_d {
        &[
            ("x", &["x_x", "x_y"]),
            ("u", &["u_x", "u_y"]),
            ("v", &["v_x", "v_y"]),
            (
                "stress",
                &["stress_xx", "stress_yy", "stress_xy", "stress_yx"],
            ),
            ("F", &["F_xx", "F_xy", "F_yx", "F_yy"]),
            ("volume", &["volume"]),
            ("density", &["density"]),
        ]
    } else {
        &[
            ("x", &["x"]),
            ("u", &["u"]),
            ("v", &["v"]),
            ("stress", &["stress"]),
            ("volume", &["volume"]),
            ("density", &["density"]),
        ]
    }
}

/// Whether a value fails the rule: both tolerances exceeded.
fn fails(yours: f64, hompm: f64, o: &CheckOptions) -> bool {
    let d = (yours - hompm).abs();
    d > o.atol && d > o.rtol * hompm.abs()
}

/// The exact fields at initial positions, in the check's column names
/// (None where the scene has no exact value for a column).
fn exact_columns(setup: &Setup, x0: &[Vec<f64>]) -> Result<BTreeMap<&'static str, Vec<f64>>> {
    let t = setup.end_time();
    let mut out: BTreeMap<&'static str, Vec<f64>> = BTreeMap::new();
    match setup {
        Setup::OneD(s) => {
            for &x in &x0[0] {
                let e = exact_1d(&s.scene, x, t);
                for (k, v) in [("x", x + e.u), ("u", e.u), ("v", e.v), ("stress", e.stress)] {
                    out.entry(k).or_default().push(v);
                }
            }
        }
        Setup::TwoD(s) => {
            for (&x, &y) in x0[0].iter().zip(&x0[1]) {
                let e = exact_2d(&s.scene, [x, y], t, false)?;
                let values = [
                    ("x_x", x + e.u[0]),
                    ("x_y", y + e.u[1]),
                    ("u_x", e.u[0]),
                    ("u_y", e.u[1]),
                    ("v_x", e.v[0]),
                    ("v_y", e.v[1]),
                    ("stress_xx", e.stress[0]),
                    ("stress_xy", e.stress[1]),
                    ("stress_yx", e.stress[2]),
                    ("stress_yy", e.stress[3]),
                    ("F_xx", e.deformation[0]),
                    ("F_xy", e.deformation[1]),
                    ("F_yx", e.deformation[2]),
                    ("F_yy", e.deformation[3]),
                ];
                for (k, v) in values {
                    out.entry(k).or_default().push(v);
                }
            }
        }
    }
    Ok(out)
}

/// Compares one field's present columns.
fn compare_field(
    columns: &[&str],
    theirs: &ParticleTable,
    ours: &ParticleTable,
    perm: &[usize],
    o: &CheckOptions,
) -> Option<FieldReport> {
    let present: Vec<&str> = columns
        .iter()
        .copied()
        .filter(|c| theirs.column(c).is_some() && ours.column(c).is_some())
        .collect();
    if present.is_empty() {
        return None;
    }
    let mut r = FieldReport {
        columns: present.iter().map(|c| c.to_string()).collect(),
        max_abs: 0.0,
        max_rel: 0.0,
        worst_particle: perm[0],
        worst_particle_rel: perm[0],
        at_worst: Pair {
            yours: 0.0,
            hompm: 0.0,
        },
        failures: 0,
        rms_exact: None,
        linf_exact: None,
    };
    let mut first = true;
    for c in &present {
        let (y, h) = (theirs.column(c)?, ours.column(c)?);
        for (row, &k) in perm.iter().enumerate() {
            let (a, b) = (y[row], h[k]);
            let d = (a - b).abs();
            if first || d > r.max_abs {
                r.max_abs = d;
                r.worst_particle = k;
                r.at_worst = Pair { yours: a, hompm: b };
                first = false;
            }
            if b != 0.0 && d / b.abs() > r.max_rel {
                r.max_rel = d / b.abs();
                r.worst_particle_rel = k;
            }
            if fails(a, b, o) {
                r.failures += 1;
            }
        }
    }
    Some(r)
}

/// RMS and L∞ over particles of the per-particle norm of (values − exact)
/// over `columns`; stress_yx falls back on stress_xy (a symmetric stress).
fn exact_errors(
    columns: &[&str],
    table: &ParticleTable,
    rows: &[usize],
    exact: &BTreeMap<&'static str, Vec<f64>>,
) -> Option<(f64, f64)> {
    let mut sum = vec![0.0; rows.len()];
    for c in columns {
        let values = table.column(c).or_else(|| {
            (*c == "stress_yx")
                .then(|| table.column("stress_xy"))
                .flatten()
        })?;
        let e = exact.get(c)?;
        for (j, &k) in rows.iter().enumerate() {
            sum[j] += (values[k] - e[j]).powi(2);
        }
    }
    let n = rows.len() as f64;
    let rms = (sum.iter().sum::<f64>() / n).sqrt();
    let linf = sum.iter().map(|s| s.sqrt()).fold(0.0, f64::max);
    Some((rms, linf))
}

/// Compares two traces step by step, equation by equation in the order
/// of the step (`table`: [`EQUATIONS_1D`] or [`EQUATIONS_2D`]), index by
/// index: the first value that fails the tolerance rule, and the keys
/// compared.
pub fn first_difference(
    theirs: &Trace,
    ours: &Trace,
    o: &CheckOptions,
    table: &[Equation],
) -> (Option<FirstDifference>, Vec<String>) {
    let mut compared: Vec<String> = Vec::new();
    for ts in &theirs.steps {
        let Some(os) = ours.steps.iter().find(|s| s.step == ts.step) else {
            continue;
        };
        for e in table {
            let (Some(y), Some(h)) = (ts.equations.get(e.key), os.equations.get(e.key)) else {
                continue;
            };
            if !compared.iter().any(|k| k == e.key) {
                compared.push(e.key.to_string());
            }
            let diff = |flat: usize, yours: f64, hompm: f64, count: Option<[usize; 2]>| {
                let (index, component) = e.locate(flat);
                FirstDifference {
                    step: ts.step,
                    equation: e.key.into(),
                    citation: e.citation.into(),
                    quantity: format!("{} {}", e.quantity, e.symbol),
                    index_kind: e.index.word().into(),
                    index,
                    component: component.map(str::to_string),
                    values: Pair { yours, hompm },
                    count,
                }
            };
            for (i, (&a, &b)) in y.iter().zip(h).enumerate() {
                if fails(a, b, o) {
                    return (Some(diff(i, a, b, None)), compared);
                }
            }
            if y.len() != h.len() {
                let i = y.len().min(h.len());
                let at = |v: &[f64]| v.get(i).copied().unwrap_or(0.0);
                return (
                    Some(diff(i, at(y), at(h), Some([y.len(), h.len()]))),
                    compared,
                );
            }
        }
    }
    (None, compared)
}

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

/// Compares `input` (the other code's particles or trace) with hompm's
/// final `state` and, for a trace, hompm's trace `ours` of the same steps.
pub fn check(
    setup: &Setup,
    state: &State,
    input: &Input,
    ours: Option<&Trace>,
    o: &CheckOptions,
) -> Result<CheckReport> {
    for (name, v) in [("--rtol", o.rtol), ("--atol", o.atol)] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(Error::InvalidArgument(format!(
                "{name} must be finite and at least 0, got {v}"
            )));
        }
    }
    let (theirs, trace) = match input {
        Input::Particles(t) => (t.clone(), None),
        Input::Trace(t) => {
            let table = state_of_trace(t).ok_or_else(|| {
                Error::Input(
                    "the trace's last step has no particle positions (book-4.12, book-4.13)".into(),
                )
            })?;
            (table, Some(t))
        }
    };
    let (perm, matched_by) = match_particles(&theirs, state, o.match_by)?;
    let n = perm.len();
    // Exact fields at the other code's X where it gives X, else hompm's.
    let names = x0_columns(state.two_d);
    let their_x0: Option<Vec<Vec<f64>>> = names
        .iter()
        .map(|c| theirs.column(c).map(<[f64]>::to_vec))
        .collect();
    let our_x0: Vec<Vec<f64>> = names
        .iter()
        .map(|c| {
            let col = state.particles.column(c).unwrap_or(&[]);
            perm.iter()
                .map(|&k| col.get(k).copied().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    let exact_yours = exact_columns(setup, their_x0.as_ref().unwrap_or(&our_x0))?;
    let exact_ours = exact_columns(setup, &our_x0)?;
    let rows_yours: Vec<usize> = (0..n).collect();
    let mut fields = BTreeMap::new();
    for (field, columns) in field_columns(state.two_d) {
        let Some(mut r) = compare_field(columns, &theirs, &state.particles, &perm, o) else {
            continue;
        };
        let needed: Vec<&str> = columns.to_vec();
        if let (Some(y), Some(h)) = (
            exact_errors(&needed, &theirs, &rows_yours, &exact_yours),
            exact_errors(&needed, &state.particles, &perm, &exact_ours),
        ) {
            r.rms_exact = Some(Pair {
                yours: y.0,
                hompm: h.0,
            });
            r.linf_exact = Some(Pair {
                yours: y.1,
                hompm: h.1,
            });
        }
        fields.insert(field.to_string(), r);
    }
    if fields.is_empty() {
        return Err(Error::Input(
            "the file has no field to compare (x, u, v, stress, F, volume or density)".into(),
        ));
    }
    let table: &[Equation] = if state.two_d {
        &EQUATIONS_2D
    } else {
        &EQUATIONS_1D
    };
    let (first, compared) = match (trace, ours) {
        (Some(t), Some(h)) => first_difference(t, h, o, table),
        _ => (None, Vec::new()),
    };
    let failures: usize = fields.values().map(|f| f.failures).sum();
    let agrees = failures == 0 && first.is_none();
    let error_ratio = fields
        .get("u")
        .and_then(|f| f.rms_exact)
        .filter(|p| p.hompm > 0.0)
        .map(|p| p.yours / p.hompm);
    let verdict = verdict(state, o, &fields, first.as_ref(), agrees, error_ratio);
    Ok(CheckReport {
        verdict,
        agrees,
        method: state.method.clone(),
        tolerance: *o,
        particles: n,
        matched_by,
        fields,
        first_difference: first,
        compared_equations: compared,
        error_ratio,
        time: setup.end_time(),
    })
}

/// The verdict's sentences.
fn verdict(
    state: &State,
    o: &CheckOptions,
    fields: &BTreeMap<String, FieldReport>,
    first: Option<&FirstDifference>,
    agrees: bool,
    error_ratio: Option<f64>,
) -> String {
    let tolerance = format!("tolerance: relative {:e} or absolute {:e}", o.rtol, o.atol);
    let mut lines = Vec::new();
    if agrees {
        let rel = fields.values().map(|f| f.max_rel).fold(0.0, f64::max);
        let abs = fields.values().map(|f| f.max_abs).fold(0.0, f64::max);
        let to = if abs == 0.0 {
            "bit for bit".to_string()
        } else {
            format!("to {rel:.1e} relative")
        };
        lines.push(format!(
            "agrees with hompm's {} {to} ({tolerance})",
            state.method
        ));
    } else if let Some(d) = first {
        let count = d
            .count
            .map(|[y, h]| format!(" (yours has {y} values, hompm {h})"))
            .unwrap_or_default();
        let component = d
            .component
            .as_ref()
            .map(|c| format!(" ({c})"))
            .unwrap_or_default();
        lines.push(format!(
            "differs from step {} at {}, {}, {} {}{component}: yours {:e}, hompm {:e}{count} ({tolerance})",
            d.step, d.citation, d.quantity, d.index_kind, d.index, d.values.yours, d.values.hompm
        ));
    } else {
        let worst = fields
            .iter()
            .filter(|(_, f)| f.failures > 0)
            .max_by(|a, b| a.1.max_rel.total_cmp(&b.1.max_rel));
        if let Some((name, f)) = worst {
            lines.push(format!(
                "differs from hompm's {} in {name} at particle {}: yours {:e}, hompm {:e} (largest relative difference {:.1e}; {tolerance}); run `hompm trace` and check the trace to find the equation",
                state.method, f.worst_particle, f.at_worst.yours, f.at_worst.hompm, f.max_rel
            ));
        }
        if first.is_none() {
            for (name, f) in fields.iter().filter(|(_, f)| f.failures > 0) {
                lines.push(format!(
                    "{name}: {} values outside the tolerance, largest difference {:.1e} absolute, {:.1e} relative",
                    f.failures, f.max_abs, f.max_rel
                ));
            }
        }
    }
    if let Some(r) = error_ratio {
        lines.push(format!(
            "your error against the exact solution is {r:.3}× hompm's (RMS of u)"
        ));
    }
    lines.join("\n")
}
