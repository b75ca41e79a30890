//! # `hompm trace`
//!
//! hompm's trace of a setup: every numbered equation's quantities at the
//! traced steps (`oracle::trace`), as JSON, CSV or a summary.
//!
//! Items: [`trace`].

use super::super::limits::Limits;
use super::super::{json, Output};
use super::{as_usage, TraceArgs};
use crate::error::{Error, Result};
use crate::oracle::run::{trace_1d, trace_2d};
use crate::oracle::setup::Setup;
use crate::oracle::trace::{Trace, EQUATIONS_1D, EQUATIONS_2D};

/// Bytes of a trace of `steps` traced steps: 8 particle and 9 DOF
/// quantities per step in 1D; 14 per particle, 11 per node and 8 per
/// Gauss point in 2D; each kept twice (values and text) and doubled for
/// the formatting.
fn trace_bytes(setup: &Setup, steps: usize) -> f64 {
    let per_step = match setup {
        Setup::OneD(s) => {
            let d = &s.discretisation;
            let particles = d.cells as f64 * d.ppc as f64;
            let dofs = 2.0 * d.cells as f64 + 8.0;
            8.0 * particles + 9.0 * dofs
        }
        Setup::TwoD(s) => {
            let c = s.cells as f64;
            let particles = c * c * (s.per_side as f64).powi(2);
            let nodes = (c + 5.0) * (c + 5.0);
            14.0 * particles + 11.0 * nodes + 32.0 * c * c
        }
    };
    steps as f64 * per_step * 8.0 * 4.0
}

/// `hompm trace`.
pub fn trace(a: TraceArgs, limits: &Limits) -> Result<Output> {
    if a.every == 0 {
        return Err(Error::Usage("--every must be at least 1".into()));
    }
    let setup = a.setup.setup().map_err(as_usage)?;
    let traced = if setup.steps() == 0 {
        0
    } else {
        (setup.steps() - 1) / a.every + 2
    };
    a.setup
        .check_limits(&setup, limits, trace_bytes(&setup, traced))?;
    let trace = match &setup {
        Setup::OneD(s) => trace_1d(s, a.every, None)?.0,
        Setup::TwoD(s) => trace_2d(s, a.every, None)?.0,
    };
    let stdout = if a.json {
        json::strict(&trace)?
    } else if a.csv {
        trace.to_csv()
    } else {
        trace_summary(&trace)
    };
    Ok(Output::text(stdout))
}

/// A readable summary: per traced step and equation, the count and range.
fn trace_summary(t: &Trace) -> String {
    let mut out = format!(
        "hompm trace, {} traced steps (--json or --csv for every value; docs/oracle.md)\n",
        t.steps.len()
    );
    for s in &t.steps {
        out.push_str(&format!("step {} (t = {:e})\n", s.step, s.time));
        for e in EQUATIONS_1D.iter().chain(EQUATIONS_2D.iter()) {
            if let Some(v) = s.equations.get(e.key) {
                let (lo, hi) = v
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                        (a.min(*x), b.max(*x))
                    });
                out.push_str(&format!(
                    "  {:<17} {:<24} {:>5} values in [{lo:.6e}, {hi:.6e}]  {}\n",
                    e.key,
                    e.citation,
                    v.len(),
                    e.symbol
                ));
            }
        }
    }
    out
}
