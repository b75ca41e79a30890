//! # hompm's side of a check: its particles as a table, and the matching
//!
//! `hompm check` compares column by column. [`State`] holds hompm's final
//! particles in the check's column names ([`state_1d`], [`state_2d`], or the
//! last step of a trace, [`state_of_trace`]); [`match_particles`] pairs the
//! other code's rows with hompm's particles by `id` (0-based; 1..=n read as
//! 1-based) or by initial position (nearest within a quarter of the
//! particle spacing), so reordered output works. An unmatched or duplicated
//! particle is [`Error::Input`] naming it.
//!
//! Items: [`State`], [`state_1d`], [`state_2d`], [`state_of_trace`],
//! [`match_particles`], [`x0_columns`].

use super::check::MatchBy;
use super::input::ParticleTable;
use super::setup::{Setup1d, Setup2d};
use super::trace::Trace;
use crate::error::{Error, Result};
use std::collections::BTreeMap;

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

/// The initial-position columns of a dimension.
pub fn x0_columns(two_d: bool) -> &'static [&'static str] {
    if two_d {
        &["x0_x", "x0_y"]
    } else {
        &["x0"]
    }
}

/// hompm's particle of each of the other code's rows, and how they were
/// matched.
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
    let use_id = match by {
        MatchBy::Id => true,
        MatchBy::X0 => false,
        MatchBy::Auto => theirs.column("id").is_some(),
    };
    if use_id {
        let Some(ids) = theirs.column("id") else {
            return Err(Error::Input("--match id needs an 'id' column".into()));
        };
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
        let how = if one_based { "id (1-based)" } else { "id" };
        return Ok((perm, how.into()));
    }
    let names = x0_columns(ours.two_d);
    let cols: Vec<&[f64]> = names.iter().filter_map(|c| theirs.column(c)).collect();
    if cols.len() != names.len() {
        if by == MatchBy::X0 {
            return Err(Error::Input(format!(
                "--match x0 needs the column(s) {}",
                names.join(", ")
            )));
        }
        return Ok(((0..n).collect(), "order (no id or x0 column)".into()));
    }
    let ours_cols: Vec<&[f64]> = names
        .iter()
        .filter_map(|c| ours.particles.column(c))
        .collect();
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
    Ok((perm, "x0".into()))
}

/// The final particle state a trace's last step holds (id = index).
pub fn state_of_trace(trace: &Trace) -> Option<ParticleTable> {
    let last = trace.steps.last()?;
    let get = |k: &str| last.equations.get(k).cloned();
    if let (Some(x), Some(u)) = (get("mls-30"), get("mls-30-u")) {
        return Some(state_of_trace_2d(&x, &u, &get));
    }
    let (x, u) = (get("book-4.13")?, get("book-4.12")?);
    let mut t = ParticleTable::default();
    let x0: Vec<f64> = x.iter().zip(&u).map(|(x, u)| x - u).collect();
    t.columns
        .push(("id".into(), (0..x.len()).map(|k| k as f64).collect()));
    t.columns.push(("x0".into(), x0));
    t.columns.push(("x".into(), x));
    t.columns.push(("u".into(), u));
    for (key, name) in [
        ("book-4.9", "v"),
        ("book-4.15", "stress"),
        ("book-4.16", "stress"),
        ("book-4.17", "volume"),
        ("book-4.18", "density"),
    ] {
        if let Some(v) = get(key) {
            if v.len() == t.rows() {
                t.columns.push((name.into(), v));
            }
        }
    }
    Some(t)
}

fn state_of_trace_2d(
    x: &[f64],
    u: &[f64],
    get: &dyn Fn(&str) -> Option<Vec<f64>>,
) -> ParticleTable {
    let n = x.len() / 2;
    let mut t = ParticleTable::default();
    let col =
        |v: &[f64], c: usize, w: usize| -> Vec<f64> { (0..n).map(|k| v[k * w + c]).collect() };
    t.columns
        .push(("id".into(), (0..n).map(|k| k as f64).collect()));
    let x0: Vec<f64> = x.iter().zip(u).map(|(x, u)| x - u).collect();
    for (name, v) in [("x0", &x0[..]), ("x", x), ("u", u)] {
        t.columns.push((format!("{name}_x"), col(v, 0, 2)));
        t.columns.push((format!("{name}_y"), col(v, 1, 2)));
    }
    if let Some(v) = get("mls-29").filter(|v| v.len() == 2 * n) {
        t.columns.push(("v_x".into(), col(&v, 0, 2)));
        t.columns.push(("v_y".into(), col(&v, 1, 2)));
    }
    for (key, name) in [("mls-35", "F"), ("mls-41", "stress")] {
        if let Some(v) = get(key).filter(|v| v.len() == 4 * n) {
            for (c, suffix) in ["xx", "xy", "yx", "yy"].iter().enumerate() {
                t.columns.push((format!("{name}_{suffix}"), col(&v, c, 4)));
            }
        }
    }
    for (key, name) in [("mls-36", "volume"), ("mls-37", "density")] {
        if let Some(v) = get(key).filter(|v| v.len() == n) {
            t.columns.push((name.into(), v));
        }
    }
    t
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
        ("x_x", p.x.clone()),
        ("x_y", p.y.clone()),
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
        method: setup.method.label(),
        two_d: true,
    }
}
