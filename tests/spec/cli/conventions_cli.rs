//! `--scheme`, `--transfer`, `--positions`, `--body-force` and `--solution`
//! on the command line: valid in `run`, `trace` and `check`, named in the
//! verdict, matched against a file that names them, refused where they
//! mean nothing (docs/conventions.md, "Conventions of other codes").

use serde_json::Value;
use std::path::PathBuf;

fn scratch(name: &str) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("conventions-cli");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

const BAR: &[&str] = &["vibrating-bar", "--cells", "4", "--steps", "20"];

fn run(extra: &[&str]) -> hompm::Result<hompm::cli::Output> {
    let mut args = vec!["run"];
    args.extend_from_slice(BAR);
    args.extend_from_slice(extra);
    hompm::cli::run(&args)
}

fn check(file: &std::path::Path, extra: &[&str]) -> hompm::Result<hompm::cli::Output> {
    let mut args = vec!["check"];
    args.extend_from_slice(BAR);
    args.extend_from_slice(extra);
    let f = file.to_str().unwrap().to_string();
    args.extend_from_slice(&["--input", &f]);
    hompm::cli::run(&args)
}

#[test]
fn a_run_with_another_codes_conventions_names_them_and_its_own_check_agrees_bit_for_bit() {
    for flags in [
        &["--scheme", "usl"][..],
        &["--scheme", "usf"],
        &["--transfer", "flip:0.99"],
        &["--transfer", "pic"],
        &["--positions", "grid"],
    ] {
        let mut with_json = flags.to_vec();
        with_json.push("--json");
        let text = run(&with_json).unwrap().stdout;
        let doc: Value = serde_json::from_str(&text).unwrap();
        assert!(doc["conventions"].is_object(), "{flags:?}");
        let file = scratch(&format!("{}.json", flags.join("_").replace(':', "-")));
        std::fs::write(&file, &text).unwrap();
        let out = check(&file, flags).unwrap();
        assert!(
            out.stdout.starts_with("agrees"),
            "{flags:?}: {}",
            out.stdout
        );
        assert!(
            out.stdout.contains(flags[1]),
            "the verdict names {flags:?}: {}",
            out.stdout
        );
        // The same file against the book's step is refused, never compared.
        let e = check(&file, &[]).err().unwrap().to_string();
        assert!(e.contains("the file says"), "{e}");
    }
}

#[test]
fn the_default_conventions_leave_the_run_document_unchanged() {
    let plain: Value = serde_json::from_str(&run(&["--json"]).unwrap().stdout).unwrap();
    assert!(plain.get("conventions").is_none());
    let named = run(&[
        "--json",
        "--scheme",
        "musl",
        "--transfer",
        "flip",
        "--positions",
        "projected",
    ])
    .unwrap()
    .stdout;
    assert_eq!(serde_json::from_str::<Value>(&named).unwrap(), plain);
}

#[test]
fn another_codes_step_differs_from_the_books_where_a_check_can_see_it() {
    // USF's velocity at 16 cells over 1999 steps differs by 3e-7 relative,
    // 300 tolerances: a file without metadata is reported as differing.
    let text = hompm::cli::run([
        "run",
        "vibrating-bar",
        "--cells",
        "16",
        "--steps",
        "1999",
        "--scheme",
        "usf",
        "--json",
    ])
    .unwrap()
    .stdout;
    let mut doc: Value = serde_json::from_str(&text).unwrap();
    doc.as_object_mut().unwrap().remove("conventions");
    let file = scratch("usf-anonymous.json");
    std::fs::write(&file, doc.to_string()).unwrap();
    let out = hompm::cli::run([
        "check",
        "vibrating-bar",
        "--cells",
        "16",
        "--steps",
        "1999",
        "--input",
        file.to_str().unwrap(),
    ])
    .unwrap();
    assert!(out.failure.is_some());
    assert!(out.stdout.starts_with("differs"), "{}", out.stdout);
}

#[test]
fn a_trace_of_another_codes_step_carries_its_grid_velocity_keys_and_the_check_names_what_it_left_out(
) {
    let mut args = vec!["trace"];
    args.extend_from_slice(BAR);
    args.extend_from_slice(&["--scheme", "usl", "--json"]);
    let text = hompm::cli::run(&args).unwrap().stdout;
    let mut doc: Value = serde_json::from_str(&text).unwrap();
    let step = &doc["steps"][0]["equations"];
    for key in ["nodal-momentum", "nodal-velocity", "nodal-velocity-updated"] {
        assert!(step.get(key).is_some(), "{key}");
    }
    assert!(step.get("book-4.10").is_none(), "USL projects nothing");
    // Without the header's conventions the check compares what both trace
    // and says what it left out, both ways.
    doc["header"]["discretisation"]
        .as_object_mut()
        .unwrap()
        .remove("conventions");
    let file = scratch("usl-trace.json");
    std::fs::write(&file, doc.to_string()).unwrap();
    let out = match check(&file, &[]) {
        Ok(o) => o.stdout,
        Err(e) => e.to_string(),
    };
    assert!(
        out.contains("not compared: your trace's keys nodal-momentum"),
        "{out}"
    );
    assert!(out.contains("another code's step"), "{out}");
    assert!(
        out.contains("not in your trace: hompm's keys book-4.10"),
        "{out}"
    );
}

#[test]
fn conventions_are_refused_where_they_mean_nothing() {
    let cases: [&[&str]; 6] = [
        &["--scheme", "usl", "--positions", "projected"],
        &["--scheme", "usl", "--mapping", "tls", "--method", "bsmpm"],
        &["--transfer", "flip:1.5"],
        &["--transfer", "apic"],
        &["--scheme", "mls"],
        &["--solution", "axis-aligned"],
    ];
    for flags in cases {
        assert!(run(flags).is_err(), "{flags:?}");
    }
    let e = hompm::cli::run([
        "run",
        "aligned-vibration",
        "--cells",
        "2",
        "--steps",
        "1",
        "--scheme",
        "usf",
    ])
    .err()
    .unwrap()
    .to_string();
    assert!(e.contains("1D only"), "{e}");
}

#[test]
fn the_axis_aligned_solution_runs_in_2d_and_its_exact_fields_follow_it() {
    let args = [
        "aligned-vibration",
        "--cells",
        "4",
        "--ppc",
        "4",
        "--steps",
        "10",
        "--solution",
        "axis-aligned",
        "--body-force",
        "nodes",
        "--method",
        "mpm",
    ];
    let mut run_args = vec!["run"];
    run_args.extend_from_slice(&args);
    let out = hompm::cli::run(&run_args).unwrap().stdout;
    assert!(
        out.contains("--solution axis-aligned") && out.contains("--body-force nodes"),
        "{out}"
    );
    let exact = |form: &str| -> Value {
        serde_json::from_str(
            &hompm::cli::run([
                "exact",
                "aligned-vibration",
                "--time",
                "0.001",
                "--cells",
                "1",
                "--ppc",
                "1",
                "--solution",
                form,
                "--json",
            ])
            .unwrap()
            .stdout,
        )
        .unwrap()
    };
    // One particle at X = (½, ½): sin(π/2) = 1 in the axis-aligned form,
    // sin(π) = 0 in the paper's.
    let aligned = exact("axis-aligned").to_string();
    let paper = exact("mls-paper").to_string();
    assert_ne!(aligned, paper);
}

#[test]
fn taichis_conventions_run_in_2d_and_a_file_of_them_checks_against_the_same_flags_only() {
    let flags = [
        "aligned-vibration",
        "--method",
        "bsmpm",
        "--cells",
        "4",
        "--ppc",
        "4",
        "--steps",
        "10",
        "--transfer",
        "apic",
        "--gradient",
        "affine",
        "--knots",
        "padded",
    ];
    let mut args = vec!["run"];
    args.extend_from_slice(&flags);
    args.push("--json");
    let text = hompm::cli::run(&args).unwrap().stdout;
    let doc: Value = serde_json::from_str(&text).unwrap();
    assert_eq!(doc["conventions"]["scheme"], "usl", "apic implies usl");
    assert_eq!(doc["conventions"]["knots"], "padded");
    let file = scratch("taichi.json");
    std::fs::write(&file, &text).unwrap();
    let f = file.to_str().unwrap().to_string();
    let mut args = vec!["check"];
    args.extend_from_slice(&flags);
    args.extend_from_slice(&["--input", &f]);
    let out = hompm::cli::run(&args).unwrap();
    assert!(out.stdout.starts_with("agrees"), "{}", out.stdout);
    assert!(out.stdout.contains("--gradient affine"), "{}", out.stdout);
    let e = hompm::cli::run([
        "check",
        "aligned-vibration",
        "--method",
        "bsmpm",
        "--cells",
        "4",
        "--ppc",
        "4",
        "--steps",
        "10",
        "--input",
        &f,
    ])
    .err()
    .unwrap()
    .to_string();
    assert!(e.contains("the file says"), "{e}");
}

#[test]
fn a_2d_trace_carries_c_p_with_apic_and_the_nodal_body_force_with_nodes() {
    let trace = |flags: &[&str]| -> Value {
        let mut args = vec![
            "trace",
            "aligned-vibration",
            "--method",
            "bsmpm",
            "--cells",
            "2",
            "--ppc",
            "4",
            "--steps",
            "2",
            "--json",
        ];
        args.extend_from_slice(flags);
        serde_json::from_str(&hompm::cli::run(&args).unwrap().stdout).unwrap()
    };
    let taichi = trace(&["--transfer", "apic", "--knots", "padded"]);
    let step = &taichi["steps"][1]["equations"];
    // 4 particles per cell, 4 cells: 16 particles × 4 entries of C_p; the
    // padded grid has (2 + 3)² nodes.
    assert_eq!(step["apic-c"].as_array().unwrap().len(), 16 * 4);
    assert_eq!(step["mls-22"].as_array().unwrap().len(), 25);
    assert!(step.get("nodal-body-force").is_none());
    let nodes = trace(&["--body-force", "nodes"]);
    let step = &nodes["steps"][0]["equations"];
    assert_eq!(step["nodal-body-force"].as_array().unwrap().len(), 2 * 16);
    assert!(step.get("apic-c").is_none());
}

/// `hompm <command> <setup> <extra> --json`'s stdout in a scratch file;
/// its path.
fn written(command: &str, setup: &[&str], extra: &[&str], name: &str) -> String {
    let mut args = vec![command];
    args.extend_from_slice(setup);
    args.extend_from_slice(extra);
    args.push("--json");
    let file = scratch(name);
    std::fs::write(&file, hompm::cli::run(&args).unwrap().stdout).unwrap();
    file.to_str().unwrap().to_string()
}

/// `hompm check <setup> <extra> --input <path>`.
fn check_file(setup: &[&str], extra: &[&str], path: &str) -> hompm::Result<hompm::cli::Output> {
    let mut args = vec!["check"];
    args.extend_from_slice(setup);
    args.extend_from_slice(extra);
    args.extend_from_slice(&["--input", path]);
    hompm::cli::run(&args)
}

const TWO_2D: &[&str] = &[
    "aligned-vibration",
    "--method",
    "mpm",
    "--cells",
    "2",
    "--ppc",
    "4",
    "--steps",
    "3",
];
const FOUR_2D: &[&str] = &[
    "aligned-vibration",
    "--method",
    "bsmpm",
    "--cells",
    "4",
    "--ppc",
    "4",
    "--steps",
    "3",
];

#[test]
fn a_trace_or_run_that_names_other_conventions_is_refused_by_a_default_check() {
    // A USL trace against the book's step: its header names the scheme.
    let usl = written("trace", BAR, &["--scheme", "usl"], "named-usl-trace.json");
    let e = check_file(BAR, &[], &usl).unwrap_err().to_string();
    assert!(e.contains("discretisation.conventions."), "{e}");
    // The axis-aligned solution, named by a run and by a trace.
    for command in ["run", "trace"] {
        let axis = written(
            command,
            TWO_2D,
            &["--solution", "axis-aligned"],
            &format!("axis-{command}.json"),
        );
        let e = check_file(TWO_2D, &[], &axis).unwrap_err().to_string();
        assert!(e.contains("solution"), "{command}: {e}");
    }
    // Knots and gradient named by a run.
    let taichi = [
        "--transfer",
        "apic",
        "--gradient",
        "affine",
        "--knots",
        "padded",
    ];
    let file = written("run", FOUR_2D, &taichi, "named-taichi.json");
    let e = check_file(
        FOUR_2D,
        &taichi[..2]
            .iter()
            .chain(&taichi[4..])
            .copied()
            .collect::<Vec<_>>(),
        &file,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("gradient = affine"), "{e}");
}

#[test]
fn a_2d_trace_with_projected_positions_checks_against_its_own_run() {
    let projected = ["--positions", "projected"];
    let trace = written("trace", FOUR_2D, &projected, "projected-trace.json");
    let out = check_file(FOUR_2D, &projected, &trace).unwrap();
    assert!(out.stdout.starts_with("agrees"), "{}", out.stdout);
}

#[test]
fn an_invalid_combination_of_conventions_is_a_usage_error_of_check() {
    for flags in [
        &["vibrating-bar", "--knots", "padded"][..],
        &["vibrating-bar", "--transfer", "apic"],
        &["aligned-vibration", "--scheme", "usf"],
        &["aligned-vibration", "--method", "mpm", "--transfer", "apic"],
        &["aligned-vibration", "--method", "mpm", "--knots", "padded"],
    ] {
        let mut args = vec!["check"];
        args.extend_from_slice(flags);
        args.extend_from_slice(&["--input", "/nonexistent"]);
        let e = hompm::cli::run(&args).unwrap_err();
        assert_eq!(hompm::cli::exit_code(&e), 2, "{flags:?}: {e}");
        let m = e.to_string();
        assert!(
            m.contains("only") || m.contains("quadratic B-splines"),
            "{flags:?}: {m}"
        );
    }
}

#[test]
fn the_2d_default_is_the_mls_papers_step_and_names_nothing() {
    let two = [
        "aligned-vibration",
        "--method",
        "bsmpm",
        "--cells",
        "2",
        "--ppc",
        "4",
        "--steps",
        "3",
        "--json",
    ];
    let mut args = vec!["run"];
    args.extend_from_slice(&two);
    let plain = hompm::cli::run(&args).unwrap().stdout;
    args.extend_from_slice(&[
        "--positions",
        "grid",
        "--scheme",
        "musl",
        "--transfer",
        "flip",
    ]);
    let named = hompm::cli::run(&args).unwrap().stdout;
    assert_eq!(plain, named);
    let doc: Value = serde_json::from_str(&plain).unwrap();
    assert!(doc.get("conventions").is_none());
    // hompm's own 2D u is its x − x0 bit for bit: the check says so.
    let file = scratch("own-2d.json");
    std::fs::write(&file, &plain).unwrap();
    let f = file.to_str().unwrap().to_string();
    let mut args = vec!["check"];
    args.extend_from_slice(&two[..9]);
    args.extend_from_slice(&["--input", &f]);
    let out = hompm::cli::run(&args).unwrap().stdout;
    assert!(out.contains("(your u_x, bit for bit)"), "{out}");
}

#[test]
fn natural_knots_run_name_themselves_and_are_refused_where_they_mean_nothing() {
    for degree in ["2", "3"] {
        let flags = [
            "--method", "bsmpm", "--degree", degree, "--knots", "natural",
        ];
        let mut with_json = flags.to_vec();
        with_json.push("--json");
        let text = run(&with_json).unwrap().stdout;
        let doc: Value = serde_json::from_str(&text).unwrap();
        assert_eq!(doc["conventions"]["knots"], "natural");
        let file = scratch(&format!("natural-{degree}.json"));
        std::fs::write(&file, &text).unwrap();
        let out = check(&file, &flags).unwrap();
        assert!(out.stdout.starts_with("agrees"), "{}", out.stdout);
        assert!(out.stdout.contains("--knots natural"), "{}", out.stdout);
        // The same file against open knots is refused, never compared.
        assert!(check(&file, &flags[..4]).is_err());
    }
    for flags in [
        &["vibrating-bar", "--knots", "natural"][..],
        &["vibrating-bar", "--method", "mpm-p2", "--knots", "natural"],
        &[
            "vibrating-bar",
            "--method",
            "bsmpm",
            "--degree",
            "4",
            "--knots",
            "natural",
        ],
        &[
            "vibrating-bar",
            "--method",
            "bsmpm",
            "--knots",
            "natural",
            "--mass",
            "consistent",
        ],
        &[
            "aligned-vibration",
            "--method",
            "bsmpm",
            "--knots",
            "natural",
        ],
    ] {
        let mut args = vec!["check"];
        args.extend_from_slice(flags);
        args.extend_from_slice(&["--input", "/nonexistent"]);
        let e = hompm::cli::run(&args).unwrap_err();
        assert_eq!(hompm::cli::exit_code(&e), 2, "{flags:?}: {e}");
        assert!(e.to_string().contains("natural"), "{flags:?}: {e}");
    }
}
