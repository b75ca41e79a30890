//! Golden tests of the registered tables: every published number of a table
//! that is declared reproduced must be reproduced within its tolerance.

use hompm::tables::{self, RunOptions, Status};

/// Thesis Appendix A.1–A.2: the 4×4 assembled matrix and the lumped diagonal
/// 9, 12, 15, 7 — exact.
///
/// Map rows: book-4.3, tls-§3-2, thesis-A-1-unnumbered-1, thesis-A-2-unnumbered-1 — one assembly, printed in three seeds.
#[test]
fn thesis_a1_reproduces_exactly() {
    let spec = tables::find("thesis-a1").unwrap();
    let report = tables::run(&spec, &RunOptions::default()).unwrap();
    assert_eq!(report.counts(), (20, 20));
    assert!(report
        .status
        .iter()
        .flatten()
        .all(|s| *s == Status::Reproduced));
}

/// Every registered table has a well-formed published JSON with a seed and page.
#[test]
fn every_published_file_is_well_formed() {
    for spec in tables::registry() {
        let p = tables::Published::parse(spec.id, spec.published_json).unwrap();
        assert_eq!(p.id, spec.id);
        assert!(p.seed.contains(".txt"), "{}", p.seed);
        assert!(!p.source.page.is_empty());
        assert!(p.count() > 0);
    }
}

/// The regression baseline (golden/reproduced.json) names each reproduced
/// cell by its row and column labels: a table that gains a row above the
/// others keeps its baseline, and a cell that stops reproducing, or whose
/// row disappears, is named by its labels.
#[test]
fn the_regression_baseline_follows_cells_by_label_not_position() {
    use hompm::report::{baseline_of, regressions};
    let spec = tables::find("thesis-a1").unwrap();
    let report = tables::run(&spec, &RunOptions::default()).unwrap();
    let baseline = baseline_of(std::slice::from_ref(&report));
    let cells = &baseline["thesis-a1"];
    assert_eq!(cells.len(), 20);
    assert_eq!(
        cells[0],
        [report.row_labels[0].clone(), report.col_labels[0].clone()]
    );

    let mut extended = report.clone();
    let width = extended.col_labels.len();
    extended.row_labels.insert(0, "a new first row".into());
    extended.status.insert(0, vec![Status::Deviates; width]);
    assert_eq!(
        regressions(std::slice::from_ref(&extended), &baseline),
        Vec::<String>::new()
    );

    let mut changed = report.clone();
    changed.status[1][2] = Status::Deviates;
    let expected = format!(
        "thesis-a1 [{} / {}]",
        report.row_labels[1], report.col_labels[2]
    );
    assert_eq!(
        regressions(std::slice::from_ref(&changed), &baseline),
        vec![expected]
    );

    let mut shorter = report.clone();
    let gone = shorter.row_labels.remove(0);
    shorter.status.remove(0);
    let named = regressions(std::slice::from_ref(&shorter), &baseline);
    assert_eq!(named.len(), width);
    assert!(named.iter().all(|n| n.contains(&gone)), "{named:?}");
}
