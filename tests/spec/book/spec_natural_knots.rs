//! `--knots natural` (issue #36): Karamelo's boundary-modified uniform
//! B-splines of degree 2 and 3 (src/basis_functions.h, read, not copied),
//! worked by hand.
//!
//! Nodes X_k = a + k h, k = 0 … N, ξ = (x − a)/h, B_p the cardinal
//! B-spline of degree p centred on its node. Inside N_k = B_p(ξ − k); the
//! ghost function beyond each wall is folded into the two nearest nodes:
//! N_0 = B_p(ξ) + 2 B_p(ξ + 1), N_1 = B_p(ξ − 1) − B_p(ξ + 1), mirrored at b.
//! Quadratic on [0, h/2]: N_0 = 1 − ξ, N_1 = ξ. Cubic on [0, h):
//! N_0 = 1 − ξ + ξ³/6, N_1 = ξ − ξ³/3, N_2 = ξ³/6. The basis changes book
//! Eq. (4.5): the lumped mass m_i = Σ_p N_i(x_p) m_p, on N + 1 nodes.

use approx::assert_relative_eq;
use hompm::basis::Basis1d;
use hompm::mpm::conventions::{Conventions, Knots, Positions};
use hompm::mpm::grid::{Grid, Method};
use hompm::mpm::mapping::{Mapping, MassMatrix};
use hompm::mpm::musl::{Constitutive, Settings, Simulation};
use hompm::mpm::particles::Particles;
use hompm::scenes::vibrating_bar::parameters;
use hompm::scenes::Discretisation;
use hompm::spline::NaturalSplines;

const NATURAL: Conventions = Conventions {
    knots: Knots::Natural,
    ..Conventions::BOOK
};

/// The settings of a plain 1D step (direct mapping, lumped mass, small
/// strain, E = 10, no gravity) with `conventions`.
fn settings(conventions: Conventions, dirichlet: Vec<usize>) -> Settings {
    let mut d = Discretisation::new(Method::Mpm, Mapping::Direct, MassMatrix::Lumped, 1, 1);
    d.conventions = conventions;
    d.settings(Constitutive::SmallStrain, 10.0, 0.0, None, dirichlet)
}

/// All N + 1 values and gradients at x, from the grid's stencil.
fn dense(grid: &Grid, x: f64) -> (Vec<f64>, Vec<f64>) {
    let s = grid.shape(x).unwrap();
    let n = grid.num_dofs();
    let (mut v, mut g) = (vec![0.0; n], vec![0.0; n]);
    for (j, (&a, &b)) in s.values.iter().zip(&s.gradients).enumerate() {
        v[s.first + j] = a;
        g[s.first + j] = b;
    }
    (v, g)
}

fn assert_all(computed: &[f64], expected: &[f64]) {
    assert_eq!(computed.len(), expected.len());
    for (c, e) in computed.iter().zip(expected) {
        assert_relative_eq!(*c, *e, epsilon = 1e-14, max_relative = 1e-13);
    }
}

#[test]
fn natural_quadratic_and_cubic_splines_are_the_folded_formulas_at_both_walls() {
    // [1, 4] on 6 cells: h = 1/2.
    let (a, b, n, h) = (1.0, 4.0, 6, 0.5);
    let q = Grid::natural(a, b, n, 2).unwrap();
    let c = Grid::natural(a, b, n, 3).unwrap();
    assert_eq!((q.num_dofs(), c.num_dofs()), (n + 1, n + 1));
    for xi in [0.0, 0.1, 0.3, 0.5] {
        // Quadratic on [0, h/2]: N_0 = 1 − ξ, N_1 = ξ.
        let mut v = vec![0.0; n + 1];
        let mut g = vec![0.0; n + 1];
        (v[0], v[1]) = (1.0 - xi, xi);
        (g[0], g[1]) = (-1.0 / h, 1.0 / h);
        let (qv, qg) = dense(&q, a + xi * h);
        assert_all(&qv, &v);
        assert_all(&qg, &g);
        // Mirrored at b: N_{N−k}(b − y) = N_k(a + y), gradients of opposite sign.
        let (rv, rg) = dense(&q, b - xi * h);
        v.reverse();
        g.reverse();
        assert_all(&rv, &v);
        assert_all(&rg, &g.iter().map(|d| -d).collect::<Vec<_>>());
    }
    for xi in [0.0, 0.25, 0.5, 0.9] {
        // Cubic on [0, h): N_0 = 1 − ξ + ξ³/6, N_1 = ξ − ξ³/3, N_2 = ξ³/6.
        let mut v = vec![0.0; n + 1];
        let mut g = vec![0.0; n + 1];
        let x3 = xi * xi * xi;
        (v[0], v[1], v[2]) = (1.0 - xi + x3 / 6.0, xi - x3 / 3.0, x3 / 6.0);
        (g[0], g[1], g[2]) = (
            (-1.0 + xi * xi / 2.0) / h,
            (1.0 - xi * xi) / h,
            xi * xi / 2.0 / h,
        );
        let (cv, cg) = dense(&c, a + xi * h);
        assert_all(&cv, &v);
        assert_all(&cg, &g);
        let (rv, rg) = dense(&c, b - xi * h);
        v.reverse();
        g.reverse();
        assert_all(&rv, &v);
        assert_all(&rg, &g.iter().map(|d| -d).collect::<Vec<_>>());
    }
    // Inside, N_k = B_p(ξ − k): at ξ = 3.25 the quadratic gives, on
    // nodes 2, 3, 4, B_2(1.25) = (3/2 − 5/4)²/2, B_2(0.25) = 3/4 − 1/16,
    // B_2(−0.75) = (3/2 − 3/4)²/2; the cubic, on nodes 2 … 5,
    // B_3(1.25) = (3/4)³/6, B_3(0.25) = 2/3 − 1/16 + 1/128,
    // B_3(−0.75) = 2/3 − 9/16 + 27/128, B_3(−1.75) = (1/4)³/6.
    let (qv, _) = dense(&q, a + 3.25 * h);
    assert_all(&qv, &[0.0, 0.0, 0.03125, 0.6875, 0.28125, 0.0, 0.0]);
    let (cv, _) = dense(&c, a + 3.25 * h);
    let cubic = [
        0.421875 / 6.0,
        2.0 / 3.0 - 0.0625 + 0.0078125,
        2.0 / 3.0 - 0.5625 + 0.2109375,
        0.015625 / 6.0,
    ];
    assert_all(&cv[2..6], &cubic);
    assert_eq!((cv[0], cv[1], cv[6]), (0.0, 0.0, 0.0));
}

#[test]
fn natural_splines_are_a_partition_of_unity_that_interpolates_at_the_walls() {
    for p in [2, 3] {
        for n in [1, 2, 3, 8] {
            let grid = Grid::natural(0.0, 2.0, n, p).unwrap();
            let (v0, _) = dense(&grid, 0.0);
            let (vn, _) = dense(&grid, 2.0);
            let delta = |k: usize| {
                (0..=n)
                    .map(|i| f64::from(u8::from(i == k)))
                    .collect::<Vec<_>>()
            };
            assert_all(&v0, &delta(0));
            assert_all(&vn, &delta(n));
            for s in 0..=97 {
                let x = 2.0 * f64::from(s) / 97.0;
                let (v, g) = dense(&grid, x);
                assert_relative_eq!(v.iter().sum::<f64>(), 1.0, epsilon = 1e-14);
                assert!(g.iter().sum::<f64>().abs() < 1e-12, "p {p} n {n} x {x}");
                // The Basis1d reference (Cox–de Boor on the uniform knots,
                // then folded) gives the same numbers.
                let local = grid.basis().local(x, 1).unwrap();
                let (lv, lg) = (local.dense(0, n + 1), local.dense(1, n + 1));
                assert_all(&v, &lv);
                assert_all(&g, &lg);
            }
        }
    }
}

#[test]
fn the_folded_functions_are_the_uniform_b_splines_with_the_ghost_coefficient_two_c0_minus_c1() {
    // Unfolded: B_{−1} … B_{N+1} on the uniform knots; for p = 2 those are
    // the padded quadratic knots a + (j − 5/2)h of --knots padded.
    let basis = NaturalSplines::new(0.0, 3.0, 3, 2).unwrap();
    assert_eq!(
        basis.uniform().knots(),
        [-2.5, -1.5, -0.5, 0.5, 1.5, 2.5, 3.5, 4.5, 5.5]
    );
    // For p = 3 the breakpoints are the nodes.
    let cubic = NaturalSplines::new(0.0, 3.0, 3, 3).unwrap();
    assert_eq!(
        cubic.uniform().knots(),
        [-3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
    );
    assert_eq!(
        basis.cells(),
        [(0.0, 0.5), (0.5, 1.5), (1.5, 2.5), (2.5, 3.0)]
    );
    assert_eq!(cubic.cells(), [(0.0, 1.0), (1.0, 2.0), (2.0, 3.0)]);
    for p in [2, 3] {
        let basis = NaturalSplines::new(0.0, 3.0, 3, p).unwrap();
        for s in 0..=31 {
            let x = 3.0 * f64::from(s) / 31.0;
            let b = basis.uniform().dense_values(x).unwrap();
            // A spline with coefficients c_k on the folded functions is the
            // uniform spline with c_{−1} = 2c_0 − c_1, c_4 = 2c_3 − c_2.
            let c = [0.3, -1.1, 2.0, 0.7];
            let ghost = [2.0 * c[0] - c[1], 2.0 * c[3] - c[2]];
            let unfolded =
                ghost[0] * b[0] + (0..4).map(|k| c[k] * b[k + 1]).sum::<f64>() + ghost[1] * b[5];
            let folded = basis.local(x, 0).unwrap().dense(0, 4);
            let value: f64 = (0..4).map(|k| c[k] * folded[k]).sum();
            assert_relative_eq!(value, unfolded, epsilon = 1e-14);
        }
    }
}

/// Particles at x = 0.25 (m = 2) and 1.25 (m = 4) on 2 cells of [0, 2].
fn two_cell_step(grid: Grid, conventions: Conventions) -> Simulation {
    let p = Particles::new(
        vec![0.25, 1.25],
        vec![0.5, 1.0],
        vec![4.0, 4.0],
        vec![1.0, -2.0],
        vec![3.0, -1.0],
    )
    .unwrap();
    let last = grid.num_dofs() - 1;
    let settings = settings(conventions, vec![0, last]);
    let mut sim = Simulation::new(grid, p, settings).unwrap();
    sim.step(0.1).unwrap();
    sim
}

#[test]
fn eq_4_5_lumped_mass_on_natural_quadratic_splines_differs_from_open_knots_at_step_1() {
    // Natural p = 2, h = 1: at ξ = 0.25, N = (3/4, 1/4, 0); at ξ = 1.25,
    // N_0 = B(1.25) = 1/32, N_1 = B(0.25) = 11/16, N_2 = B(−0.75) = 9/32
    // (every ghost term B(±2.25), B(−1.75) is 0). m_i = Σ_p N_i m_p:
    // (2·3/4 + 4/32, 2/4 + 4·11/16, 4·9/32) = (1.625, 3.25, 1.125).
    let natural = two_cell_step(Grid::natural(0.0, 2.0, 2, 2).unwrap(), NATURAL);
    assert_all(&natural.workspace().mass, &[1.625, 3.25, 1.125]);
    // Open knots {0,0,0,1,2,2,2}: four functions, N_0(0.25) = (3/4)²,
    // m_0 = 2·9/16 = 1.125.
    let open = two_cell_step(
        Grid::new(Method::Bsmpm { degree: 2 }, 0.0, 2.0, 2).unwrap(),
        Conventions::BOOK,
    );
    assert_eq!(open.workspace().mass.len(), 4);
    assert_relative_eq!(open.workspace().mass[0], 1.125, epsilon = 1e-14);
    // The wall condition holds on the wall nodes only.
    let ws = natural.workspace();
    assert_eq!(ws.mapping.velocity[0], 0.0);
    assert_eq!(ws.mapping.velocity[2], 0.0);
    assert!(ws.mapping.velocity[1] != 0.0);
    // Natural p = 3 on 3 cells, one particle at ξ = 1/2 with m = 6:
    // m_i = 6 (1 − ξ + ξ³/6, ξ − ξ³/3, ξ³/6, 0) = (3.125, 2.75, 0.125, 0).
    let grid = Grid::natural(0.0, 3.0, 3, 3).unwrap();
    let p = Particles::new(vec![0.5], vec![1.0], vec![6.0], vec![0.0], vec![0.0]).unwrap();
    let settings = settings(NATURAL, vec![0, 3]);
    let mut sim = Simulation::new(grid, p, settings).unwrap();
    sim.step(0.1).unwrap();
    assert_all(&sim.workspace().mass, &[3.125, 2.75, 0.125, 0.0]);
}

#[test]
fn the_bar_on_natural_knots_has_one_node_per_grid_point_and_fixes_the_wall_nodes() {
    let bar = parameters("thesis-table-4.1").unwrap();
    for (p, open_nodes) in [(2, 18), (3, 19)] {
        let mut d = Discretisation::direct(Method::Bsmpm { degree: p }, 16, 4);
        assert_eq!(bar.simulation(&d).unwrap().grid.num_dofs(), open_nodes);
        d.conventions = Conventions {
            positions: Positions::Grid,
            ..NATURAL
        };
        let sim = bar.simulation(&d).unwrap();
        assert_eq!(sim.grid.num_dofs(), 17);
        assert_eq!(sim.grid.knots(), Knots::Natural);
        assert_relative_eq!(sim.grid.cell_size(), 25.0 / 16.0);
        assert_eq!(sim.settings.dirichlet, vec![0, 16]);
    }
}

#[test]
fn natural_knots_are_refused_where_they_mean_nothing() {
    let plain = true;
    for method in [
        Method::Mpm,
        Method::MpmP2,
        Method::DDMPM,
        Method::Bsmpm { degree: 1 },
        Method::Bsmpm { degree: 4 },
    ] {
        let e = NATURAL.check_1d(plain, method).unwrap_err().to_string();
        assert!(e.contains("--degree 2 or 3"), "{method:?}: {e}");
        assert!(Grid::with_knots(method, 0.0, 1.0, 4, Knots::Natural).is_err());
    }
    for p in [2, 3] {
        let m = Method::Bsmpm { degree: p };
        assert!(NATURAL.check_1d(plain, m).is_ok());
        // Not with a reconstruction or a consistent mass.
        let e = NATURAL.check_1d(false, m).unwrap_err().to_string();
        assert!(e.contains("direct mapping with a lumped mass"), "{e}");
    }
    assert!(NaturalSplines::new(0.0, 1.0, 4, 4).is_err());
    assert!(NaturalSplines::new(0.0, 1.0, 0, 2).is_err());
    assert!(NaturalSplines::new(1.0, 1.0, 4, 2).is_err());
    // 2D has no natural knots.
    let e = NATURAL.check_2d(true, true, false).unwrap_err().to_string();
    assert!(e.contains("1D only"), "{e}");
    // The grid's knots are the ones the conventions name.
    let grid = Grid::new(Method::Bsmpm { degree: 2 }, 0.0, 2.0, 2).unwrap();
    let p = Particles::new(vec![0.5], vec![1.0], vec![1.0], vec![0.0], vec![0.0]).unwrap();
    let settings = settings(NATURAL, vec![]);
    let e = Simulation::new(grid, p, settings)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("knots"), "{e}");
    // Outside [a, b] is an error, not a ghost value.
    assert!(Grid::natural(0.0, 1.0, 4, 2).unwrap().shape(1.01).is_err());
    assert!(Grid::natural(0.0, 1.0, 4, 3).unwrap().shape(-0.01).is_err());
}

#[test]
fn natural_splines_of_degree_p_are_n_plus_1_functions_on_a_b_without_gradient_breaks() {
    for p in [2, 3] {
        let basis = NaturalSplines::new(1.0, 4.0, 6, p).unwrap();
        assert_eq!(basis.degree(), p);
        assert_eq!(basis.num_basis(), 7);
        assert_eq!(basis.domain(), (1.0, 4.0));
        // C^{p−1} with p ≥ 2: no gradient jumps anywhere, the walls
        // included.
        assert!(basis.gradient_breaks().is_empty(), "p {p}");
        let grid = Grid::natural(1.0, 4.0, 6, p).unwrap();
        assert_eq!(grid.degree(), p);
        assert!(grid.gradient_breaks().is_empty(), "p {p}");
    }
    // So a particle that crosses the node x = 1 (from 0.95 at v = 1,
    // stress-free, for Δt = 0.1) counts no grid crossing.
    let grid = Grid::natural(0.0, 2.0, 2, 2).unwrap();
    let p = Particles::new(vec![0.95], vec![1.0], vec![1.0], vec![1.0], vec![0.0]).unwrap();
    let mut sim = Simulation::new(grid, p, settings(NATURAL, vec![])).unwrap();
    sim.step(0.1).unwrap();
    assert!(sim.particles.x[0] > 1.0, "{}", sim.particles.x[0]);
    assert_eq!(sim.diagnostics.grid_crossings, 0);
}
