//! Golden tests of `tls-fig6` (convergence orders stated in TLS paper §6.1)
//! and `thesis-facts` (numbers quoted in the texts).

use crate::common;

use hompm::tables::{self, RunOptions, Status};

/// TLS paper §6.1: MPM converges with order 2 in displacement and velocity and
/// order 1 in stress; BSMPM with either reconstruction is third order in
/// displacement and velocity. The stated third order in stress is not
/// reproduced (2.03; docs/reproduction.md).
///
/// Map rows: book-4.38, tls-§5.4-1 — one convergence study, printed in two seeds.
#[test]
fn tls_fig_6_orders_reproduce_except_third_order_in_stress() {
    let report = tables::run(
        &tables::find("tls-fig6").unwrap(),
        &RunOptions {
            quick: true,
            ..Default::default()
        },
    )
    .unwrap();
    let orders = ["displacement", "velocity"];
    for method in ["MPM", "BSMPM + cubic spline", "BSMPM + TLS"] {
        let entries: Vec<(&str, &str)> = orders.iter().map(|o| (method, *o)).collect();
        common::assert_reproduced(&report, &entries);
    }
    common::assert_reproduced(&report, &[("MPM", "stress")]);
    for method in ["BSMPM + cubic spline", "BSMPM + TLS"] {
        let [r, c] = common::cell(&report, method, "stress");
        assert_eq!(report.status[r][c], Status::Deviates, "{method}");
        let s = report.computed[r][c].unwrap();
        assert!((s - 2.0).abs() < 0.1, "{method}: stress order {s}");
    }
    // Plain BSMPM's particle velocity does not converge (the note's order is negative).
    assert!(report
        .notes
        .iter()
        .any(|n| n.starts_with("BSMPM-p2 Direct: particle velocity at t order -0.4")));
}

/// Text facts: positions, Courant numbers, strains, crossings.
#[test]
fn thesis_text_facts_reproduce_as_their_sentences_state_them() {
    let report = tables::run(
        &tables::find("thesis-facts").unwrap(),
        &RunOptions::default(),
    )
    .unwrap();
    common::assert_reproduced(
        &report,
        &[
            ("x_p left of the bar's middle, L = 25 m", "value"),
            ("x_p left of the bar's middle, L = 1 m", "value"),
            ("Courant number, bar Table 4.1", "value"),
            ("Courant number, column Table 4.3, 50 DOFs", "value"),
            ("Courant number, column Table 4.3, 80 DOFs", "value"),
            ("maximum strain, bar Table 4.1", "value"),
            ("maximum strain, bar Table 4.2", "value"),
            ("maximum strain, column Table 4.3", "value"),
            ("'maximal strain' [m], bar TLS Table 2", "value"),
            ("'maximal strain' [m], bar TLS Table 4", "value"),
            ("grid crossings, MPM, bar TLS Table 4", "value"),
        ],
    );
    // The thesis' Courant number for the large-deformation bar uses the wave
    // speed of the small-deformation bar: 3.2e-3 = 1.28e-4 · 25.
    let c = report.computed[3][0].unwrap();
    assert!((c - 3.2e-3 / 10.0 * 2f64.sqrt()).abs() < 1e-9);
}
