//! # The regression baseline
//!
//! golden/reproduced.json lists, per table, the published numbers that
//! reproduced when it was last updated (`hompm reproduce
//! --update-baseline`), each named by its row and column labels; `hompm
//! reproduce` fails when one of them no longer reproduces. Measured wall
//! times are left out: they vary from run to run.
//!
//! Items: [`Baseline`], [`baseline_of`], [`regressions`].

use crate::tables::{Status, TableReport, Tolerance};
use std::collections::BTreeMap;

/// The cells that reproduced, per table: the regression baseline. Each cell
/// is named by its row and column labels, as the tables couple by label,
/// so a table whose rows are reordered or extended keeps its baseline.
pub type Baseline = BTreeMap<String, Vec<[String; 2]>>;

/// The reproduced cells of a set of reports, except measured wall times
/// ([`Tolerance::Timing`]), which vary from run to run.
pub fn baseline_of(reports: &[TableReport]) -> Baseline {
    reports
        .iter()
        .map(|r| {
            let cells = r
                .status
                .iter()
                .enumerate()
                .flat_map(|(i, row)| {
                    row.iter()
                        .enumerate()
                        .filter(move |(j, s)| {
                            **s == Status::Reproduced && r.tolerance[i][*j] != Tolerance::Timing
                        })
                        .map(move |(j, _)| [r.row_labels[i].clone(), r.col_labels[j].clone()])
                })
                .collect();
            (r.id.clone(), cells)
        })
        .collect()
}

/// Cells marked reproduced in the baseline that no longer reproduce, or
/// whose row or column label the table no longer has.
pub fn regressions(reports: &[TableReport], baseline: &Baseline) -> Vec<String> {
    let mut out = Vec::new();
    for r in reports {
        for [row, col] in baseline.get(&r.id).into_iter().flatten() {
            let i = r.row_labels.iter().position(|l| l == row);
            let j = r.col_labels.iter().position(|l| l == col);
            let status = i.zip(j).and_then(|(i, j)| r.status.get(i)?.get(j));
            if status != Some(&Status::Reproduced) {
                out.push(format!("{} [{row} / {col}]", r.id));
            }
        }
    }
    out
}
