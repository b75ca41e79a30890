//! The command line as users meet it: JSON schemas, and one-line errors.

use std::process::Command;

fn hompm(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_hompm"))
        .args(args)
        .output()
        .expect("the binary runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn basis_json_has_the_documented_keys() {
    let (code, out, _) = hompm(&[
        "basis",
        "--degree",
        "2",
        "--knots",
        "0,0,0,0.5,1,1,1",
        "--at",
        "0,0.25,1",
        "--json",
    ]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["degree"], 2);
    assert_eq!(v["knots"].as_array().unwrap().len(), 7);
    assert_eq!(v["points"].as_array().unwrap().len(), 3);
    let values = v["values"].as_array().unwrap();
    assert_eq!(values.len(), 3);
    assert_eq!(values[0].as_array().unwrap().len(), 4);
    assert!(
        v.get("derivatives").is_none(),
        "derivatives only with --derivatives"
    );
    let (_, out, _) = hompm(&[
        "basis",
        "--degree",
        "2",
        "--knots",
        "0,0,0,0.5,1,1,1",
        "--at",
        "0.25",
        "--json",
        "--derivatives",
    ]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let d = v["derivatives"][0].as_array().unwrap();
    let sum: f64 = d.iter().map(|x| x.as_f64().unwrap()).sum();
    assert!(sum.abs() < 1e-12);
}

#[test]
fn bad_input_is_one_line_on_stderr_and_non_zero() {
    let cases: &[&[&str]] = &[
        &[
            "basis", "--degree", "2", "--knots", "0,1,0.5", "--at", "0.2",
        ],
        &[
            "basis",
            "--degree",
            "2",
            "--knots",
            "0,0,0,1,1,1",
            "--at",
            "2",
        ],
        &[
            "basis",
            "--degree",
            "2",
            "--knots",
            "0,0,0,1,1,1",
            "--at",
            "nan",
        ],
        &[
            "basis", "--degree", "9", "--knots", "0,0,1,1", "--at", "0.5",
        ],
        &[
            "basis", "--degree", "1", "--knots", "0,0,x,1", "--at", "0.5",
        ],
        &["basis", "--degree", "-1", "--knots", "0,1", "--at", "0.5"],
        &[
            "basis",
            "--degree",
            "1",
            "--knots",
            "0,0,0,0,1,1",
            "--at",
            "0.5",
        ],
        &["basis", "--degree", "1", "--knots", "", "--at", "0.5"],
        &["table", "no-such-table"],
        &["frobnicate"],
        &[],
        &["basis", "--degree", "1", "--knots", "0,1\n2", "--at", "0"],
        &["table", "no\nsuch\u{1b}[31mtable"],
        &[
            "run",
            "vibrating-bar",
            "--cells",
            "8",
            "--ppc",
            "12",
            "--steps",
            "1",
            "--dt",
            "31.25",
        ],
    ];
    for args in cases {
        let (code, out, err) = hompm(args);
        assert_ne!(code, 0, "{args:?} succeeded");
        assert!(out.is_empty(), "{args:?} printed to stdout: {out}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    }
}

#[test]
fn table_json_follows_the_schema() {
    let (code, out, _) = hompm(&["table", "thesis-a1", "--json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for key in [
        "id",
        "title",
        "seed",
        "source",
        "setup",
        "row_labels",
        "col_labels",
        "published",
        "computed",
        "deviation",
        "status",
    ] {
        assert!(v.get(key).is_some(), "missing key {key}");
    }
    assert_eq!(v["status"][4][0], "reproduced");
    let (code, out, _) = hompm(&["table", "--list"]);
    assert_eq!(code, 0);
    assert!(out.contains("thesis-a1"));
}

#[test]
fn reproduce_prints_the_summary_line() {
    let (code, out, _) = hompm(&["reproduce", "--quick"]);
    assert_eq!(code, 0);
    assert!(out
        .lines()
        .any(|l| l.contains("published numbers reproduced;")
            && l.ends_with("to their printed digits")));
}

#[test]
fn mass_json_has_the_documented_keys() {
    let (code, out, err) = hompm(&[
        "mass",
        "--degree",
        "3",
        "--spans",
        "8",
        "--dim",
        "2",
        "--dirichlet",
        "--condition",
        "--solve",
        "pmg",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for key in [
        "size",
        "lambda_min",
        "lambda_max",
        "condition_number",
        "iterations",
        "residuals",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert_eq!(v["size"], 81);
    assert_eq!(v["iterations"], 15, "book Table 4.4, p = 3, 1/h = 8");
    let kappa = v["condition_number"].as_f64().unwrap();
    assert!(
        (kappa - 440.0).abs() < 0.01 * 440.0,
        "book Table 4.2: {kappa}"
    );
    let (code, _, err) = hompm(&["mass", "--degree", "2", "--spans", "4", "--solve", "nope"]);
    assert_ne!(code, 0);
    assert_eq!(err.trim_end().lines().count(), 1);
}

/// JSON never carries `null` for a number that cannot be written (issue #13):
/// before the first step the minima over steps have no value and are left
/// out; after a step they are numbers.
#[test]
fn run_json_has_no_null_standing_for_infinity() {
    for steps in ["0", "3"] {
        let (code, out, err) = hompm(&["run", "vibrating-bar", "--steps", steps, "--json"]);
        assert_eq!(code, 0, "{err}");
        assert!(!out.contains("null"), "--steps {steps}: {out}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        let d = &v["diagnostics"];
        assert_eq!(d["min_lumped_mass"].is_number(), steps != "0");
        assert_eq!(d["min_mass_diagonal_ratio"].is_number(), steps != "0");
    }
}

/// `hompm reconstruct --taylor-average`: on a cell far from the origin the
/// TLS author's antiderivative forms round differently from the exact
/// average (docs/conventions.md, "The TLS author's cell average"), and each
/// prints what the library computes with that average; a value that is not
/// one of the three is one line on stderr and exit 2.
#[test]
fn reconstruct_prints_the_tls_fit_under_each_taylor_average() {
    use hompm::reconstruct::taylor::{reconstruct, CellAverage, TlsOptions};
    let (points, values) = ([999.1, 1000.0, 1000.5], [1.2, 2.0, 2.5]);
    let at = [1000.0 - 0.5773502691896257, 1000.0 + 0.5773502691896257];
    let join = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:?}"))
            .collect::<Vec<_>>()
            .join(",")
    };
    let printed = |average: &str| {
        let (code, out, err) = hompm(&[
            "reconstruct",
            "--method",
            "tls-conservative",
            "--cells=999,1001",
            &format!("--points={}", join(&points)),
            &format!("--values={}", join(&values)),
            "--integrals=4",
            &format!("--at={}", join(&at)),
            "--taylor-average",
            average,
            "--json",
        ]);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        let got: Vec<f64> = v["values"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        got
    };
    let library = |average| {
        let options = TlsOptions {
            average,
            ..TlsOptions::default()
        };
        let r = reconstruct(&[(999.0, 1001.0)], &points, &values, Some(&[4.0]), options).unwrap();
        at.iter()
            .map(|&x| r.value_at(x).unwrap())
            .collect::<Vec<f64>>()
    };
    let exact = printed("exact");
    for (name, average) in [
        ("exact", CellAverage::Exact),
        (
            "antiderivative-difference",
            CellAverage::AntiderivativeDifference,
        ),
        (
            "antiderivative-six-terms",
            CellAverage::AntiderivativeSixTerms,
        ),
    ] {
        let got = printed(name);
        assert_eq!(got, library(average), "{name}");
        if average != CellAverage::Exact {
            assert_ne!(got, exact, "{name} rounds like the exact average");
        }
    }
    let (code, out, err) = hompm(&[
        "reconstruct",
        "--method",
        "tls-conservative",
        "--cells=0,1",
        "--points=0.2,0.5,0.7",
        "--values=1,2,3",
        "--integrals=2",
        "--at=0.5",
        "--taylor-average",
        "rounded",
    ]);
    assert_eq!((code, out.as_str()), (2, ""));
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
}
