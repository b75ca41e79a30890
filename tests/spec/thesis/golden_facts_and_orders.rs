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
            ("maximum strain, column Table 4.4", "value"),
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

/// Thesis §4.2, Table 4.4: "the maximum strain ε is equal to 9 %". The
/// column's large-strain update (book Eq. 4.16) holds the base at
/// F = 1/(1 + ρ|g|H/E), a strain of 8.93 %, which prints as 9 %, where
/// the small-strain ρ|g|H/E = 9.81 % would print as 10 % (the thesis rounds:
/// Table 4.3's 0.49 % is printed 0.5 %). The experiment: a ULFEM column of
/// Table 4.4 (50 elements, Δt = 1e-3 s: Courant number 0.5) loaded by
/// gravity ramped over 20 s (200 wave transits), whose
/// base element then carries that stretch.
#[test]
fn the_large_deformation_column_strains_nine_percent_at_its_base_under_its_own_law() {
    use hompm::fem::ulfem::{Ulfem, UlfemMaterial};
    use hompm::mpm::musl::{Constitutive, GravityRamp};
    use hompm::scenes::column;
    use hompm::tables::facts::column_static_strain;
    let c = column::parameters("thesis-table-4.4").unwrap();
    assert_eq!(c.constitutive, Constitutive::LargeStrain);
    let elements = 50;
    let material = UlfemMaterial {
        density: c.density,
        young: c.young,
        constitutive: c.constitutive,
        gravity: c.gravity,
        gravity_ramp: Some(GravityRamp::over(20.0)),
    };
    let mut column = Ulfem::new(c.height, elements, material, |_| 0.0, vec![0]).unwrap();
    for _ in 0..20_000 {
        column.step(1e-3).unwrap();
    }
    // The base element's stretch F = h/h0, its centre X = h0/2 carrying the
    // weight ρ|g|(H − h0/2) above it.
    let h0 = c.height / elements as f64;
    let stretch = (column.x[1] - column.x[0]) / h0;
    let s_centre = c.density * c.gravity.abs() * (c.height - h0 / 2.0) / c.young;
    // Within the ramp's dynamic remainder, about s/(ωT) = 3e-4 with
    // ω = πc/(2H) and T = 20 s.
    assert!(
        (stretch - 1.0 / (1.0 + s_centre)).abs() < 5e-4,
        "F = {stretch}"
    );
    let strain = column_static_strain(&c);
    assert!((strain - 0.0981 / 1.0981).abs() < 1e-12);
    // The base element's centre carries 1 % less weight than the base.
    assert!(
        (strain - (1.0 - stretch)).abs() < 1.5e-3,
        "{strain} vs {}",
        1.0 - stretch
    );
    assert!((0.0981 - (1.0 - stretch)).abs() > 8e-3);
    // Rounded to the printed digit: 9 % under the column's law, 10 % as ρ|g|H/E.
    assert_eq!((100.0 * strain).round(), 9.0);
    assert_eq!((100.0 * 0.0981f64).round(), 10.0);
    assert_eq!(
        (1000.0 * column_static_strain(&column::parameters("thesis-table-4.3").unwrap())).round(),
        5.0
    );
    // Each law's static stretch carries the weight: σ(F) = −ρ|g|H, with
    // σ = E(1 − 1/F) (large strain) and the 1D neo-Hookean σ = E(F² − 1)/(2F)
    // at ν = 0.
    let weight = -c.density * c.gravity.abs() * c.height;
    let f = 1.0 - strain;
    assert!((c.young * (1.0 - 1.0 / f) - weight).abs() < 1e-9 * weight.abs());
    let neo = column::ColumnParameters {
        constitutive: Constitutive::NeoHookean,
        ..c
    };
    let f = 1.0 - column_static_strain(&neo);
    assert!((c.young * (f * f - 1.0) / (2.0 * f) - weight).abs() < 1e-9 * weight.abs());
}
