//! Shared proptest strategies and golden-test helpers.
#![allow(dead_code)]

use hompm::spline::KnotVector;
use proptest::prelude::*;

/// Open knot vectors on [0, L] with random degree 0..=max_degree, random
/// interior breakpoints (spacing ≥ `min_gap`·L) and random interior
/// multiplicities 1..=p+1.
pub fn open_knots(max_degree: usize, min_gap: f64) -> impl Strategy<Value = KnotVector> {
    (0..=max_degree, 0usize..=6, 0.5f64..4.0).prop_flat_map(move |(p, interior, length)| {
        (
            Just(p),
            Just(length),
            proptest::collection::vec(0.0f64..1.0, interior),
            proptest::collection::vec(1usize..=p + 1, interior),
        )
            .prop_map(move |(p, length, raw, mult)| {
                // Spread the breakpoints so that neighbours are ≥ min_gap apart.
                let mut pts: Vec<f64> = raw.clone();
                pts.sort_by(|a, b| a.partial_cmp(b).unwrap());
                let k = pts.len() as f64;
                let usable = 1.0 - (k + 1.0) * min_gap;
                let pts: Vec<f64> = pts
                    .iter()
                    .enumerate()
                    .map(|(i, t)| (min_gap * (i as f64 + 1.0) + usable * t) * length)
                    .collect();
                let mut knots = vec![0.0; p + 1];
                for (t, m) in pts.iter().zip(&mult) {
                    knots.extend(std::iter::repeat_n(*t, *m));
                }
                knots.extend(std::iter::repeat_n(length, p + 1));
                KnotVector::new(knots, p).expect("strategy builds valid knots")
            })
    })
}

/// General (not necessarily open) non-decreasing knot vectors with degree 0..=5.
pub fn general_knots() -> impl Strategy<Value = KnotVector> {
    (0usize..=5).prop_flat_map(|p| {
        proptest::collection::vec(0u8..12, (2 * p + 2)..(2 * p + 10)).prop_filter_map(
            "valid knot vector",
            move |mut ints| {
                ints.sort();
                let knots: Vec<f64> = ints.iter().map(|&i| i as f64 * 0.25).collect();
                KnotVector::new(knots, p).ok()
            },
        )
    })
}

/// Points spread over the domain, including both ends.
pub fn sample_points(kv: &KnotVector, fractions: &[f64]) -> Vec<f64> {
    let (a, b) = kv.domain();
    let mut pts: Vec<f64> = fractions.iter().map(|f| a + f * (b - a)).collect();
    pts.push(a);
    pts.push(b);
    pts
}

/// Asserts, entry by entry, that the named (row, column) entries of a table
/// reproduce their published numbers. Rows are matched by the start of their
/// label. A number that regresses fails here; a deviating number that gets
/// fixed does not (no test pins a count of deviations).
pub fn assert_reproduced(report: &hompm::tables::TableReport, entries: &[(&str, &str)]) {
    for (row, col) in entries {
        let [i, j] = cell(report, row, col);
        assert_eq!(
            report.status[i][j],
            hompm::tables::Status::Reproduced,
            "{} {row} / {col}: published {:?}, computed {:?}",
            report.id,
            report.published[i][j],
            report.computed[i][j]
        );
    }
}

/// The (row, column) position of the cell named by its row label's start
/// and its column label: tests name cells by label, never by position.
pub fn cell(report: &hompm::tables::TableReport, row: &str, col: &str) -> [usize; 2] {
    let i = report
        .row_labels
        .iter()
        .position(|l| l.starts_with(row))
        .unwrap_or_else(|| panic!("{}: no row '{row}'", report.id));
    let j = report
        .col_labels
        .iter()
        .position(|l| l == col)
        .unwrap_or_else(|| panic!("{}: no column '{col}'", report.id));
    [i, j]
}

/// Run settings with the same mapping for force and velocity, no gravity,
/// no Dirichlet DOFs and the small-strain update (book Eq. 4.15): the
/// setting of the hand-built scenes of the spec and property tests.
pub fn free_settings(
    mapping: hompm::mpm::mapping::Mapping,
    mass: hompm::mpm::mapping::MassMatrix,
    young: f64,
) -> hompm::mpm::musl::Settings {
    hompm::mpm::musl::Settings {
        force_mapping: mapping,
        velocity_mapping: mapping,
        mass,
        constitutive: hompm::mpm::musl::Constitutive::SmallStrain,
        young,
        poisson: 0.0,
        body_force: None,
        gravity: 0.0,
        gravity_ramp: None,
        dirichlet: vec![],
        consistent_acceleration: false,
        tls_density_average: hompm::reconstruct::taylor::CellAverage::Exact,
        conventions: Default::default(),
    }
}

/// The published numbers of a registered table, parsed from its
/// golden/published JSON.
pub fn published(id: &str) -> hompm::tables::Published {
    let spec = hompm::tables::find(id).unwrap();
    hompm::tables::Published::parse(id, spec.published_json).unwrap()
}

/// Every `.rs` file under src/, sorted, with its path relative to src/ and
/// its text (for the tests that read the crate's own sources).
pub fn source_files() -> Vec<(std::path::PathBuf, String)> {
    fn walk(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    let src = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/src"));
    let mut files = Vec::new();
    walk(src, &mut files);
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).unwrap();
            (p.strip_prefix(src).unwrap().to_path_buf(), text)
        })
        .collect()
}

/// Δt = 0 and Δt = NaN are refused by `step` as `Error::NotPositive` naming
/// the time step and carrying the value (1D and 2D share
/// `mpm::check_time_step`).
pub fn assert_refuses_bad_time_steps(mut step: impl FnMut(f64) -> hompm::Result<()>) {
    for dt in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
        match step(dt) {
            Err(hompm::Error::NotPositive { what, value }) => {
                assert_eq!(what, "the time step");
                assert!(
                    value == dt || (value.is_nan() && dt.is_nan()),
                    "{value} for {dt}"
                );
            }
            other => panic!("Δt = {dt}: {other:?}"),
        }
    }
}

/// The 2D setup of the oracle's tests: the aligned vibration on 4 × 4
/// cells × 4 PPC, 3 steps (on 2 × 2 cells the one free node stands still,
/// and so does every particle).
pub const SETUP_2D: &[&str] = &[
    "aligned-vibration",
    "--cells",
    "4",
    "--ppc",
    "4",
    "--steps",
    "3",
];
