//! # The arithmetic of a comparison: fields, traces, errors
//!
//! What `oracle::check` does with two tables of numbers, one function per
//! question:
//!
//! - [`compare_field`]: one field's columns, particle by particle, under
//!   the tolerance rule with the absolute tolerance scaled by the field's
//!   size in hompm's run ([`Tolerance`]);
//! - [`exact_errors`]: RMS (MLS paper Eq. 43) and L∞ errors against the
//!   exact solution, summed without overflow;
//! - [`first_difference`]: two traces, step by step and equation by
//!   equation in the order of the step; a quantity of another length than
//!   hompm's is refused, never compared in part.
//!
//! Every difference is finite: a difference beyond the largest double is
//! written as the largest double ([`saturate`]).
//!
//! Items: [`Tolerance`], [`Pair`], [`ValueAt`], [`FieldReport`],
//! [`FirstDifference`], [`TraceComparison`], [`compare_field`],
//! [`exact_errors`], [`first_difference`], [`saturate`], [`scale_of`],
//! [`sci`].

use super::input::ParticleTable;
use super::trace::{Equation, Trace};
use crate::error::{Error, Result};
use serde::Serialize;
use std::collections::BTreeMap;

/// The tolerance rule: a value fails when |d| > atol·scale and
/// |d| > rtol·|hompm| (`oracle::check`'s module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    /// Relative to the value.
    pub rtol: f64,
    /// Relative to the field's scale.
    pub atol: f64,
}

impl Tolerance {
    /// Whether `yours` fails against `hompm` with the absolute tolerance
    /// `atol_abs` (atol × scale).
    pub fn fails(&self, yours: f64, hompm: f64, atol_abs: f64) -> bool {
        let d = saturate((yours - hompm).abs());
        d > atol_abs && d > self.rtol * hompm.abs()
    }

    /// How many tolerances off a difference is: |d| over the larger of
    /// the two thresholds (∞-free: saturated).
    fn excess(&self, yours: f64, hompm: f64, atol_abs: f64) -> f64 {
        let d = saturate((yours - hompm).abs());
        let threshold = atol_abs.max(self.rtol * hompm.abs());
        if threshold > 0.0 {
            saturate(d / threshold)
        } else if d > 0.0 {
            f64::MAX
        } else {
            0.0
        }
    }
}

/// `x`, or ±[`f64::MAX`] where it overflowed.
pub fn saturate(x: f64) -> f64 {
    if x.is_infinite() {
        f64::MAX.copysign(x)
    } else {
        x
    }
}

/// `x` in exponent form with `digits` decimals, never a text that reads
/// back as ±∞: a value that rounds past the largest double is written in
/// full ([`f64::MAX`] prints as 1.7976931348623157e308).
pub fn sci(x: f64, digits: usize) -> String {
    let text = format!("{x:.digits$e}");
    if text.parse::<f64>().is_ok_and(f64::is_finite) {
        text
    } else {
        format!("{x:e}")
    }
}

/// The largest magnitude among `values` (0 for none).
pub fn scale_of<'a>(values: impl IntoIterator<Item = &'a f64>) -> f64 {
    values.into_iter().fold(0.0, |m: f64, v| m.max(v.abs()))
}

/// A quantity of both codes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Pair {
    /// The other code's.
    pub yours: f64,
    /// hompm's.
    pub hompm: f64,
}

/// One value of both codes, with where it is.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ValueAt {
    /// hompm's particle index.
    pub particle: usize,
    /// The column.
    pub column: String,
    /// Both values.
    pub values: Pair,
    /// |yours − hompm| over the larger of the two tolerances.
    pub times_tolerance: f64,
}

/// The comparison of one field.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FieldReport {
    /// The columns compared.
    pub columns: Vec<String>,
    /// The field's scale: its largest magnitude in hompm's run.
    pub scale: f64,
    /// The absolute tolerance used, atol × scale, in the field's units.
    pub atol_abs: f64,
    /// Largest |yours − hompm| over particles and components.
    pub max_abs: f64,
    /// Largest |yours − hompm|/|hompm| (where hompm's value is not 0).
    pub max_rel: f64,
    /// Largest |yours − hompm| as a multiple of the tolerance that value
    /// had, max(atol_abs, rtol·|hompm|): below 1 for every agreeing field.
    pub max_times_tolerance: f64,
    /// hompm's index of the particle with the largest absolute difference.
    pub worst_particle: usize,
    /// hompm's index of the particle with the largest relative difference.
    pub worst_particle_rel: usize,
    /// The values at the worst particle (largest absolute difference).
    pub at_worst: Pair,
    /// The value furthest outside the tolerance, if any is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub worst_failure: Option<ValueAt>,
    /// Values that fail the tolerance rule.
    pub failures: usize,
    /// RMS error against the exact solution (Eq. 43), where one exists.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rms_exact: Option<Pair>,
    /// L∞ error against the exact solution (largest per-particle norm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub linf_exact: Option<Pair>,
}

/// Compares one field's `columns` that both tables have: row `r` of
/// `theirs` against particle `perm[r]` of `ours`. `None` if neither
/// gives any of them. `floor(column)` is a column's least absolute
/// tolerance: 0, or for a column derived from the other code's positions
/// (`u = x − x0`) the rounding it carries, or for the 2D stress what F's
/// tolerance becomes through the material (`oracle::check`). The report's
/// `atol_abs` is the largest over the field's columns.
pub fn compare_field(
    columns: &[&str],
    theirs: &ParticleTable,
    ours: &ParticleTable,
    perm: &[usize],
    t: &Tolerance,
    floor: impl Fn(&str) -> f64,
) -> Result<Option<FieldReport>> {
    let present: Vec<(&str, &[f64], &[f64])> = columns
        .iter()
        .filter_map(|c| Some((*c, theirs.column(c)?, ours.column(c)?)))
        .collect();
    let Some(&first) = perm.first() else {
        return Err(Error::Input("the file has no particles".into()));
    };
    if present.is_empty() {
        return Ok(None);
    }
    let mismatch = |c: &str| {
        Error::Input(format!(
            "the column '{c}' has another length than the particles matched"
        ))
    };
    let scale = scale_of(present.iter().flat_map(|(_, _, h)| h.iter()));
    let atol_of = |c: &str| (t.atol * scale).max(floor(c));
    let atol_abs = present
        .iter()
        .map(|(c, _, _)| atol_of(c))
        .fold(t.atol * scale, f64::max);
    let mut r = FieldReport {
        columns: present.iter().map(|(c, _, _)| c.to_string()).collect(),
        scale,
        atol_abs,
        max_abs: 0.0,
        max_rel: 0.0,
        max_times_tolerance: 0.0,
        worst_particle: first,
        worst_particle_rel: first,
        at_worst: Pair {
            yours: 0.0,
            hompm: 0.0,
        },
        worst_failure: None,
        failures: 0,
        rms_exact: None,
        linf_exact: None,
    };
    let mut any = false;
    for (c, y, h) in &present {
        if y.len() != perm.len() {
            return Err(mismatch(c));
        }
        let atol_abs = atol_of(c);
        for (&a, &k) in y.iter().zip(perm) {
            let b = *h.get(k).ok_or_else(|| mismatch(c))?;
            let d = saturate((a - b).abs());
            if !any || d > r.max_abs {
                r.max_abs = d;
                r.worst_particle = k;
                r.at_worst = Pair { yours: a, hompm: b };
                any = true;
            }
            if b != 0.0 && saturate(d / b.abs()) > r.max_rel {
                r.max_rel = saturate(d / b.abs());
                r.worst_particle_rel = k;
            }
            let excess = t.excess(a, b, atol_abs);
            r.max_times_tolerance = r.max_times_tolerance.max(excess);
            if t.fails(a, b, atol_abs) {
                r.failures += 1;
                if r.worst_failure
                    .as_ref()
                    .is_none_or(|w| excess > w.times_tolerance)
                {
                    r.worst_failure = Some(ValueAt {
                        particle: k,
                        column: c.to_string(),
                        values: Pair { yours: a, hompm: b },
                        times_tolerance: excess,
                    });
                }
            }
        }
    }
    Ok(Some(r))
}

/// RMS and L∞ over particles of the per-particle norm of (values − exact)
/// over `columns`, row `rows[j]` of `table` against `exact[c][j]`;
/// stress_yx falls back on stress_xy (a symmetric stress). The sums are
/// scaled by the largest difference, so no finite input overflows them.
pub fn exact_errors(
    columns: &[&str],
    table: &ParticleTable,
    rows: &[usize],
    exact: &BTreeMap<&'static str, Vec<f64>>,
) -> Option<(f64, f64)> {
    let mut differences: Vec<Vec<f64>> = Vec::with_capacity(columns.len());
    for c in columns {
        let values = table.column(c).or_else(|| {
            (*c == "stress_yx")
                .then(|| table.column("stress_xy"))
                .flatten()
        })?;
        let e = exact.get(c)?;
        let d: Option<Vec<f64>> = rows
            .iter()
            .zip(e)
            .map(|(&k, e)| values.get(k).map(|v| saturate(v - e)))
            .collect();
        differences.push(d.filter(|d| d.len() == rows.len())?);
    }
    let m = scale_of(differences.iter().flatten());
    if rows.is_empty() {
        return None;
    }
    if m == 0.0 {
        return Some((0.0, 0.0));
    }
    let mut sum = vec![0.0; rows.len()];
    for d in &differences {
        for (s, v) in sum.iter_mut().zip(d) {
            *s += (v / m).powi(2);
        }
    }
    let n = rows.len() as f64;
    let rms = saturate(m * (sum.iter().sum::<f64>() / n).sqrt());
    let linf = saturate(m * sum.iter().map(|s| s.sqrt()).fold(0.0, f64::max));
    Some((rms, linf))
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
    /// Both values.
    pub values: Pair,
    /// The absolute tolerance at this step and equation (atol × the
    /// largest magnitude of hompm's quantity there).
    pub atol_abs: f64,
}

/// What comparing two traces found.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TraceComparison {
    /// The first value outside the tolerance.
    pub first: Option<FirstDifference>,
    /// The keys compared, in the order of the step.
    pub compared: Vec<String>,
    /// The other code's keys that were not compared: not one of hompm's
    /// keys, or one that hompm's run does not trace at that step.
    pub ignored: Vec<String>,
    /// hompm's keys that the other code's trace lacks at a step both trace.
    pub missing: Vec<String>,
}

/// Compares two traces step by step, equation by equation in the order
/// of the step (`table`: `EQUATIONS_1D` or `EQUATIONS_2D`), index by
/// index: the first value that fails the tolerance rule, the keys
/// compared and those ignored. Both traces must hold the same steps; a
/// quantity both trace with different numbers of values is
/// [`Error::Input`].
pub fn first_difference(
    theirs: &Trace,
    ours: &Trace,
    t: &Tolerance,
    table: &[Equation],
) -> Result<TraceComparison> {
    let mut out = TraceComparison::default();
    for ts in &theirs.steps {
        let Some(os) = ours.steps.iter().find(|s| s.step == ts.step) else {
            return Err(Error::Input(format!(
                "your trace has step {}, which hompm's run does not reach",
                ts.step
            )));
        };
        for key in os.equations.keys() {
            if !ts.equations.contains_key(key) && !out.missing.contains(key) {
                out.missing.push(key.clone());
            }
        }
        for key in ts.equations.keys() {
            let known = table.iter().any(|e| e.key == key);
            if (!known || !os.equations.contains_key(key)) && !out.ignored.contains(key) {
                out.ignored.push(key.clone());
            }
        }
        for e in table {
            let (Some(y), Some(h)) = (ts.equations.get(e.key), os.equations.get(e.key)) else {
                continue;
            };
            if y.len() != h.len() {
                return Err(Error::Input(format!(
                    "step {}, {}: your trace has {} values, hompm's has {} ({} {} per {})",
                    ts.step,
                    e.key,
                    y.len(),
                    h.len(),
                    e.quantity,
                    e.symbol,
                    e.index.word()
                )));
            }
            if !out.compared.iter().any(|k| k == e.key) {
                out.compared.push(e.key.to_string());
            }
            if out.first.is_some() {
                continue;
            }
            let atol_abs = t.atol * scale_of(h);
            if let Some(i) = y.iter().zip(h).position(|(&a, &b)| t.fails(a, b, atol_abs)) {
                let (index, component) = e.locate(i);
                out.first = Some(FirstDifference {
                    step: ts.step,
                    equation: e.key.into(),
                    citation: e.citation.into(),
                    quantity: format!("{} {}", e.quantity, e.symbol),
                    index_kind: e.index.word().into(),
                    index,
                    component: component.map(str::to_string),
                    values: Pair {
                        yours: y[i],
                        hompm: h[i],
                    },
                    atol_abs,
                });
            }
        }
    }
    Ok(out)
}
