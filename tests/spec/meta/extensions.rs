//! One registration per extension (issue #26): a 1D basis is registered in
//! src/mpm/grid.rs ([`METHOD_FAMILIES`] and the arms of [`Method`]), a 2D
//! mapping in src/mpm2d/step.rs ([`Mapping2d::ALL`], `info` and
//! `reconstruction`). These tests walk the registrations and check that
//! every registered extension reaches the command line, the labels and the
//! JSON without a second list to edit.

use hompm::cli;
use hompm::mpm::grid::{Grid, Method, NodeIntegrals, METHOD_FAMILIES};
use hompm::mpm2d::Mapping2d;
use hompm::scenes::aligned_vibration::AlignedMethod;

fn run_json(args: &str) -> serde_json::Value {
    let out = cli::run(args.split_whitespace()).unwrap_or_else(|e| panic!("{args}: {e}"));
    serde_json::from_str(&out.stdout).unwrap()
}

#[test]
fn every_registered_1d_method_family_runs_from_the_command_line_under_its_name() {
    for family in METHOD_FAMILIES {
        let v = run_json(&format!(
            "run vibrating-bar --method {} --degree 2 --cells 4 --steps 2 --json",
            family.name
        ));
        assert_eq!(v["method"], family.name);
        let method = (family.method)(2, NodeIntegrals::Exact).unwrap();
        // The run used the family's member: its stencil reaches as far.
        let grid = Grid::new(method, 0.0, 1.0, 4).unwrap();
        assert_eq!(
            grid.stencil_width(),
            method.functions_per_particle().min(grid.num_dofs()),
            "{}",
            family.name
        );
    }
}

#[test]
fn functions_per_particle_count_the_basis_functions_that_are_non_zero_at_a_point() {
    // Counted from the basis itself: at an interior point that is not a
    // knot, the functions with a non-zero value (P1: 2, P2: 3, B-splines of
    // degree p: p + 1). DDMPM's modified gradient reaches one node further
    // on each side (TLS paper §3.3): 4.
    for method in [
        Method::Mpm,
        Method::MpmP2,
        Method::Bsmpm { degree: 1 },
        Method::Bsmpm { degree: 2 },
        Method::Bsmpm { degree: 3 },
    ] {
        let grid = Grid::new(method, 0.0, 1.0, 8).unwrap();
        let local = grid.basis().local(0.4321, 0).unwrap();
        let non_zero = local.values().iter().filter(|v| v.abs() > 1e-14).count();
        assert_eq!(method.functions_per_particle(), non_zero, "{method:?}");
    }
    assert_eq!(Method::DDMPM.functions_per_particle(), 4);
    assert_eq!(Method::DDMPM.node_integrals(), Some(NodeIntegrals::Exact));
    assert_eq!(Method::Mpm.node_integrals(), None);
}

#[test]
fn every_registered_2d_mapping_is_a_method_of_the_aligned_vibration_on_the_command_line() {
    for mapping in Mapping2d::ALL {
        let method = match mapping {
            Mapping2d::Direct => "bsmpm".to_string(),
            m => format!("bsmpm-{}", m.name()),
        };
        let v = run_json(&format!(
            "run aligned-vibration --method {method} --cells 2 --steps 1 --json"
        ));
        assert_eq!(v["method"], method.as_str());
        assert_eq!(v["mapping"], mapping.name());
        // The oracle's trace runs it too, and a reconstruction records its
        // Gauss-point values (MLS paper Eqs. 18-21).
        let trace = cli::run(
            format!("trace aligned-vibration --method {method} --cells 2 --steps 1")
                .split_whitespace(),
        )
        .unwrap_or_else(|e| panic!("trace {method}: {e}"));
        assert_eq!(
            trace.stdout.contains("mls-18-21"),
            mapping != Mapping2d::Direct,
            "{method}"
        );
        // The mapping's JSON name is serde's.
        assert_eq!(
            serde_json::to_value(mapping).unwrap(),
            serde_json::json!(mapping.name())
        );
        assert_eq!(Mapping2d::from_name(mapping.name()), Some(mapping));
    }
    assert_eq!(Mapping2d::from_name("bsmpm"), None);
}

#[test]
fn aligned_methods_keep_their_json_and_labels_through_the_registration() {
    // The JSON of the closed list that the registration replaced.
    let cases = [
        (AlignedMethod::Mpm, r#""mpm""#, "MPM"),
        (
            AlignedMethod::bsmpm(2),
            r#"{"bsmpm":{"degree":2}}"#,
            "BSMPM-p2",
        ),
        (
            AlignedMethod::bsmpm_with(2, Mapping2d::Mls),
            r#"{"bsmpm-mls":{"degree":2}}"#,
            "BSMPM-p2-MLS",
        ),
        (
            AlignedMethod::bsmpm_with(3, Mapping2d::MlsPhase1),
            r#"{"bsmpm-mls-phase1":{"degree":3}}"#,
            "BSMPM-p3-MLS-phase-1",
        ),
        (
            AlignedMethod::bsmpm_with(2, Mapping2d::Tls),
            r#"{"bsmpm-tls":{"degree":2}}"#,
            "BSMPM-p2-TLS",
        ),
        (
            AlignedMethod::TotalLagrangian { degree: 2 },
            r#"{"total-lagrangian":{"degree":2}}"#,
            "TL-FE-p2",
        ),
    ];
    for (method, json, label) in cases {
        assert_eq!(serde_json::to_string(&method).unwrap(), json);
        assert_eq!(serde_json::from_str::<AlignedMethod>(json).unwrap(), method);
        assert_eq!(method.label(), label);
    }
    for bad in [
        r#""bsmpm""#,
        r#"{"bsmpm-direct":{"degree":2}}"#,
        r#"{"bsmpm-nope":{"degree":2}}"#,
        r#"{"mpm":{"degree":2}}"#,
        r#"{"bsmpm":{"degree":2},"bsmpm-tls":{"degree":2}}"#,
    ] {
        assert!(serde_json::from_str::<AlignedMethod>(bad).is_err(), "{bad}");
    }
}

/// Issue #37: a 1D mapping is one registration, as a 2D one: its name in
/// JSON (serde's) is its registered name, `from_name` finds it, the
/// command line offers every registered mapping with its summary, and the
/// method label in words uses its label.
#[test]
fn every_registered_1d_mapping_keeps_its_name_json_and_help_through_the_registration() {
    use hompm::mpm::mapping::Mapping;
    let words = |t: &str| t.split_whitespace().collect::<Vec<_>>().join(" ");
    let help = words(&hompm::cli::run(["run", "--help"]).unwrap().stdout);
    let grid = Grid::new(Method::Mpm, 0.0, 1.0, 4).unwrap();
    let ws = hompm::mpm::mapping::MappingWorkspace::new(&grid, 8).unwrap();
    for m in Mapping::ALL {
        let info = m.info();
        // Every mapping but the direct one has its reconstruction, named by
        // its legend.
        assert_eq!(
            ws.reconstruction(m).map(|r| r.name()),
            (m != Mapping::Direct).then_some(info.legend),
            "{}",
            info.name
        );
        assert_eq!(
            serde_json::to_value(m).unwrap(),
            serde_json::json!(info.name)
        );
        assert_eq!(Mapping::from_name(info.name), Some(m));
        assert!(
            help.contains(info.name) && help.contains(&words(info.summary)),
            "{}",
            info.name
        );
        let d = hompm::scenes::Discretisation::new(
            hompm::mpm::grid::Method::Mpm,
            m,
            hompm::mpm::mapping::MassMatrix::Lumped,
            4,
            2,
        );
        assert!(hompm::oracle::method_label_1d(&d).contains(info.label));
    }
    assert_eq!(Mapping::from_name("nope"), None);
    let out = hompm::cli::run([
        "run",
        "vibrating-bar",
        "--cells",
        "4",
        "--ppc",
        "2",
        "--steps",
        "1",
        "--dt",
        "1e-4",
        "--mapping",
        "cubic-spline-clipped",
        "--mass",
        "consistent",
        "--json",
    ])
    .unwrap();
    let doc: serde_json::Value = serde_json::from_str(&out.stdout).unwrap();
    assert_eq!(doc["mapping"], "cubic-spline-clipped");
}
