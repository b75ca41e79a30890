//! One MUSL step of book §4.2.2 computed by hand, equation by equation.
//!
//! Two P1 elements on [0, 2] (h = 1, nodes 0, 1, 2) and two particles:
//!
//! | p | x_p  | V_p | ρ_p | m_p | v_p | σ_p | traction |
//! |---|------|-----|-----|-----|-----|-----|----------|
//! | 0 | 0.5  | 1   | 2   | 2   | 1   | 3   | 0        |
//! | 1 | 1.25 | 0.5 | 4   | 2   | −2  | −1  | 0.5      |
//!
//! with E = 10, g = −1, Δt = 0.1 and no Dirichlet DOF. At the particles
//! φ = (½, ½) on nodes 0, 1 with ∇φ = (−1, 1) for p = 0, and φ = (¾, ¼) on
//! nodes 1, 2 with ∇φ = (−1, 1) for p = 1. Each number below was worked out
//! on paper from the equation named in the test.

use approx::assert_relative_eq;
use hompm::mpm::grid::{Grid, Method};
use hompm::mpm::mapping::{Mapping, MassMatrix};
use hompm::mpm::musl::{Constitutive, Settings, Simulation};
use hompm::mpm::particles::Particles;

const DT: f64 = 0.1;

fn two_particles(constitutive: Constitutive) -> Simulation {
    let grid = Grid::new(Method::Mpm, 0.0, 2.0, 2).unwrap();
    let mut p = Particles::new(
        vec![0.5, 1.25],
        vec![1.0, 0.5],
        vec![2.0, 4.0],
        vec![1.0, -2.0],
        vec![3.0, -1.0],
    )
    .unwrap();
    p.traction = vec![0.0, 0.5];
    let settings = Settings {
        force_mapping: Mapping::Direct,
        velocity_mapping: Mapping::Direct,
        mass: MassMatrix::Lumped,
        constitutive,
        young: 10.0,
        gravity: -1.0,
        gravity_ramp: None,
        dirichlet: vec![],
        consistent_acceleration: false,
    };
    let mut sim = Simulation::new(grid, p, settings).unwrap();
    sim.step(DT).unwrap();
    sim
}

fn assert_all(computed: &[f64], expected: &[f64]) {
    assert_eq!(computed.len(), expected.len());
    for (c, e) in computed.iter().zip(expected) {
        assert_relative_eq!(*c, *e, epsilon = 1e-12, max_relative = 1e-12);
    }
}

#[test]
fn eq_4_5_lumped_mass_is_the_mass_weighted_basis_sum() {
    // m = [2·½, 2·½ + 2·¾, 2·¼]
    assert_all(
        &two_particles(Constitutive::SmallStrain).workspace().mass,
        &[1.0, 2.5, 0.5],
    );
}

#[test]
fn eq_4_6_internal_force_is_stress_times_volume_times_gradient() {
    // σV = 3 and −0.5: f = [3·(−1), 3·1 + (−0.5)(−1), (−0.5)·1]
    let sim = two_particles(Constitutive::SmallStrain);
    assert_all(&sim.workspace().internal_force, &[-3.0, 3.5, -0.5]);
}

#[test]
fn thesis_3_2_gravity_and_traction_loads() {
    // m g φ: [−1, −1 − 1.5, −0.5]; traction 0.5 φ on particle 1: [0, 0.375, 0.125]
    let sim = two_particles(Constitutive::SmallStrain);
    assert_all(&sim.workspace().gravity_force, &[-1.0, -2.5, -0.5]);
    assert_all(&sim.workspace().traction_force, &[0.0, 0.375, 0.125]);
}

#[test]
fn eq_4_8_nodal_acceleration_is_net_force_over_lumped_mass() {
    // a = [(0 − 1 + 3)/1, (0.375 − 2.5 − 3.5)/2.5, (0.125 − 0.5 + 0.5)/0.5]
    let sim = two_particles(Constitutive::SmallStrain);
    assert_all(&sim.workspace().acceleration, &[2.0, -2.25, 0.25]);
}

#[test]
fn eq_4_9_particle_velocity_takes_the_interpolated_acceleration() {
    // v0 = 1 + 0.1(½·2 + ½·(−2.25)), v1 = −2 + 0.1(¾·(−2.25) + ¼·0.25)
    assert_all(
        &two_particles(Constitutive::SmallStrain).particles.v,
        &[0.9875, -2.1625],
    );
}

#[test]
fn eq_4_10_nodal_velocity_is_projected_momentum_over_lumped_mass() {
    // p = [2·0.9875·½, 2·0.9875·½ + 2·(−2.1625)·¾, 2·(−2.1625)·¼] over m
    let sim = two_particles(Constitutive::SmallStrain);
    assert_all(
        &sim.workspace().mapping.velocity,
        &[0.9875, -0.9025, -2.1625],
    );
}

#[test]
fn eqs_4_11_to_4_13_displacement_and_position_move_with_the_grid() {
    // Δu_i = 0.1 v_i = [0.09875, −0.09025, −0.21625];
    // Δu_0 = ½(0.09875 − 0.09025), Δu_1 = ¾(−0.09025) + ¼(−0.21625)
    let sim = two_particles(Constitutive::SmallStrain);
    assert_all(&sim.particles.u, &[0.00425, -0.12175]);
    assert_all(&sim.particles.x, &[0.50425, 1.12825]);
    assert_all(&sim.particles.x0, &[0.5, 1.25]);
}

#[test]
fn eq_4_14_strain_increment_is_the_gradient_of_the_displacement_increment() {
    // Δε_0 = −0.09875 − 0.09025, Δε_1 = 0.09025 − 0.21625
    let sim = two_particles(Constitutive::SmallStrain);
    assert_all(&sim.workspace().strain_increment, &[-0.189, -0.126]);
    assert_all(&sim.particles.strain, &[-0.189, -0.126]);
}

#[test]
fn eq_4_15_small_strain_stress_update() {
    // σ = 3 + 10(−0.189), −1 + 10(−0.126)
    assert_all(
        &two_particles(Constitutive::SmallStrain).particles.stress,
        &[1.11, -2.26],
    );
}

#[test]
fn eq_4_16_large_strain_stress_update() {
    // σ = 3 + (10 − 3)(−0.189), −1 + (10 + 1)(−0.126)
    assert_all(
        &two_particles(Constitutive::LargeStrain).particles.stress,
        &[1.677, -2.386],
    );
}

#[test]
fn eq_4_17_volume_grows_with_the_strain_increment() {
    // V = 1·(1 − 0.189), 0.5·(1 − 0.126)
    assert_all(
        &two_particles(Constitutive::SmallStrain).particles.volume,
        &[0.811, 0.437],
    );
}

#[test]
fn eq_4_18_density_shrinks_with_the_strain_increment_and_mass_is_kept() {
    // ρ = 2/(1 − 0.189), 4/(1 − 0.126)
    let sim = two_particles(Constitutive::SmallStrain);
    let p = &sim.particles;
    assert_all(&p.density, &[2.0 / 0.811, 4.0 / 0.874]);
    assert_relative_eq!(p.density[0], 2.466_091_245_376_079, epsilon = 1e-12);
    for k in 0..2 {
        assert_relative_eq!(p.density[k] * p.volume[k], p.mass[k], epsilon = 1e-13);
    }
}

#[test]
fn the_step_advances_time_and_counts_one_grid_crossing() {
    // Particle 1 moves from 1.25 to 1.12825: it stays in element 1; particle 0
    // stays in element 0. Then a second step of a fast particle crosses.
    let sim = two_particles(Constitutive::SmallStrain);
    assert_eq!(sim.diagnostics.steps, 1);
    assert_relative_eq!(sim.time, DT);
    assert_eq!(sim.diagnostics.grid_crossings, 0);
    let grid = Grid::new(Method::Mpm, 0.0, 2.0, 2).unwrap();
    let p = Particles::new(vec![0.9], vec![0.2], vec![1.0], vec![3.0], vec![0.0]).unwrap();
    let settings = Settings {
        young: 1.0,
        gravity: 0.0,
        ..sim.settings.clone()
    };
    let mut fast = Simulation::new(grid, p, settings).unwrap();
    fast.step(0.1).unwrap();
    assert_relative_eq!(fast.particles.x[0], 1.2, epsilon = 1e-12);
    assert_eq!(fast.diagnostics.grid_crossings, 1);
}
