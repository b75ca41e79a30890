//! # hompm's side of a check: its particles as a table, and the matching
//!
//! `hompm check` compares column by column. [`State`] holds hompm's final
//! particles in the check's column names ([`state_1d`], [`state_2d`], or the
//! last step of a trace, [`state_of_trace`]); [`match_particles`] pairs the
//! other code's rows with hompm's particles by `id` (0-based; 1..=n read as
//! 1-based), by initial position (nearest within a quarter of the
//! particle spacing), so reordered output works, or, when asked, by row
//! order. Where both id and x0 are given they must agree. An unmatched or
//! duplicated particle, or an id that contradicts its x0, is
//! [`Error::Input`] naming the row.
//!
//! Items: [`State`], [`MatchBy`], [`state_1d`], [`state_2d`],
//! [`state_of_trace`], [`match_particles`].
//!
//! Its columns are those of the oracle's column schema, `oracle::columns`
//! (tested: hompm's own state has exactly the known columns).

use super::columns::x0_columns;
use super::setup::{Setup1d, Setup2d};
use super::table::{ParticleTable, TableBuilder};
use super::trace::TraceStep;
use crate::error::{Error, Result};
use serde::Serialize;
use std::collections::BTreeMap;

/// How the other code's particles are matched with hompm's
/// ([`match_particles`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum MatchBy {
    /// By `id` if the file has it, else by initial position; neither is
    /// refused.
    #[default]
    Auto,
    /// By the `id` column.
    Id,
    /// By the initial position (x0, or x0_x and x0_y).
    X0,
    /// Row k is hompm's particle k.
    Order,
}

/// hompm's particles (and the exact fields at their X) as a table in the
/// check's column names.
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    /// hompm's particle columns.
    pub particles: ParticleTable,
    /// The particle spacing (for matching by position).
    pub spacing: f64,
    /// hompm's method label.
    pub method: String,
    /// Whether the scene is 2D.
    pub two_d: bool,
}

/// The other code's initial positions, if it gives them: `None` without
/// them, an error when a 2D file gives one coordinate only.
fn their_x0(theirs: &ParticleTable, two_d: bool) -> Result<Option<Vec<&[f64]>>> {
    let names = x0_columns(two_d);
    let cols: Vec<&[f64]> = names.iter().filter_map(|c| theirs.column(c)).collect();
    match cols.len() {
        0 => Ok(None),
        k if k == names.len() => Ok(Some(cols)),
        _ => Err(Error::Input(format!(
            "the file gives only some of {}; give both coordinates or neither",
            names.join(" and ")
        ))),
    }
}

/// hompm's particle of each of the other code's rows, and how they were
/// matched (module docs; docs/oracle.md "Matching"):
///
/// - `Auto`: by `id` when the file has it, else by initial position; a
///   file with neither is refused (`--match order` takes its rows in
///   hompm's order);
/// - `Id`: by `id` (0-based; ids 1..=n read as 1-based);
/// - `X0`: by initial position, nearest within a quarter spacing, any id
///   column aside;
/// - `Order`: row k is hompm's particle k.
///
/// Where the file gives initial positions and the match is not by them,
/// every row's x0 must lie within a quarter spacing of its particle's,
/// or the file is refused: an id that names another particle than its x0
/// never decides a verdict.
pub fn match_particles(
    theirs: &ParticleTable,
    ours: &State,
    by: MatchBy,
) -> Result<(Vec<usize>, String)> {
    let n = ours.particles.rows();
    if theirs.rows() != n {
        return Err(Error::Input(format!(
            "your file has {} particles, the setup has {n}; check --cells, --ppc and the scene",
            theirs.rows()
        )));
    }
    let x0 = their_x0(theirs, ours.two_d)?;
    let ids = theirs.column("id");
    let (perm, how) = match (by, ids, &x0) {
        (MatchBy::X0, _, Some(x0)) => (by_position(x0, ours)?, "x0"),
        (MatchBy::X0, _, None) => {
            return Err(Error::Input(format!(
                "--match x0 needs the column(s) {}",
                x0_columns(ours.two_d).join(", ")
            )))
        }
        (MatchBy::Id | MatchBy::Auto, Some(ids), _) => by_id(ids, n)?,
        (MatchBy::Id, None, _) => {
            return Err(Error::Input("--match id needs an 'id' column".into()))
        }
        (MatchBy::Auto, None, Some(x0)) => (by_position(x0, ours)?, "x0"),
        (MatchBy::Order, _, _) => ((0..n).collect(), "order (--match order)"),
        (MatchBy::Auto, None, None) => {
            return Err(Error::Input(format!(
                "the file has neither an 'id' nor {}: its particles cannot be matched with hompm's; add one, or give --match order to take its rows in hompm's order",
                x0_columns(ours.two_d).join(" and ")
            )))
        }
    };
    if let (Some(x0), false) = (&x0, how == "x0") {
        agree_with_x0(x0, ours, &perm, how)?;
    }
    Ok((perm, how.into()))
}

/// By `id`: 0-based, or 1-based when every id is at least 1 and n occurs.
fn by_id(ids: &[f64], n: usize) -> Result<(Vec<usize>, &'static str)> {
    let one_based = ids.iter().all(|&i| i >= 1.0) && ids.contains(&(n as f64));
    let mut seen = vec![None; n];
    let mut perm = Vec::with_capacity(n);
    for (row, &id) in ids.iter().enumerate() {
        let k = id - if one_based { 1.0 } else { 0.0 };
        if k.fract() != 0.0 || k < 0.0 || k >= n as f64 {
            return Err(Error::Input(format!(
                "row {}: id {id} is not a particle of the setup (0..{n})",
                row + 1
            )));
        }
        let k = k as usize;
        if let Some(other) = seen[k] {
            return Err(Error::Input(format!(
                "rows {other} and {} both have id {id}",
                row + 1
            )));
        }
        seen[k] = Some(row + 1);
        perm.push(k);
    }
    Ok((perm, if one_based { "id (1-based)" } else { "id" }))
}

/// Every row's x0 within a quarter spacing of its matched particle's.
fn agree_with_x0(x0: &[&[f64]], ours: &State, perm: &[usize], how: &str) -> Result<()> {
    let ours_cols = our_x0(ours);
    let quarter = 0.25 * ours.spacing;
    for (row, &k) in perm.iter().enumerate() {
        let d2: f64 = ours_cols
            .iter()
            .zip(x0)
            .map(|(o, t)| (o[k] - t[row]).powi(2))
            .sum();
        if d2.sqrt() > quarter || d2.is_nan() {
            return Err(Error::Input(format!(
                "row {}: matched by {how} to hompm's particle {k} at {:?}, but its x0 is {:?}, more than a quarter spacing ({quarter:e}) away; if your ids are not hompm's numbering, give --match x0",
                row + 1,
                ours_cols.iter().map(|c| c[k]).collect::<Vec<_>>(),
                x0.iter().map(|c| c[row]).collect::<Vec<_>>(),
            )));
        }
    }
    Ok(())
}

/// hompm's initial-position columns.
fn our_x0(ours: &State) -> Vec<&[f64]> {
    x0_columns(ours.two_d)
        .iter()
        .filter_map(|c| ours.particles.column(c))
        .collect()
}

/// By initial position: the nearest of hompm's particles within a quarter
/// spacing, each taken once.
fn by_position(cols: &[&[f64]], ours: &State) -> Result<Vec<usize>> {
    let n = ours.particles.rows();
    let ours_cols = our_x0(ours);
    let s = ours.spacing;
    let key = |p: &[f64]| -> (i64, i64) {
        let kx = (p[0] / s).floor() as i64;
        let ky = p.get(1).map_or(0, |y| (y / s).floor() as i64);
        (kx, ky)
    };
    let mut buckets: BTreeMap<(i64, i64), Vec<usize>> = BTreeMap::new();
    for k in 0..n {
        let p: Vec<f64> = ours_cols.iter().map(|c| c[k]).collect();
        buckets.entry(key(&p)).or_default().push(k);
    }
    let mut seen = vec![None; n];
    let mut perm = Vec::with_capacity(n);
    for row in 0..n {
        let p: Vec<f64> = cols.iter().map(|c| c[row]).collect();
        let (kx, ky) = key(&p);
        let mut best: Option<(f64, usize)> = None;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for &k in buckets.get(&(kx + dx, ky + dy)).into_iter().flatten() {
                    let d2: f64 = ours_cols
                        .iter()
                        .zip(&p)
                        .map(|(c, v)| (c[k] - v).powi(2))
                        .sum();
                    if best.is_none_or(|(b, _)| d2 < b) {
                        best = Some((d2, k));
                    }
                }
            }
        }
        match best {
            Some((d2, k)) if d2.sqrt() <= 0.25 * s => {
                if let Some(other) = seen[k] {
                    return Err(Error::Input(format!(
                        "rows {other} and {} both match hompm's particle {k} at {:?}",
                        row + 1,
                        ours_cols.iter().map(|c| c[k]).collect::<Vec<_>>()
                    )));
                }
                seen[k] = Some(row + 1);
                perm.push(k);
            }
            _ => {
                return Err(Error::Input(format!(
                "row {}: no particle of the setup starts within a quarter spacing ({:e}) of {p:?}",
                row + 1,
                0.25 * s
            )))
            }
        }
    }
    Ok(perm)
}

/// The values of `key` at a trace's final step, which must hold
/// `width` per particle, or an error naming the key and both counts.
fn traced<'a>(
    step: &'a TraceStep,
    key: &str,
    particles: usize,
    width: usize,
) -> Result<Option<&'a [f64]>> {
    let Some(v) = step.equations.get(key) else {
        return Ok(None);
    };
    if v.len() != particles * width {
        return Err(Error::Input(format!(
            "step {}, {key}: your trace has {} values; the setup's {particles} particles need {}",
            step.step,
            v.len(),
            particles * width
        )));
    }
    Ok(Some(v))
}

/// The final particle state a trace's final step holds (id = index), for
/// a setup of `particles` particles: positions and displacements (book
/// Eqs. 4.12–4.13; MLS paper Eq. 30) are required, every other particle
/// quantity is taken where given, and every one must have a value (2D: a
/// pair or a 2 × 2 row) per particle.
pub fn state_of_trace(step: &TraceStep, particles: usize, two_d: bool) -> Result<ParticleTable> {
    let (x_key, u_key) = if two_d {
        ("mls-30", "mls-30-u")
    } else {
        ("book-4.13", "book-4.12")
    };
    let width = if two_d { 2 } else { 1 };
    let (Some(x), Some(u)) = (
        traced(step, x_key, particles, width)?,
        traced(step, u_key, particles, width)?,
    ) else {
        return Err(Error::Input(format!(
            "the trace's final step {} has no particle positions and displacements ({x_key}, {u_key}); they are its final state",
            step.step
        )));
    };
    let mut t = TableBuilder::default();
    t.column("id".into(), (0..particles).map(|k| k as f64).collect())?;
    let x0: Vec<f64> = x.iter().zip(u).map(|(x, u)| x - u).collect();
    let split = |v: &[f64], c: usize, w: usize| -> Vec<f64> {
        v.iter().skip(c).step_by(w).copied().collect()
    };
    if two_d {
        for (name, v) in [("x0", &x0[..]), ("x", x), ("u", u)] {
            t.column(format!("{name}_x"), split(v, 0, 2))?;
            t.column(format!("{name}_y"), split(v, 1, 2))?;
        }
        if let Some(v) = traced(step, "mls-29", particles, 2)? {
            t.column("v_x".into(), split(v, 0, 2))?;
            t.column("v_y".into(), split(v, 1, 2))?;
        }
        for (key, name) in [("mls-35", "F"), ("mls-41", "stress")] {
            if let Some(v) = traced(step, key, particles, 4)? {
                for (c, suffix) in ["xx", "xy", "yx", "yy"].iter().enumerate() {
                    t.column(format!("{name}_{suffix}"), split(v, c, 4))?;
                }
            }
        }
        for (key, name) in [("mls-36", "volume"), ("mls-37", "density")] {
            if let Some(v) = traced(step, key, particles, 1)? {
                t.column(name.into(), v.to_vec())?;
            }
        }
    } else {
        t.column("x0".into(), x0)?;
        t.column("x".into(), x.to_vec())?;
        t.column("u".into(), u.to_vec())?;
        for (key, name) in [
            ("book-4.9", "v"),
            ("book-4.15", "stress"),
            ("book-4.16", "stress"),
            ("book-4.17", "volume"),
            ("book-4.18", "density"),
        ] {
            if let Some(v) = traced(step, key, particles, 1)? {
                t.column(name.into(), v.to_vec()).map_err(|_| {
                    Error::Input(format!(
                        "step {}: the trace has both book-4.15 and book-4.16; a step updates the stress by one of them",
                        step.step
                    ))
                })?;
            }
        }
    }
    Ok(t.into_table())
}

/// hompm's final 1D state as a check table.
pub fn state_1d(setup: &Setup1d, sim: &crate::mpm::musl::Simulation) -> State {
    let p = &sim.particles;
    let d = &setup.discretisation;
    let mut t = ParticleTable::default();
    t.columns
        .push(("id".into(), (0..p.len()).map(|k| k as f64).collect()));
    for (name, col) in [
        ("x0", &p.x0),
        ("x", &p.x),
        ("u", &p.displacement),
        ("v", &p.velocity),
        ("stress", &p.stress),
        ("volume", &p.volume),
        ("density", &p.density),
    ] {
        t.columns.push((name.into(), col.clone()));
    }
    State {
        particles: t,
        spacing: setup.scene.length() / (d.cells * d.ppc) as f64,
        method: super::method_label_1d(d),
        two_d: false,
    }
}

/// hompm's final 2D state as a check table.
pub fn state_2d(setup: &Setup2d, sim: &crate::mpm2d::step::Simulation2d) -> State {
    let p = &sim.particles;
    let mut t = ParticleTable::default();
    let n = p.len();
    let pair = |v: &Vec<[f64; 2]>, c: usize| -> Vec<f64> { v.iter().map(|a| a[c]).collect() };
    let entry = |v: &Vec<nalgebra::Matrix2<f64>>, i: usize, j: usize| -> Vec<f64> {
        v.iter().map(|m| m[(i, j)]).collect()
    };
    let cols: Vec<(&str, Vec<f64>)> = vec![
        ("id", (0..n).map(|k| k as f64).collect()),
        ("x0_x", pair(&p.x0, 0)),
        ("x0_y", pair(&p.x0, 1)),
        ("x_x", pair(&p.x, 0)),
        ("x_y", pair(&p.x, 1)),
        ("u_x", pair(&p.displacement, 0)),
        ("u_y", pair(&p.displacement, 1)),
        ("v_x", pair(&p.velocity, 0)),
        ("v_y", pair(&p.velocity, 1)),
        ("stress_xx", entry(&p.stress, 0, 0)),
        ("stress_yy", entry(&p.stress, 1, 1)),
        ("stress_xy", entry(&p.stress, 0, 1)),
        ("stress_yx", entry(&p.stress, 1, 0)),
        ("F_xx", entry(&p.deformation, 0, 0)),
        ("F_xy", entry(&p.deformation, 0, 1)),
        ("F_yx", entry(&p.deformation, 1, 0)),
        ("F_yy", entry(&p.deformation, 1, 1)),
        ("volume", p.volume.clone()),
        ("density", p.density.clone()),
    ];
    for (name, v) in cols {
        t.columns.push((name.into(), v));
    }
    State {
        particles: t,
        spacing: setup.scene.length / (setup.cells * setup.per_side) as f64,
        method: format!(
            "{}{}{}",
            setup.method.label(),
            super::conventions_suffix(&setup.conventions, 2),
            if setup.scene.solution.is_mls_paper() {
                String::new()
            } else {
                format!(" on the {} solution", setup.scene.solution.name())
            }
        ),
        two_d: true,
    }
}
