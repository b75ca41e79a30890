//! The table registry couples by label, never by position (issue #14):
//! computed rows find their published rows by label, tolerances are read by
//! label from the published JSON, and an unknown label is an error.

use hompm::tables::{self, Computed, Published, TableSpec, Tolerance};
use hompm::Error;

fn spec(id: &'static str) -> TableSpec {
    tables::find(id).unwrap()
}

#[test]
fn tolerances_are_read_by_label_from_the_published_json() {
    let p = Published::parse("tls-3", spec("tls-3").published_json).unwrap();
    assert_eq!(
        p.tolerance.at("TLS", "MPM Error_M"),
        Tolerance::MachinePrecision
    );
    assert_eq!(
        p.tolerance.at("Cubic-spline", "MPM Error_M"),
        Tolerance::RMS
    );
    let p = Published::parse("tls-1", spec("tls-1").published_json).unwrap();
    let integral = "Relative error for integral (2 Gauss points per element)";
    assert_eq!(p.tolerance.at(integral, "TLS"), Tolerance::MachinePrecision);
    assert_eq!(p.tolerance.at(integral, "Cubic-splines"), Tolerance::RMS);
    // A rule that names a label the table does not have is refused.
    let renamed = spec("tls-3")
        .published_json
        .replacen("\"TLS\": {", "\"TLS mapping\": {", 1);
    assert!(matches!(
        Published::parse("tls-3", &renamed),
        Err(Error::Published { .. })
    ));
}

#[test]
fn computed_rows_are_placed_by_label_and_unknown_labels_are_errors() {
    let s = spec("tls-3");
    let p = Published::parse(s.id, s.published_json).unwrap();
    // Rows in the opposite order of the JSON still land on their labels.
    let computed = Computed {
        rows: vec![
            Computed::row("TLS", [1e-15; 6]),
            Computed::row("Cubic-spline", [2.0; 6]),
        ],
        notes: vec![],
        ..Default::default()
    };
    let r = tables::compare(&s, &p, computed).unwrap();
    assert_eq!(r.row_labels, ["Cubic-spline", "TLS"]);
    assert_eq!(r.computed[0][0], Some(2.0));
    assert_eq!(r.computed[1][0], Some(1e-15));
    // A row that is not returned is not computed.
    let only_tls = Computed {
        rows: vec![Computed::row("TLS", [1e-15; 6])],
        notes: vec![],
        ..Default::default()
    };
    let r = tables::compare(&s, &p, only_tls).unwrap();
    assert!(r.computed[0].iter().all(Option::is_none));
    for rows in [
        vec![Computed::row("Spline", [1.0; 6])],
        vec![
            Computed::row("TLS", [1.0; 6]),
            Computed::row("TLS", [1.0; 6]),
        ],
        vec![Computed::row("TLS", [1.0; 5])],
    ] {
        let bad = Computed {
            rows,
            notes: vec![],
            ..Default::default()
        };
        assert!(matches!(
            tables::compare(&s, &p, bad),
            Err(Error::Published { .. })
        ));
    }
}
