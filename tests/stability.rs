//! Stability where methods fail: every failure the seeds describe is a typed
//! error or a diagnosed result, never a silent NaN.

use hompm::mpm::grid::Method;
use hompm::mpm::mapping::{Mapping, MassMatrix};

use hompm::studies::critical_courant;
use hompm::Error;

/// Thesis §5.2: P2 Lagrange end-node functions are negative inside the
/// element, so material-point lumped masses can be negative. With one particle
/// per element (at its centre) every step has a negative active mass, and the
/// displacement error at t = 0.5 s is 60× that of two particles per element.
#[test]
fn quadratic_lagrange_negative_masses_are_diagnosed() {
    let n = hompm::studies::failures::quadratic_lagrange_negative_masses().unwrap();
    assert!(
        n.min_lumped_mass < 0.0,
        "min lumped mass {}",
        n.min_lumped_mass
    );
    // Every step but the first, where the centred particles give exactly zero vertex masses.
    assert!(
        n.negative_mass_steps >= n.steps - 10,
        "{}",
        n.negative_mass_steps
    );
    assert_eq!(n.negative_mass_steps_two_ppc, 0);
    assert!(
        n.error_one_ppc > 20.0 * n.error_two_ppc,
        "1 PPC: {}, 2 PPC: {}",
        n.error_one_ppc,
        n.error_two_ppc
    );
    // With the same single particle per element, P1 (positive masses) does better.
    assert!(
        n.error_one_ppc > n.error_linear_one_ppc,
        "P2 {} vs P1 {}",
        n.error_one_ppc,
        n.error_linear_one_ppc
    );
}

/// Thesis §5.1.3: the column under self-weight (Table 4.3, 2 PPC, Δt = 1e-4 s,
/// t = 0.5 s) has no grid crossings with 50 DOFs and crossings with 80 DOFs,
/// where linear MPM loses its accuracy; quadratic B-splines on the same
/// spans do not suffer (thesis §6.2.3).
#[test]
fn linear_mpm_grid_crossing_in_the_column() {
    let g = hompm::studies::failures::column_grid_crossing().unwrap();
    let (p50, p80, b80) = (g.linear_50, g.linear_80, g.bspline_80);
    assert_eq!(p50.crossings, 0);
    assert!(p80.crossings > 50, "{} crossings", p80.crossings);
    assert!(
        p80.error > 10.0 * p50.error,
        "80 DOFs {} vs 50 DOFs {}",
        p80.error,
        p50.error
    );
    assert_eq!(
        b80.crossings, 0,
        "quadratic B-splines have no gradient discontinuity"
    );
    assert!(
        b80.error < p80.error / 10.0,
        "B-spline {} vs P1 {}",
        b80.error,
        p80.error
    );
}

/// Thesis §7.2.4: for the large-deformation column (Table 4.4, 64 spans,
/// 4 PPC, Δt = 1e-4 s, t = 0.5 s) a consistent mass in the velocity
/// projection meets near-zero entries at the moving top: with the spline
/// mapping the nodal velocities become unrealistically high (diagnosed), and
/// with the direct mapping the run blows up (typed error); the lumped
/// projection of the thesis' own choice stays bounded.
#[test]
fn near_zero_consistent_masses_are_diagnosed() {
    let z = hompm::studies::failures::near_zero_consistent_masses().unwrap();
    assert!(
        z.min_mass_diagonal_ratio < 1e-10,
        "ratio {}",
        z.min_mass_diagonal_ratio
    );
    assert!(
        z.max_nodal_velocity > 100.0 * z.max_particle_velocity,
        "{} vs {}",
        z.max_nodal_velocity,
        z.max_particle_velocity
    );
    let step = z.direct_blow_up_step.expect("the direct mapping blows up");
    assert!(step > 0 && step <= 5000, "step {step}");
    assert!(z.direct_blow_up_particle.is_some_and(|p| p < 256));
    assert!(z.lumped_velocity_ratio < 2.0, "{}", z.lumped_velocity_ratio);
}

/// Thesis Eq. (3.5): the CFL estimate C = cΔt/h ≤ 1 is safe for linear MPM
/// with lumped mass; a consistent mass in the acceleration lowers the
/// limit, and P2 has the lowest one (docs/reproduction.md has the full map).
#[test]
fn largest_stable_time_step_against_the_cfl_estimate() {
    let p1 = critical_courant(Method::Mpm, false, 8, 4).unwrap();
    let p1c = critical_courant(Method::Mpm, true, 8, 4).unwrap();
    let b2 = critical_courant(Method::Bsmpm { degree: 2 }, false, 8, 4).unwrap();
    let b2c = critical_courant(Method::Bsmpm { degree: 2 }, true, 8, 4).unwrap();
    let p2 = critical_courant(Method::MpmP2, false, 8, 4).unwrap();
    assert!(p1 >= 1.0, "P1 lumped: {p1}");
    assert!(
        p1c < p1 && b2c < b2,
        "consistent {p1c}, {b2c} vs lumped {p1}, {b2}"
    );
    assert!(p2 < p1 && p2 < b2, "P2 {p2}");
}

/// Bad input is a typed error: a particle outside the grid, dt ≤ 0, NaN data.
#[test]
fn bad_runs_are_typed_errors() {
    use hompm::mpm::grid::Grid;
    use hompm::mpm::musl::{Constitutive, Settings, Simulation};
    use hompm::mpm::particles::Particles;
    let settings = Settings {
        force_mapping: Mapping::Direct,
        velocity_mapping: Mapping::Direct,
        mass: MassMatrix::Lumped,
        constitutive: Constitutive::SmallStrain,
        young: 1.0,
        gravity: 0.0,
        gravity_ramp: None,
        dirichlet: vec![0],
        consistent_acceleration: false,
    };
    let grid = || Grid::new(Method::Mpm, 0.0, 1.0, 4).unwrap();
    let outside = Particles::uniform(0.0, 2.0, 8, 1.0).unwrap();
    assert!(matches!(
        Simulation::new(grid(), outside, settings.clone()),
        Err(Error::OutsideDomain { .. })
    ));
    let ok = Particles::uniform(0.0, 1.0, 8, 1.0).unwrap();
    let mut sim = Simulation::new(grid(), ok, settings.clone()).unwrap();
    assert!(matches!(sim.step(0.0), Err(Error::InvalidArgument(_))));
    assert!(matches!(sim.step(f64::NAN), Err(Error::InvalidArgument(_))));
    assert!(Particles::new(vec![0.5], vec![1.0], vec![1.0], vec![f64::NAN], vec![0.0]).is_err());
    assert!(Particles::new(vec![0.5], vec![-1.0], vec![1.0], vec![0.0], vec![0.0]).is_err());
    assert!(Simulation::new(
        grid(),
        Particles::uniform(0.0, 1.0, 4, 1.0).unwrap(),
        Settings {
            young: -1.0,
            ..settings.clone()
        }
    )
    .is_err());
    assert!(Simulation::new(
        grid(),
        Particles::uniform(0.0, 1.0, 4, 1.0).unwrap(),
        Settings {
            dirichlet: vec![99],
            ..settings
        }
    )
    .is_err());
}

/// The CFL warning of `hompm run` (`mpm::monitor`) uses constants: they are
/// the critical Courant numbers the study measures (16 cells, 4 PPC, lumped
/// acceleration), rounded down to two digits.
#[test]
fn the_monitors_critical_courant_numbers_are_the_measured_ones() {
    use hompm::mpm::monitor::measured_critical_courant;
    for method in [
        Method::Mpm,
        Method::DDMPM,
        Method::MpmP2,
        Method::Bsmpm { degree: 1 },
        Method::Bsmpm { degree: 2 },
        Method::Bsmpm { degree: 3 },
    ] {
        let measured = critical_courant(method, false, 16, 4).unwrap();
        let constant = measured_critical_courant(method).unwrap();
        assert!(
            constant <= measured && measured - constant < 0.01,
            "{method:?}: constant {constant}, measured {measured}"
        );
    }
    assert_eq!(measured_critical_courant(Method::Bsmpm { degree: 4 }), None);
}
