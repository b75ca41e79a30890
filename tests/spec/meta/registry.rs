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

/// Issue #25: a number is reproduced to its digits when the computed value,
/// rounded to the published value's printed significant digits, equals it.
#[test]
fn printed_digits_are_counted_from_the_transcription_and_compared_after_rounding() {
    use hompm::tables::{equal_to_digits, significant_digits, Published};
    for (literal, digits) in [
        ("4.9665e-06", 5),
        ("0.27", 2),
        ("450", 3),
        ("-0.0012", 2),
        ("1.0200e-5", 5),
        ("0", 1),
        ("1E+3", 1),
    ] {
        assert_eq!(significant_digits(literal), digits, "{literal}");
    }
    assert!(equal_to_digits(6.4964e-8, 6.496405e-8, 5));
    assert!(!equal_to_digits(1.0137e-9, 1.013860e-9, 5));
    assert!(equal_to_digits(1.0137e-9, 1.01365e-9 + 1e-24, 5));
    assert!(!equal_to_digits(450.0, 451.0, 3));
    assert!(!equal_to_digits(0.27, f64::NAN, 2));
    let json = include_str!("../../../golden/published/thesis-7.1.json");
    let p = Published::parse("thesis-7.1", json).unwrap();
    assert!(
        p.digits.iter().flatten().all(|d| *d == Some(5)),
        "{:?}",
        p.digits
    );
    let blank = json.replacen("4.9665e-06", "null", 1);
    let q = Published::parse("thesis-7.1", &blank).unwrap();
    assert_eq!(q.digits[0][0], None);
    assert_eq!(q.values[0][0], None);
}
