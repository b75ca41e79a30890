//! # What a check can see: the time resolution of the tolerance
//!
//! Two codes that differ by a term of first order in Δt (a position
//! update from the grid velocity instead of the re-projected one, MLS
//! paper Eq. 30 against book Eq. 4.11; a body force at the nodes instead
//! of the particles) differ less the smaller Δt is. Below some Δt the
//! difference falls under the tolerance and `check` agrees, although the
//! codes are not the same. The check says where that Δt lies (issue #35):
//!
//! - hompm runs the setup a second time with the same end time T and
//!   about twice the step, Δt' = T / ⌈steps / 2⌉;
//! - for each compared field of the solution, the largest change between
//!   the two runs, D, measures hompm's own first-order time error: at Δt
//!   it is E = D·Δt/(Δt' − Δt), or e = E/s relative to the field's scale s;
//! - the tolerance lets through a difference of up to about
//!   τ = max(rtol, atol) relative to s; so a difference of first order in
//!   Δt is visible only if its coefficient is at least τ/e times hompm's
//!   own (`fraction_of_own_error`), and a difference as large as hompm's
//!   own time error is visible only for Δt ≥ Δt·τ/e (`visible_from_dt`).
//!
//! The estimate assumes the change from Δt to Δt' is dominated by the
//! first-order term (true for the MUSL and 2D steps of hompm at the time
//! steps of its scenes; a higher-order or unstable case is reported as
//! measured). It costs one run of about half the steps, and is made only
//! when a check of final particles agrees (a trace compares step 1, where
//! a first-order term is visible long before it is in the final state).
//!
//! Items: [`TimeResolution`], [`FieldResolution`], [`time_resolution`].

use super::columns::PHYSICAL_FIELDS;
use super::compare::{saturate, scale_of, Tolerance};
use super::run::reference;
use super::setup::Setup;
use super::state::State;
use crate::error::Result;
use serde::Serialize;
use std::collections::BTreeMap;

/// One field's time resolution.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FieldResolution {
    /// Largest change of the field between Δt and Δt', over particles
    /// and components.
    pub change: f64,
    /// hompm's own first-order time error at Δt relative to the field's
    /// scale, e = change·Δt/(Δt' − Δt)/scale.
    pub own_error: f64,
    /// The smallest coefficient, as a fraction of hompm's own, of a
    /// difference of first order in Δt that the tolerance sees: τ/e.
    pub fraction_of_own_error: f64,
    /// The Δt from which a difference as large as hompm's own time error
    /// is visible, Δt·τ/e.
    pub visible_from_dt: f64,
}

/// What the tolerance can see at this Δt.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TimeResolution {
    /// The check's Δt.
    pub dt: f64,
    /// The second run's step, T / ⌈steps/2⌉.
    pub coarse_dt: f64,
    /// τ = max(rtol, atol), relative to a field's scale.
    pub tolerance: f64,
    /// Per compared field of the solution.
    pub fields: BTreeMap<String, FieldResolution>,
    /// One sentence for the verdict.
    pub sentence: String,
}

/// The setup with another step and step count (same scene, method, grid).
fn with_steps(setup: &Setup, dt: f64, steps: usize) -> Setup {
    let mut s = *setup;
    match &mut s {
        Setup::OneD(x) => {
            x.dt = dt;
            x.steps = steps;
        }
        Setup::TwoD(x) => {
            x.dt = dt;
            x.steps = steps;
        }
    }
    s
}

/// The time resolution of an agreeing check of final particles (module
/// docs), over `compared`, the fields the check compared with their
/// columns: `None` for a run of one step (no coarser step has the same
/// end time), when hompm's run at the coarser step fails, or when no field
/// of the solution changes.
pub fn time_resolution(
    setup: &Setup,
    state: &State,
    compared: &[(String, Vec<String>)],
    o: &Tolerance,
) -> Result<Option<TimeResolution>> {
    let steps = setup.steps();
    if steps < 2 {
        return Ok(None);
    }
    let coarse_steps = steps.div_ceil(2);
    let coarse_dt = setup.end_time() / coarse_steps as f64;
    let dt = setup.dt();
    if coarse_dt <= dt {
        return Ok(None);
    }
    let Ok((coarse, _)) = reference(&with_steps(setup, coarse_dt, coarse_steps), None) else {
        return Ok(None);
    };
    let tolerance = o.rtol.max(o.atol);
    let mut fields = BTreeMap::new();
    for (name, columns) in compared {
        if !PHYSICAL_FIELDS.contains(&name.as_str()) {
            continue;
        }
        let mut change: f64 = 0.0;
        for c in columns {
            let (Some(fine), Some(rough)) = (state.particles.column(c), coarse.particles.column(c))
            else {
                continue;
            };
            for (a, b) in fine.iter().zip(rough) {
                change = change.max(saturate((a - b).abs()));
            }
        }
        let scale = scale_of(
            columns
                .iter()
                .filter_map(|c| state.particles.column(c))
                .flatten(),
        );
        if scale == 0.0 || change == 0.0 {
            continue;
        }
        let own_error = saturate(change * dt / (coarse_dt - dt) / scale);
        fields.insert(
            name.clone(),
            FieldResolution {
                change,
                own_error,
                fraction_of_own_error: saturate(tolerance / own_error),
                visible_from_dt: saturate(dt * tolerance / own_error),
            },
        );
    }
    let Some((name, best)) = fields.iter().min_by(|a, b| {
        a.1.fraction_of_own_error
            .total_cmp(&b.1.fraction_of_own_error)
    }) else {
        return Ok(None);
    };
    let sentence = if best.fraction_of_own_error < 1.0 {
        let percent = 100.0 * best.fraction_of_own_error;
        let percent = if percent >= 0.1 {
            format!("{percent:.1}%")
        } else {
            format!("{percent:.1e}%")
        };
        format!(
            "at Δt = {dt:e} the tolerance sees a difference of first order in Δt down to {percent} of hompm's own time error ({name}: {:.1e} relative to its largest value, from a second run at Δt = {coarse_dt:e})",
            best.own_error
        )
    } else {
        format!(
            "warning: at Δt = {dt:e} a difference of first order in Δt as large as hompm's own time error ({name}: {:.1e} relative) is below the tolerance, so this check cannot see it; check at Δt ≥ {:.1e} or lower --rtol/--atol",
            best.own_error, best.visible_from_dt
        )
    };
    Ok(Some(TimeResolution {
        dt,
        coarse_dt,
        tolerance,
        fields,
        sentence,
    }))
}
