//! Golden tests of thesis Tables 5.1–7.2: the vibrating bar's RMS errors and
//! convergence orders for linear Lagrange, B-spline and spline-based MPM.

use hompm::tables::{self, RunOptions, Status};

fn check(id: &str) {
    let spec = tables::find(id).unwrap();
    let report = tables::run(
        &spec,
        &RunOptions {
            quick: true,
            ..Default::default()
        },
    )
    .unwrap();
    let (rep, total) = report.counts();
    assert_eq!(rep, total, "{id}: {}", report.render_text());
    assert!(report
        .status
        .iter()
        .flatten()
        .all(|s| *s == Status::Reproduced));
    let text: Vec<String> = report
        .computed
        .iter()
        .map(|r| {
            r.iter()
                .map(|v| format!("{:.6e}", v.unwrap()))
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect();
    insta::with_settings!({snapshot_path => "../golden/snapshots", prepend_module_to_snapshot => false}, {
        insta::assert_snapshot!(format!("{}_computed", id.replace(['-', '.'], "_")), text.join("\n"));
    });
}

/// Table 5.1 (RMS, P1 MPM) and 5.2 (orders): all 19 numbers.
#[test]
fn thesis_5_linear_lagrange() {
    check("thesis-5.1");
    check("thesis-5.2");
}

/// Table 6.2 (RMS, quadratic B-spline MPM) and 6.1 (orders): all 19 numbers.
#[test]
fn thesis_6_bspline() {
    check("thesis-6.2");
    check("thesis-6.1");
}

/// Table 7.1 (RMS, spline-based MPM) and 7.2 (orders): all 19 numbers.
#[test]
fn thesis_7_spline_based() {
    check("thesis-7.1");
    check("thesis-7.2");
}
