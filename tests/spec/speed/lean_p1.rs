//! The lean 1D P1 MUSL step (benches/lean/p1.rs) against
//! `Simulation::step` on the vibrating bar of thesis Table 4.1.

use super::p1::LeanP1;
use hompm::mpm::grid::Method;
use hompm::scenes::{vibrating_bar, Discretisation};

/// Book Eqs. (4.5)–(4.18) with P1 elements, two ways: after 5000 steps on
/// 64 cells with 4 particles each, x, u, v, σ, V, ρ and ε agree bit for
/// bit for every particle, and the bar has moved (the comparison is not
/// of two states at rest).
#[test]
fn the_lean_p1_step_computes_bit_for_bit_what_hompm_s_step_computes() {
    let p = vibrating_bar::parameters("thesis-table-4.1").unwrap();
    let mut sim = p
        .simulation(&Discretisation::direct(Method::Mpm, 64, 4))
        .unwrap();
    let mut lean = LeanP1::from_simulation(&sim);
    let dt = 1e-5;
    for _ in 0..5000 {
        sim.step(dt).unwrap();
        lean.step(dt);
    }
    let q = &sim.particles;
    assert_eq!(lean.x, q.x);
    assert_eq!(lean.displacement, q.displacement);
    assert_eq!(lean.velocity, q.velocity);
    assert_eq!(lean.stress, q.stress);
    assert_eq!(lean.volume, q.volume);
    assert_eq!(lean.density, q.density);
    assert_eq!(lean.strain, q.strain);
    assert!(q.displacement.iter().any(|u| u.abs() > 1e-6));
}

/// `Simulation::without_diagnostics` times the step without its monitors
/// (benches/lean_p1.rs): the particles evolve bit for bit as with them on,
/// for P1 and for consistent-mass B-splines with a spline mapping, and
/// nothing is recorded but the step count.
#[test]
fn turning_the_diagnostics_off_changes_no_particle_and_records_nothing() {
    use hompm::mpm::mapping::{ConsistentSolver, Mapping, MassMatrix};
    let p = vibrating_bar::parameters("thesis-table-4.2").unwrap();
    for d in [
        Discretisation::direct(Method::Mpm, 16, 4),
        Discretisation::new(
            Method::Bsmpm { degree: 2 },
            Mapping::CubicSpline,
            MassMatrix::Consistent(ConsistentSolver::Cholesky),
            16,
            4,
        ),
    ] {
        let mut on = p.simulation(&d).unwrap();
        let mut off = p.simulation(&d).unwrap().without_diagnostics();
        assert!(on.records_diagnostics() && !off.records_diagnostics());
        on.run(1e-5, 300).unwrap();
        off.run(1e-5, 300).unwrap();
        assert_eq!(on.particles, off.particles);
        assert!(on.diagnostics.max_particle_velocity > 0.0);
        assert!(on.diagnostics.final_energy > 0.0);
        assert_eq!(off.diagnostics.steps, 300);
        assert_eq!(off.diagnostics.max_particle_velocity, 0.0);
        assert_eq!(off.diagnostics.max_mass_error, 0.0);
        assert_eq!(off.diagnostics.max_abs_strain, 0.0);
        assert_eq!(off.diagnostics.final_energy, 0.0);
        assert_eq!(off.diagnostics.min_lumped_mass, f64::INFINITY);
    }
}
