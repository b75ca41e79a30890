//! # The attribution table: `mls-convergence-study` (issue #38)
//!
//! Why hompm's B-spline MPM stops converging on the MLS paper's aligned
//! vibration (MLS paper Eqs. 38–43), and which convention of another
//! code's step restores it: the RMS errors (Eq. 43) of u, v and σ on 8,
//! 16, 32 and 64 cells and the orders between successive sizes, after one
//! period (t = 0.02 s), at t = 0.195 s (u at its peak) and at T = 0.2 s,
//! for every combination of
//! [`crate::studies::mls_convergence::combinations`]. The default run is
//! reduced (8 and 16 cells, one period, the stability scan to one period);
//! `--full` runs the whole grid to T.
//!
//! The only published numbers are the MLS paper's claim that BSMPM shows
//! "a lack of convergence for finer meshes" (the claim of `mls-aligned`'s
//! fourth row), stated on hompm's BSMPM at T between 16 and 32 cells; every
//! other number is computed. The notes carry each run's errors, stop,
//! mapping errors and cost, the cost against the accuracy of every
//! combination, and the largest stable Δt of each on 16 cells.
//!
//! Items: [`table`], [`rows`], [`notes`], [`row_label`], [`ROW_TIMES`],
//! [`column_labels`].

use super::{Computed, LabelledRow, RunOptions, Study, TableSpec};
use crate::error::Result;
use crate::scenes::aligned_vibration::{parameters, AlignedErrors};
use crate::studies::mls_convergence::{
    convention_study, pair_order, ConventionRun, ConventionStudy, ConventionStudyOptions,
};
use crate::studies::mls_paper::EARLY_TIME;

/// The sizes of the table's columns.
const SIZES: [usize; 4] = [8, 16, 32, 64];
/// The quantities, in the order of the columns.
const QUANTITIES: [&str; 3] = ["u", "v", "σ"];

/// The times of a combination's rows. One period and T are zeros of u
/// (exact u = 0, F = I, σ = 0: the u and σ errors there measure the phase,
/// and v is at its peak); t = 0.195 s is a peak of u (v = 0).
pub const ROW_TIMES: [&str; 3] = [
    "t = 0.02 s (one period)",
    "t = 0.195 s (u at its peak)",
    "T = 0.2 s",
];

/// The registration of `mls-convergence-study`.
pub fn table() -> TableSpec {
    TableSpec {
        id: "mls-convergence-study",
        published_json: include_str!("../../golden/published/mls-convergence-study.json"),
        setup: "Aligned vibration (MLS paper Eqs. 38-42 with the derived pi^2 body force), E = 1e7 Pa (mls-paper-e1e7), nu = 0.3, rho0 = 1000, A = 0.1 m, dt = 1e-5 s, 9 PPC, quadratic B-splines with the direct mapping and a lumped mass (hompm run aligned-vibration --ppc 9 with the flags of each row, listed in the notes): hompm's BSMPM (MUSL, FLIP, grid positions, body force at the particles, open knots) with one convention switched, the Taichi-style step (--transfer apic --gradient affine --knots padded, USL) with one switched back, the MLS paper's reconstruction (--method bsmpm-mls) and conservative 2D TLS (--method bsmpm-tls) and hompm's partition-of-unity TLS (--method bsmpm-pu-tls) alone and under USL or FLIP 0.99, and the total-Lagrangian reference on the same splines (--method tl-fe, no grid crossing). RMS errors (Eq. 43) after one period (t = 0.02 s) and at T = 0.2 s, zeros of u where the u and sigma errors measure the phase, and at t = 0.195 s, a peak of u; orders log(e_coarse/e_fine)/log 2. Default: 8 and 16 cells to one period; --full (hompm table --full, hompm reproduce --full): 8-64 cells to T. A run that stops has no errors after its stop (the notes name the step and cause). Stability: the largest dt reaching the end time on 16 cells, scanned in steps of sqrt 2 from 1e-5 s and bisected three times.",
        compute,
    }
}

fn compute(o: &RunOptions) -> Result<Computed> {
    if o.quick {
        // --quick runs the pipeline on 8 cells for 100 steps: too short for
        // any row, so the notes only.
        let study = convention_study(&ConventionStudyOptions {
            sizes: vec![8],
            early_steps: 100,
            steps: 100,
            stability: None,
            ..ConventionStudyOptions::default_run()
        })?;
        return Ok(Computed {
            rows: Vec::new(),
            notes: notes(&study),
            study: None,
        });
    }
    let options = if o.full {
        ConventionStudyOptions::full_run()
    } else {
        ConventionStudyOptions::default_run()
    };
    let study = convention_study(&options)?;
    Ok(Computed {
        rows: rows(&study)?,
        notes: notes(&study),
        study: Some(Study::MlsConvergence(Box::new(study))),
    })
}

/// The row of combination `label` at the time `ROW_TIMES[time]`.
pub fn row_label(label: &str, time: usize) -> String {
    format!("{label}, {}", ROW_TIMES[time.min(ROW_TIMES.len() - 1)])
}

/// The column labels: per quantity, the errors at 8, 16, 32, 64 cells,
/// then the orders 8-16, 16-32, 32-64.
pub fn column_labels() -> Vec<String> {
    let mut out = Vec::new();
    for q in QUANTITIES {
        out.extend(SIZES.iter().map(|n| format!("{q} {n}")));
        out.extend(
            SIZES
                .windows(2)
                .map(|w| format!("{q} order {}-{}", w[0], w[1])),
        );
    }
    out
}

fn quantity(e: &AlignedErrors, q: usize) -> f64 {
    [e.displacement, e.velocity, e.stress][q]
}

/// One row: the errors of `runs` (one combination, by size) at the record
/// of `ROW_TIMES[time]`, and the orders between successive sizes.
fn row_values(runs: &[&ConventionRun], time: usize) -> Vec<Option<f64>> {
    let at = |n: usize| -> Option<AlignedErrors> {
        let r = runs.iter().find(|r| r.cells == n)?;
        [r.early, r.peak, r.end].get(time).copied().flatten()
    };
    let mut out = Vec::new();
    for q in 0..QUANTITIES.len() {
        let e: Vec<Option<f64>> = SIZES
            .iter()
            .map(|&n| at(n).map(|e| quantity(&e, q)))
            .collect();
        out.extend(e.iter().copied());
        out.extend(SIZES.windows(2).zip(e.windows(2)).map(|(n, e)| {
            e[0].zip(e[1])
                .map(|(c, f)| pair_order((n[0], c), (n[1], f)))
        }));
    }
    out
}

/// The computed rows: for each combination, a row for each time of
/// [`ROW_TIMES`] the study recorded (t = 0.02 s, t = 0.195 s, T = 0.2 s; a
/// study run at other times gives no rows). Errors only if the parameter
/// set of the scene is missing.
pub fn rows(study: &ConventionStudy) -> Result<Vec<LabelledRow>> {
    let duration = parameters("mls-paper-e1e7")?.duration;
    let o = &study.options;
    let same = |a: Option<f64>, b: f64| a.is_some_and(|a| (a - b).abs() <= 1e-9 * b);
    let recorded = [
        same(Some(o.early_time()), EARLY_TIME),
        same(o.peak_time(), duration - EARLY_TIME / 4.0),
        same(Some(o.end_time()), duration),
    ];
    let mut out = Vec::new();
    for (i, c) in study.combinations.iter().enumerate() {
        let runs: Vec<&ConventionRun> = study.runs.iter().filter(|r| r.combination == i).collect();
        for time in (0..ROW_TIMES.len()).filter(|&t| recorded[t]) {
            out.push((row_label(c.label, time), row_values(&runs, time)));
        }
    }
    Ok(out)
}

fn errors_words(e: Option<AlignedErrors>) -> String {
    e.map_or("—".into(), |e| {
        format!(
            "u {:.2e} v {:.2e} σ {:.2e}",
            e.displacement, e.velocity, e.stress
        )
    })
}

fn run_words(r: &ConventionRun, o: &ConventionStudyOptions) -> String {
    let mut s = format!(
        "{} cells: t = {} s: {}",
        r.cells,
        o.early_time(),
        errors_words(r.early)
    );
    if let Some(t) = o.peak_time() {
        s.push_str(&format!("; t = {t} s: {}", errors_words(r.peak)));
    }
    if o.steps != o.early_steps {
        s.push_str(&format!(
            "; t = {} s: {}",
            o.end_time(),
            errors_words(r.end)
        ));
    }
    if let Some(stop) = &r.stop {
        s.push_str(&format!(
            "; stopped in step {} (t = {:.5} s): {}",
            stop.step,
            stop.time,
            short_cause(&stop.cause)
        ));
    }
    s.push_str(&format!(
        "; mapping errors mass {:.1e}, momentum {:.1e}; {:.1} s, {:.0} ns per particle-step",
        r.conservation.mass,
        r.conservation.momentum,
        r.seconds,
        r.ns_per_particle_step()
    ));
    s
}

fn number(x: Option<f64>, orders: bool) -> String {
    match x {
        Some(v) if orders => format!("{v:.2}"),
        Some(v) => format!("{v:.2e}"),
        None => "—".into(),
    }
}

/// One line of the attribution grid: a row's errors by size and orders,
/// per quantity.
fn grid_line(label: &str, values: &[Option<f64>]) -> String {
    let per = SIZES.len() + SIZES.len() - 1;
    let parts: Vec<String> = QUANTITIES
        .iter()
        .enumerate()
        .map(|(q, name)| {
            let v = &values[q * per..(q + 1) * per];
            let errors: Vec<String> = v[..SIZES.len()].iter().map(|x| number(*x, false)).collect();
            let orders: Vec<String> = v[SIZES.len()..].iter().map(|x| number(*x, true)).collect();
            format!("{name} {} (orders {})", errors.join(" "), orders.join(" "))
        })
        .collect();
    format!("{label}: {}", parts.join("; "))
}

/// The error of a stop without the matrices it prints.
fn short_cause(cause: &str) -> &str {
    cause.split(" (F = [").next().unwrap_or(cause)
}

/// The notes: the attribution grid (one line per row: errors at 8, 16, 32,
/// 64 cells and the orders), then per combination its flags and every run
/// (stop, mapping errors, wall time), the cost against the accuracy at the
/// finest size, and the stability limit.
pub fn notes(study: &ConventionStudy) -> Vec<String> {
    let o = &study.options;
    let (early_time, end_time) = (o.early_time(), o.end_time());
    let peak = o
        .peak_steps
        .map(|k| format!(" and after {k} (t = {} s)", k as f64 * o.dt))
        .unwrap_or_default();
    let mut notes = vec![format!(
        "{} combinations × sizes {:?}, {} PPC, Δt = {:e} s, {} steps (t = {end_time} s), errors also after {} steps (t = {early_time} s){peak}; runs two at a time on two cores, so a wall time includes the sharing. Grid below: RMS errors at 8, 16, 32, 64 cells (— not run or stopped) and the orders 8-16, 16-32, 32-64.",
        study.combinations.len(),
        o.sizes,
        o.per_side * o.per_side,
        o.dt,
        o.steps,
        o.early_steps
    )];
    if let Ok(rows) = rows(study) {
        notes.extend(rows.iter().map(|(label, values)| grid_line(label, values)));
    }
    for (i, c) in study.combinations.iter().enumerate() {
        let runs: Vec<String> = study
            .runs
            .iter()
            .filter(|r| r.combination == i)
            .map(|r| run_words(r, o))
            .collect();
        notes.push(format!("{} ({}): {}", c.label, c.flags, runs.join(" | ")));
    }
    let finest = o.sizes.iter().copied().max().unwrap_or(0);
    for (i, c) in study.combinations.iter().enumerate() {
        if let Some(r) = study
            .runs
            .iter()
            .find(|r| r.combination == i && r.cells == finest)
        {
            let (last, t) = match (r.end, r.peak) {
                (Some(e), _) => (Some(e), end_time),
                (None, Some(e)) => (Some(e), o.peak_time().unwrap_or(end_time)),
                (None, None) => (r.early, early_time),
            };
            notes.push(format!(
                "cost against accuracy, {} at {finest} cells: {:.0} ns per particle-step, {} at t = {t} s",
                c.label,
                r.ns_per_particle_step(),
                errors_words(last),
            ));
        }
    }
    for s in &study.stability {
        let Some(c) = study.combinations.get(s.combination) else {
            continue;
        };
        let Some(so) = o.stability else { continue };
        let stable = s
            .largest_stable
            .map_or("none from the smallest tried".into(), |d| {
                format!("{d:.3e} s")
            });
        let unstable = match (s.smallest_unstable, &s.stop) {
            (Some(d), Some(stop)) => format!(
                "the run at Δt = {d:.3e} s stops in step {} (t = {:.5} s): {}",
                stop.step,
                stop.time,
                short_cause(&stop.cause)
            ),
            _ => format!("no Δt up to {:e} s stops", so.largest_dt),
        };
        notes.push(format!(
            "stability, {} on {} cells to t = {} s: largest stable Δt {stable}; {unstable} ({} runs)",
            c.label, so.cells, so.end_time, s.trials
        ));
    }
    notes
}
