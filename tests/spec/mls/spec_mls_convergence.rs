//! Issue #38: the one-at-a-time attribution of `mls-convergence-study`.
//! A tiny version of the study (8 and 16 cells, 4 PPC, one period in 400
//! steps of 5e-5 s) checks the table's structure and that every
//! combination runs the step its flags name on the command line.

use hompm::cli;
use hompm::mpm2d::Mapping2d;
use hompm::scenes::aligned_vibration::{parameters, AlignedErrors, AlignedMethod};
use hompm::studies::mls_convergence::{
    combinations, convention_study, largest_stable_dt, run_combination, ConventionRun,
    ConventionStudy, ConventionStudyOptions, StabilityOptions, BSMPM, REFERENCE, TAICHI,
};
use hompm::tables::{self, mls_convergence, Computed, Published};
use std::sync::OnceLock;

/// One period (t = 0.02 s) on 8 and 16 cells with 4 PPC and Δt = 5e-5 s
/// (400 steps), run once for the tests below.
fn tiny() -> &'static ConventionStudy {
    static STUDY: OnceLock<ConventionStudy> = OnceLock::new();
    STUDY.get_or_init(|| {
        convention_study(&ConventionStudyOptions {
            sizes: vec![8, 16],
            per_side: 2,
            dt: 5e-5,
            early_steps: 400,
            peak_steps: None,
            steps: 400,
            stability: None,
        })
        .unwrap()
    })
}

/// Whether both runs reached one period; every combination with the
/// direct mapping or PU-TLS must (the tiny study is far inside their
/// stability limits), MLS and per-cell TLS may stop on these coarse 4-PPC
/// grids (MLS: a singular moment matrix; conservative TLS: det F <= 0).
fn reached_one_period(method: AlignedMethod, a: &ConventionRun, b: &ConventionRun) -> bool {
    let reached = a.early.is_some() && b.early.is_some();
    let direct = !matches!(
        method,
        AlignedMethod::Bsmpm {
            mapping: Mapping2d::Mls | Mapping2d::Tls,
            ..
        }
    );
    assert!(
        reached || !direct,
        "{method:?} stopped: {:?} {:?}",
        a.stop,
        b.stop
    );
    reached
}

fn triple(e: AlignedErrors) -> [f64; 3] {
    [e.displacement, e.velocity, e.stress]
}

#[test]
fn the_attribution_table_has_every_combination_after_one_period_with_errors_at_8_and_16_cells_and_their_orders(
) {
    let study = tiny();
    let spec = tables::find("mls-convergence-study").unwrap();
    let published = Published::parse(spec.id, spec.published_json).unwrap();
    let rows = mls_convergence::rows(study).unwrap();
    // One period recorded, T not reached: one row per combination.
    assert_eq!(rows.len(), combinations().len());
    assert_eq!(published.col_labels, mls_convergence::column_labels());
    let report = tables::compare(
        &spec,
        &published,
        Computed {
            rows: rows.clone(),
            ..Computed::default()
        },
    )
    .unwrap();
    let col = |label: &str| report.col_labels.iter().position(|c| c == label).unwrap();
    for c in combinations() {
        let r = report
            .row_labels
            .iter()
            .position(|l| *l == mls_convergence::row_label(c.label, 0))
            .unwrap();
        // Not recorded: the rows at t = 0.195 s and at T.
        for time in 1..mls_convergence::ROW_TIMES.len() {
            let later = mls_convergence::row_label(c.label, time);
            let k = report.row_labels.iter().position(|l| *l == later).unwrap();
            assert!(report.computed[k].iter().all(Option::is_none), "{later}");
        }
        let row = &report.computed[r];
        let (run8, run16) = (
            study.run(c.label, 8).unwrap(),
            study.run(c.label, 16).unwrap(),
        );
        if !reached_one_period(c.method, run8, run16) {
            // A reconstruction that stopped: its stop is named, and its
            // row has nothing after it.
            for run in [run8, run16].into_iter().filter(|r| r.early.is_none()) {
                assert!(run.stop.is_some(), "{}", c.label);
                let cells = run.cells;
                assert!(["u", "v", "σ"]
                    .iter()
                    .all(|q| row[col(&format!("{q} {cells}"))].is_none()));
            }
            continue;
        }
        let e8 = triple(run8.early.unwrap());
        let e16 = triple(run16.early.unwrap());
        for (q, name) in ["u", "v", "σ"].iter().enumerate() {
            assert_eq!(row[col(&format!("{name} 8"))], Some(e8[q]), "{}", c.label);
            assert_eq!(row[col(&format!("{name} 16"))], Some(e16[q]), "{}", c.label);
            assert_eq!(row[col(&format!("{name} 32"))], None);
            assert_eq!(row[col(&format!("{name} order 16-32"))], None);
            // The order between 8 and 16 cells is log2 of the error ratio.
            let order = row[col(&format!("{name} order 8-16"))].unwrap();
            assert!(
                (order - (e8[q] / e16[q]).log2()).abs() < 1e-12,
                "{}",
                c.label
            );
        }
    }
}

#[test]
fn every_combination_changes_the_errors_so_no_switched_convention_is_silently_ignored() {
    let study = tiny();
    let all = combinations();
    assert_eq!(all[0].label, BSMPM);
    assert!(all.iter().any(|c| c.label == TAICHI));
    assert!(all.iter().any(|c| c.label == REFERENCE));
    let all: Vec<_> = all
        .into_iter()
        .filter(|c| study.run(c.label, 16).unwrap().early.is_some())
        .collect();
    let errors: Vec<[f64; 3]> = all
        .iter()
        .map(|c| triple(study.run(c.label, 16).unwrap().early.unwrap()))
        .collect();
    for i in 0..all.len() {
        for j in 0..i {
            assert!(
                (0..3).all(|q| errors[i][q] != errors[j][q]),
                "{} and {} give the same error {:?}",
                all[i].label,
                all[j].label,
                errors[i]
            );
        }
    }
}

#[test]
fn every_combination_is_the_run_its_flags_name_on_the_command_line() {
    let base = parameters("mls-paper-e1e7").unwrap();
    for c in combinations() {
        let args = format!(
            "run aligned-vibration --cells 4 --ppc 4 --steps 20 {} --json",
            c.flags
        );
        let out = cli::run(args.split_whitespace()).unwrap_or_else(|e| panic!("{args}: {e}"));
        let doc: serde_json::Value = serde_json::from_str(&out.stdout).unwrap();
        let d = &doc["diagnostics"];
        let run = run_combination(&base, &c, 4, 2, 1e-5, 20, [None; 2]).unwrap();
        let e = run.end.unwrap();
        assert_eq!(
            d["rms_displacement"].as_f64(),
            Some(e.displacement),
            "{args}"
        );
        assert_eq!(d["rms_velocity"].as_f64(), Some(e.velocity), "{args}");
        assert_eq!(d["rms_stress"].as_f64(), Some(e.stress), "{args}");
    }
}

#[test]
fn the_largest_stable_time_step_reaches_the_end_and_the_next_one_tried_stops() {
    let base = parameters("mls-paper-e1e7").unwrap();
    let c = combinations().into_iter().next().unwrap();
    let o = StabilityOptions {
        cells: 4,
        end_time: 0.01,
        smallest_dt: 1e-4,
        largest_dt: 0.1,
        bisections: 2,
    };
    let limit = largest_stable_dt(&base, &c, 2, &o).unwrap();
    let (lo, hi) = (
        limit.largest_stable.unwrap(),
        limit.smallest_unstable.unwrap(),
    );
    assert!(lo < hi && hi / lo <= 2f64.sqrt().powf(0.25) * (1.0 + 1e-12));
    let steps = |dt: f64| ((o.end_time / dt) - 1e-9).ceil() as usize;
    let stable = run_combination(&base, &c, 4, 2, lo, steps(lo), [None; 2]).unwrap();
    assert!(stable.stop.is_none() && stable.end.is_some());
    let unstable = run_combination(&base, &c, 4, 2, hi, steps(hi), [None; 2]).unwrap();
    assert_eq!(unstable.stop, limit.stop);
    assert!(unstable.stop.is_some());
}

/// The report's charts of the study (issue #38, deliverables 3 and 4):
/// the convergence and work-precision charts draw one line per
/// combination, and the stability chart one point per combination with a
/// stable Δt and a footnote naming where each stops.
#[test]
fn the_study_s_charts_show_every_combination_and_name_every_stop() {
    use hompm::report::convention_charts;
    use hompm::studies::mls_convergence::{StabilityLimit, Stop};
    let mut study = tiny().clone();
    study.options.stability = Some(StabilityOptions {
        cells: 16,
        end_time: 0.02,
        smallest_dt: 1e-5,
        largest_dt: 3e-3,
        bisections: 3,
    });
    // Limits made up for the chart: the first combination stops at
    // 2e-4 s, the others never up to the scan's largest Δt.
    study.stability = (0..study.combinations.len())
        .map(|c| StabilityLimit {
            combination: c,
            largest_stable: Some(1e-4 * (1.0 + c as f64)),
            smallest_unstable: (c == 0).then_some(2e-4),
            stop: (c == 0).then(|| Stop {
                step: 17,
                time: 17.0 * 2e-4,
                cause: "det F <= 0 at particle 3".into(),
            }),
            trials: 5,
        })
        .collect();
    let spec = tables::find("mls-convergence-study").unwrap();
    let published = Published::parse(spec.id, spec.published_json).unwrap();
    let report = tables::compare(
        &spec,
        &published,
        Computed {
            rows: mls_convergence::rows(&study).unwrap(),
            notes: vec![],
            study: Some(tables::Study::MlsConvergence(Box::new(study.clone()))),
        },
    )
    .unwrap();
    let dir = std::env::temp_dir().join(format!("hompm-convention-charts-{}", std::process::id()));
    convention_charts(&dir, &[report]).unwrap();
    let svg = |stem: &str| std::fs::read_to_string(dir.join(format!("{stem}.svg"))).unwrap();
    // The tiny study records only its end (one period), which is where the
    // charts read the errors.
    for stem in ["convention_convergence", "convention_work_precision"] {
        let text = svg(stem);
        for c in &study.combinations {
            let escaped = c.label.replace('&', "&amp;");
            assert!(text.contains(&escaped), "{stem}: {}", c.label);
        }
    }
    let stability = svg("convention_stability");
    assert!(stability.contains("stops at Δt = 2.000e-4 s (step 17: det F &lt;= 0 at particle 3)"));
    assert_eq!(
        stability.matches("no stop up to Δt = 3.0e-3 s").count(),
        study.combinations.len() - 1
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
