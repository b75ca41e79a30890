//! p-multigrid, book §4.7, Eqs. (4.59)–(4.62), stated on the operators the
//! V-cycle applies: the transfers between degree p and p − 1 on the same
//! knot spans, P_ij = ∫ φ_i^p φ_j^{p−1}, prolongation M_p⁻¹P and restriction
//! M_{p−1}⁻¹Pᵀ.

use approx::assert_relative_eq;
use hompm::solve::pmultigrid::{PMultigrid, PMultigridOptions, Transfer};
use hompm::sparse::SparseMatrix;
use hompm::spline::KnotVector;

const SPANS: usize = 8;

/// Greville abscissae: the B-spline coefficients of f(x) = x.
fn greville(kv: &KnotVector) -> Vec<f64> {
    let (t, p) = (kv.knots(), kv.degree());
    (0..kv.num_basis())
        .map(|i| t[i + 1..=i + p].iter().sum::<f64>() / p as f64)
        .collect()
}

fn apply(m: &SparseMatrix, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; m.rows()];
    m.mul_vec(x, &mut y);
    y
}

fn hierarchy(degree: usize, transfer: Transfer) -> PMultigrid {
    let options = PMultigridOptions {
        transfer,
        ..PMultigridOptions::default()
    };
    PMultigrid::unit_mass(SPANS, degree, 1, false, options).unwrap()
}

#[test]
fn prolongation_reproduces_the_polynomials_of_the_coarse_space() {
    // S_{p−1} (C^{p−2}) is not inside S_p (C^{p−1}), but global polynomials
    // of degree ≤ p − 1 are in both; the consistent (L2) prolongation maps
    // their coarse coefficients to their fine coefficients. Both transfers
    // keep constants (partition of unity).
    for degree in 2..=4 {
        let fine = KnotVector::open_uniform(0.0, 1.0, SPANS, degree).unwrap();
        let coarse = KnotVector::open_uniform(0.0, 1.0, SPANS, degree - 1).unwrap();
        for transfer in [Transfer::Consistent, Transfer::Lumped] {
            let mg = hierarchy(degree, transfer);
            let (_, transfers) = mg.level(degree - 1).unwrap();
            let (prolongation, _) = transfers.unwrap();
            let ones = apply(prolongation, &vec![1.0; coarse.num_basis()]);
            for v in ones {
                assert_relative_eq!(v, 1.0, epsilon = 1e-12);
            }
            if transfer == Transfer::Consistent {
                let x = apply(prolongation, &greville(&coarse));
                for (a, b) in x.iter().zip(greville(&fine)) {
                    assert_relative_eq!(*a, b, epsilon = 1e-12);
                }
            }
        }
    }
}

#[test]
fn restriction_is_the_mass_scaled_transpose_of_prolongation() {
    // M_{p−1} R = Pᵀ = (M_p I)ᵀ: with lumped M this is
    // (M_L,{p−1}) R = Iᵀ (M_L,p), entry by entry.
    let degree = 3;
    let mg = hierarchy(degree, Transfer::Lumped);
    let (fine_mass, transfers) = mg.level(degree - 1).unwrap();
    let (coarse_mass, _) = mg.level(degree - 2).unwrap();
    let (prolongation, restriction) = transfers.unwrap();
    let (mf, mc) = (fine_mass.row_sums(), coarse_mass.row_sums());
    for (i, mc_i) in mc.iter().enumerate() {
        for (j, mf_j) in mf.iter().enumerate() {
            let lhs = mc_i * restriction.get(i, j);
            let rhs = prolongation.get(j, i) * mf_j;
            assert_relative_eq!(lhs, rhs, epsilon = 1e-14);
        }
    }
}

#[test]
fn a_two_grid_cycle_removes_a_smooth_error_that_smoothing_barely_touches() {
    // f = M x* for a smooth x* (the first sine mode) and one pre- and one
    // post-smoothing sweep: the coarse-grid correction (Eqs. 4.61–4.62)
    // brings the residual down by far more than the two sweeps alone.
    let degree = 2;
    let run = |coarse_correction: bool| {
        let options = PMultigridOptions {
            pre_smoothing: 1,
            post_smoothing: 1,
            coarse_correction,
            ..PMultigridOptions::default()
        };
        let mg = PMultigrid::unit_mass(32, degree, 1, false, options).unwrap();
        let n = mg.matrix().rows();
        let exact: Vec<f64> = (0..n)
            .map(|i| (std::f64::consts::PI * i as f64 / (n - 1) as f64).sin())
            .collect();
        let f = apply(mg.matrix(), &exact);
        mg.solve(&f, 1.0, 1).unwrap().residuals[1]
    };
    let (with, without) = (run(true), run(false));
    assert!(
        with < 0.05 * without,
        "one cycle: {with:e} with, {without:e} without the correction"
    );
}

/// The hierarchy takes any 1D level matrices (issue #14): with ρ = 3 every
/// mass and mixed mass is three times the book's, the transfers M⁻¹P are
/// unchanged, and the V-cycle solves M x = f in as many cycles as for
/// ρ = 1. A level without its mixed matrix is refused.
#[test]
fn the_hierarchy_takes_other_level_matrices_than_the_books() {
    use hompm::mass::{unit_density_levels, LevelMatrices};
    let book = unit_density_levels(SPANS, 3, true).unwrap();
    let dense: Vec<LevelMatrices> = book
        .iter()
        .map(|l| LevelMatrices {
            mass: l.mass.scale_rows(&vec![3.0; l.mass.rows()]),
            mixed_to_coarser: l
                .mixed_to_coarser
                .as_ref()
                .map(|p| p.scale_rows(&vec![3.0; p.rows()])),
        })
        .collect();
    let options = PMultigridOptions::default();
    let unit = PMultigrid::from_levels(&book, 1, options).unwrap();
    let heavy = PMultigrid::from_levels(&dense, 1, options).unwrap();
    let f: Vec<f64> = (0..unit.matrix().rows())
        .map(|i| (i as f64).sin())
        .collect();
    let a = unit.solve(&f, 1e-10, 100).unwrap();
    let b = heavy.solve(&f, 1e-10, 100).unwrap();
    assert_eq!(a.iterations, b.iterations);
    for (x, y) in a.solution.iter().zip(&b.solution) {
        assert_relative_eq!(3.0 * y, *x, max_relative = 1e-8, epsilon = 1e-12);
    }
    let mut broken = book.clone();
    broken[2].mixed_to_coarser = None;
    assert!(PMultigrid::from_levels(&broken, 1, options).is_err());
    assert!(PMultigrid::from_levels(&[], 1, options).is_err());
}
