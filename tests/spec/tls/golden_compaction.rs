//! Column compaction (TLS paper §6.2): the standard-MPM and TLS stress errors
//! of Fig. 10 and TLS's conservation (Table 7). The full 3×3 table runs in
//! `hompm reproduce`; this test runs the two cheapest cells.

use hompm::mpm::grid::Method;
use hompm::mpm::mapping::Mapping;
use hompm::studies::tls_paper::compaction;

#[test]
fn tls_fig_10_tls_cuts_the_compaction_stress_error_five_fold_and_conserves() {
    let mpm = compaction(Method::Mpm, Mapping::Direct).unwrap();
    let tls = compaction(Method::Mpm, Mapping::Tls).unwrap();
    // Fig. 10: E = 4.4677e-2 (ours +5.3 %), E_TLS = 9.2396e-3 (ours −1.5 %).
    assert!(
        (mpm.stress_error / 4.4677e-2 - 1.0).abs() < 0.06,
        "{}",
        mpm.stress_error
    );
    assert!(
        (tls.stress_error / 9.2396e-3 - 1.0).abs() < 0.02,
        "{}",
        tls.stress_error
    );
    // TLS reduces the MPM error about five-fold and conserves to ≤ 1e-13.
    assert!(mpm.stress_error > 4.5 * tls.stress_error);
    assert!(tls.mass_error <= 1e-13 && tls.momentum_error <= 1e-12);
    // "material points cross element boundaries 180 times": 189 here.
    assert!((170..=200).contains(&mpm.crossings), "{}", mpm.crossings);
}

/// TLS paper §6.1 (Fig. 9): every reconstruction reduces the MPM stress error
/// against ULFEM at least five-fold, and BSMPM + cubic splines most (14.2 here,
/// 13.5 published); the other published factors are not reproduced
/// (docs/reproduction.md).
#[test]
fn reconstructions_reduce_the_large_deformation_stress_error() {
    use hompm::studies::tls_paper::stress_errors_against_ulfem;
    let b = Method::Bsmpm { degree: 2 };
    let v = [
        (Method::Mpm, Mapping::Direct),
        (b, Mapping::CubicSpline),
        (b, Mapping::Tls),
        (Method::DDMPM, Mapping::CubicSpline),
        (Method::DDMPM, Mapping::Tls),
    ];
    let e = stress_errors_against_ulfem("tls-table-4", 400, 20, 8, 1e-4, 1000, &v).unwrap();
    let factors: Vec<f64> = e[1..].iter().map(|(_, x)| e[0].1 / x).collect();
    assert!(factors.iter().all(|f| *f > 5.0), "{factors:?}");
    assert!(
        factors[0] > factors[1] && factors[0] > factors[3] - 3.0,
        "{factors:?}"
    );
    assert!((factors[0] / 13.5 - 1.0).abs() < 0.1, "{factors:?}");
}
