//! The lean 2D steps (benches/lean/mpm2d.rs) against `Simulation2d::step`
//! on the aligned vibration of the MLS paper (Eqs. 4–5, 22–37, 41 and the
//! body force of Eq. 42 with π²).

use super::mpm2d::{Axis, BilinearAxis, Lean2d, OpenBSplines};
use hompm::mpm2d::step::Simulation2d;
use hompm::scenes::aligned_vibration::{parameters, AlignedMethod};

/// Runs hompm and the lean step side by side for `steps` steps on `cells`
/// cells per side with 9 particles per cell, and asserts that x, u, v, F,
/// σ, V and ρ agree bit for bit for every particle, and that the body has
/// moved (the comparison is not of two states at rest).
fn assert_lean_is_hompm<const W: usize, A: Axis<W>>(
    method: AlignedMethod,
    cells: usize,
    steps: usize,
) {
    let scene = parameters("mls-paper-e1e7").unwrap();
    let mut sim: Simulation2d = scene.simulation(method, cells, 3, 1.0).unwrap();
    let mut lean = Lean2d::<W, A>::from_simulation(&sim, &scene);
    for _ in 0..steps {
        sim.step(scene.dt).unwrap();
        lean.step(scene.dt);
    }
    let q = &sim.particles;
    assert_eq!(lean.x, q.x);
    assert_eq!(lean.displacement, q.displacement);
    assert_eq!(lean.velocity, q.velocity);
    let deformation: Vec<[f64; 4]> = q
        .deformation
        .iter()
        .map(|f| [f[(0, 0)], f[(0, 1)], f[(1, 0)], f[(1, 1)]])
        .collect();
    assert_eq!(lean.deformation, deformation);
    assert!(q.stress.iter().all(|s| s[(0, 1)] == s[(1, 0)]));
    let stress: Vec<[f64; 3]> = q
        .stress
        .iter()
        .map(|s| [s[(0, 0)], s[(0, 1)], s[(1, 1)]])
        .collect();
    assert_eq!(lean.stress, stress);
    assert_eq!(lean.volume, q.volume);
    assert_eq!(lean.density, q.density);
    assert_eq!(lean.time, sim.time);
    let moved = q.displacement.iter().map(|u| u[0].abs().max(u[1].abs()));
    assert!(moved.fold(0.0, f64::max) > 1e-3);
}

/// MLS paper Eqs. (4)–(5), (22)–(37) and (41) with quadratic B-splines
/// (BSMPM, p = 2; `LeanBsmpm2d<3>`), two ways: after 2000 steps (t = 0.02 s, two periods of
/// the vibration) on 16 × 16 cells with 9 particles each, every particle's
/// state agrees bit for bit.
#[test]
fn the_lean_bsmpm_2d_step_computes_bit_for_bit_what_hompm_s_step_computes() {
    assert_lean_is_hompm::<3, OpenBSplines>(AlignedMethod::bsmpm(2), 16, 2000);
}

/// The same for cubic B-splines (p = 3), 500 steps on 8 × 8 cells: the lean
/// step (`LeanBsmpm2d<4>`) is generic over the degree.
#[test]
fn the_lean_cubic_bsmpm_2d_step_computes_bit_for_bit_what_hompm_s_step_computes() {
    assert_lean_is_hompm::<4, OpenBSplines>(AlignedMethod::bsmpm(3), 8, 500);
}

/// The same for bilinear MPM (`LeanBilinear2d`), 2000 steps on 16 × 16 cells.
#[test]
fn the_lean_bilinear_2d_step_computes_bit_for_bit_what_hompm_s_step_computes() {
    assert_lean_is_hompm::<2, BilinearAxis>(AlignedMethod::Mpm, 16, 2000);
}
