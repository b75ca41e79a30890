//! DDMPM, TLS paper §3.3, stated on uniform P1 elements of size h, where every
//! node integral is hand-computable:
//!
//! - V_j = ∫ φ_j = h inside, h/2 at the two end nodes;
//! - ∫ φ_j ∇φ_{j−1} = −½, ∫ φ_j ∇φ_{j+1} = ½, ∫ φ_j ∇φ_j = 0 inside
//!   (−½ at the first node, +½ at the last);
//! - ∇̃φ_i(x) = Σ_j φ_j(x)/V_j ∫ φ_j ∇φ_i;
//! - ∇̄φ_i = α ∇φ_i + (1 − α) ∇̃φ_i with α = 2 φ_k φ_{k+1} on element k.

use approx::assert_relative_eq;
use hompm::mpm::grid::{Grid, Method, NodeIntegrals};

use crate::common;

/// The DDMPM gradient of every DOF at x, as a dense vector.
fn ddmpm_gradients(grid: &Grid, x: f64) -> Vec<f64> {
    let s = grid.shape(x).unwrap();
    let mut out = vec![0.0; grid.num_dofs()];
    for (j, g) in s.gradients.iter().enumerate() {
        out[s.first + j] += g;
    }
    out
}

/// The P1 gradient of every DOF at x (the element containing x, half-open).
fn p1_gradients(grid: &Grid, x: f64) -> Vec<f64> {
    let p1 = Grid::new(Method::Mpm, 0.0, grid.domain().1, grid.num_cells()).unwrap();
    let s = p1.shape(x).unwrap();
    let mut out = vec![0.0; grid.num_dofs()];
    for (j, g) in s.gradients.iter().enumerate() {
        out[s.first + j] = *g;
    }
    out
}

#[test]
fn at_an_interior_cell_centre_alpha_is_one_half() {
    // Element k = 2 of 5 on [0, 5] (h = 1): φ_2 = φ_3 = ½ at x = 2.5, so
    // α = 2·½·½ = ½ and ∇̃φ = [∇̃φ_1, ∇̃φ_2, ∇̃φ_3, ∇̃φ_4] = [−¼, −¼, ¼, ¼]/h.
    let h = 1.0;
    let grid = Grid::new(Method::DDMPM, 0.0, 5.0, 5).unwrap();
    let g = ddmpm_gradients(&grid, 2.5);
    let smoothed = [-0.25 / h, -0.25 / h, 0.25 / h, 0.25 / h];
    let standard = [0.0, -1.0 / h, 1.0 / h, 0.0];
    for (a, i) in (1..=4).enumerate() {
        let expected = 0.5 * standard[a] + 0.5 * smoothed[a];
        assert_relative_eq!(g[i], expected, epsilon = 1e-14);
    }
    // [−1/8, −5/8, 5/8, 1/8]/h, written out.
    assert_relative_eq!(g[2], -0.625, epsilon = 1e-14);
    assert_relative_eq!(g[4], 0.125, epsilon = 1e-14);
    assert_eq!(g[0], 0.0);
    assert_eq!(g[5], 0.0);
}

#[test]
fn at_a_node_alpha_vanishes_and_the_gradient_is_the_smoothed_one() {
    // x = 3 is node 3 (the start of element 3): φ_3 = 1, φ_4 = 0, α = 0, so
    // ∇̄φ_i = ∇̃φ_i = ∫ φ_3 ∇φ_i / V_3 = [−½, 0, ½]/h for i = 2, 3, 4.
    let h = 0.5;
    let grid = Grid::new(Method::DDMPM, 0.0, 3.0, 6).unwrap();
    let g = ddmpm_gradients(&grid, 3.0 * h);
    assert_relative_eq!(g[2], -0.5 / h, epsilon = 1e-13);
    assert_relative_eq!(g[3], 0.0, epsilon = 1e-13);
    assert_relative_eq!(g[4], 0.5 / h, epsilon = 1e-13);
    let p1 = p1_gradients(&grid, 3.0 * h);
    assert_ne!(
        g[3], p1[3],
        "the P1 gradient is not the DDMPM one at a node"
    );
}

#[test]
fn at_the_first_node_the_half_volume_and_one_sided_integrals_enter() {
    // Node 0: V_0 = h/2, ∫ φ_0 ∇φ_0 = −½, ∫ φ_0 ∇φ_1 = ½, so at x = 0
    // (α = 0) ∇̄φ_0 = −1/h and ∇̄φ_1 = 1/h.
    let h = 0.25;
    let grid = Grid::new(Method::DDMPM, 0.0, 1.0, 4).unwrap();
    let g = ddmpm_gradients(&grid, 0.0);
    assert_relative_eq!(g[0], -1.0 / h, epsilon = 1e-13);
    assert_relative_eq!(g[1], 1.0 / h, epsilon = 1e-13);
}

#[test]
fn the_modified_gradient_reproduces_the_gradient_of_a_linear_field() {
    // Σ_i x_i ∇̃φ_i = Σ_j φ_j/V_j ∫ φ_j Σ_i x_i ∇φ_i = Σ_j φ_j = 1, and so is
    // the blend with the P1 gradient: a linear displacement gives a uniform
    // strain everywhere, for any α.
    let grid = Grid::new(Method::DDMPM, -1.0, 2.0, 7).unwrap();
    let h = grid.cell_size();
    for k in 0..=70 {
        let x = -1.0 + 3.0 * k as f64 / 70.0;
        let g = ddmpm_gradients(&grid, x);
        let slope: f64 = g
            .iter()
            .enumerate()
            .map(|(i, gi)| (-1.0 + i as f64 * h) * gi)
            .sum();
        assert_relative_eq!(slope, 1.0, epsilon = 1e-12);
    }
}

#[test]
fn the_blend_is_two_phi_k_phi_k_plus_one_everywhere_in_an_element() {
    // Inside interior element k, ∇̄φ_{k−1} = (1 − α) φ_k ∫φ_k∇φ_{k−1}/V_k
    // = −(1 − α) φ_k/(2h); with α = 2 φ_k φ_{k+1} this pins α at every x.
    let grid = Grid::new(Method::DDMPM, 0.0, 6.0, 6).unwrap();
    for t in [0.1, 0.3, 0.5, 0.7, 0.9] {
        let x = 3.0 + t;
        let (phi_k, phi_k1) = (1.0 - t, t);
        let alpha = 2.0 * phi_k * phi_k1;
        let g = ddmpm_gradients(&grid, x);
        assert_relative_eq!(g[2], -(1.0 - alpha) * phi_k / 2.0, epsilon = 1e-14);
        assert_relative_eq!(g[5], (1.0 - alpha) * phi_k1 / 2.0, epsilon = 1e-14);
    }
}

// ---- The node-integral rules (issue #11; TLS paper §3.3, Table 8) ----

/// |V − V_exact| + |G − G_exact| summed over the nodes of `grid` after a
/// refresh from the particles, against the exact integrals over Ω.
fn node_integral_error(grid: &mut Grid, xs: &[f64], vs: &[f64]) -> f64 {
    let exact = Grid::new(Method::DDMPM, 0.0, grid.domain().1, grid.num_cells()).unwrap();
    grid.refresh_node_integrals(xs, vs).unwrap();
    let dv: f64 = grid
        .node_volumes()
        .iter()
        .zip(exact.node_volumes())
        .map(|(a, b)| (a - b).abs())
        .sum();
    let dg: f64 = grid
        .node_gradient_integrals()
        .iter()
        .zip(exact.node_gradient_integrals())
        .flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y).abs()))
        .sum();
    dv + dg
}

#[test]
fn particle_quadrature_node_integrals_are_the_particle_sums() {
    // Two particles on [0, 2] with h = 1: x = 0.25 (V = 0.5) and x = 1.5
    // (V = 1). V_0 = 0.5·0.75, V_1 = 0.5·0.25 + 1·0.5, V_2 = 1·0.5;
    // ∫φ_0∇φ_1 ≈ 0.5·0.75·1, ∫φ_1∇φ_1 ≈ 0.5·0.25·1 + 1·0.5·(−1).
    let mut grid = Grid::new(Method::DDMPM_PARTICLES, 0.0, 2.0, 2).unwrap();
    grid.refresh_node_integrals(&[0.25, 1.5], &[0.5, 1.0])
        .unwrap();
    let v = grid.node_volumes();
    assert_relative_eq!(v[0], 0.375, epsilon = 1e-15);
    assert_relative_eq!(v[1], 0.625, epsilon = 1e-15);
    assert_relative_eq!(v[2], 0.5, epsilon = 1e-15);
    let g = grid.node_gradient_integrals();
    assert_relative_eq!(g[0][2], 0.375, epsilon = 1e-15);
    assert_relative_eq!(g[1][1], 0.125 - 0.5, epsilon = 1e-15);
    assert_relative_eq!(g[2][0], -0.5, epsilon = 1e-15);
    // The exact rule ignores the particles.
    let mut exact = Grid::new(Method::DDMPM, 0.0, 2.0, 2).unwrap();
    exact
        .refresh_node_integrals(&[0.25, 1.5], &[0.5, 1.0])
        .unwrap();
    assert_relative_eq!(exact.node_volumes()[1], 1.0, epsilon = 1e-15);
}

#[test]
fn one_subpoint_is_particle_quadrature_bit_for_bit() {
    let xs = [0.1, 0.45, 0.8, 1.3, 1.95];
    let vs = [0.2, 0.3, 0.25, 0.4, 0.1];
    let mut a = Grid::new(Method::DDMPM_PARTICLES, 0.0, 2.0, 4).unwrap();
    let mut b = Grid::new(Method::ddmpm_subpoints(1), 0.0, 2.0, 4).unwrap();
    a.refresh_node_integrals(&xs, &vs).unwrap();
    b.refresh_node_integrals(&xs, &vs).unwrap();
    assert_eq!(a.node_volumes(), b.node_volumes());
    assert_eq!(a.node_gradient_integrals(), b.node_gradient_integrals());
}

#[test]
fn subpoints_converge_to_the_exact_integrals_as_their_number_grows() {
    // Seven particles tile [0, 3] (three cells), so their domains straddle
    // the nodes at 1 and 2: one point per particle is not exact there. The
    // integrand φ_j∇φ_i jumps at a node, so the midpoint subpoints converge
    // as O(1/n): the error halves with every doubling of n.
    let xs: Vec<f64> = (0..7).map(|p| (p as f64 + 0.5) * 3.0 / 7.0).collect();
    let vs = vec![3.0 / 7.0; 7];
    let mut errors = Vec::new();
    for n in [1, 2, 4, 8, 16, 32, 64] {
        let mut grid = Grid::new(Method::ddmpm_subpoints(n), 0.0, 3.0, 3).unwrap();
        errors.push(node_integral_error(&mut grid, &xs, &vs));
    }
    assert!(errors[0] > 1e-2, "{errors:?}");
    for w in errors.windows(2) {
        assert!(w[1] <= 0.55 * w[0], "not O(1/n): {errors:?}");
    }
    assert!(errors[6] < 0.02 * errors[0], "{errors:?}");
    // Domains that do not straddle a node (two per cell) are integrated
    // exactly by one point: P1 integrands are linear inside an element.
    let xs: Vec<f64> = (0..6).map(|p| (p as f64 + 0.5) * 0.5).collect();
    let mut grid = Grid::new(Method::DDMPM_PARTICLES, 0.0, 3.0, 3).unwrap();
    assert!(node_integral_error(&mut grid, &xs, &[0.5; 6]) < 1e-14);
}

#[test]
fn the_modified_gradient_reproduces_a_linear_field_under_every_rule() {
    // Σ_i x_i ∇̃φ_i = Σ_j φ_j/V_j Σ_q w_q φ_j(x_q) Σ_i x_i ∇φ_i(x_q)
    // = Σ_j φ_j = 1 whatever the quadrature points, as long as every node
    // that φ_j(x) > 0 reaches has V_j > 0: true inside the material.
    let xs: Vec<f64> = (0..11).map(|p| 0.3 + 0.17 * p as f64).collect();
    let vs = vec![0.17; 11];
    for method in [
        Method::DDMPM,
        Method::DDMPM_PARTICLES,
        Method::ddmpm_subpoints(3),
        Method::ddmpm_subpoints(16),
    ] {
        let mut grid = Grid::new(method, 0.0, 3.0, 6).unwrap();
        grid.refresh_node_integrals(&xs, &vs).unwrap();
        let h = grid.cell_size();
        for &x in &xs[1..10] {
            let g = ddmpm_gradients(&grid, x);
            let slope: f64 = g.iter().enumerate().map(|(i, gi)| i as f64 * h * gi).sum();
            assert_relative_eq!(slope, 1.0, epsilon = 1e-12);
        }
    }
}

#[test]
fn at_a_node_alpha_vanishes_under_every_rule() {
    // At node j, α = 0 and ∇̄φ_i = ∫φ_j∇φ_i / V_j with the rule's integrals.
    let xs = [0.2, 0.55, 0.9, 1.2, 1.7];
    let vs = [0.3, 0.35, 0.3, 0.35, 0.5];
    for method in [Method::DDMPM_PARTICLES, Method::ddmpm_subpoints(4)] {
        let mut grid = Grid::new(method, 0.0, 2.0, 4).unwrap();
        grid.refresh_node_integrals(&xs, &vs).unwrap();
        let j = 2;
        let (v, gi) = (grid.node_volumes()[j], grid.node_gradient_integrals()[j]);
        let g = ddmpm_gradients(&grid, 1.0);
        for (slot, i) in (j - 1..=j + 1).enumerate() {
            assert_relative_eq!(g[i], gi[slot] / v, epsilon = 1e-13);
        }
    }
}

#[test]
fn a_node_no_particle_reaches_adds_nothing_instead_of_dividing_by_zero() {
    // Particles only in the first of four cells: V_2 = V_3 = V_4 = 0. The
    // gradient at x = 1.25 (cell 2, nodes 2 and 3) is then α∇φ only, finite.
    let mut grid = Grid::new(Method::DDMPM_PARTICLES, 0.0, 2.0, 4).unwrap();
    grid.refresh_node_integrals(&[0.1, 0.3], &[0.2, 0.2])
        .unwrap();
    assert_eq!(grid.node_volumes()[3], 0.0);
    let g = ddmpm_gradients(&grid, 1.25);
    let alpha = 2.0 * 0.5 * 0.5;
    assert_relative_eq!(g[2], -alpha / 0.5, epsilon = 1e-14);
    assert_relative_eq!(g[3], alpha / 0.5, epsilon = 1e-14);
    assert!(g.iter().all(|v| v.is_finite()));
}

#[test]
fn node_integral_rules_refuse_bad_input() {
    assert!(Grid::new(Method::ddmpm_subpoints(0), 0.0, 1.0, 2).is_err());
    let mut grid = Grid::new(Method::DDMPM_PARTICLES, 0.0, 1.0, 2).unwrap();
    assert!(grid.refresh_node_integrals(&[0.5], &[]).is_err());
    assert!(grid.refresh_node_integrals(&[0.5], &[f64::NAN]).is_err());
    assert!(grid.refresh_node_integrals(&[1.5], &[0.1]).is_err());
    assert_eq!(Method::ddmpm_subpoints(8).label(), "DDMPM (8 subpoints)");
    assert_eq!(Method::DDMPM.label(), "DDMPM");
    assert_eq!(NodeIntegrals::Particles.label(), "particle quadrature");
}

#[test]
fn a_step_refreshes_the_node_integrals_from_the_particles_at_its_start() {
    use hompm::mpm::mapping::{Mapping, MassMatrix};
    use hompm::mpm::musl::Simulation;
    use hompm::mpm::particles::Particles;
    let grid = Grid::new(Method::DDMPM_PARTICLES, 0.0, 2.0, 4).unwrap();
    let mut p = Particles::uniform(0.0, 1.3, 8, 1.0).unwrap();
    p.velocity = (0..8).map(|k| 0.1 * k as f64).collect();
    let settings = common::free_settings(Mapping::Direct, MassMatrix::Lumped, 10.0);
    let mut sim = Simulation::new(grid, p, settings).unwrap();
    for _ in 0..3 {
        let (xs, vs) = (sim.particles.x.clone(), sim.particles.volume.clone());
        sim.step(1e-2).unwrap();
        let mut expected = Grid::new(Method::DDMPM_PARTICLES, 0.0, 2.0, 4).unwrap();
        expected.refresh_node_integrals(&xs, &vs).unwrap();
        assert_eq!(sim.grid.node_volumes(), expected.node_volumes());
        // Partition of unity: Σ_j V_j = Σ_p V_p.
        let total: f64 = sim.grid.node_volumes().iter().sum();
        assert_relative_eq!(total, vs.iter().sum::<f64>(), epsilon = 1e-14);
    }
}

#[test]
fn end_subpoints_include_both_ends_of_the_particle_domain() {
    // x_p = 0.9, V_p = 0.4 on [0, 2] with h = 1: three subpoints at 0.7,
    // 0.9 and 1.1, weight 0.4/3 each, so V_0 = w(0.3 + 0.1),
    // V_1 = w(0.7 + 0.9 + 0.9), V_2 = w·0.1. Midpoints (0.7667, 0.9, 1.0333)
    // would give other values.
    let w = 0.4 / 3.0;
    let mut ends = Grid::new(Method::ddmpm_end_subpoints(3), 0.0, 2.0, 2).unwrap();
    ends.refresh_node_integrals(&[0.9], &[0.4]).unwrap();
    let v = ends.node_volumes();
    assert_relative_eq!(v[0], w * 0.4, epsilon = 1e-15);
    assert_relative_eq!(v[1], w * 2.5, epsilon = 1e-15);
    assert_relative_eq!(v[2], w * 0.1, epsilon = 1e-15);
    let mut mid = Grid::new(Method::ddmpm_subpoints(3), 0.0, 2.0, 2).unwrap();
    mid.refresh_node_integrals(&[0.9], &[0.4]).unwrap();
    assert!((mid.node_volumes()[2] - w * 0.1).abs() > 1e-3);
    assert!(Grid::new(Method::ddmpm_end_subpoints(1), 0.0, 1.0, 2).is_err());
    assert_eq!(
        Method::ddmpm_end_subpoints(4).label(),
        "DDMPM (4 subpoints incl. ends)"
    );
}

/// TLS paper §6.2: with n subpoints per particle the node volumes are
/// V_j = Σ_p Σ_s (V_p/n) φ_j(x_p + V_p (t_s − ½)), t_s = (s + ½)/n (the
/// midpoints) or s/(n − 1) (both ends), each subpoint clamped to the grid,
/// summed particle by particle and, in a particle, from its left end to
/// its right: the grid's V_j are that sum bit for bit (a subpoint placed or
/// visited otherwise changes the rounding, if not the value).
#[test]
fn subpoint_node_volumes_are_the_sum_over_each_particle_from_its_left_end() {
    use hompm::lagrange::{LagrangeBasis, LagrangeOrder};
    let (a, b, cells) = (0.0, 3.0, 5);
    let basis = LagrangeBasis::new(a, b, cells, LagrangeOrder::Linear).unwrap();
    let xs: Vec<f64> = (0..23).map(|p| 0.05 + 0.13 * p as f64).collect();
    let vs: Vec<f64> = (0..23).map(|p| 0.09 + 0.011 * (p % 7) as f64).collect();
    for (method, n, t) in [
        (
            Method::ddmpm_subpoints(7),
            7,
            (|s, n| (s as f64 + 0.5) / n as f64) as fn(usize, usize) -> f64,
        ),
        (
            Method::Ddmpm {
                node_integrals: NodeIntegrals::EndSubpoints(6),
            },
            6,
            |s, n| s as f64 / (n - 1) as f64,
        ),
    ] {
        let mut expected = vec![0.0; cells + 1];
        for (&x, &v) in xs.iter().zip(&vs) {
            for s in 0..n {
                let at = (x + v * (t(s, n) - 0.5)).clamp(a, b);
                let (mut phi, mut grad) = ([0.0; 2], [0.0; 2]);
                let k = basis.evaluate_into(at, &mut phi, &mut grad).unwrap();
                expected[k] += v / n as f64 * phi[0];
                expected[k + 1] += v / n as f64 * phi[1];
            }
        }
        let mut grid = Grid::new(method, a, b, cells).unwrap();
        grid.refresh_node_integrals(&xs, &vs).unwrap();
        assert_eq!(grid.node_volumes(), &expected[..], "{method:?}");
    }
}
