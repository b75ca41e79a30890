//! # Facts quoted in the texts (`thesis-facts`)
//!
//! Particle positions, Courant numbers (thesis Eq. 3.5, C = cΔt/Δx), maximal
//! strains and grid-crossing counts, each computed the way its sentence
//! states it. Rows 12–13 and 16–17 quote "maximal strain … m" from the TLS
//! paper: the unit and the values show they are maximal *displacements*, and
//! they are computed as such.
//!
//! Items: [`table`].

use super::{Computed, TableSpec};
use crate::error::Result;
use crate::mpm::grid::Method;
use crate::mpm::mapping::Mapping;
use crate::mpm::particles::Particles;
use crate::scenes::{column, vibrating_bar, Discretisation};

fn direct(method: Method, cells: usize, ppc: usize) -> Discretisation {
    Discretisation::direct(method, cells, ppc)
}

/// (max |u_p|, grid crossings) of a bar run.
fn bar_run(params: &str, cells: usize, ppc: usize, dt: f64, steps: usize) -> Result<(f64, usize)> {
    let p = vibrating_bar::parameters(params)?;
    let mut sim = p.simulation(&direct(Method::Mpm, cells, ppc))?;
    let mut umax: f64 = 0.0;
    for _ in 0..steps {
        sim.step(dt)?;
        umax = sim.particles.u.iter().fold(umax, |a, u| a.max(u.abs()));
    }
    Ok((umax, sim.diagnostics.grid_crossings))
}

fn compute(quick: bool) -> Result<Computed> {
    let middle = |l: f64| -> Result<f64> {
        let p = Particles::uniform(0.0, l, 128, 1.0)?;
        Ok(p.x0[63])
    };
    let bar = |n: &str| vibrating_bar::parameters(n);
    let col = |n: &str| column::parameters(n);
    let courant = |c: f64, dt: f64, h: f64| c * dt / h;
    let b1 = bar("thesis-table-4.1")?;
    let b2 = bar("thesis-table-4.2")?;
    let c3 = col("thesis-table-4.3")?;
    let c4 = col("thesis-table-4.4")?;
    let (u_small, _) = bar_run("tls-table-2", 40, 12, 1e-7, 19)?;
    let (u_large, x_tls) = if quick {
        (f64::NAN, 0)
    } else {
        bar_run("tls-table-4", 20, 8, 1e-4, 1000)?
    };
    let (_, x_book) = if quick {
        (0.0, 0)
    } else {
        bar_run("book-table-4.1-large", 20, 8, 1e-5, 10_000)?
    };
    let compaction = if quick {
        None
    } else {
        Some(crate::studies::tls_paper::compaction(
            Method::Mpm,
            Mapping::Direct,
        )?)
    };
    // Each fact under the sentence that states it (golden/published/thesis-facts.json).
    let facts: Vec<(&str, Option<f64>)> = vec![
        ("x_p left of the bar's middle, L = 25 m, 32 el × 4 PPC (thesis §5.1.1)", Some(middle(25.0)?)),
        ("x_p left of the bar's middle, L = 1 m, 32 el × 4 PPC (thesis §5.1.2)", Some(middle(1.0)?)),
        ("Courant number, bar Table 4.1, 32 elements, Δt = 1e-5 (thesis §5.1.1)", Some(courant(b1.wave_speed(), 1e-5, b1.length / 32.0))),
        ("Courant number, bar Table 4.2, 32 elements, Δt = 1e-5 (thesis §5.1.2)", Some(courant(b2.wave_speed(), 1e-5, b2.length / 32.0))),
        ("Courant number, column Table 4.3, 50 DOFs, Δt = 1e-4 (thesis §5.1.3)", Some(courant(c3.wave_speed(), 1e-4, c3.height / 49.0))),
        ("Courant number, column Table 4.3, 80 DOFs, Δt = 1e-4 (thesis §5.1.3)", Some(courant(c3.wave_speed(), 1e-4, c3.height / 79.0))),
        ("Courant number, column Table 4.4, 65 DOFs, Δt = 1e-4 (thesis §5.1.4)", Some(courant(c4.wave_speed(), 1e-4, c4.height / 64.0))),
        ("maximum strain, bar Table 4.1 (thesis §4.1)", Some(b1.v0 / b1.wave_speed())),
        ("maximum strain, bar Table 4.2 (thesis §4.1)", Some(b2.v0 / b2.wave_speed())),
        ("maximum strain, column Table 4.3 (thesis §4.2)", Some(c3.density * c3.gravity.abs() * c3.height / c3.young)),
        ("maximum strain, column Table 4.4 (thesis §4.2)", Some(c4.density * c4.gravity.abs() * c4.height / c4.young)),
        ("'maximal strain' [m], bar TLS Table 2, 1.9e-6 s (TLS §6.1)", Some(u_small)),
        ("'maximal strain' [m], bar TLS Table 4, 0.1 s (TLS §6.1)", (!quick).then_some(u_large)),
        ("grid crossings, MPM, bar TLS Table 4, 20 el × 8 PPC, 0.1 s (TLS §6.1: more than)", (!quick).then_some(x_tls as f64)),
        ("grid crossings, MPM, bar book Table 4.1 large, 20 el × 8 PPC, 0.1 s (book §4.5: more than)", (!quick).then_some(x_book as f64)),
        ("grid crossings, MPM, column compaction, 50 el × 20 PPC (TLS §6.2)", (!quick).then(|| compaction.map(|c| c.crossings as f64)).flatten()),
        ("'maximal strain' [m], column compaction (TLS §6.2)", (!quick).then(|| compaction.map(|c| c.max_displacement)).flatten()),
    ];
    Ok(Computed {
        rows: facts.into_iter().map(|(label, v)| (label.to_string(), vec![v])).collect(),
        notes: vec![
            "Courant numbers use the element (knot-span) size Δx = L/elements: 50 DOFs = 49 elements, \
             80 DOFs = 79, 65 DOFs = 64 (thesis Fig. 5.1: n_e elements have n_e + 1 nodes)."
                .into(),
            "Maximum strains are the analytic amplitudes the text's parameters imply: v0/c for the bar, \
             ρ|g|H/E (static) for the column; the dynamic column peaks at about twice that."
                .into(),
            "Column compaction (rows 16–17): standard MPM run of tls-fig10; the 'maximal strain' is the \
             maximal |u_p| at the end of the run."
                .into(),
        ], ..Default::default() })
}

/// The registered `thesis-facts` table.
pub fn table() -> TableSpec {
    TableSpec {
        id: "thesis-facts",
        published_json: include_str!("../../golden/published/thesis-facts.json"),
        setup:
            "Each row computed as its sentence states it; see the notes and docs/reproduction.md.",
        compute: |o| compute(o.quick),
    }
}
