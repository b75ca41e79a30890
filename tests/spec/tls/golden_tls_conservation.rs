//! TLS paper Table 3 (and book §4.5): conservation of total mass and momentum
//! by the TLS and cubic-spline mappings, vibrating bar, 40 elements, 12 PPC.

use crate::common;

use hompm::mpm::grid::Method;
use hompm::mpm::mapping::Mapping;
use hompm::studies::tls_paper::conservation_errors;
use hompm::tables::{self, RunOptions};

/// TLS conserves mass and momentum to machine precision (≤ 1e-13) for MPM,
/// DDMPM and BSMPM (TLS paper §5.5, Table 3).
///
/// Map rows: book-4.42, book-4.43, book-4.44, tls-15, tls-§5.4-3 — one conservation proof, printed in two seeds.
#[test]
fn tls_mapping_conserves_to_machine_precision() {
    for method in [Method::Mpm, Method::DDMPM, Method::Bsmpm { degree: 2 }] {
        let (m, p) = conservation_errors(method, Mapping::Tls, 40, 12).unwrap();
        assert!(
            m <= 1e-13 && p <= 1e-13,
            "{method:?}: mass {m:e}, momentum {p:e}"
        );
    }
}

/// The registered table (TLS paper Table 3): every TLS error at machine
/// precision and three cubic-spline errors reproduce, each checked by name;
/// the MPM cubic-spline mass error and the BSMPM cubic-spline momentum error
/// match the paper to < 0.3 %. The four deviating entries are explained in
/// docs/reproduction.md.
#[test]
fn tls_table_3_tls_errors_are_at_machine_precision_and_three_cubic_spline_errors_reproduce() {
    let report = tables::run(
        &tables::find("tls-3").unwrap(),
        &RunOptions {
            quick: true,
            ..Default::default()
        },
    )
    .unwrap();
    common::assert_reproduced(
        &report,
        &[
            ("TLS", "MPM Error_M"),
            ("TLS", "MPM Error_P"),
            ("TLS", "DDMPM Error_M"),
            ("TLS", "DDMPM Error_P"),
            ("TLS", "BSMPM Error_M"),
            ("Cubic-spline", "MPM Error_M"),
            ("Cubic-spline", "BSMPM Error_M"),
            ("Cubic-spline", "BSMPM Error_P"),
        ],
    );
    for col in ["MPM Error_M", "BSMPM Error_P"] {
        let [r, c] = common::cell(&report, "Cubic-spline", col);
        assert!(
            report.deviation[r][c].unwrap().abs() < 0.003,
            "Cubic-spline / {col}"
        );
    }
}
