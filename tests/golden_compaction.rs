//! Column compaction (TLS paper §6.2): the standard-MPM and TLS stress errors
//! of Fig. 10 and TLS's conservation (Table 7). The full 3×3 table runs in
//! `hompm reproduce`; this test runs the two cheapest cells.

use hompm::mpm::grid::Method;
use hompm::mpm::mapping::Mapping;
use hompm::tables::tls::compaction;

#[test]
fn compaction_mpm_and_tls() {
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
