//! # Facts quoted in the texts (`thesis-facts`)
//!
//! Particle positions, Courant numbers (thesis Eq. 3.5, C = cΔt/Δx), maximal
//! strains and grid-crossing counts, each computed the way its sentence
//! states it. Rows 12–13 and 16–17 quote "maximal strain … m" from the TLS
//! paper: the unit and the values show they are maximal *displacements*, and
//! they are computed as such.
//!
//! Items: [`table`], [`column_static_strain`].

use super::{Computed, TableSpec};
use crate::error::Result;
use crate::mpm::grid::Method;
use crate::mpm::mapping::Mapping;
use crate::mpm::musl::Constitutive;
use crate::mpm::particles::Particles;
use crate::scenes::column::{self, ColumnParameters};
use crate::scenes::vibrating_bar::{self, BarParameters};
use crate::studies::bar_extremes;
use crate::studies::tls_paper::{compaction, SMALL_BAR_DT, SMALL_BAR_STEPS};

/// One fact: the sentence's label and its computed value (`None`: not
/// computed in a quick run).
type Fact = (&'static str, Option<f64>);

/// Thesis §5.1.1–5.1.2: the particle just left of the bar's middle, 32
/// elements × 4 PPC (128 particles at the centres of equal sub-intervals).
fn particle_positions() -> Result<Vec<Fact>> {
    let middle = |l: f64| -> Result<f64> { Ok(Particles::uniform(0.0, l, 128, 1.0)?.x0[63]) };
    Ok(vec![
        (
            "x_p left of the bar's middle, L = 25 m, 32 el × 4 PPC (thesis §5.1.1)",
            Some(middle(25.0)?),
        ),
        (
            "x_p left of the bar's middle, L = 1 m, 32 el × 4 PPC (thesis §5.1.2)",
            Some(middle(1.0)?),
        ),
    ])
}

/// The benchmarks of thesis Tables 4.1–4.4: two bars and two columns.
fn thesis_benchmarks() -> Result<(
    BarParameters,
    BarParameters,
    ColumnParameters,
    ColumnParameters,
)> {
    Ok((
        vibrating_bar::parameters("thesis-table-4.1")?,
        vibrating_bar::parameters("thesis-table-4.2")?,
        column::parameters("thesis-table-4.3")?,
        column::parameters("thesis-table-4.4")?,
    ))
}

/// Thesis Eq. (3.5), C = c Δt/Δx, with Δx the element size: n DOFs are
/// n − 1 elements (thesis Fig. 5.1).
fn courant_numbers() -> Result<Vec<Fact>> {
    let courant = |c: f64, dt: f64, h: f64| Some(c * dt / h);
    let (b1, b2, c3, c4) = thesis_benchmarks()?;
    Ok(vec![
        (
            "Courant number, bar Table 4.1, 32 elements, Δt = 1e-5 (thesis §5.1.1)",
            courant(b1.wave_speed(), 1e-5, b1.length / 32.0),
        ),
        (
            "Courant number, bar Table 4.2, 32 elements, Δt = 1e-5 (thesis §5.1.2)",
            courant(b2.wave_speed(), 1e-5, b2.length / 32.0),
        ),
        (
            "Courant number, column Table 4.3, 50 DOFs, Δt = 1e-4 (thesis §5.1.3)",
            courant(c3.wave_speed(), 1e-4, c3.height / 49.0),
        ),
        (
            "Courant number, column Table 4.3, 80 DOFs, Δt = 1e-4 (thesis §5.1.3)",
            courant(c3.wave_speed(), 1e-4, c3.height / 79.0),
        ),
        (
            "Courant number, column Table 4.4, 65 DOFs, Δt = 1e-4 (thesis §5.1.4)",
            courant(c4.wave_speed(), 1e-4, c4.height / 64.0),
        ),
    ])
}

/// The static strain at the base of a column under its own weight, with
/// the column's own constitutive update: the base carries the Cauchy stress
/// σ = −ρ₀|g|H (in 1D the weight above it, whatever the deformation), so
/// with s = ρ₀|g|H/E the small-strain law σ = Eε (book Eq. 4.15) gives
/// ε = s, and the large-strain update σ ← σ + (E − σ)Δε (book Eq. 4.16),
/// whose solution is σ = E(1 − 1/F), gives F = 1/(1 + s) and the
/// engineering strain 1 − F = s/(1 + s). The 1D neo-Hookean law with
/// ν = 0, σ = E(F² − 1)/(2F), gives F = √(1 + s²) − s.
pub fn column_static_strain(column: &ColumnParameters) -> f64 {
    let s = column.density * column.gravity.abs() * column.height / column.young;
    match column.constitutive {
        Constitutive::SmallStrain => s,
        Constitutive::LargeStrain => s / (1.0 + s),
        Constitutive::NeoHookean => 1.0 - ((1.0 + s * s).sqrt() - s),
    }
}

/// Thesis §4.1–4.2: the analytic strain amplitudes, v0/c for the bar and
/// the static strain at the base for the column, under the column's own
/// constitutive update ([`column_static_strain`]).
fn maximum_strains() -> Result<Vec<Fact>> {
    let (b1, b2, c3, c4) = thesis_benchmarks()?;
    Ok(vec![
        (
            "maximum strain, bar Table 4.1 (thesis §4.1)",
            Some(b1.v0 / b1.wave_speed()),
        ),
        (
            "maximum strain, bar Table 4.2 (thesis §4.1)",
            Some(b2.v0 / b2.wave_speed()),
        ),
        (
            "maximum strain, column Table 4.3 (thesis §4.2)",
            Some(column_static_strain(&c3)),
        ),
        (
            "maximum strain, column Table 4.4 (thesis §4.2)",
            Some(column_static_strain(&c4)),
        ),
    ])
}

/// TLS paper §6.1–6.2 and book §4.5: maximal displacements and grid-crossing
/// counts of standard MPM runs (all but the first skipped when `quick`).
fn run_facts(quick: bool) -> Result<Vec<Fact>> {
    let small = bar_extremes("tls-table-2", 40, 12, SMALL_BAR_DT, SMALL_BAR_STEPS)?;
    // The long runs, each once; `None` in a quick run.
    let tls = (!quick)
        .then(|| bar_extremes("tls-table-4", 20, 8, 1e-4, 1000))
        .transpose()?;
    let book = (!quick)
        .then(|| bar_extremes("book-table-4.1-large", 20, 8, 1e-5, 10_000))
        .transpose()?;
    let column = (!quick)
        .then(|| compaction(Method::Mpm, Mapping::Direct))
        .transpose()?;
    Ok(vec![
        ("'maximal strain' [m], bar TLS Table 2, 1.9e-6 s (TLS §6.1)", Some(small.max_displacement)),
        ("'maximal strain' [m], bar TLS Table 4, 0.1 s (TLS §6.1)", tls.map(|r| r.max_displacement)),
        ("grid crossings, MPM, bar TLS Table 4, 20 el × 8 PPC, 0.1 s (TLS §6.1: more than)", tls.map(|r| r.crossings as f64)),
        ("grid crossings, MPM, bar book Table 4.1 large, 20 el × 8 PPC, 0.1 s (book §4.5: more than)", book.map(|r| r.crossings as f64)),
        ("grid crossings, MPM, column compaction, 50 el × 20 PPC (TLS §6.2)", column.map(|r| r.crossings as f64)),
        ("'maximal strain' [m], column compaction (TLS §6.2)", column.map(|r| r.max_displacement)),
    ])
}

fn compute(quick: bool) -> Result<Computed> {
    let facts = [
        particle_positions()?,
        courant_numbers()?,
        maximum_strains()?,
        run_facts(quick)?,
    ];
    Ok(Computed {
        rows: facts.into_iter().flatten().map(|(label, v)| (label.to_string(), vec![v])).collect(),
        notes: vec![
            "Courant numbers use the element (knot-span) size Δx = L/elements: 50 DOFs = 49 elements, \
             80 DOFs = 79, 65 DOFs = 64 (thesis Fig. 5.1: n_e elements have n_e + 1 nodes)."
                .into(),
            "Maximum strains are the analytic amplitudes the text's parameters imply: v0/c for the bar; \
             for the column the static strain at the base under its own law: ρ|g|H/E with the \
             small-strain update (Table 4.3), s/(1 + s) with s = ρ|g|H/E and the large-strain update \
             σ = E(1 − 1/F) (Table 4.4: 8.93 %; ρ|g|H/E = 9.81 % would print as 10 %). The dynamic \
             column peaks at about twice that."
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
