//! The reproducers of issue #13, in process: each gives a typed error (one
//! line, with the numbers) or a correct result, never a panic, a silent NaN
//! or a diverged run reported as a success.

use hompm::cli::{self, Output};
use hompm::error::DivergenceCause;
use hompm::Error;

fn run(args: &str) -> hompm::Result<Output> {
    cli::run(args.split_whitespace())
}

fn refused(args: &str) -> Error {
    match run(args) {
        Ok(out) => panic!("{args} succeeded: {}", out.stdout),
        Err(e) => {
            assert!(!cli::one_line(&e.to_string()).contains('\n'));
            e
        }
    }
}

#[test]
fn sizes_beyond_the_limits_are_refused_before_any_work_with_the_estimate() {
    for args in [
        "run vibrating-bar --cells 9223372036854775807",
        "run vibrating-bar --cells 1000000000",
        "mass --degree 9223372036854775808 --spans 16",
        "mass --degree 1 --spans 100000 --condition",
        "mass --degree 100 --spans 4 --dim 2",
        "run vibrating-bar --cells 1 --ppc 1 --steps 100000000000",
    ] {
        match refused(args) {
            Error::OverLimit { flag, needed, .. } => {
                assert!(flag.starts_with("--max-"), "{args}: {flag}");
                assert!(!needed.is_empty());
            }
            other => panic!("{args}: {other:?}"),
        }
    }
    // --condition on 100 001 DOFs: two dense matrices of 80 GB each.
    let e = refused("mass --degree 1 --spans 100000 --condition");
    assert!(e.to_string().contains("149.0 GiB"), "{e}");
    // A raised limit lets the same command through to the next limit.
    assert!(run("--max-memory 1GiB mass --degree 2 --spans 12000 --condition").is_err());
    assert!(
        run("--max-memory 4GiB --max-seconds 60 mass --degree 2 --spans 12000 --condition")
            .is_err()
    );
    assert!(run("--max-memory 1TiB mass --degree 2 --spans 40 --condition").is_ok());
}

#[test]
fn huge_degrees_and_orders_are_errors_not_panics_or_hangs() {
    assert!(matches!(
        refused("basis --degree 18446744073709551615 --knots 0,1 --at 0"),
        Error::InvalidDegree(_)
    ));
    assert!(matches!(
        refused("reconstruct --method tls --cells 0,1 --points 0.2,0.5,0.7 --values 1,2,3 --at 0.5 --order 18446744073709551615"),
        Error::InvalidDegree(_)
    ));
    assert!(matches!(
        refused("reconstruct --method tls --cells 0,1 --points 0.2,0.5,0.7 --values 1,2,3 --at 0.5 --order 21"),
        Error::InvalidDegree(_)
    ));
}

#[test]
fn numbers_double_precision_cannot_compute_are_refused_with_the_reason() {
    for args in [
        "basis --degree 1 --knots 0,0,5e-324,5e-324 --at 0",
        "basis --degree 1 --knots -1e308,-1e308,1e308,1e308 --at 0",
    ] {
        assert!(matches!(refused(args), Error::InvalidKnots(_)), "{args}");
    }
    let e = refused("reconstruct --method tls-conservative --cells 0,1e308 --points 1e307,5e307,7e307 --values 1,2,3 --integrals 1 --at 1");
    assert!(e.to_string().contains("overflows"), "{e}");
    match refused("mass --degree 2 --spans 8 --solve cg --tol 5e-324") {
        Error::InvalidArgument(m) => assert!(m.contains("ε"), "{m}"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_spectrum_below_rounding_is_named_ill_conditioned_with_kappa() {
    match refused("mass --degree 30 --spans 8 --condition") {
        Error::IllConditioned { kappa_at_least, .. } => assert!(kappa_at_least > 1e13),
        other => panic!("{other:?}"),
    }
}

/// The cause behind a time step above the critical one: the divergence the
/// run failed with (the cause itself when there is no such wrapper).
fn underlying(cause: DivergenceCause) -> DivergenceCause {
    match cause {
        DivergenceCause::TimeStepAboveCritical { failure, .. } => match *failure {
            Error::Diverged { cause, .. } => underlying(cause),
            other => panic!("{other:?}"),
        },
        other => other,
    }
}

#[test]
fn diverged_runs_are_errors_naming_step_particle_and_cause() {
    // Δt = 31.25 is far above the critical step; the failure it leads to is
    // the energy growth.
    match refused("run vibrating-bar --cells 8 --ppc 12 --steps 1 --dt 31.25") {
        Error::Diverged {
            step,
            particle,
            cause,
            ..
        } => {
            assert_eq!(step, 1);
            assert!(particle.is_some());
            assert!(
                matches!(cause, DivergenceCause::TimeStepAboveCritical { dt, critical_dt, .. } if dt == 31.25 && critical_dt < dt)
            );
            match underlying(cause) {
                DivergenceCause::EnergyGrowth {
                    energy,
                    bound,
                    budget,
                } => assert!(
                    energy > budget && bound == hompm::mpm::monitor::ENERGY_GROWTH_BOUND,
                    "{energy} {budget}"
                ),
                other => panic!("{other:?}"),
            }
        }
        other => panic!("{other:?}"),
    }
    match refused("run column-top-load --params thesis-table-8.1 --method bsmpm --degree 2 --ppc 3 --steps 300 --dt 0.0125 --json") {
        Error::Diverged { step, particle, cause, .. } => {
            assert!(step < 300);
            assert!(particle.is_some());
            match underlying(cause) {
                DivergenceCause::StrainLimit { strain } => assert!(strain.abs() >= 1.0),
                other => panic!("{other:?}"),
            }
        }
        other => panic!("{other:?}"),
    }
    // Δt far above the critical step: the cause is named, not an infinite
    // right-hand side.
    match refused("run vibrating-bar --dt 1e308 --steps 1") {
        Error::Diverged { step, cause, .. } => {
            assert_eq!(step, 1);
            match cause {
                DivergenceCause::TimeStepAboveCritical {
                    dt, critical_dt, ..
                } => assert!(dt == 1e308 && critical_dt < dt),
                other => panic!("{other:?}"),
            }
        }
        other => panic!("{other:?}"),
    }
}

/// t = n·Δt must exist: a run whose end time overflows is refused before
/// it starts, instead of reporting "t = inf" and RMS errors of null.
#[test]
fn a_run_whose_time_overflows_is_refused() {
    let e = refused("run vibrating-bar --cells 1 --dt 1e308");
    assert!(e.to_string().contains("overflows the time"), "{e}");
}

#[test]
fn suspicious_runs_succeed_with_warnings_on_stderr_and_in_json() {
    // P2 with one particle per element: negative lumped masses (thesis §5.2).
    let out =
        run("run vibrating-bar --method mpm-p2 --cells 4 --ppc 1 --steps 100 --json").unwrap();
    assert!(
        out.warnings
            .iter()
            .any(|w| w.contains("negative lumped masses")),
        "{:?}",
        out.warnings
    );
    let v: serde_json::Value = serde_json::from_str(&out.stdout).unwrap();
    assert_eq!(v["warnings"][0]["kind"], "negative-lumped-mass");
    // Thesis Table 4.1: E = 100, ρ = 1, L = 25, so c = 10 and h = 25/16;
    // MPM's measured C_crit = 1.65 gives Δt_crit = 1.65 · 1.5625 / 10 = 0.2578.
    let out = run("run vibrating-bar --dt 0.26 --steps 5").unwrap();
    assert!(
        out.warnings.iter().any(|w| w.contains("critical step")),
        "{:?}",
        out.warnings
    );
    let out = run("run vibrating-bar --dt 0.257 --steps 5").unwrap();
    assert!(out.warnings.is_empty(), "{:?}", out.warnings);
}

#[test]
fn every_reconstruction_refuses_a_query_outside_the_cells() {
    for method in ["tls", "cubic-spline", "cubic-spline-natural", "mls"] {
        let args = format!("reconstruct --method {method} --cells 0,0.5,1 --points 0.1,0.2,0.4,0.6,0.8,0.9 --values 1,2,3,4,5,6 --at 1.5");
        assert!(
            matches!(refused(&args), Error::OutsideDomain { .. }),
            "{method}"
        );
        let inside = args.replace("--at 1.5", "--at 0.5,1");
        assert!(run(&inside).is_ok(), "{method}");
    }
}

#[test]
fn usage_errors_are_one_sentence_and_exit_two() {
    for args in [
        "",
        "frobnicate",
        "run vibrating-bar --cells -1",
        "mass --degree 2 --spans 8 --solve bogus",
    ] {
        let e = refused(args);
        assert!(matches!(e, Error::Usage(_)), "{args}: {e:?}");
        assert_eq!(cli::exit_code(&e), 2);
    }
    let e = refused("run vibrating-bar --cells -1");
    assert!(e.to_string().contains("negative"), "{e}");
    assert!(!refused("mass --degree 2 --spans 8 --solve bogus")
        .to_string()
        .contains('\n'));
    assert_eq!(cli::one_line("a\nb\u{1b}c"), "a\\nb\\u{1b}c");
}

#[test]
fn arguments_are_checked_before_the_expensive_part() {
    // Bad --tol is refused before a spectrum that would take minutes.
    let e = refused("mass --degree 2 --spans 3000 --condition --solve cg --tol 0");
    assert!(matches!(e, Error::InvalidArgument(_)), "{e:?}");
    // reproduce checks --only and --out before computing a table.
    assert!(matches!(
        refused("reproduce --only no-such-table"),
        Error::UnknownTable(_)
    ));
    assert!(matches!(
        refused("reproduce --out /proc/hompm-cannot-write-here --quick"),
        Error::Io(_)
    ));
}

#[test]
fn table_list_json_is_json() {
    let out = run("table --list --json").unwrap();
    let v: serde_json::Value = serde_json::from_str(&out.stdout).unwrap();
    let ids: Vec<&str> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t["id"].as_str().unwrap())
        .collect();
    assert_eq!(ids, hompm::tables::ids());
}

/// `hompm run aligned-vibration` (MLS paper): the JSON has the 1D run's keys
/// with [x, y] pairs and 2×2 tensors as rows, and what the 2D scene cannot
/// do is refused with a sentence.
#[test]
fn the_2d_run_prints_tensor_fields_and_refuses_what_it_cannot_do() {
    let out = run("run aligned-vibration --method bsmpm-mls --cells 4 --steps 5 --json").unwrap();
    let v: serde_json::Value = serde_json::from_str(&out.stdout).unwrap();
    assert_eq!(v["scene"], "aligned-vibration");
    assert_eq!(v["mapping"], "mls");
    assert_eq!(v["ppc"], 9);
    assert_eq!(v["particles"]["x"].as_array().unwrap().len(), 16 * 9);
    assert_eq!(v["particles"]["stress"][0].as_array().unwrap().len(), 4);
    assert_eq!(
        v["particles"]["deformation_gradient"][0]
            .as_array()
            .unwrap()
            .len(),
        4
    );
    for key in [
        "rms_displacement",
        "rms_velocity",
        "rms_stress",
        "mapping_mass_error",
    ] {
        assert!(v["diagnostics"][key].as_f64().unwrap().is_finite(), "{key}");
    }
    // BSMPM with 2D TLS: its mapping is named, it conserves the mass to
    // the rounding of the sums, and it reports its repairs and κ.
    let out = run("run aligned-vibration --method bsmpm-tls --cells 4 --steps 5 --json").unwrap();
    let v: serde_json::Value = serde_json::from_str(&out.stdout).unwrap();
    assert_eq!(v["mapping"], "tls");
    let d = &v["diagnostics"];
    assert!(d["mapping_mass_error"].as_f64().unwrap() < 1e-13, "{d}");
    assert_eq!(d["most_repaired_cells"], 0);
    assert!(d["largest_condition_number"].as_f64().unwrap() >= 1.0);
    for (args, needle) in [
        (
            "run aligned-vibration --method ddmpm --steps 1",
            "runs mpm, bsmpm",
        ),
        (
            "run aligned-vibration --ppc 5 --steps 1",
            "must be a square",
        ),
        (
            "run vibrating-bar --method bsmpm-mls",
            "only in the 2D scene",
        ),
        (
            "run vibrating-bar --method bsmpm-tls",
            "only in the 2D scene",
        ),
        (
            "run aligned-vibration --method bsmpm-tls --degree 0 --steps 1",
            "needs --degree ≥ 1",
        ),
        (
            "run aligned-vibration --params nope --steps 1",
            "unknown parameter set",
        ),
        (
            "run aligned-vibration --cells 5000 --steps 100000",
            "--max-memory",
        ),
    ] {
        let e = refused(args).to_string();
        assert!(e.contains(needle), "{args}: {e}");
    }
}

/// Every 1D scene prints its run as JSON (an unset option of a parameter
/// set is left out, not written as null), and DDMPM's JSON names its
/// node-integral rule (TLS paper §3.3; issue #11).
#[test]
fn every_1d_scene_prints_json_and_ddmpm_names_its_node_integrals() {
    for scene in ["vibrating-bar", "column-self-weight", "column-top-load"] {
        let out = run(&format!("run {scene} --steps 3 --json")).unwrap();
        let v: serde_json::Value = serde_json::from_str(&out.stdout).unwrap();
        assert_eq!(v["scene"], scene);
        assert!(v.get("node_integrals").is_none(), "{scene}");
    }
    for (flag, rule) in [
        ("exact", serde_json::json!("exact")),
        ("particles", serde_json::json!("particles")),
        ("subpoints:8", serde_json::json!({"subpoints": 8})),
    ] {
        let out = run(&format!(
            "run column-self-weight --method ddmpm --node-integrals {flag} --steps 3 --json"
        ))
        .unwrap();
        let v: serde_json::Value = serde_json::from_str(&out.stdout).unwrap();
        assert_eq!(v["node_integrals"], rule, "{flag}");
    }
    for (args, needle) in [
        (
            "run vibrating-bar --method mpm --node-integrals particles",
            "ddmpm only",
        ),
        (
            "run vibrating-bar --method ddmpm --node-integrals subpoints:0",
            "N ≥ 1",
        ),
        (
            "run vibrating-bar --method ddmpm --node-integrals gauss",
            "not a node-integral rule",
        ),
    ] {
        let e = refused(args).to_string();
        assert!(e.contains(needle), "{args}: {e}");
    }
}
