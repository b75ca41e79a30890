//! The 2D engine of the MLS paper, equation by equation: the neo-Hookean
//! law (Eqs. 40–41), the body force of the manufactured solution (Eq. 42,
//! checked by finite differences), MLS at the Gauss points (Eqs. 10–17),
//! a step computed by hand (Eqs. 22–37 on a 2×2 bilinear grid), the Kronecker
//! assembly against the 2D tensor basis of `spline::tensor`, and the patch
//! test (a uniform state produces no spurious force).

use approx::assert_relative_eq;
use hompm::error::Error;
use hompm::mpm::diagnostics::compensated_sum;
use hompm::mpm2d::mls::{GaussGrid, MlsShapes};
use hompm::mpm2d::step::{
    map_direct, map_reconstructed, Formulation, Mapping2d, Settings2d, Simulation2d,
};
use hompm::mpm2d::{Basis2d, Grid2d, NeoHookean, Particles2d};
use hompm::rng::SplitMix64;
use hompm::scenes::aligned_vibration::{parameters, AlignedMethod};
use hompm::spline::{KnotVector, TensorBasis2d};
use nalgebra::Matrix2;

fn material() -> NeoHookean {
    NeoHookean::from_young_poisson(1e7, 0.3).unwrap()
}

/// The Cauchy stress of the compressible neo-Hookean solid computed without
/// its closed form: P = ∂W/∂F of the strain energy
/// W = μ/2 (tr FᵀF − 2) − μ ln J + λ/2 (ln J)² by central differences,
/// then σ = P Fᵀ / J. Agrees with Eq. (41) to about 1e-8.
fn cauchy_stress_from_the_energy(m: &NeoHookean, f: &Matrix2<f64>) -> Matrix2<f64> {
    let energy = |g: &Matrix2<f64>| {
        let j: f64 = g.determinant();
        0.5 * m.mu * ((g.transpose() * g).trace() - 2.0) - m.mu * j.ln()
            + 0.5 * m.lambda * j.ln() * j.ln()
    };
    let h = 1e-6;
    let mut p = Matrix2::zeros();
    for a in 0..2 {
        for b in 0..2 {
            let (mut up, mut down) = (*f, *f);
            up[(a, b)] += h;
            down[(a, b)] -= h;
            p[(a, b)] = (energy(&up) - energy(&down)) / (2.0 * h);
        }
    }
    p * f.transpose() / f.determinant()
}

/// The settings of the hand-built scenes: [`material`] and an MLS support
/// of one cell.
fn settings(formulation: Formulation, mapping: Mapping2d) -> Settings2d {
    Settings2d {
        formulation,
        mapping,
        material: material(),
        mls_support: 1.0,
        conventions: hompm::mpm::conventions::Conventions::MLS_PAPER,
    }
}

/// An updated-Lagrangian simulation with the direct mapping of `p` on
/// 3 × 3 cells of [0, 1]² with `basis`.
fn direct_on_three_cells(
    basis: Basis2d,
    p: Particles2d,
    body_force: Option<Box<dyn hompm::mpm2d::BodyForce2d>>,
) -> Simulation2d {
    let grid = Grid2d::new(basis, 1.0, 3).unwrap();
    let settings = settings(Formulation::UpdatedLagrangian, Mapping2d::Direct);
    Simulation2d::new(grid, p, settings, body_force).unwrap()
}

/// Σ_p m_p |v_p|, the scale of the momenta's rounding.
fn speed_scale(p: &Particles2d) -> f64 {
    (0..p.len())
        .map(|k| p.mass[k] * p.velocity[k][0].hypot(p.velocity[k][1]))
        .sum()
}

/// b = (0, −10) per unit mass everywhere.
struct Gravity;
impl hompm::mpm2d::BodyForce2d for Gravity {
    fn fill(&self, _t: f64, _x0: &[[f64; 2]], out: &mut [[f64; 2]]) {
        out.iter_mut().for_each(|o| *o = [0.0, -10.0]);
    }
}

/// Map rows: mls-40, mls-41 — Eq. (41) is checked through its relation to Eq. (40).
#[test]
fn cauchy_stress_is_piola_times_f_transposed_over_j_and_the_printed_piola_is_its_transpose() {
    let m = material();
    let f = Matrix2::new(1.2, 0.3, -0.1, 0.9);
    let j = f.determinant();
    let sigma = m.cauchy_stress(&f).unwrap();
    let p = m.first_piola(&f).unwrap();
    // Eq. (41): σ = P Fᵀ / J.
    assert_relative_eq!(sigma, p * f.transpose() / j, max_relative = 1e-12);
    // Eq. (41) against the derivative of the strain energy.
    let expected = cauchy_stress_from_the_energy(&m, &f);
    assert_relative_eq!(
        sigma,
        expected,
        max_relative = 1e-6,
        epsilon = 1e-6 * sigma.norm()
    );
    // Eq. (40) as printed is the nominal stress J F⁻¹ σ = Pᵀ …
    let printed = m.first_piola_as_printed(&f).unwrap();
    assert_relative_eq!(printed, p.transpose(), max_relative = 1e-12);
    // … which differs from P for a non-symmetric F, and agrees for a symmetric one.
    assert!((printed - p).norm() > 1e-3 * p.norm());
    let s = Matrix2::new(1.2, 0.0, 0.0, 0.7);
    assert_relative_eq!(
        m.first_piola_as_printed(&s).unwrap(),
        m.first_piola(&s).unwrap(),
        max_relative = 1e-12
    );
    // Lamé constants of E = 1e7, ν = 0.3.
    assert_relative_eq!(m.lambda, 1e7 * 0.3 / (1.3 * 0.4), max_relative = 1e-15);
    assert_relative_eq!(m.mu, 1e7 / 2.6, max_relative = 1e-15);
}

#[test]
fn an_inverted_deformation_gradient_is_an_inverted_deformation_error() {
    let m = material();
    for (f, j) in [
        (Matrix2::new(-1.0, 2.0, 0.5, 1.0), -2.0),
        (Matrix2::zeros(), 0.0),
    ] {
        let e = m.cauchy_stress(&f).unwrap_err();
        let expected = Error::InvertedDeformation {
            particle: None,
            step: None,
            time: None,
            jacobian: j,
            deformation: [f[(0, 0)], f[(0, 1)], f[(1, 0)], f[(1, 1)]],
        };
        assert_eq!(e, expected, "{f}");
        assert_eq!(m.first_piola(&f).unwrap_err(), expected);
    }
    let nan = Matrix2::new(f64::NAN, 0.0, 0.0, 1.0);
    assert!(matches!(
        m.cauchy_stress(&nan),
        Err(Error::InvertedDeformation { jacobian, .. }) if jacobian.is_nan()
    ));
    assert!(NeoHookean::from_young_poisson(1e7, 0.5).is_err());
    assert!(NeoHookean::from_young_poisson(-1.0, 0.3).is_err());
    // The open ends of E > 0 and −1 < ν: E = 0 and ν = −1 are refused too
    // (μ = E/(2(1 + ν)) would be 0 or infinite).
    assert!(NeoHookean::from_young_poisson(0.0, 0.3).is_err());
    assert!(NeoHookean::from_young_poisson(1e7, -1.0).is_err());
    assert!(NeoHookean::from_young_poisson(1e7, -0.99).is_ok());
}

/// b = ü − ∇_X·P/ρ₀ by central differences of the manufactured solution.
fn body_force_by_finite_differences(x0: [f64; 2], t: f64) -> [f64; 2] {
    let s = parameters("mls-paper-e1e7").unwrap();
    let m = s.material().unwrap();
    let (hx, ht) = (1e-5, 1e-7);
    let p_at = |x: [f64; 2]| m.first_piola(&s.deformation_gradient(x, t)).unwrap();
    let mut div = [0.0; 2];
    for (d, item) in div.iter_mut().enumerate() {
        // (∇·P)_i = Σ_J ∂P_iJ/∂X_J.
        for col in 0..2 {
            let mut plus = x0;
            let mut minus = x0;
            plus[col] += hx;
            minus[col] -= hx;
            *item += (p_at(plus)[(d, col)] - p_at(minus)[(d, col)]) / (2.0 * hx);
        }
    }
    let u = |t: f64| s.displacement(x0, t);
    let acc = [0, 1].map(|d| (u(t + ht)[d] - 2.0 * u(t)[d] + u(t - ht)[d]) / (ht * ht));
    [0, 1].map(|d| acc[d] - div[d] / s.density)
}

#[test]
fn the_body_force_has_pi_squared_where_eq_42_prints_pi() {
    let s = parameters("mls-paper-e1e7").unwrap();
    for (x0, t) in [
        ([0.13, 0.71], 0.0031),
        ([0.4, 0.22], 0.0117),
        ([0.9, 0.55], 0.1234),
    ] {
        let fd = body_force_by_finite_differences(x0, t);
        let derived = s.body_force(x0, t).unwrap();
        let printed = s.body_force_as_printed(x0, t).unwrap();
        for d in 0..2 {
            assert_relative_eq!(derived[d], fd[d], max_relative = 1e-4);
            // The printed formula is short by exactly a factor π.
            assert_relative_eq!(
                printed[d] * std::f64::consts::PI,
                derived[d],
                max_relative = 1e-12
            );
            assert!((printed[d] - fd[d]).abs() > 0.5 * fd[d].abs());
        }
    }
}

/// Map rows: mls-38, mls-39 — the displacement and its initial conditions are one manufactured solution.
#[test]
fn the_manufactured_solution_satisfies_the_walls_and_starts_undeformed() {
    let s = parameters("mls-paper-e1e8").unwrap();
    for t in [0.0, 0.003, 0.05] {
        for y in [0.0, 0.3, 1.0] {
            assert!(s.displacement([0.0, y], t)[0].abs() < 1e-15);
            assert!(s.displacement([1.0, y], t)[0].abs() < 1e-15);
            assert!(s.displacement([y, 0.0], t)[1].abs() < 1e-15);
            assert!(s.displacement([y, 1.0], t)[1].abs() < 1e-15);
        }
    }
    // sin(π) is 1.2e-16 in floating point.
    assert_relative_eq!(
        s.deformation_gradient([0.3, 0.6], 0.0),
        Matrix2::identity(),
        epsilon = 1e-15
    );
    // c = √(E/ρ₀).
    assert_relative_eq!(s.wave_speed(), (1e8f64 / 1000.0).sqrt());
    // v = ∂u/∂t.
    let (x0, t, dt) = ([0.21, 0.67], 0.0042, 1e-8);
    let v = s.velocity(x0, t);
    for (d, vd) in v.iter().enumerate() {
        let fd = (s.displacement(x0, t + dt)[d] - s.displacement(x0, t - dt)[d]) / (2.0 * dt);
        assert_relative_eq!(*vd, fd, max_relative = 1e-6);
    }
}

fn scattered_particles(cells: usize, per_side: usize, jitter: f64, seed: u64) -> Particles2d {
    let mut rng = SplitMix64::new(seed);
    let mut p = Particles2d::cell_centred(1.0, cells, per_side, 1000.0, |_| [0.0; 2]).unwrap();
    let d = 1.0 / (cells * per_side) as f64;
    for k in 0..p.len() {
        p.x[k][0] += jitter * d * (rng.uniform() - 0.5);
        p.x[k][1] += jitter * d * (rng.uniform() - 0.5);
    }
    p
}

fn cells_of(grid: &Grid2d, coords: &[f64]) -> Vec<usize> {
    coords
        .iter()
        .map(|&c| grid.axis().cell_of(c).unwrap())
        .collect()
}

/// The cells along axis `c` of the positions `x`.
fn cells_along(grid: &Grid2d, x: &[[f64; 2]], c: usize) -> Vec<usize> {
    cells_of(grid, &x.iter().map(|x| x[c]).collect::<Vec<_>>())
}

/// Positions [x, y] from separate coordinate lists.
fn pairs(x: &[f64], y: &[f64]) -> Vec<[f64; 2]> {
    x.iter().zip(y).map(|(&x, &y)| [x, y]).collect()
}

#[test]
fn mls_shape_functions_reproduce_constants_and_linear_fields_at_every_gauss_point() {
    for (support, seed) in [(1.0, 1), (2.0, 2)] {
        let grid = Grid2d::new(Basis2d::BSpline { degree: 2 }, 1.0, 4).unwrap();
        let p = scattered_particles(4, 3, 0.8, seed);
        let mut mls = MlsShapes::new(support, 4, p.len()).unwrap();
        let gauss = GaussGrid {
            abscissae: grid.gauss_abscissae(),
            cells: 4,
            cell_size: 0.25,
        };
        mls.evaluate(
            &gauss,
            &p.x,
            &cells_along(&grid, &p.x, 0),
            &cells_along(&grid, &p.x, 1),
        )
        .unwrap();
        let n = 8;
        for g in 0..n * n {
            let xg = [grid.gauss_abscissae()[g % n], grid.gauss_abscissae()[g / n]];
            let (mut s0, mut sx, mut sy) = (0.0, 0.0, 0.0);
            let range = mls.start[g]..mls.end[g];
            assert!(range.len() >= 3);
            for e in range {
                let k = mls.particle[e] as usize;
                s0 += mls.phi[e];
                sx += mls.phi[e] * p.x[k][0];
                sy += mls.phi[e] * p.x[k][1];
                // Only particles inside the support r < 1.5 carry weight.
                assert!((p.x[k][0] - xg[0]).abs() < 1.5 * support * 0.25);
            }
            assert_relative_eq!(s0, 1.0, epsilon = 1e-12);
            assert_relative_eq!(sx, xg[0], epsilon = 1e-12);
            assert_relative_eq!(sy, xg[1], epsilon = 1e-12);
        }
    }
}

/// MLS paper Eqs. (10), (14)–(17) evaluated directly, over all particles:
/// at each Gauss point x_g the support is exactly the particles with
/// w(x_g − x_p) = w(r_x) w(r_y) > 0, r = |x_g − x_p|/(s h), and
/// φ_gp = w_p [1, x_g, y_g] A⁻¹ [1, x_p, y_p]ᵀ with A = Σ_p w_p p pᵀ in
/// global coordinates. Five cells (odd, more than the four of the reach) so
/// that the cell binning and the gathering are exercised away from the
/// corners.
///
/// Map rows: mls-6, mls-7, mls-8, mls-9, mls-10, mls-11, mls-12, mls-13, mls-14, mls-15, mls-16, mls-17 — the engine's shape functions (MlsShapes) are compared with Eqs. (6)–(17) written out directly, which checks each of them at once.
#[test]
fn mls_shape_functions_are_eq_14_over_exactly_the_particles_in_the_support() {
    let weight = |d: f64| {
        let r = d.abs();
        if r <= 0.5 {
            0.75 - r * r
        } else if r < 1.5 {
            0.5 * (1.5 - r) * (1.5 - r)
        } else {
            0.0
        }
    };
    let cells = 5;
    // The unit square, and a square of side 100 (h = 20), where a reach
    // 1.5 s + h or 1.5 + s h instead of 1.5 s h would miss a column of cells.
    for (length, support, seed) in [(1.0, 1.0, 3), (1.0, 1.6, 4), (100.0, 1.0, 5)] {
        let h = length / cells as f64;
        let grid = Grid2d::new(Basis2d::BSpline { degree: 2 }, length, cells).unwrap();
        let mut p = scattered_particles(cells, 3, 0.9, seed);
        p.x.iter_mut().flatten().for_each(|c| *c *= length);
        let mut mls = MlsShapes::new(support, cells, p.len()).unwrap();
        let gauss = GaussGrid {
            abscissae: grid.gauss_abscissae(),
            cells,
            cell_size: h,
        };
        let (cx, cy) = (cells_along(&grid, &p.x, 0), cells_along(&grid, &p.x, 1));
        mls.evaluate(&gauss, &p.x, &cx, &cy).unwrap();
        let n = 2 * cells;
        let mut largest_condition = 0.0f64;
        for g in 0..n * n {
            let xg = [grid.gauss_abscissae()[g % n], grid.gauss_abscissae()[g / n]];
            let w: Vec<f64> = (0..p.len())
                .map(|k| {
                    weight((p.x[k][0] - xg[0]) / (support * h))
                        * weight((p.x[k][1] - xg[1]) / (support * h))
                })
                .collect();
            let mut a = nalgebra::Matrix3::zeros();
            for (k, &wk) in w.iter().enumerate() {
                let q = nalgebra::Vector3::new(1.0, p.x[k][0], p.x[k][1]);
                a += wk * q * q.transpose();
            }
            let a_inv = a.try_inverse().unwrap();
            // κ₁ of the moment matrix in the local scaled basis
            // [1, (x − x_g)/(s h), (y − y_g)/(s h)] (docs/conventions.md, "2D MPM").
            let mut local = nalgebra::Matrix3::zeros();
            for (k, &wk) in w.iter().enumerate() {
                let d = [
                    (p.x[k][0] - xg[0]) / (support * h),
                    (p.x[k][1] - xg[1]) / (support * h),
                ];
                let q = nalgebra::Vector3::new(1.0, d[0], d[1]);
                local += wk * q * q.transpose();
            }
            let norm1 = |m: &nalgebra::Matrix3<f64>| m.abs().row_sum().max();
            let local_inv = local.try_inverse().unwrap();
            largest_condition = largest_condition.max(norm1(&local) * norm1(&local_inv));
            let mut expected: Vec<(usize, f64)> = (0..p.len())
                .filter(|&k| w[k] > 0.0)
                .map(|k| {
                    let pg = nalgebra::Vector3::new(1.0, xg[0], xg[1]);
                    let pp = nalgebra::Vector3::new(1.0, p.x[k][0], p.x[k][1]);
                    (k, w[k] * (pg.transpose() * a_inv * pp)[0])
                })
                .collect();
            let mut computed: Vec<(usize, f64)> = (mls.start[g]..mls.end[g])
                .map(|e| (mls.particle[e] as usize, mls.phi[e]))
                .collect();
            expected.sort_by_key(|e| e.0);
            computed.sort_by_key(|e| e.0);
            let ids = |v: &[(usize, f64)]| v.iter().map(|e| e.0).collect::<Vec<_>>();
            assert_eq!(
                ids(&computed),
                ids(&expected),
                "support of Gauss point {g}, s = {support}"
            );
            for ((k, phi), (_, want)) in computed.iter().zip(&expected) {
                assert!(
                    (phi - want).abs() <= 1e-10 * (1.0 + want.abs()),
                    "φ at Gauss point {g}, particle {k}: {phi} against {want}"
                );
            }
        }
        assert_relative_eq!(
            mls.largest_condition,
            largest_condition,
            max_relative = 1e-9
        );
    }
}

/// The neighbour lists are sized for the average density; a cluster of
/// particles denser than that grows them. 400 particles spread 2×2 per cell
/// over 10×10 cells, and 400 more on a 20×20 lattice in the corner
/// [0.401, 0.427]² of cell (4, 4). The first cell whose gathering reaches
/// the cluster is (2, 2), where the cluster's cell is the last column and
/// the last row gathered, and the Gauss point (0.279, 0.279) has all of it
/// in its support: about 500 candidates against the 4 × 80 the lists start
/// with, so the count that sizes the lists must include that column. The
/// shape functions still reproduce linear fields (MLS paper Eq. 14 with
/// p = [1, x, y]).
#[test]
fn mls_neighbour_lists_grow_for_a_cluster_denser_than_the_average() {
    let cells = 10;
    let h = 0.1;
    let (mut x, mut y) = (Vec::new(), Vec::new());
    for j in 0..2 * cells {
        for i in 0..2 * cells {
            x.push((i as f64 + 0.5) * h / 2.0);
            y.push((j as f64 + 0.5) * h / 2.0);
        }
    }
    for j in 0..20 {
        for i in 0..20 {
            x.push(0.401 + i as f64 * 0.026 / 19.0);
            y.push(0.401 + j as f64 * 0.026 / 19.0);
        }
    }
    let grid = Grid2d::new(Basis2d::BSpline { degree: 2 }, 1.0, cells).unwrap();
    let mut mls = MlsShapes::new(1.0, cells, x.len()).unwrap();
    let gauss = GaussGrid {
        abscissae: grid.gauss_abscissae(),
        cells,
        cell_size: h,
    };
    let (cx, cy) = (cells_of(&grid, &x), cells_of(&grid, &y));
    mls.evaluate(&gauss, &pairs(&x, &y), &cx, &cy).unwrap();
    let n = 2 * cells;
    let mut most = 0;
    for g in 0..n * n {
        let xg = [grid.gauss_abscissae()[g % n], grid.gauss_abscissae()[g / n]];
        let (mut s0, mut sx, mut sy) = (0.0, 0.0, 0.0);
        most = most.max(mls.end[g] - mls.start[g]);
        for e in mls.start[g]..mls.end[g] {
            let k = mls.particle[e] as usize;
            s0 += mls.phi[e];
            sx += mls.phi[e] * x[k];
            sy += mls.phi[e] * y[k];
        }
        assert_relative_eq!(s0, 1.0, epsilon = 1e-12);
        assert_relative_eq!(sx, xg[0], epsilon = 1e-12);
        assert_relative_eq!(sy, xg[1], epsilon = 1e-12);
    }
    assert!(
        most > 320,
        "the cluster puts {most} particles in one support"
    );
}

#[test]
fn mls_with_collinear_particles_is_a_singular_system_error() {
    let grid = Grid2d::new(Basis2d::BSpline { degree: 2 }, 1.0, 2).unwrap();
    // All particles on the line y = 0.3: A(x) is singular at every Gauss point.
    let x: Vec<f64> = (0..20).map(|k| 0.025 + 0.05 * k as f64).collect();
    let y = vec![0.3; 20];
    let mut mls = MlsShapes::new(1.0, 2, 20).unwrap();
    let gauss = GaussGrid {
        abscissae: grid.gauss_abscissae(),
        cells: 2,
        cell_size: 0.5,
    };
    let err = mls
        .evaluate(
            &gauss,
            &pairs(&x, &y),
            &cells_of(&grid, &x),
            &cells_of(&grid, &y),
        )
        .unwrap_err();
    match err {
        Error::SingularMoments {
            point,
            points_in_support,
            condition_number,
            limit,
        } => {
            assert_eq!(point.len(), 2);
            assert!(point.iter().all(|c| (0.0..=1.0).contains(c)));
            assert!(points_in_support >= 3, "{points_in_support}");
            assert!(condition_number > limit, "κ₁ = {condition_number:e}");
            assert_eq!(limit, hompm::reconstruct::mls::MLS_MAX_CONDITION);
        }
        other => panic!("collinear particles gave {other:?}"),
    }
}

/// Map rows: mls-4, mls-5, mls-22, mls-23, mls-25 — the three nodal sums of phase 1 come from one dense assembly with the tensor basis N_i and ∇N_i, so the engine's tensor stencil is pinned by the same comparison.
#[test]
fn direct_mapping_equals_a_dense_assembly_with_the_tensor_basis() {
    // Degree 4 (width 5) takes the loops whose width is known at run time.
    for degree in [2, 4] {
        direct_mapping_equals_a_dense_assembly_at_degree(degree);
    }
}

fn direct_mapping_equals_a_dense_assembly_at_degree(degree: usize) {
    let p = randomly_moving(scattered_particles(3, 2, 0.9, 7), 11);
    let mut sim = direct_on_three_cells(Basis2d::BSpline { degree }, p.clone(), None);
    map_direct(&sim.grid, &sim.particles, &mut sim.workspace);
    let kv = KnotVector::open_uniform(0.0, 1.0, 3, degree).unwrap();
    let tensor = TensorBasis2d::new(kv.clone(), kv);
    let n = tensor.num_basis();
    let (mut m, mut mv, mut f) = (vec![0.0; n], vec![[0.0; 2]; n], vec![[0.0; 2]; n]);
    for k in 0..p.len() {
        let loc = tensor.local_basis(p.x[k][0], p.x[k][1]).unwrap();
        for ((&i, &nv), g) in loc.indices.iter().zip(&loc.values).zip(&loc.gradients) {
            m[i] += nv * p.mass[k];
            for d in 0..2 {
                mv[i][d] += nv * p.mass[k] * p.velocity[k][d];
                f[i][d] -= p.volume[k] * (p.stress[k][(d, 0)] * g[0] + p.stress[k][(d, 1)] * g[1]);
            }
        }
    }
    let ws = &sim.workspace;
    for i in 0..n {
        assert_relative_eq!(ws.mass[i], m[i], max_relative = 1e-13, epsilon = 1e-15);
        for d in 0..2 {
            assert_relative_eq!(ws.momentum[i][d], mv[i][d], epsilon = 1e-13);
            assert_relative_eq!(ws.force[i][d], f[i][d], epsilon = 1e-13);
        }
    }
}

/// One particle at (¼, ¼) of a 2×2 bilinear grid on [0, 1]² (h = ½), with
/// m = 2, V = ½, v = (1, −2), σ = [[3, 1], [1, −4]], body force b = (0, −10),
/// Δt = 0.01. At the particle every one of the four functions of cell (0, 0)
/// is ¼, with gradients ∇N = (∓1, ∓1)/… worked out below; only the centre
/// node (1, 1) is free in both directions, node (1, 0) only in x, node (0, 1)
/// only in y, node (0, 0) in neither.
///
/// Map rows: mls-20, mls-22, mls-23, mls-24, mls-26, mls-27, mls-28, mls-29, mls-30, mls-32, mls-33, mls-34, mls-35, mls-36, mls-37, mls-41 — one step computed by hand checks every equation of the step in order.
#[test]
fn one_bilinear_step_by_hand() {
    let grid = Grid2d::new(Basis2d::Bilinear, 1.0, 2).unwrap();
    let mut p = Particles2d::new(vec![[0.25, 0.25]], vec![0.5], 4.0, vec![[1.0, -2.0]]).unwrap();
    p.stress[0] = Matrix2::new(3.0, 1.0, 1.0, -4.0);
    let mut sim = Simulation2d::new(
        grid,
        p,
        settings(Formulation::UpdatedLagrangian, Mapping2d::Direct),
        Some(Box::new(Gravity)),
    )
    .unwrap();
    let dt = 0.01;
    sim.step(dt).unwrap();
    // N = ¼ at all four nodes of cell (0, 0); with h = ½ and local
    // coordinates (½, ½): ∇N_(0,0) = (−1, −1), ∇N_(1,0) = (1, −1),
    // ∇N_(0,1) = (−1, 1), ∇N_(1,1) = (1, 1).
    // Masses (Eq. 22 direct): m_i = ¼ · 2 = ½ at nodes 0, 1, 3, 4 (index i + 3j).
    let ws = &sim.workspace;
    for i in [0, 1, 3, 4] {
        assert_relative_eq!(ws.mass[i], 0.5);
    }
    // Forces f_i = N m b − V σ ∇N (Eqs. 24–26). Node (1, 1) = index 4:
    // f = ¼·2·(0, −10) − ½·(3 + 1, 1 − 4) = (−2, −3.5); a = f/m = (−4, −7).
    // Node (1, 0) = index 1, x free: f_x = 0 − ½ (3·1 + 1·(−1)) = −1; a_x = −2.
    // Node (0, 1) = index 3, y free: f_y = −20·¼ − ½ (1·(−1) + (−4)·1) = −2.5; a_y = −5.
    // Momenta (mv)_i = ¼·2·(1, −2) = (½, −1), then + f Δt (Eq. 28), then
    // v_i = (mv)_i / m_i: node 4 (1 − 0.04, −2 − 0.07) = (0.96, −2.07);
    // node 1 x: (½ − 0.01)/½ = 0.98; node 3 y: (−1 − 0.025)/½ = −2.05.
    // Eq. (29): v_p += Δt Σ N a = 0.01·¼·(−4 − 2, −7 − 5) = (−0.015, −0.03).
    let v = sim.particles.velocity[0];
    assert_relative_eq!(v[0], 1.0 - 0.015, max_relative = 1e-14);
    assert_relative_eq!(v[1], -2.0 - 0.03, max_relative = 1e-14);
    // Eq. (30): x_p += Δt Σ N v_i = 0.01·¼·(0.96 + 0.98, −2.07 − 2.05).
    assert_relative_eq!(
        sim.particles.x[0][0],
        0.25 + 0.0025 * 1.94,
        max_relative = 1e-14
    );
    assert_relative_eq!(
        sim.particles.x[0][1],
        0.25 + 0.0025 * (-4.12),
        max_relative = 1e-14
    );
    // Eqs. (31)–(33): (mv)^L = ¼·2·v_p = ½ v_p at every node; v^L = v_p on
    // the free components: node 4 (v_x, v_y), node 1 (v_x, 0), node 3 (0, v_y).
    // Eq. (34): L = Σ v^L ⊗ ∇N = v^L_4 ⊗ (1, 1) + (v_x, 0) ⊗ (1, −1) + (0, v_y) ⊗ (−1, 1)
    //   = [[2 v_x, 0], [0, 2 v_y]].
    let l = Matrix2::new(2.0 * v[0], 0.0, 0.0, 2.0 * v[1]);
    let f = Matrix2::identity() + l * dt;
    assert_relative_eq!(sim.particles.deformation[0], f, max_relative = 1e-14);
    // Eqs. (36)–(37): V = det F V⁰, ρ = m / V.
    assert_relative_eq!(
        sim.particles.volume[0],
        f.determinant() * 0.5,
        max_relative = 1e-14
    );
    assert_relative_eq!(
        sim.particles.density[0],
        2.0 / (f.determinant() * 0.5),
        max_relative = 1e-14
    );
    // Eq. (41) from the strain energy, not from the function the step calls.
    let sigma = sim.particles.stress[0];
    assert_relative_eq!(
        sigma,
        cauchy_stress_from_the_energy(&material(), &f),
        max_relative = 1e-6,
        epsilon = 1e-6 * sigma.norm()
    );
    // One step taken, at t = Δt.
    assert_eq!((sim.steps, sim.time), (1, dt));
    // The nodes no particle reaches have no mass, and get a = 0 (Eq. 27)
    // and v^L = 0 (Eq. 33), not 0/0.
    for i in [2, 5, 6, 7, 8] {
        assert_eq!(ws.mass[i], 0.0);
        assert_eq!(
            (ws.acceleration[i], ws.velocity_end[i]),
            ([0.0; 2], [0.0; 2]),
            "node {i}"
        );
    }
}

/// Eq. (29) hands the particles exactly the momentum the grid gained:
/// Σ_p m_p Δv_p = Δt Σ_p m_p Σ_i N_i(x_p) a_i = Δt Σ_i m_i a_i (Eq. 22),
/// for any basis, since the same N_i(x_p) weigh both sums. Scattered
/// particles with random velocities and stresses under gravity, one step,
/// for the bilinear basis and B-splines of degree 2 and 4 (width 5, the
/// loops whose width is known only at run time).
#[test]
fn the_particle_velocity_update_hands_the_particles_the_momentum_the_grid_gained() {
    for basis in [
        Basis2d::Bilinear,
        Basis2d::BSpline { degree: 2 },
        Basis2d::BSpline { degree: 4 },
    ] {
        let p = randomly_moving(scattered_particles(3, 2, 0.9, 5), 17);
        let before = p.total_momentum();
        let mut sim = direct_on_three_cells(basis, p, Some(Box::new(Gravity)));
        let dt = 1e-3;
        sim.step(dt).unwrap();
        let after = sim.particles.total_momentum();
        let ws = &sim.workspace;
        // Rounding of the momenta themselves, ~1e-16 Σ m |v| each.
        let rounding = 1e-13 * speed_scale(&sim.particles);
        for d in 0..2 {
            let gained: f64 = ws
                .mass
                .iter()
                .zip(&ws.acceleration)
                .map(|(m, a)| m * a[d])
                .sum();
            assert!(gained.abs() > 1e-3, "{basis:?}: the test needs a force");
            assert_relative_eq!(after[d] - before[d], dt * gained, epsilon = rounding);
        }
    }
}

/// Eqs. (34)–(35) for any basis: after a step, F_p = (I + Δt L_p) with
/// L_p = Σ_i v_i^L ⊗ ∇N_i(x_p) at the positions the step started from,
/// recomputed here with the 2D tensor basis of `spline::tensor` from the
/// step's own v^L. Random velocities make L full (off-diagonal terms too);
/// degree 4 (width 5) takes the loops whose width is known only at run time.
///
/// Map rows: mls-5, mls-34, mls-35 — the velocity gradient is Σ v_i ⊗ ∇N_i with the tensor gradient, and it and the F update are one computation.
#[test]
fn the_deformation_update_is_eq_34_with_the_tensor_basis_at_the_old_positions() {
    for degree in [1, 2, 4] {
        let basis = match degree {
            1 => Basis2d::Bilinear,
            d => Basis2d::BSpline { degree: d },
        };
        let p = randomly_moving(scattered_particles(3, 2, 0.9, 41), 43);
        let mut sim = direct_on_three_cells(basis, p.clone(), None);
        let dt = 1e-3;
        sim.step(dt).unwrap();
        let kv = KnotVector::open_uniform(0.0, 1.0, 3, degree).unwrap();
        let tensor = TensorBasis2d::new(kv.clone(), kv);
        let v = &sim.workspace.velocity_end;
        let mut largest_shear: f64 = 0.0;
        for k in 0..p.len() {
            let loc = tensor.local_basis(p.x[k][0], p.x[k][1]).unwrap();
            let mut l = Matrix2::<f64>::zeros();
            for (&i, g) in loc.indices.iter().zip(&loc.gradients) {
                for (r, c) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                    l[(r, c)] += v[i][r] * g[c];
                }
            }
            largest_shear = largest_shear.max(l[(0, 1)].abs().min(l[(1, 0)].abs()));
            let f = Matrix2::identity() + l * dt;
            assert_relative_eq!(sim.particles.deformation[k], f, epsilon = 1e-14);
            assert_relative_eq!(
                sim.particles.volume[k],
                f.determinant() * p.volume[k],
                max_relative = 1e-14
            );
        }
        assert!(
            largest_shear > 0.1,
            "degree {degree}: L needs both off-diagonal terms"
        );
    }
}

/// A particle velocity that is not finite ends the step with
/// `Error::NonFiniteVelocity`, even where the walls hide it from the grid:
/// on one bilinear cell every node is a wall node, so v_x is zeroed on the
/// grid, the particle's F stays I and only the final check sees the NaN.
#[test]
fn a_non_finite_particle_velocity_is_a_blow_up_even_behind_the_walls() {
    let mut p = Particles2d::new(vec![[0.5, 0.5]], vec![1.0], 1.0, vec![[0.0; 2]]).unwrap();
    p.velocity[0] = [f64::NAN, 0.0];
    let grid = Grid2d::new(Basis2d::Bilinear, 1.0, 1).unwrap();
    let mut sim = Simulation2d::new(
        grid,
        p,
        settings(Formulation::UpdatedLagrangian, Mapping2d::Direct),
        None,
    )
    .unwrap();
    sim.step(1e-3).unwrap_err();
    assert_eq!(sim.particles.deformation[0], Matrix2::identity());
    // A failed step is not taken; the next one fails the same way, as step 1.
    match sim.step(0.5) {
        Err(Error::NonFiniteVelocity {
            particle: 0,
            step: Some(1),
            time: Some(t),
            velocity,
        }) => assert!(t == 0.5 && velocity[0].is_nan() && velocity[1] == 0.0),
        other => panic!("expected a NaN velocity at step 1, got {other:?}"),
    }
}

/// Velocities uniform in [−½, ½]² and symmetric stresses, from `seed`.
fn randomly_moving(mut p: Particles2d, seed: u64) -> Particles2d {
    let mut rng = SplitMix64::new(seed);
    for k in 0..p.len() {
        p.velocity[k] = [rng.uniform() - 0.5, rng.uniform() - 0.5];
        let a = rng.uniform();
        p.stress[k] = Matrix2::new(a, 0.3 * a, 0.3 * a, -a);
    }
    p
}

/// The step records the largest mapping errors of mass and momentum so far:
/// |Σ_i m_i − Σ_p m_p| / Σ_p m_p and |Σ_i (mv)_i − Σ_p m_p v_p| / Σ_p m_p |v_p|.
/// The MLS mapping does not conserve either exactly, so each is checked
/// against the same sums over a mapping done apart, over two steps.
#[test]
fn the_step_records_the_largest_mapping_errors_of_mass_and_momentum() {
    let grid = || Grid2d::new(Basis2d::BSpline { degree: 2 }, 1.0, 4).unwrap();
    let settings = settings(Formulation::UpdatedLagrangian, Mapping2d::Mls);
    let mapping_errors = |p: &Particles2d| {
        let mut apart = Simulation2d::new(grid(), p.clone(), settings, None).unwrap();
        map_reconstructed(&apart.grid, &apart.particles, &mut apart.workspace).unwrap();
        let ws = &apart.workspace;
        let grid_mass: f64 = ws.mass.iter().sum();
        let grid_momentum = ws
            .momentum
            .iter()
            .fold([0.0; 2], |s, m| [s[0] + m[0], s[1] + m[1]]);
        let (mass, momentum) = (p.total_mass(), p.total_momentum());
        (
            (grid_mass - mass).abs() / mass,
            (grid_momentum[0] - momentum[0]).hypot(grid_momentum[1] - momentum[1]) / speed_scale(p),
        )
    };
    // A density that varies, so MLS's ρ_g is not the constant it reproduces
    // exactly and the grid mass differs from the particles'.
    let mut p = randomly_moving(scattered_particles(4, 3, 0.9, 23), 29);
    for k in 0..p.len() {
        p.density[k] *= 1.0 + 0.5 * p.x[k][0] * p.x[k][0] * p.x[k][1];
        p.mass[k] = p.density[k] * p.volume[k];
    }
    let first = mapping_errors(&p);
    let mut sim = Simulation2d::new(grid(), p, settings, None).unwrap();
    sim.step(1e-4).unwrap();
    assert!(first.0 > 1e-6 && first.1 > 1e-6, "{first:?}");
    assert_relative_eq!(sim.conservation.mass, first.0, max_relative = 1e-12);
    assert_relative_eq!(sim.conservation.momentum, first.1, max_relative = 1e-12);
    let second = mapping_errors(&sim.particles);
    sim.step(1e-4).unwrap();
    assert_relative_eq!(
        sim.conservation.mass,
        first.0.max(second.0),
        max_relative = 1e-12
    );
    assert_relative_eq!(
        sim.conservation.momentum,
        first.1.max(second.1),
        max_relative = 1e-12
    );
}

/// The two formulations map different stresses at different points. One
/// particle with X = (¼, ¼) that arrives moved to x = (¾, ¼) (a restart, say),
/// F = [[1.25, 0.5], [0, 0.8]] (det F = 1, so V = V⁰ = ½), m = 2, at rest,
/// and σ = [[3, 1], [1, −4]] set by hand (the mapping only reads it), on the
/// 2×2 bilinear grid of [`one_bilinear_step_by_hand`].
/// - Updated Lagrangian (MLS paper Eqs. 22, 25): the basis at x, cell (1, 0),
///   so the mass sits on nodes 1, 2, 4, 5 (index i + 3j); at node 4,
///   ∇N(x) = (−1, 1) and f = −V σ ∇N = −½ (−2, −5) = (1, 2.5), a = f/m = (2, 5).
/// - Total Lagrangian (the reference): the basis at X, cell (0, 0), nodes
///   0, 1, 3, 4; at node 4, ∇_X N = (1, 1) and f = −V⁰ P ∇_X N with
///   P = J σ F⁻ᵀ, F⁻ᵀ = [[0.8, 0], [−0.5, 1.25]], σ F⁻ᵀ = [[1.9, 1.25],
///   [2.8, −5]]: f = −½ (3.15, −2.2) = (−1.575, 1.1), a = (−3.15, 2.2).
#[test]
fn the_total_lagrangian_reference_maps_first_piola_stress_at_the_initial_positions() {
    let mut p = Particles2d::new(vec![[0.25, 0.25]], vec![0.5], 4.0, vec![[0.0, 0.0]]).unwrap();
    p.x[0][0] = 0.75;
    p.deformation[0] = Matrix2::new(1.25, 0.5, 0.0, 0.8);
    p.stress[0] = Matrix2::new(3.0, 1.0, 1.0, -4.0);
    for (formulation, nodes, acceleration) in [
        (Formulation::UpdatedLagrangian, [1, 2, 4, 5], [2.0, 5.0]),
        (Formulation::TotalLagrangian, [0, 1, 3, 4], [-3.15, 2.2]),
    ] {
        let grid = Grid2d::new(Basis2d::Bilinear, 1.0, 2).unwrap();
        let mut sim = Simulation2d::new(
            grid,
            p.clone(),
            settings(formulation, Mapping2d::Direct),
            None,
        )
        .unwrap();
        sim.step(1e-3).unwrap();
        let ws = &sim.workspace;
        for (i, &m) in ws.mass.iter().enumerate() {
            let expected = if nodes.contains(&i) { 0.5 } else { 0.0 };
            assert_relative_eq!(m, expected, epsilon = 1e-15);
        }
        // The nodal update (Eq. 27) leaves a = f/m in `acceleration`.
        assert_relative_eq!(ws.acceleration[4][0], acceleration[0], max_relative = 1e-14);
        assert_relative_eq!(ws.acceleration[4][1], acceleration[1], max_relative = 1e-14);
    }
}

/// A particle turned inside out is `Error::InvertedDeformation` naming the
/// particle, the step that failed and the time it reached. Particle 1 at
/// (⅙, ⅙) of a 3×3 bilinear grid (h = ⅓) falls at v = (0, −10) with F = I
/// (so σ = 0) and no body force; particle 0 rests in the far corner cell,
/// which shares no node with it. Then ∇N = (±1.5, ±1.5) at particle 1, the
/// nodes above it carry v^L_y = −10 and the ones below are walls, so
/// L = [[0, 0], [0, −30]] (Eq. 34) and F = I + L Δt = diag(1, −2) at
/// Δt = 0.1 (Eq. 35): J = −2. The total-Lagrangian reference refuses a
/// singular F that a caller put in the same way, at the mapping.
#[test]
fn a_particle_turned_inside_out_is_an_error_naming_it_its_step_and_time() {
    let falling = Particles2d::new(
        vec![[5.0 / 6.0, 5.0 / 6.0], [1.0 / 6.0, 1.0 / 6.0]],
        vec![0.05, 0.05],
        4.0,
        vec![[0.0, 0.0], [0.0, -10.0]],
    )
    .unwrap();
    let mut sim = direct_on_three_cells(Basis2d::Bilinear, falling, None);
    match sim.step(0.1) {
        Err(Error::InvertedDeformation {
            particle: Some(1),
            step: Some(1),
            time: Some(t),
            jacobian,
            deformation,
        }) => {
            assert_eq!(t, 0.1);
            assert_relative_eq!(jacobian, -2.0, max_relative = 1e-12);
            for (got, want) in deformation.iter().zip([1.0, 0.0, 0.0, -2.0]) {
                assert_relative_eq!(*got, want, max_relative = 1e-12, epsilon = 1e-12);
            }
        }
        other => panic!("expected an inverted particle 1 at step 1, got {other:?}"),
    }
    let mut flat = Particles2d::new(vec![[0.5, 0.5]], vec![0.1], 4.0, vec![[0.0, 0.0]]).unwrap();
    flat.deformation[0] = Matrix2::new(1.0, 2.0, 0.5, 1.0);
    let mut sim = Simulation2d::new(
        Grid2d::new(Basis2d::Bilinear, 1.0, 3).unwrap(),
        flat,
        settings(Formulation::TotalLagrangian, Mapping2d::Direct),
        None,
    )
    .unwrap();
    sim.run(0.01, 2).unwrap_err();
    assert_eq!(
        (sim.steps, sim.time),
        (0, 0.0),
        "a failed step is not taken"
    );
    assert_eq!(
        sim.step(0.25).unwrap_err(),
        Error::InvertedDeformation {
            particle: Some(0),
            step: Some(1),
            time: Some(0.25),
            jacobian: 0.0,
            deformation: [1.0, 2.0, 0.5, 1.0],
        }
    );
}

/// The largest particle speed after 20 steps from a uniform deformation F
/// (diagonal, no shear) at rest, with its uniform stress.
fn speed_after_uniform_state(basis: Basis2d, mapping: Mapping2d) -> f64 {
    let grid = Grid2d::new(basis, 1.0, 5).unwrap();
    let mut p = Particles2d::cell_centred(1.0, 5, 3, 1000.0, |_| [0.0; 2]).unwrap();
    let f = Matrix2::new(1.2, 0.0, 0.0, 0.9);
    let sigma = material().cauchy_stress(&f).unwrap();
    for k in 0..p.len() {
        p.deformation[k] = f;
        p.stress[k] = sigma;
        p.volume[k] *= f.determinant();
        p.density[k] = p.mass[k] / p.volume[k];
    }
    let mut sim = Simulation2d::new(
        grid,
        p,
        settings(Formulation::UpdatedLagrangian, mapping),
        None,
    )
    .unwrap();
    sim.run(1e-5, 20).unwrap();
    sim.particles
        .velocity
        .iter()
        .map(|v| v[0].abs().max(v[1].abs()))
        .fold(0.0, f64::max)
}

/// The patch test: a uniform stress has no divergence, every interior nodal
/// force cancels and the walls take the normal ones, so the particles must
/// stay at rest. It holds whenever the force integral ∫∇N_i dΩ is computed
/// exactly: particle quadrature (3×3 midpoints per cell) is exact for P1 and
/// quadratic B-splines, 2×2 Gauss (MLS) for degree ≤ 3. A wrong stencil or
/// gradient gives |v| of order σΔt/(ρh) ~ 0.1 m/s per step.
#[test]
fn a_uniform_state_stays_at_rest_without_spurious_forces() {
    for (basis, mapping) in [
        (Basis2d::Bilinear, Mapping2d::Direct),
        (Basis2d::BSpline { degree: 2 }, Mapping2d::Direct),
        (Basis2d::BSpline { degree: 2 }, Mapping2d::Mls),
        (Basis2d::BSpline { degree: 3 }, Mapping2d::Mls),
    ] {
        let vmax = speed_after_uniform_state(basis, mapping);
        assert!(vmax < 1e-8, "{basis:?} {mapping:?}: |v| = {vmax:e}");
    }
}

/// Cubic B-splines with particle quadrature fail the patch test at the walls:
/// the midpoint rule's error (d²/24)·[N_i''] over the support does not vanish
/// for the functions next to a wall, whose second derivative is non-zero
/// there. The spurious force is a property of the method, not of the code.
#[test]
fn cubic_bsplines_with_particle_quadrature_fail_the_patch_test_at_the_walls() {
    let vmax = speed_after_uniform_state(Basis2d::BSpline { degree: 3 }, Mapping2d::Direct);
    assert!(vmax > 1e-3, "|v| = {vmax:e}");
}

#[test]
fn a_particle_leaving_the_square_and_bad_steps_are_errors() {
    let s = parameters("mls-paper-e1e7").unwrap();
    let mut sim = s.simulation(AlignedMethod::Mpm, 2, 2, 1.0).unwrap();
    crate::common::assert_refuses_bad_time_steps(|dt| sim.step(dt));
    sim.particles.x[3][0] = 1.5;
    assert!(matches!(
        sim.step(1e-5),
        Err(Error::ParticleLeftGrid { particle: 3, .. })
    ));
    assert!(Grid2d::new(Basis2d::Bilinear, 1.0, 0).is_err());
    assert!(Particles2d::new(vec![[0.1, f64::NAN]], vec![1.0], 1.0, vec![[0.0; 2]]).is_err());
    assert!(MlsShapes::new(0.0, 2, 4).is_err());
}

#[test]
fn the_direct_mappings_conserve_mass_and_momentum_to_rounding() {
    let s = parameters("mls-paper-e1e7").unwrap();
    for method in [AlignedMethod::Mpm, AlignedMethod::bsmpm(2)] {
        let run = s.run(method, 4, 3, 50, 0).unwrap();
        assert!(run.conservation.mass < 1e-13, "{:?}", run.conservation);
        assert!(run.conservation.momentum < 1e-13, "{:?}", run.conservation);
        assert_eq!(run.history.len(), 2);
    }
}

/// MLS paper Eqs. (18)–(25) and (31)–(32): with a uniform density and
/// linear velocity and stress fields, MLS reproduces the fields exactly at
/// the Gauss points, and 2×2 Gauss quadrature integrates them exactly
/// against quadratic B-splines, so the nodal mass, momenta and internal
/// force equal ρ∫N_i, ρ∫N_i v and −∫∇N_i σ, computed here independently
/// with the tensor basis and a 3×3 Gauss rule per cell.
///
/// Map rows: mls-18, mls-19, mls-20, mls-21, mls-22, mls-31, mls-32 — every Gauss-point value and nodal sum of the MLS mapping is exact for linear fields.
#[test]
fn the_mls_mapping_integrates_linear_fields_exactly() {
    let cells = 3;
    let grid = Grid2d::new(Basis2d::BSpline { degree: 2 }, 1.0, cells).unwrap();
    let mut p = scattered_particles(cells, 3, 0.8, 5);
    let v = |x: f64, y: f64| [0.3 + 2.0 * x - y, -0.1 + 0.5 * x + 1.5 * y];
    let sigma = |x: f64, y: f64| Matrix2::new(1.0 + x, 0.5 * y, 0.5 * y, 2.0 - x + y);
    for k in 0..p.len() {
        p.velocity[k] = v(p.x[k][0], p.x[k][1]);
        p.stress[k] = sigma(p.x[k][0], p.x[k][1]);
    }
    let rho = p.density[0];
    let mut sim = Simulation2d::new(
        grid,
        p.clone(),
        settings(Formulation::UpdatedLagrangian, Mapping2d::Mls),
        None,
    )
    .unwrap();
    hompm::mpm2d::step::map_reconstructed(&sim.grid, &sim.particles, &mut sim.workspace).unwrap();
    let kv = KnotVector::open_uniform(0.0, 1.0, cells, 2).unwrap();
    let tensor = TensorBasis2d::new(kv.clone(), kv);
    let n = tensor.num_basis();
    let (mut m, mut mv, mut f) = (vec![0.0; n], vec![[0.0; 2]; n], vec![[0.0; 2]; n]);
    let rule = hompm::quadrature::GaussLegendre::new(3).unwrap();
    let h = 1.0 / cells as f64;
    for cy in 0..cells {
        for cx in 0..cells {
            let qx = rule.on_interval(cx as f64 * h, (cx + 1) as f64 * h);
            let qy = rule.on_interval(cy as f64 * h, (cy + 1) as f64 * h);
            for a in &qx {
                for b in &qy {
                    let w = a.weight * b.weight;
                    let loc = tensor.local_basis(a.x, b.x).unwrap();
                    let (vq, sq) = (v(a.x, b.x), sigma(a.x, b.x));
                    for ((&i, &nv), g) in loc.indices.iter().zip(&loc.values).zip(&loc.gradients) {
                        m[i] += w * rho * nv;
                        for d in 0..2 {
                            mv[i][d] += w * rho * nv * vq[d];
                            f[i][d] -= w * (sq[(d, 0)] * g[0] + sq[(d, 1)] * g[1]);
                        }
                    }
                }
            }
        }
    }
    let ws = &sim.workspace;
    for i in 0..n {
        assert_relative_eq!(ws.mass[i], m[i], max_relative = 1e-10);
        for d in 0..2 {
            assert_relative_eq!(ws.momentum[i][d], mv[i][d], epsilon = 1e-10 * rho);
            assert_relative_eq!(ws.force[i][d], f[i][d], epsilon = 1e-10);
        }
    }
    // Eqs. (31)–(32): the end-of-step momentum is the same integral.
    hompm::mpm2d::step::end_of_step_velocity(
        &sim.grid,
        &sim.particles,
        &mut sim.workspace,
        Mapping2d::Mls,
    );
    for (got, want) in sim.workspace.momentum_end.iter().zip(&mv) {
        for (g, w) in got.iter().zip(want) {
            assert_relative_eq!(*g, *w, epsilon = 1e-10 * rho);
        }
    }
}

/// The total-Lagrangian reference follows the manufactured solution: on
/// the aligned vibration its error after one period falls by more than
/// 4× from 4 to 8 cells (second order or better), where it has no grid
/// crossing to spoil it.
#[test]
fn the_total_lagrangian_reference_converges_on_the_aligned_vibration() {
    let s = parameters("mls-paper-e1e7").unwrap();
    let m = AlignedMethod::TotalLagrangian { degree: 2 };
    let coarse = s.run(m, 4, 3, 2000, 0).unwrap().last;
    let fine = s.run(m, 8, 3, 2000, 0).unwrap().last;
    assert!(
        coarse.displacement / fine.displacement > 4.0,
        "{coarse:?} {fine:?}"
    );
    assert!(coarse.stress / fine.stress > 2.0, "{coarse:?} {fine:?}");
}

/// The evidence of `mls-aligned` is computed from the study's runs as the
/// published rows say: the fitted order of MPM, the largest ratio
/// BSMPM/MPM, the pairwise orders and the ratio MLS/BSMPM at the finest
/// size (checked here by hand on the quick study: 4 and 8 cells, 400 steps).
#[test]
fn the_claims_are_computed_from_the_runs_as_their_labels_say() {
    use hompm::studies::mls_paper::{aligned_study, AlignedStudyOptions};
    let study = aligned_study(&AlignedStudyOptions::quick_run()).unwrap();
    let rows = hompm::tables::mls::claims(&study);
    assert_eq!(rows.len(), 12);
    let u = |m: AlignedMethod, c: usize| study.run(m, c).unwrap().last.displacement;
    let (mpm, bs, mls) = (
        AlignedMethod::Mpm,
        AlignedMethod::bsmpm(2),
        AlignedMethod::bsmpm_with(2, Mapping2d::Mls),
    );
    let order = |m| (u(m, 4) / u(m, 8)).log2();
    // Rows by the claim their label quotes, at T (the rows "after one
    // period" are the same claims at t = 0.02 s).
    let at_t = |claim: &str| -> f64 {
        let (label, values) = rows
            .iter()
            .find(|(l, _)| l.contains(claim) && !l.contains("after one period"))
            .unwrap_or_else(|| panic!("no row quotes {claim}"));
        values[0].unwrap_or_else(|| panic!("{label}: not computed"))
    };
    assert_relative_eq!(
        at_t("'does not converge well'"),
        order(mpm),
        max_relative = 1e-12
    );
    let ratio = (u(bs, 4) / u(mpm, 4)).max(u(bs, 8) / u(mpm, 8));
    assert_relative_eq!(at_t("'considerably lower'"), ratio, max_relative = 1e-12);
    assert_relative_eq!(
        at_t("'can lead to the second order'"),
        order(bs),
        max_relative = 1e-12
    );
    assert_relative_eq!(
        at_t("'lack of convergence for finer meshes'"),
        order(bs),
        max_relative = 1e-12
    );
    assert_relative_eq!(
        at_t("'converges well for finer meshes'"),
        order(mls),
        max_relative = 1e-12
    );
    assert_relative_eq!(
        at_t("'improves the accuracy of B-spline MPM significantly'"),
        u(mls, 8) / u(bs, 8),
        max_relative = 1e-12
    );
    // No record at t = 0.02 s in 400 steps: the early rows are not computed.
    let early: Vec<_> = rows
        .iter()
        .filter(|(l, _)| l.contains("after one period"))
        .collect();
    assert_eq!(early.len(), 6);
    assert!(early.iter().all(|(_, v)| v.iter().all(Option::is_none)));
}

/// MLS paper §4 initial state, worked by hand: on [0, 2]² with one cell and
/// 2 × 2 particles per cell, the particles sit at the centres (½, ½) … (3/2,
/// 3/2) with volume 1 and mass ρV = 3; with v(X) = (x, −2y) the total mass is
/// 12 and the momentum Σ m v = (12, −24). A particle set needs cells ≥ 1,
/// per side ≥ 1 and a finite L > 0; a grid keeps its length.
#[test]
fn particle_sums_and_refusals_on_a_hand_built_set() {
    let p = Particles2d::cell_centred(2.0, 1, 2, 3.0, |x| [x[0], -2.0 * x[1]]).unwrap();
    assert_eq!((p.len(), p.is_empty()), (4, false));
    assert_eq!(p.total_mass(), 12.0);
    assert_eq!(p.total_momentum(), [12.0, -24.0]);
    for (length, cells, per_side) in [
        (0.0, 1, 2),
        (f64::NAN, 1, 2),
        (f64::INFINITY, 1, 2),
        (-1.0, 1, 2),
        (2.0, 0, 2),
        (2.0, 1, 0),
    ] {
        assert!(
            matches!(
                Particles2d::cell_centred(length, cells, per_side, 3.0, |_| [0.0; 2]),
                Err(Error::InvalidArgument(_))
            ),
            "L = {length}, cells = {cells}, per side = {per_side}"
        );
    }
    assert!(Particles2d::cell_centred(1e-100, 1, 1, 3.0, |_| [0.0; 2]).is_ok());
    let grid = Grid2d::new(Basis2d::BSpline { degree: 2 }, 2.0, 2).unwrap();
    assert_eq!(grid.length(), 2.0);
}

// ---------------------------------------------------------------------------
// Taylor least squares in 2D (TLS paper §5.2–5.5 on a rectangular cell).

use hompm::mpm2d::reconstruction::{GaussReconstruction, Reconstruction};
use hompm::mpm2d::step::StepObserver2d;
use hompm::mpm2d::tls::{TaylorBasis2d, TaylorOrder2d, TlsShapes, TlsVariant};
use hompm::reconstruct::taylor::DegenerateCells;

/// TLS paper Eq. (12) on a rectangle: ∫_Ω ψ_i = |Ω| δ_i1, integrated with an
/// independent 3×3 Gauss rule (exact for the quadratics), and the values at
/// the upper corner by hand (ξ = η = 1).
#[test]
fn the_2d_taylor_basis_integrates_to_the_cell_area_times_delta_i1() {
    let (lower, upper) = ([0.3, -1.0], [0.8, 0.5]);
    let basis = TaylorBasis2d::new(lower, upper).unwrap();
    let rule = hompm::quadrature::GaussLegendre::new(3).unwrap();
    let mut integral = [0.0; 6];
    for a in rule.on_interval(lower[0], upper[0]) {
        for b in rule.on_interval(lower[1], upper[1]) {
            for (i, psi) in basis.evaluate([a.x, b.x]).iter().enumerate() {
                integral[i] += a.weight * b.weight * psi;
            }
        }
    }
    let area = 0.5 * 1.5;
    assert_relative_eq!(basis.area(), area, max_relative = 1e-15);
    assert_relative_eq!(integral[0], area, max_relative = 1e-14);
    for (i, v) in integral.iter().enumerate().skip(1) {
        assert!(v.abs() < 1e-15, "∫ψ_{} = {v}", i + 1);
    }
    let corner = basis.evaluate(upper);
    let by_hand = [1.0, 1.0, 1.0, 1.0 / 3.0, 1.0, 1.0 / 3.0];
    for (c, h) in corner.iter().zip(by_hand) {
        assert_relative_eq!(*c, h, max_relative = 1e-15);
    }
}

/// The TLS shape functions of `particles` on `cells`² cells of [0, 1]².
fn tls_shapes(
    particles: &Particles2d,
    cells: usize,
    order: TaylorOrder2d,
    variant: TlsVariant,
    degenerate: DegenerateCells,
) -> hompm::error::Result<(TlsShapes, Grid2d)> {
    let grid = Grid2d::new(Basis2d::BSpline { degree: 2 }, 1.0, cells)?;
    let mut shapes = TlsShapes::new(order, variant, degenerate, cells, particles.len())?;
    let gauss = GaussGrid {
        abscissae: grid.gauss_abscissae(),
        cells,
        cell_size: grid.cell_size(),
    };
    let (cx, cy) = (
        cells_along(&grid, &particles.x, 0),
        cells_along(&grid, &particles.x, 1),
    );
    shapes.evaluate(&gauss, particles, &cx, &cy)?;
    Ok((shapes, grid))
}

/// Σ_p φ_gp f(x_p) at every Gauss point, with the point.
fn reconstructed_at_gauss_points(
    shapes: &TlsShapes,
    grid: &Grid2d,
    p: &Particles2d,
    f: impl Fn(f64, f64) -> f64,
) -> Vec<([f64; 2], f64)> {
    let lists = shapes.lists();
    let (a, n) = (grid.gauss_abscissae(), 2 * grid.cells_per_side());
    let mut out = Vec::new();
    for gy in 0..n {
        for gx in 0..n {
            let g = gx + n * gy;
            let value = (lists.start[g]..lists.end[g])
                .map(|e| {
                    let k = lists.particle[e] as usize;
                    lists.phi[e] * f(p.x[k][0], p.x[k][1])
                })
                .sum();
            out.push(([a[gx], a[gy]], value));
        }
    }
    out
}

/// Unconstrained TLS (Eq. 13) reproduces every quadratic on scattered
/// particles. Conservative TLS (Eq. 14) reproduces every quadratic whose
/// particle sum Σ V_p f_p is its cell integral: particles at the 3×3 Gauss
/// points of each cell with the Gauss weights as volumes. A linear Taylor
/// basis reproduces linear fields but not x².
#[test]
fn tls_2d_reproduces_every_polynomial_of_its_order() {
    let quadratic =
        |x: f64, y: f64| 0.7 - 1.3 * x + 2.1 * y + 0.9 * x * x - 1.7 * x * y + 0.4 * y * y;
    let linear = |x: f64, y: f64| 0.7 - 1.3 * x + 2.1 * y;
    let p = scattered_particles(3, 3, 0.8, 11);
    for (order, f, exact) in [
        (
            TaylorOrder2d::Quadratic,
            &quadratic as &dyn Fn(f64, f64) -> f64,
            true,
        ),
        (TaylorOrder2d::Linear, &linear, true),
        (TaylorOrder2d::Linear, &quadratic, false),
    ] {
        let (shapes, grid) = tls_shapes(
            &p,
            3,
            order,
            TlsVariant::Unconstrained,
            DegenerateCells::Error,
        )
        .unwrap();
        let worst = reconstructed_at_gauss_points(&shapes, &grid, &p, f)
            .iter()
            .map(|(x, v)| (v - f(x[0], x[1])).abs())
            .fold(0.0, f64::max);
        assert_eq!(worst < 1e-12, exact, "{order:?}: worst error {worst:e}");
    }
    // Particles at the 3×3 Gauss points of every cell, volumes = weights.
    let cells = 2;
    let rule = hompm::quadrature::GaussLegendre::new(3).unwrap();
    let (mut positions, mut volumes) = (Vec::new(), Vec::new());
    for cy in 0..cells {
        for cx in 0..cells {
            let h = 1.0 / cells as f64;
            for a in rule.on_interval(cx as f64 * h, (cx + 1) as f64 * h) {
                for b in rule.on_interval(cy as f64 * h, (cy + 1) as f64 * h) {
                    positions.push([a.x, b.x]);
                    volumes.push(a.weight * b.weight);
                }
            }
        }
    }
    let n = positions.len();
    let p = Particles2d::new(positions, volumes, 1000.0, vec![[0.0; 2]; n]).unwrap();
    let (shapes, grid) = tls_shapes(
        &p,
        cells,
        TaylorOrder2d::Quadratic,
        TlsVariant::Conservative,
        DegenerateCells::Error,
    )
    .unwrap();
    for (x, v) in reconstructed_at_gauss_points(&shapes, &grid, &p, quadratic) {
        assert_relative_eq!(v, quadratic(x[0], x[1]), max_relative = 1e-12);
    }
}

/// Records, at every phase-1 mapping, the relative mass error and the
/// momentum error relative to Σ m|v|, with compensated sums.
pub(super) struct ConservationProbe {
    /// The largest relative errors of mass and momentum so far.
    pub(super) largest: [f64; 2],
    /// The phase-1 mappings observed.
    pub(super) mappings: usize,
}

impl StepObserver2d for ConservationProbe {
    fn observe(
        &mut self,
        point: hompm::mpm2d::step::StepPoint2d,
        sim: &mut Simulation2d,
    ) -> hompm::error::Result<()> {
        if point != hompm::mpm2d::step::StepPoint2d::GridMapping {
            return Ok(());
        }
        let (p, ws) = (&sim.particles, &sim.workspace);
        let mass = compensated_sum(p.mass.iter().copied());
        let grid_mass = compensated_sum(ws.mass.iter().copied());
        let scale = compensated_sum(
            (0..p.len()).map(|k| p.mass[k] * p.velocity[k][0].hypot(p.velocity[k][1])),
        );
        let mut momentum: f64 = 0.0;
        for d in 0..2 {
            let particles = compensated_sum((0..p.len()).map(|k| p.mass[k] * p.velocity[k][d]));
            let grid = compensated_sum(ws.momentum.iter().map(|m| m[d]));
            momentum = momentum.max((grid - particles).abs() / scale.max(f64::MIN_POSITIVE));
        }
        self.largest[0] = self.largest[0].max((grid_mass - mass).abs() / mass);
        self.largest[1] = self.largest[1].max(momentum);
        self.mappings += 1;
        Ok(())
    }
}

/// TLS paper §5.5 in 2D: the conservative TLS mapping keeps mass and
/// momentum to ≤ 1e-13 relative at every step of the aligned vibration on
/// 8 × 8 cells, while MLS on the same run loses far more.
#[test]
fn the_conservative_tls_mapping_keeps_mass_and_momentum_at_every_step() {
    let s = parameters("mls-paper-e1e7").unwrap();
    let mut largest = Vec::new();
    for method in [
        AlignedMethod::bsmpm_with(2, Mapping2d::Tls),
        AlignedMethod::bsmpm_with(2, Mapping2d::Mls),
    ] {
        let mut sim = s.simulation(method, 8, 3, 1.0).unwrap();
        let mut probe = ConservationProbe {
            largest: [0.0; 2],
            mappings: 0,
        };
        for _ in 0..300 {
            sim.step_observed(s.dt, &mut probe).unwrap();
        }
        assert_eq!(probe.mappings, 300);
        // By step 300 particles have crossed cells and TLS has lowered the
        // basis of some (16 at most in one step); MLS has no repair to
        // report. Conservation holds through the repairs.
        let repaired = sim.reconstruction_record.most_repaired;
        match method {
            AlignedMethod::Bsmpm {
                mapping: Mapping2d::Tls,
                ..
            } => assert!(repaired > 0),
            _ => assert_eq!(repaired, 0),
        }
        assert!(sim.reconstruction_record.largest_condition >= 1.0);
        largest.push(probe.largest);
    }
    let [tls, mls] = [largest[0], largest[1]];
    assert!(tls[0] <= 1e-13 && tls[1] <= 1e-13, "TLS {tls:?}");
    assert!(mls[0] > 1e-6, "MLS {mls:?}");
}

/// TLS paper §5.3 in 2D: a cell whose particles lie on a line cannot carry
/// a quadratic (or linear) fit. Under `Error` it is `Error::SingularCell`
/// naming the cell and its corners; under `ReduceBasis` the cell falls back
/// to the constant basis, counts as repaired, and still conserves:
/// Σ_g ω_g φ_gp = V_p for every particle.
#[test]
fn a_cell_of_collinear_particles_is_refused_by_name_or_repaired_conservatively() {
    let mut p = scattered_particles(2, 3, 0.5, 3);
    // The nine particles of cell (1, 0) onto the line y = 0.3 x − 0.05.
    for k in 0..p.len() {
        if p.x[k][0] > 0.5 && p.x[k][1] < 0.5 {
            p.x[k][1] = 0.3 * p.x[k][0] - 0.05;
        }
    }
    let strict = tls_shapes(
        &p,
        2,
        TaylorOrder2d::Quadratic,
        TlsVariant::Conservative,
        DegenerateCells::Error,
    );
    match strict {
        Err(Error::SingularCell {
            cell,
            lower,
            upper,
            detail,
        }) => {
            assert_eq!(cell, [1, 0]);
            assert_eq!((lower, upper), (vec![0.5, 0.0], vec![1.0, 0.5]));
            assert!(detail.contains("9 particles"), "{detail}");
        }
        other => panic!("expected a singular cell, got {other:?}"),
    }
    let (shapes, grid) = tls_shapes(
        &p,
        2,
        TaylorOrder2d::Quadratic,
        TlsVariant::Conservative,
        DegenerateCells::ReduceBasis,
    )
    .unwrap();
    assert_eq!(shapes.repaired(), 1);
    assert_every_particle_carries_its_volume(&shapes, grid.gauss_weight(), &p.volume);
    assert!(TlsShapes::new(
        TaylorOrder2d::Quadratic,
        TlsVariant::Conservative,
        DegenerateCells::VirtualPoints,
        2,
        4
    )
    .is_err());
}

/// The nodal masses of phase 1 with one particle at x = 0.5 ∓ δ, on either
/// side of the boundary between cells (0, ·) and (1, ·) of a 2×2 grid:
/// the largest change of a nodal mass relative to the largest mass.
fn mass_jump_across_a_cell_boundary(mapping: Mapping2d, delta: f64) -> f64 {
    let masses = |x: f64| {
        let mut p = scattered_particles(2, 3, 0.6, 9);
        let k = (0..p.len())
            .min_by(|&a, &b| (p.x[a][0] - 0.5).abs().total_cmp(&(p.x[b][0] - 0.5).abs()))
            .unwrap();
        p.x[k][0] = x;
        let grid = Grid2d::new(Basis2d::BSpline { degree: 2 }, 1.0, 2).unwrap();
        let settings = settings(Formulation::UpdatedLagrangian, mapping);
        let mut sim = Simulation2d::new(grid, p, settings, None).unwrap();
        match mapping {
            Mapping2d::Direct => map_direct(&sim.grid, &sim.particles, &mut sim.workspace),
            _ => map_reconstructed(&sim.grid, &sim.particles, &mut sim.workspace).unwrap(),
        }
        sim.workspace.mass.clone()
    };
    let (left, right) = (masses(0.5 - delta), masses(0.5 + delta));
    let largest = left.iter().cloned().fold(0.0, f64::max);
    left.iter()
        .zip(&right)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
        / largest
}

/// Why 2D TLS stops once particles cross cells (docs/reproduction-notes.md,
/// "2D TLS"): its fit is per cell, so a particle that moves by 2δ across a
/// cell boundary changes the nodal masses by O(1), where the direct
/// mapping (C¹ quadratic B-splines) and MLS (a C¹ weight over overlapping
/// supports) change them by O(δ). Grid crossing, which BSMPM removes, comes
/// back through the reconstruction.
#[test]
fn a_particle_crossing_a_cell_boundary_moves_tls_nodal_masses_by_a_jump() {
    let delta = 1e-9;
    let direct = mass_jump_across_a_cell_boundary(Mapping2d::Direct, delta);
    let mls = mass_jump_across_a_cell_boundary(Mapping2d::Mls, delta);
    let tls = mass_jump_across_a_cell_boundary(Mapping2d::Tls, delta);
    assert!(direct < 1e-7, "direct {direct:e}");
    assert!(mls < 1e-7, "MLS {mls:e}");
    assert!(tls > 1e-3, "TLS {tls:e}");
}

/// Eqs. (26)–(28) and (31)–(33), one buffer per quantity: after a step the
/// phase-1 buffers still hold f_i and (mv)_i^t, and the later ones hold
/// what their equations make of them, with zero normal components on the
/// walls: (mv)^{t+1} = (mv)^t + Δt f, a = f/m, v^{t+1} = (mv)^{t+1}/m and
/// v^L = (mv)^L/m.
#[test]
fn every_nodal_buffer_keeps_the_quantity_of_its_equation_through_a_step() {
    for basis in [Basis2d::Bilinear, Basis2d::BSpline { degree: 2 }] {
        let p = randomly_moving(scattered_particles(3, 2, 0.9, 41), 43);
        let mut sim = direct_on_three_cells(basis, p, Some(Box::new(Gravity)));
        let dt = 1e-3;
        sim.step(dt).unwrap();
        let (ws, n) = (&sim.workspace, sim.grid.nodes_per_side());
        let mut checked = 0;
        for i in 0..ws.mass.len() {
            let m = ws.mass[i];
            if m <= 0.0 {
                continue;
            }
            let (ix, iy) = (i % n, i / n);
            for d in 0..2 {
                let on_wall = if d == 0 {
                    ix == 0 || ix == n - 1
                } else {
                    iy == 0 || iy == n - 1
                };
                let wall = |x: f64| if on_wall { 0.0 } else { x };
                let next = wall(ws.momentum[i][d] + dt * ws.force[i][d]);
                assert_eq!(ws.momentum_next[i][d], next, "{basis:?} node {i}");
                assert_eq!(ws.acceleration[i][d], wall(ws.force[i][d] / m));
                assert_eq!(ws.velocity_next[i][d], next / m);
                assert_eq!(ws.velocity_end[i][d], wall(ws.momentum_end[i][d] / m));
                checked += usize::from(!on_wall && ws.force[i][d] != 0.0);
            }
        }
        assert!(checked > 4, "{basis:?}: the test needs interior forces");
        // (mv)^t and (mv)^L differ: the particles' velocities changed.
        assert_ne!(ws.momentum, ws.momentum_end);
    }
}

/// Σ_g ω φ_gp = V_p for every particle p: a conservative reconstruction's
/// shape functions carry each particle's volume to the Gauss points (TLS
/// paper §5.5 in 2D; the PU-TLS module doc), to 1e-13.
pub(super) fn assert_every_particle_carries_its_volume(
    shapes: &dyn GaussReconstruction,
    omega: f64,
    volumes: &[f64],
) {
    let lists = shapes.lists();
    let mut carried = vec![0.0; volumes.len()];
    for g in 0..lists.start.len() {
        for e in lists.start[g]..lists.end[g] {
            carried[lists.particle[e] as usize] += omega * lists.phi[e];
        }
    }
    for (k, c) in carried.iter().enumerate() {
        assert_relative_eq!(*c, volumes[k], max_relative = 1e-13);
    }
}
