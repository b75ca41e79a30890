//! # Comparing another code's output with hompm's
//!
//! [`check`] takes the other code's particles (or trace) and hompm's run of
//! the same [`Setup`], and reports:
//!
//! - per field (x0, x, u, v, stress, F, volume, density): the largest
//!   absolute and relative difference, the particle of each, the worst
//!   value outside the tolerance, and the absolute tolerance used;
//! - both codes' RMS and L∞ errors against the exact solution, the RMS of
//!   MLS paper Eq. (43) with the Euclidean norm per particle (Frobenius for
//!   tensors; a symmetric stress given as xx, yy, xy counts xy twice),
//!   evaluated at the particles' initial positions at t = steps × Δt;
//! - with a trace: the first step, equation and index where the two
//!   differ, both values and the equation's citation;
//! - a verdict in plain words, naming every field it compared.
//!
//! **The rule** (issue #35; docs/oracle.md "What agrees means"): `check`
//! says "agrees" only when it compared at least one of u, v, stress or F
//! ([`PHYSICAL_FIELDS`]) for every particle, and, with a trace, the
//! equations of its final step; a file that gives none of them is refused
//! ([`Error::Input`], exit 2) with the columns it ignored. Its input is
//! read strictly (`oracle::input`): a trace's steps must lie in 1..=steps,
//! end at the last step, and give every quantity hompm also traces with
//! hompm's number of values.
//!
//! **The tolerance rule** (after Uintah's regression tester): a value
//! fails only when both |yours − hompm| > atol·s and |yours − hompm| >
//! rtol·|hompm|, where s is the field's scale: the largest magnitude of
//! that field in hompm's run (of that equation's quantity at that step,
//! for a trace). The absolute tolerance thus has the field's units, and
//! rounding around a zero of a stress in Pa is judged against the
//! stress's size, not against 1e-12 Pa. The defaults, [`DEFAULT_RTOL`]
//! and [`DEFAULT_ATOL`], come from measurement (docs/oracle.md): they
//! separate rounding (another summation order, another compiler) from a
//! change of solver or of its stopping rule. The relative difference is
//! |yours − hompm|/|hompm|, left out where hompm's value is 0. A
//! difference beyond the largest double is written as the largest double
//! (`f64::MAX`), never as ∞.
//!
//! **Matching particles** is `oracle::state`'s: by `id`, by initial
//! position, or by order when asked; an id and an x0 that name different
//! particles are refused.
//!
//! Items: [`check`], [`CheckOptions`], [`MatchBy`], [`CheckReport`],
//! [`FieldReport`], [`Pair`], [`ValueAt`], [`FirstDifference`]
//! (re-exported from `oracle::compare`), [`check_header`], [`check_metadata`]
//! (from `oracle::provenance`),
//! [`DEFAULT_RTOL`], [`DEFAULT_ATOL`], [`PHYSICAL_FIELDS`],
//! [`field_columns`].

use super::columns::x0_columns;
pub use super::columns::{field_columns, PHYSICAL_FIELDS};
use super::compare::{
    compare_field, exact_errors, first_difference, saturate, scale_of, sci, Tolerance,
    TraceComparison,
};
pub use super::compare::{FieldReport, FirstDifference, Pair, ValueAt};
use super::exact::{exact_1d, exact_2d};
use super::input::{Input, ParticleTable};
use super::provenance::check_steps;
pub use super::provenance::{check_header, check_metadata};
use super::setup::Setup;
pub use super::state::MatchBy;
use super::state::{match_particles, state_of_trace, State};
use super::trace::{Equation, Trace, EQUATIONS_1D, EQUATIONS_2D};
use super::visibility::TimeResolution;
use crate::error::{Error, Result};
use serde::Serialize;
use std::collections::BTreeMap;

/// The default relative tolerance (module docs).
pub const DEFAULT_RTOL: f64 = 1e-9;
/// The default absolute tolerance, as a fraction of the field's scale
/// (module docs).
pub const DEFAULT_ATOL: f64 = 1e-12;

/// What a check is asked to do.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CheckOptions {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance, as a fraction of each field's scale.
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

impl CheckOptions {
    /// The tolerance rule of these options.
    pub fn tolerance(&self) -> Tolerance {
        Tolerance {
            rtol: self.rtol,
            atol: self.atol,
        }
    }
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
    /// The fields compared, in the order of [`field_columns`].
    pub compared_fields: Vec<String>,
    /// Per field.
    pub fields: BTreeMap<String, FieldReport>,
    /// The file's columns that were not compared (not hompm's names).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub ignored_columns: Vec<String>,
    /// hompm's columns derived from the other code's (`u = x − x0`).
    pub derived_columns: Vec<String>,
    /// Where the traces first differ (with a trace).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub first_difference: Option<FirstDifference>,
    /// The equation keys compared in the trace (with a trace).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub compared_equations: Vec<String>,
    /// The trace's keys that were not compared (with a trace).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub ignored_equations: Vec<String>,
    /// hompm's trace keys that the other code's trace lacks.
    pub missing_equations: Vec<String>,
    /// The ratio of your RMS error of u to hompm's, where both exist.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error_ratio: Option<f64>,
    /// The time the exact solution is evaluated at, steps × Δt.
    pub time: f64,
    /// What the tolerance can see at this Δt (an agreeing check of final
    /// particles; `oracle::visibility`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_resolution: Option<TimeResolution>,
}

impl CheckReport {
    /// The compared fields with their columns.
    pub fn compared_columns(&self) -> Vec<(String, Vec<String>)> {
        self.compared_fields
            .iter()
            .filter_map(|f| Some((f.clone(), self.fields.get(f)?.columns.clone())))
            .collect()
    }

    /// Adds what the tolerance can see to the report and its verdict.
    pub fn with_time_resolution(mut self, r: TimeResolution) -> Self {
        self.verdict.push('\n');
        self.verdict.push_str(&r.sentence);
        self.time_resolution = Some(r);
        self
    }
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
    let n = state.particles.rows();
    let (theirs, trace) = match input {
        Input::Particles(t) => (t.clone(), None),
        Input::Trace(t) => {
            let mut sorted = t.clone();
            sorted.steps = super::input_json::ordered_steps(sorted.steps)?;
            let last = check_steps(&sorted, setup.steps())?;
            let table = state_of_trace(last, n, state.two_d)?;
            (table, Some(sorted))
        }
    };
    check_metadata(&theirs.metadata, setup)?;
    let (perm, matched_by) = match_particles(&theirs, state, o.match_by)?;
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
    let rows_yours: Vec<usize> = (0..perm.len()).collect();
    let tolerance = o.tolerance();
    let mut fields = BTreeMap::new();
    let mut compared_fields = Vec::new();
    let floor = derived_rounding(&theirs, setup.steps());
    let stress = stress_floor(setup, &state.particles, &tolerance)?;
    let least = |c: &str| {
        let derived = theirs
            .derived
            .iter()
            .any(|d| d.starts_with(&format!("{c} =")));
        if derived {
            floor
        } else if c.starts_with("stress") {
            stress
        } else {
            0.0
        }
    };
    for (field, columns) in field_columns(state.two_d) {
        let Some(mut r) =
            compare_field(columns, &theirs, &state.particles, &perm, &tolerance, least)?
        else {
            continue;
        };
        if let (Some(y), Some(h)) = (
            exact_errors(columns, &theirs, &rows_yours, &exact_yours),
            exact_errors(columns, &state.particles, &perm, &exact_ours),
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
        compared_fields.push(field.to_string());
        fields.insert(field.to_string(), r);
    }
    if !compared_fields
        .iter()
        .any(|f| PHYSICAL_FIELDS.contains(&f.as_str()))
    {
        return Err(nothing_physical(
            &compared_fields,
            &theirs.ignored,
            state.two_d,
        ));
    }
    let table: &[Equation] = if state.two_d {
        &EQUATIONS_2D
    } else {
        &EQUATIONS_1D
    };
    let traced = match (&trace, ours) {
        (Some(t), Some(h)) => first_difference(t, h, &tolerance, table)?,
        (Some(_), None) => {
            return Err(Error::InvalidArgument(
                "a trace is checked against hompm's trace of the same steps".into(),
            ))
        }
        _ => TraceComparison::default(),
    };
    let failures: usize = fields.values().map(|f| f.failures).sum();
    let agrees = failures == 0 && traced.first.is_none();
    let error_ratio = fields
        .get("u")
        .and_then(|f| f.rms_exact)
        .filter(|p| p.hompm > 0.0)
        .map(|p| saturate(p.yours / p.hompm));
    let mut report = CheckReport {
        verdict: String::new(),
        agrees,
        method: state.method.clone(),
        tolerance: *o,
        particles: perm.len(),
        matched_by,
        compared_fields,
        fields,
        ignored_columns: theirs.ignored.clone(),
        derived_columns: theirs.derived.clone(),
        first_difference: traced.first,
        compared_equations: traced.compared,
        ignored_equations: traced.ignored,
        missing_equations: traced.missing,
        error_ratio,
        time: setup.end_time(),
        time_resolution: None,
    };
    report.verdict = verdict(&report);
    Ok(report)
}

/// The refusal of a file that gives none of [`PHYSICAL_FIELDS`].
fn nothing_physical(compared: &[String], ignored: &[String], two_d: bool) -> Error {
    let physical: Vec<&str> = field_columns(two_d)
        .iter()
        .filter(|(f, _)| PHYSICAL_FIELDS.contains(f))
        .flat_map(|(_, c)| c.iter().copied())
        .collect();
    let ignored = if ignored.is_empty() {
        "no other column".to_string()
    } else {
        format!("the file's other columns, {}, were ignored", list(ignored))
    };
    Error::Input(format!(
        "nothing of the solution was compared: the file gives {} but none of u, v, stress or F ({}); {ignored}; map yours with --columns, e.g. --columns {}=YOURS",
        if compared.is_empty() {
            "no field".to_string()
        } else {
            compared.join(", ")
        },
        physical.join(", "),
        physical[0]
    ))
}

/// At most ten names, then how many more.
fn list(names: &[String]) -> String {
    let shown: Vec<String> = names
        .iter()
        .take(10)
        .map(|n| super::table::short(n))
        .collect();
    if names.len() > 10 {
        format!("{} and {} more", shown.join(", "), names.len() - 10)
    } else {
        shown.join(", ")
    }
}

/// A ratio or difference for a sentence: three digits, in exponent form
/// when large.
fn magnitude(x: f64) -> String {
    if x.abs() == f64::MAX {
        "more than 1e308".to_string()
    } else if (1e-3..1e4).contains(&x.abs()) {
        format!("{x:.3}")
    } else {
        sci(x, 3)
    }
}

/// The verdict's sentences.
fn verdict(r: &CheckReport) -> String {
    let o = &r.tolerance;
    let tolerance = format!(
        "tolerance: relative {:e}, or absolute {:e} × each field's largest value",
        o.rtol, o.atol
    );
    let fields = r.compared_fields.join(", ");
    let mut lines = Vec::new();
    if r.agrees {
        let rel = r.fields.values().map(|f| f.max_rel).fold(0.0, f64::max);
        let abs = r.fields.values().map(|f| f.max_abs).fold(0.0, f64::max);
        // The relative figure alone misleads where it is taken at a value
        // the absolute tolerance covers (u near 0: 6.0e-7 relative under
        // rtol 1e-9, issue #36's Karamelo runs): the share of the tolerance
        // used is said with it.
        let (share, field) = r
            .fields
            .iter()
            .map(|(name, f)| (f.max_times_tolerance, name.as_str()))
            .fold((0.0, ""), |a, b| if b.0 > a.0 { b } else { a });
        let to = if abs == 0.0 {
            "bit for bit".to_string()
        } else if rel > o.rtol {
            format!(
                "to {} relative at values the absolute tolerance covers (the largest difference is {} of its tolerance, in {field})",
                sci(rel, 1),
                magnitude(share)
            )
        } else {
            format!(
                "to {} relative (the largest difference is {} of its tolerance, in {field})",
                sci(rel, 1),
                magnitude(share)
            )
        };
        let equations = if r.compared_equations.is_empty() {
            String::new()
        } else {
            format!(
                " and the trace's {} equations at every traced step",
                r.compared_equations.len()
            )
        };
        lines.push(format!(
            "agrees with hompm's {} {to} in {fields}{equations} ({tolerance})",
            r.method
        ));
    } else if let Some(d) = &r.first_difference {
        let component = d
            .component
            .as_ref()
            .map(|c| format!(" ({c})"))
            .unwrap_or_default();
        lines.push(format!(
            "differs from step {} at {}, {}, {} {}{component}: yours {:e}, hompm {:e} ({tolerance})",
            d.step, d.citation, d.quantity, d.index_kind, d.index, d.values.yours, d.values.hompm
        ));
    } else {
        let worst = r
            .fields
            .iter()
            .filter_map(|(name, f)| f.worst_failure.as_ref().map(|w| (name, w)))
            .max_by(|a, b| a.1.times_tolerance.total_cmp(&b.1.times_tolerance));
        if let Some((name, w)) = worst {
            let rel = if w.values.hompm != 0.0 {
                let d = saturate((w.values.yours - w.values.hompm).abs());
                format!("{} relative", magnitude(saturate(d / w.values.hompm.abs())))
            } else {
                "hompm's value is 0".to_string()
            };
            lines.push(format!(
                "differs from hompm's {} in {name} ({}) at particle {}: yours {:e}, hompm {:e} ({rel}, {}× the tolerance; {tolerance}); run `hompm trace` and check the trace to find the equation",
                r.method,
                w.column,
                w.particle,
                w.values.yours,
                w.values.hompm,
                magnitude(w.times_tolerance)
            ));
        }
        for (name, f) in r.fields.iter().filter(|(_, f)| f.failures > 0) {
            lines.push(format!(
                "{name}: {} values outside the tolerance, largest difference {} absolute, {} relative",
                f.failures,
                sci(f.max_abs, 1),
                sci(f.max_rel, 1)
            ));
        }
    }
    if let Some(f) = r.fields.get("stress") {
        if f.atol_abs > r.tolerance.atol * f.scale {
            lines.push(format!(
                "stress: absolute tolerance {} = (λ + 2μ)·atol·max|F|, what F's tolerance becomes through the neo-Hookean law",
                sci(f.atol_abs, 1)
            ));
        }
    }
    if !r.derived_columns.is_empty() {
        let floor = r.fields.get("u").map_or(0.0, |f| f.atol_abs);
        lines.push(format!(
            "derived from your columns: {} (compared as hompm's; differences below {} absolute, 4√n·ε·max|x| for the rounding your positions gather over n steps, are not visible; a u accumulated apart from x would show them)",
            list(&r.derived_columns),
            sci(floor, 1)
        ));
    }
    if !r.ignored_columns.is_empty() {
        lines.push(format!(
            "not compared: your columns {} (not hompm's names; map them with --columns ours=theirs)",
            list(&r.ignored_columns)
        ));
    }
    if !r.ignored_equations.is_empty() {
        lines.push(format!(
            "not compared: your trace's keys {} (not traced by hompm's run of this setup{})",
            list(&r.ignored_equations),
            if r.ignored_equations.iter().any(|k| k.starts_with("nodal-")) {
                "; they belong to another code's step: give its --scheme, --transfer or --positions"
            } else {
                ""
            }
        ));
    }
    if !r.missing_equations.is_empty() {
        lines.push(format!(
            "not in your trace: hompm's keys {} (not compared)",
            list(&r.missing_equations)
        ));
    }
    if let Some(ratio) = r.error_ratio {
        lines.push(format!(
            "your error against the exact solution is {}× hompm's (RMS of u)",
            magnitude(ratio)
        ));
    }
    lines.join("\n")
}

/// The least absolute tolerance of a displacement derived as x − x0:
/// 4√n·ε·max|x|, four standard deviations of the rounding a position
/// gathers over n steps when each step rounds x by at most ε|x|
/// (docs/conventions.md, "Conventions of other codes"). 0 when nothing
/// is derived.
fn derived_rounding(theirs: &ParticleTable, steps: usize) -> f64 {
    if theirs.derived.is_empty() {
        return 0.0;
    }
    let largest = ["x", "x_x", "x_y"]
        .iter()
        .filter_map(|c| theirs.column(c))
        .map(|v| scale_of(v.iter()))
        .fold(0.0, f64::max);
    4.0 * (steps.max(1) as f64).sqrt() * f64::EPSILON * largest
}

/// The least absolute tolerance of the 2D stress: (λ + 2μ) times F's
/// absolute tolerance, atol·max|F|. σ is a function of F whose slope is
/// at most about λ + 2μ near F = I, so two codes whose F agree within F's
/// tolerance may differ in σ by this much through rounding alone
/// (Taichi's MLS-MPM at 64 cells: F within 3e-14, σ within 5.4e-7 Pa;
/// docs/conventions.md, "Conventions of other codes"). In 1D only the
/// neo-Hookean strip computes σ from F, with E = λ + 2μ at ν = 0 and |F|
/// at most 1 + |A|π/L, the bound of its exact solution (the MLS paper's
/// code at 64 cells: σ within 2.4e-8 Pa, 8e-13 of max|σ|; issue #40); 0
/// for the incremental laws, whose stress is not a function of an F.
fn stress_floor(setup: &Setup, ours: &ParticleTable, t: &Tolerance) -> Result<f64> {
    let s = match setup {
        Setup::TwoD(s) => s,
        Setup::OneD(s) => {
            return Ok(match s.scene {
                crate::oracle::setup::Scene1d::ManufacturedStrip(p) => {
                    let (lambda, mu) = p.lame();
                    let largest_f = 1.0 + p.amplitude.abs() * std::f64::consts::PI / p.length;
                    (lambda + 2.0 * mu) * t.atol * largest_f
                }
                _ => 0.0,
            })
        }
    };
    let m = s.scene.material()?;
    let largest_f = ["F_xx", "F_xy", "F_yx", "F_yy"]
        .iter()
        .filter_map(|c| ours.column(c))
        .map(|v| scale_of(v.iter()))
        .fold(0.0, f64::max);
    Ok((m.lambda + 2.0 * m.mu) * t.atol * largest_f)
}
