//! TLS paper Table 3 (and book §4.5): conservation of total mass and momentum
//! by the TLS and cubic-spline mappings, vibrating bar, 40 elements, 12 PPC.

use hompm::mpm::grid::Method;
use hompm::mpm::mapping::Mapping;
use hompm::tables::tls::conservation_errors;
use hompm::tables::{self, RunOptions};

/// TLS conserves mass and momentum to machine precision (≤ 1e-13) for MPM,
/// DDMPM and BSMPM (TLS paper §5.5, Table 3).
#[test]
fn tls_mapping_conserves_to_machine_precision() {
    for method in [Method::Mpm, Method::Ddmpm, Method::Bsmpm { degree: 2 }] {
        let (m, p) = conservation_errors(method, Mapping::Tls, 40, 12).unwrap();
        assert!(
            m <= 1e-13 && p <= 1e-13,
            "{method:?}: mass {m:e}, momentum {p:e}"
        );
    }
}

/// The registered table: 8 of 12 reproduce; the MPM cubic-spline mass error
/// and the BSMPM cubic-spline momentum error match the paper to < 0.3 %.
#[test]
fn tls_3_table() {
    let report = tables::run(&tables::find("tls-3").unwrap(), &RunOptions { quick: true }).unwrap();
    assert_eq!(report.counts(), (8, 12), "{}", report.render_text());
    assert!(report.deviation[0][0].unwrap().abs() < 0.003);
    assert!(report.deviation[0][5].unwrap().abs() < 0.003);
}
