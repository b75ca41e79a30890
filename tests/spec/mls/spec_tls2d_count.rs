//! The particle-count basis rule of 2D TLS (issue #40, item 5): the rule of
//! QuocAnh90/MPM2D_basic's `TLS2D.m:56-76` (cc01c1b), offered as
//! `BasisRule::ParticleCount` and `--method bsmpm-tls-by-count`, against
//! the engine's conditioning rule (src/mpm2d/tls.rs, docs/conventions.md
//! "2D TLS").

use hompm::mpm2d::reconstruction::{GaussGrid, GaussReconstruction};
use hompm::mpm2d::tls::{BasisRule, TaylorOrder2d, TlsShapes, TlsVariant};
use hompm::mpm2d::{Basis2d, Grid2d, Mapping2d, Particles2d};
use hompm::reconstruct::taylor::DegenerateCells;

/// The values Σ_p φ_gp f_p at the four Gauss points of the one cell of
/// [0, 1]² under `rule`, with the basis built at `order`.
fn one_cell(
    local: &[[f64; 2]],
    f: impl Fn([f64; 2]) -> f64,
    variant: TlsVariant,
    order: TaylorOrder2d,
    rule: BasisRule,
) -> [f64; 4] {
    let n = local.len();
    let grid = Grid2d::new(Basis2d::BSpline { degree: 2 }, 1.0, 1).unwrap();
    let particles = Particles2d::new(local.to_vec(), vec![0.1; n], 1.0, vec![[0.0; 2]; n]).unwrap();
    let mut shapes = TlsShapes::new(order, variant, DegenerateCells::ReduceBasis, 1, n)
        .unwrap()
        .with_basis_rule(rule);
    let gauss = GaussGrid {
        abscissae: grid.gauss_abscissae(),
        cells: 1,
        cell_size: 1.0,
    };
    shapes
        .evaluate(&gauss, &particles, &vec![0; n], &vec![0; n])
        .unwrap();
    let lists = shapes.lists();
    let values = (0..4).map(|g| {
        (lists.start[g]..lists.end[g])
            .map(|e| lists.phi[e] * f(local[lists.particle[e] as usize]))
            .sum()
    });
    let mut out = [0.0; 4];
    out.iter_mut().zip(values).for_each(|(o, v)| *o = v);
    out
}

fn field(x: [f64; 2]) -> f64 {
    3.0 + (2.0 * x[0]).sin() * (1.0 + x[1] * x[1]) - 4.0 * x[0] * x[1]
}

/// Scattered points in the unit cell, none on a conic through too few.
const POINTS: [[f64; 2]; 9] = [
    [0.12, 0.17],
    [0.81, 0.23],
    [0.47, 0.52],
    [0.22, 0.88],
    [0.91, 0.74],
    [0.58, 0.09],
    [0.35, 0.61],
    [0.69, 0.43],
    [0.05, 0.45],
];

#[test]
fn the_count_rule_is_tls2d_m_lines_56_to_76() {
    use TaylorOrder2d::{Constant, Linear, Quadratic};
    let (c, u) = (TlsVariant::Conservative, TlsVariant::Unconstrained);
    let count = BasisRule::ParticleCount;
    let expected_conservative = [
        Constant, Constant, Constant, Linear, Linear, Linear, Quadratic, Quadratic,
    ];
    let expected_unconstrained = [
        Linear, Linear, Linear, Linear, Linear, Linear, Quadratic, Quadratic,
    ];
    for n in 0..8 {
        assert_eq!(
            count.start(Quadratic, c, n),
            expected_conservative[n],
            "{n}"
        );
        assert_eq!(
            count.start(Quadratic, u, n),
            expected_unconstrained[n],
            "{n}"
        );
        // Never above the order the shapes were built with, and the
        // engine's rule always starts there.
        assert_eq!(
            count.start(Linear, c, n),
            expected_conservative[n].min(Linear)
        );
        assert_eq!(BasisRule::Conditioning.start(Quadratic, c, n), Quadratic);
        assert_eq!(BasisRule::Conditioning.start(Linear, u, n), Linear);
    }
}

/// The rules agree where the count rule starts at the engine's basis or at
/// the basis the engine's repair reaches, and differ in a conservative cell
/// of 5 particles (the engine interpolates with five quadratic functions,
/// the count rule fits a plane) and of 2 (the engine interpolates a plane,
/// the count rule keeps the cell average α₁ = Σ V_p f_p / |Ω_e|).
#[test]
fn the_rules_differ_only_in_conservative_cells_of_five_and_of_two_particles() {
    use TaylorOrder2d::{Linear, Quadratic};
    let (cond, count) = (BasisRule::Conditioning, BasisRule::ParticleCount);
    for variant in [TlsVariant::Conservative, TlsVariant::Unconstrained] {
        for n in 1..=9 {
            let p = &POINTS[..n];
            let engine = one_cell(p, field, variant, Quadratic, cond);
            let by_count = one_cell(p, field, variant, Quadratic, count);
            let differs = variant == TlsVariant::Conservative && (n == 5 || n == 2);
            let largest = engine
                .iter()
                .zip(&by_count)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            if differs {
                assert!(largest > 1e-3, "{variant:?}, {n} particles: {largest:e}");
            } else {
                assert_eq!(engine, by_count, "{variant:?}, {n} particles");
            }
        }
    }
    // What the count rule does there: a plane on 5 particles (the engine
    // built at the linear order gives it bit for bit), the average on 2.
    let c = TlsVariant::Conservative;
    assert_eq!(
        one_cell(&POINTS[..5], field, c, Quadratic, count),
        one_cell(&POINTS[..5], field, c, Linear, cond)
    );
    let average: f64 = POINTS[..2].iter().map(|&x| 0.1 * field(x)).sum();
    for v in one_cell(&POINTS[..2], field, c, Quadratic, count) {
        approx::assert_relative_eq!(v, average, max_relative = 1e-15);
    }
}

/// A degenerate quadratic is still reduced under the count rule, where
/// `TLS2D.m` solves a singular system: on six particles in two rows η² is
/// the same at every particle, so the unconstrained fit's ψ₁ and ψ₆ are
/// parallel (the conservative fit, without ψ₁, stays regular). The values
/// stay finite and equal the engine's.
#[test]
fn the_count_rule_still_reduces_a_degenerate_basis() {
    let rows: Vec<[f64; 2]> = [1.0, 3.0, 5.0]
        .iter()
        .flat_map(|&i| [[i / 6.0, 1.0 / 6.0], [i / 6.0, 5.0 / 6.0]])
        .collect();
    for variant in [TlsVariant::Conservative, TlsVariant::Unconstrained] {
        let q = TaylorOrder2d::Quadratic;
        let by_count = one_cell(&rows, field, variant, q, BasisRule::ParticleCount);
        assert!(by_count.iter().all(|v| v.is_finite()));
        assert_eq!(
            by_count,
            one_cell(&rows, field, variant, q, BasisRule::Conditioning)
        );
    }
}

#[test]
fn the_count_rule_is_registered_as_bsmpm_tls_by_count() {
    assert_eq!(
        Mapping2d::from_name("tls-by-count"),
        Some(Mapping2d::TlsByCount)
    );
    assert!(Mapping2d::TlsByCount.reconstructs_end_of_step());
}
