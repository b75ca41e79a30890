//! DDMPM, TLS paper §3.3, stated on uniform P1 elements of size h, where every
//! node integral is hand-computable:
//!
//! - V_j = ∫ φ_j = h inside, h/2 at the two end nodes;
//! - ∫ φ_j ∇φ_{j−1} = −½, ∫ φ_j ∇φ_{j+1} = ½, ∫ φ_j ∇φ_j = 0 inside
//!   (−½ at the first node, +½ at the last);
//! - ∇̃φ_i(x) = Σ_j φ_j(x)/V_j ∫ φ_j ∇φ_i;
//! - ∇̄φ_i = α ∇φ_i + (1 − α) ∇̃φ_i with α = 2 φ_k φ_{k+1} on element k.

use approx::assert_relative_eq;
use hompm::mpm::grid::{Grid, Method};

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
    let grid = Grid::new(Method::Ddmpm, 0.0, 5.0, 5).unwrap();
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
    let grid = Grid::new(Method::Ddmpm, 0.0, 3.0, 6).unwrap();
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
    let grid = Grid::new(Method::Ddmpm, 0.0, 1.0, 4).unwrap();
    let g = ddmpm_gradients(&grid, 0.0);
    assert_relative_eq!(g[0], -1.0 / h, epsilon = 1e-13);
    assert_relative_eq!(g[1], 1.0 / h, epsilon = 1e-13);
}

#[test]
fn the_modified_gradient_reproduces_the_gradient_of_a_linear_field() {
    // Σ_i x_i ∇̃φ_i = Σ_j φ_j/V_j ∫ φ_j Σ_i x_i ∇φ_i = Σ_j φ_j = 1, and so is
    // the blend with the P1 gradient: a linear displacement gives a uniform
    // strain everywhere, for any α.
    let grid = Grid::new(Method::Ddmpm, -1.0, 2.0, 7).unwrap();
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
    let grid = Grid::new(Method::Ddmpm, 0.0, 6.0, 6).unwrap();
    for t in [0.1, 0.3, 0.5, 0.7, 0.9] {
        let x = 3.0 + t;
        let (phi_k, phi_k1) = (1.0 - t, t);
        let alpha = 2.0 * phi_k * phi_k1;
        let g = ddmpm_gradients(&grid, x);
        assert_relative_eq!(g[2], -(1.0 - alpha) * phi_k / 2.0, epsilon = 1e-14);
        assert_relative_eq!(g[5], (1.0 - alpha) * phi_k1 / 2.0, epsilon = 1e-14);
    }
}
