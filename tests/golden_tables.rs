//! Golden tests of the registered tables: every published number of a table
//! that is declared reproduced must be reproduced within its tolerance.

use hompm::tables::{self, RunOptions, Status};

/// Thesis Appendix A.1–A.2: the 4×4 assembled matrix and the lumped diagonal
/// 9, 12, 15, 7 — exact.
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
