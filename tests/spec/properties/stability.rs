//! Stability where methods fail: every failure the seeds describe is a typed
//! error or a diagnosed result, never a silent NaN.

use hompm::error::DivergenceCause;
use hompm::mpm::grid::{Grid, Method};
use hompm::mpm::mapping::{Mapping, MassMatrix};
use hompm::mpm::monitor::{measured_critical_courant, StabilityMonitor, Warning};
use hompm::mpm::musl::Simulation;
use hompm::mpm::particles::Particles;

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

/// Direct mappings, lumped mass, small strain, no gravity: the settings of
/// the hand-built runs below, with Young's modulus and the Dirichlet DOFs.
fn direct_lumped_settings(young: f64, dirichlet: Vec<usize>) -> hompm::mpm::musl::Settings {
    hompm::mpm::musl::Settings {
        force_mapping: Mapping::Direct,
        velocity_mapping: Mapping::Direct,
        mass: MassMatrix::Lumped,
        constitutive: hompm::mpm::musl::Constitutive::SmallStrain,
        young,
        poisson: 0.0,
        body_force: None,
        gravity: 0.0,
        gravity_ramp: None,
        dirichlet,
        consistent_acceleration: false,
        tls_density_average: hompm::reconstruct::taylor::CellAverage::Exact,
        conventions: Default::default(),
    }
}

/// `particles` uniform particles (ρ = 1) on `cells` cells of [0, 1], with
/// E = 1 and no Dirichlet DOF.
fn unit_bar(method: Method, cells: usize, particles: usize) -> Simulation {
    let grid = Grid::new(method, 0.0, 1.0, cells).unwrap();
    let particles = Particles::uniform(0.0, 1.0, particles, 1.0).unwrap();
    Simulation::new(grid, particles, direct_lumped_settings(1.0, vec![])).unwrap()
}

/// Bad input is a typed error: a particle outside the grid, dt ≤ 0, NaN data.
#[test]
fn bad_runs_are_typed_errors() {
    use hompm::mpm::musl::Settings;
    let settings = direct_lumped_settings(1.0, vec![0]);
    let grid = || Grid::new(Method::Mpm, 0.0, 1.0, 4).unwrap();
    let outside = Particles::uniform(0.0, 2.0, 8, 1.0).unwrap();
    assert!(matches!(
        Simulation::new(grid(), outside, settings.clone()),
        Err(Error::OutsideDomain { .. })
    ));
    let ok = Particles::uniform(0.0, 1.0, 8, 1.0).unwrap();
    let mut sim = Simulation::new(grid(), ok, settings.clone()).unwrap();
    crate::common::assert_refuses_bad_time_steps(|dt| sim.step(dt));
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

/// `mpm::monitor` by hand. Two particles of mass 2 on one P1 cell, no loads
/// (g = 0, no traction), σ = ε = 0: the energy is Σ ½ m_p v_p². With
/// v = (1, 0) it is E₀ = 1, so the budget is 10 × (E₀ + 0) = 10, and
/// v = (1, 3) reaches it exactly (1 + 9): the run goes on at the budget and
/// stops above it, naming the fastest particle. A strain of ±1 stops it too.
#[test]
fn the_monitor_stops_above_the_energy_budget_and_at_unit_strain() {
    let particles = Particles::new(
        vec![0.25, 0.75],
        vec![0.5, 0.5],
        vec![4.0, 4.0],
        vec![1.0, 0.0],
        vec![0.0, 0.0],
    )
    .unwrap();
    let settings = direct_lumped_settings(100.0, vec![]);
    let grid = Grid::new(Method::Mpm, 0.0, 1.0, 1).unwrap();
    let mut sim = Simulation::new(grid, particles, settings).unwrap();
    // c = √(E/ρ) = 5, h = 1: the critical step of P1 is 1.65 h / c = 0.33.
    let mut monitor = StabilityMonitor::new(&sim, 0.1).unwrap();
    assert_eq!(monitor.energy_budget(), 10.0);
    assert!(monitor.warnings().is_empty());
    assert_eq!(monitor.check(&sim), Ok(()));

    sim.particles.velocity = vec![1.0, 3.0];
    assert_eq!(sim.energy(), 10.0);
    assert_eq!(monitor.check(&sim), Ok(()), "at the budget the run goes on");
    sim.particles.velocity = vec![1.0, 3.5];
    match monitor.check(&sim) {
        Err(Error::Diverged {
            particle: Some(1),
            cause: DivergenceCause::EnergyGrowth { energy, budget, .. },
            ..
        }) => assert_eq!((energy, budget), (13.25, 10.0)),
        other => panic!("expected energy growth at particle 1, got {other:?}"),
    }

    sim.particles.velocity = vec![1.0, 0.0];
    sim.particles.strain = vec![0.0, -0.999];
    assert_eq!(monitor.check(&sim), Ok(()));
    sim.particles.strain = vec![0.0, -1.0];
    match monitor.check(&sim) {
        Err(Error::Diverged {
            particle: Some(1),
            cause: DivergenceCause::StrainLimit { strain },
            ..
        }) => assert_eq!(strain, -1.0),
        other => panic!("expected the strain limit at particle 1, got {other:?}"),
    }

    // Above the critical step: the CFL warning, recorded at once.
    let above = StabilityMonitor::new(&sim, 0.34).unwrap();
    match above.warnings() {
        [w @ Warning::TimeStepAboveCritical {
            dt,
            critical_dt,
            critical_courant,
        }] => {
            assert_eq!((*dt, *critical_courant), (0.34, 1.65));
            assert!((critical_dt - 0.33).abs() < 1e-15);
            assert!(
                w.to_string()
                    .contains("dt = 3.4e-1 is above the critical step"),
                "{w}"
            );
        }
        other => panic!("expected one CFL warning, got {other:?}"),
    }
}

/// Thesis §5.2: negative lumped masses do not stop a run; the monitor keeps
/// one warning, from the first step that had one, with the latest count and
/// the most negative mass.
#[test]
fn the_monitor_keeps_one_negative_mass_warning_from_its_first_step() {
    let mut sim = unit_bar(Method::MpmP2, 1, 2);
    let mut monitor = StabilityMonitor::new(&sim, 1e-3).unwrap();
    monitor.check(&sim).unwrap();
    assert!(monitor.warnings().is_empty(), "no negative mass yet");
    (sim.diagnostics.steps, sim.diagnostics.negative_mass_steps) = (3, 1);
    sim.diagnostics.min_lumped_mass = -0.25;
    monitor.check(&sim).unwrap();
    (sim.diagnostics.steps, sim.diagnostics.negative_mass_steps) = (5, 2);
    sim.diagnostics.min_lumped_mass = -0.5;
    monitor.check(&sim).unwrap();
    let expected = Warning::NegativeLumpedMass {
        first_step: 3,
        steps: 2,
        min_lumped_mass: -0.5,
    };
    assert_eq!(monitor.warnings(), &[expected.clone()][..]);
    assert_eq!(
        expected.to_string(),
        "negative lumped masses in 2 steps from step 3 (min -5e-1; thesis §5.2)"
    );
}

/// The check that ends every step: the first particle with a non-finite
/// position, velocity or stress, or a volume ≤ 0, is a
/// `NonPhysicalParticle` (naming whether negative masses came before);
/// otherwise the first particle outside [a, b] is `ParticleLeftGrid`. A
/// particle exactly on an end of the grid is inside.
#[test]
fn the_step_check_names_the_first_non_physical_particle_then_the_first_outside() {
    let mut sim = unit_bar(Method::Mpm, 2, 3);
    sim.particles.x = vec![0.0, 0.5, 1.0];
    assert_eq!(
        sim.check_particles_are_physical(),
        Ok(()),
        "both ends are inside"
    );

    let non_physical = |sim: &Simulation| match sim.check_particles_are_physical() {
        Err(Error::NonPhysicalParticle {
            particle,
            negative_masses,
            ..
        }) => (particle, negative_masses),
        other => panic!("expected a non-physical particle, got {other:?}"),
    };
    // One bad field at a time, each on its own.
    let clean = sim.particles.clone();
    for (field, bad) in [
        ("x", f64::NAN),
        ("v", f64::INFINITY),
        ("stress", f64::NEG_INFINITY),
        ("volume", 0.0),
        ("volume", -0.1),
    ] {
        sim.particles = clean.clone();
        let target = match field {
            "x" => &mut sim.particles.x,
            "v" => &mut sim.particles.velocity,
            "stress" => &mut sim.particles.stress,
            _ => &mut sim.particles.volume,
        };
        target[1] = bad;
        target[2] = bad;
        assert_eq!(non_physical(&sim), (1, false), "{field} = {bad}");
    }
    // Two failures in one particle are still found (the check's first,
    // vectorised pass ORs the failures; an XOR would cancel a pair).
    for (x, v, volume) in [
        (f64::INFINITY, 0.0, 1.0 / 3.0),
        (f64::NEG_INFINITY, 0.0, 1.0 / 3.0),
        (2.0, 0.0, -0.1),
        (-1.0, 0.0, -0.1),
        (-1.0, f64::NAN, 1.0 / 3.0),
        (0.5, f64::NAN, 0.0),
    ] {
        sim.particles = clean.clone();
        (
            sim.particles.x[1],
            sim.particles.velocity[1],
            sim.particles.volume[1],
        ) = (x, v, volume);
        assert_eq!(
            non_physical(&sim),
            (1, false),
            "x = {x}, v = {v}, V = {volume}"
        );
    }
    // Every particle failing the same way is found too (the filter must
    // not depend on a healthy particle to trigger the exact pass).
    for field in ["x", "stress", "volume", "left", "right"] {
        sim.particles = clean.clone();
        let p = &mut sim.particles;
        match field {
            "x" => p.x.fill(f64::NAN),
            "stress" => p.stress.fill(f64::NAN),
            "volume" => p.volume.fill(0.0),
            "left" => p.x = vec![-1.0, -2.0, -3.0],
            _ => p.x = vec![2.0, 3.0, 4.0],
        }
        match sim.check_particles_are_physical() {
            Err(Error::NonPhysicalParticle { particle: 0, .. }) => {
                assert!(["x", "stress", "volume"].contains(&field))
            }
            Err(Error::ParticleLeftGrid { particle: 0, .. }) => {
                assert!(["left", "right"].contains(&field))
            }
            other => panic!("every particle's {field} bad: {other:?}"),
        }
    }
    sim.particles = clean.clone();
    sim.particles.x[1] = f64::NAN;
    sim.diagnostics.negative_mass_steps = 2;
    assert_eq!(non_physical(&sim), (1, true));

    // Outside: the first particle beyond either end, after the physical check.
    sim.particles = clean.clone();
    for (x, first) in [
        ([0.5, 0.0f64.next_down(), -1.0], 1),
        ([0.5, 1.0f64.next_up(), 2.0], 1),
        ([-1.0, 0.5, 2.0], 0),
        // Both ends are inside while another particle is out.
        ([0.0, 1.0, 2.0], 2),
        ([1.0, 0.0, -1.0], 2),
    ] {
        sim.particles.x = x.to_vec();
        match sim.check_particles_are_physical() {
            Err(Error::ParticleLeftGrid { particle, a, b, .. }) => {
                assert_eq!((particle, a, b), (first, 0.0, 1.0), "{x:?}");
            }
            other => panic!("expected particle {first} outside for {x:?}, got {other:?}"),
        }
    }
    sim.particles.stress[2] = f64::NAN;
    assert_eq!(non_physical(&sim), (2, true), "non-physical comes first");
}

/// Issue #37: the 2D run is watched by the 1D run's monitor. Its energy is
/// Σ ½ m_p |v_p|²; above ENERGY_GROWTH_BOUND × (initial kinetic energy +
/// the loads' work) the run stops with the same typed error as in 1D,
/// naming the step, the time and the fastest particle. There is no strain
/// limit in 2D (a finite-strain solid; the step refuses det F ≤ 0).
#[test]
fn the_2d_monitor_stops_above_the_energy_budget_and_names_the_fastest_particle() {
    use hompm::mpm::monitor::{Watched, ENERGY_GROWTH_BOUND};
    use hompm::mpm2d::monitor::{kinetic_energy, stability_monitor};
    let scene = hompm::scenes::aligned_vibration::parameters("mls-paper-e1e7").unwrap();
    let method = hompm::scenes::aligned_vibration::AlignedMethod::bsmpm(2);
    let mut sim = scene.simulation(method, 2, 2, 1.0).unwrap();
    let p = &sim.particles;
    let by_hand: f64 = (0..p.len())
        .map(|k| 0.5 * p.mass[k] * (p.velocity[k][0].powi(2) + p.velocity[k][1].powi(2)))
        .sum();
    assert_eq!(kinetic_energy(&sim), by_hand);
    assert!(by_hand > 0.0, "the aligned vibration starts moving");
    let work = 3.0 * by_hand;
    let mut monitor = stability_monitor(&sim, work);
    assert_eq!(
        monitor.energy_budget(),
        ENERGY_GROWTH_BOUND * (by_hand + work)
    );
    assert!(monitor.warnings().is_empty());
    assert_eq!(monitor.check_watched(&sim), Ok(()));

    // Particle 5 alone carries 40 × the initial energy: above the budget of 40×.
    let m5 = sim.particles.mass[5];
    let speed = (2.0 * 40.0 * by_hand / m5).sqrt();
    for v in sim.particles.velocity.iter_mut() {
        *v = [0.0, 0.0];
    }
    sim.particles.velocity[5] = [0.0, speed * 0.999];
    assert_eq!(
        monitor.check_watched(&sim),
        Ok(()),
        "below the budget the run goes on"
    );
    sim.particles.velocity[5] = [0.0, speed * 1.001];
    sim.steps = 7;
    sim.time = 7e-5;
    match monitor.check_watched(&sim) {
        Err(Error::Diverged {
            step: 7,
            time,
            particle: Some(5),
            cause:
                DivergenceCause::EnergyGrowth {
                    energy,
                    budget,
                    bound,
                },
        }) => {
            assert_eq!(time, 7e-5);
            assert_eq!(
                (energy, budget, bound),
                (kinetic_energy(&sim), 40.0 * by_hand, ENERGY_GROWTH_BOUND)
            );
        }
        other => panic!("expected energy growth at particle 5, got {other:?}"),
    }
    // A large deformation alone is no divergence in 2D.
    sim.particles.velocity[5] = [0.0, 0.0];
    sim.particles.deformation[2] = nalgebra::Matrix2::new(3.0, 0.0, 0.0, 0.5);
    assert_eq!(sim.strain_at_limit(), None);
    assert_eq!(monitor.check_watched(&sim), Ok(()));
}

/// Issue #37: `hompm run aligned-vibration` goes through the monitor with
/// progress after each step, as the 1D run; its loads' work is the
/// manufactured body force's bound (total mass × 2 max|b| × L√2), which
/// grows with the mass and is at least what any sampled b gives.
#[test]
fn the_2d_run_reports_progress_every_step_and_budgets_the_body_forces_work() {
    let scene = hompm::scenes::aligned_vibration::parameters("mls-paper-e1e7").unwrap();
    let setup = hompm::oracle::setup::Setup2d {
        scene,
        set_name: "mls-paper-e1e7",
        method: hompm::scenes::aligned_vibration::AlignedMethod::bsmpm(2),
        cells: 2,
        per_side: 2,
        dt: 1e-5,
        steps: 6,
        conventions: hompm::mpm::conventions::Conventions::MLS_PAPER,
    };
    let mut seen = Vec::new();
    let run = hompm::oracle::run::run_2d_observed(
        &setup,
        &mut hompm::mpm2d::step::NoObserver2d,
        &mut |k| seen.push(k),
    )
    .unwrap();
    assert_eq!(seen, [1, 2, 3, 4, 5, 6]);
    assert!(run.warnings.is_empty());
    assert_eq!(run.simulation.steps, 6);

    let w1 = scene.work_bound(1.0).unwrap();
    assert_eq!(scene.work_bound(3.0).unwrap(), 3.0 * w1);
    let period = 2.0 * scene.length / scene.wave_speed();
    for (x, y, t) in [(0.25, 0.5, 0.25), (0.125, 0.875, 0.5), (0.75, 0.25, 0.75)] {
        let b = scene
            .body_force([x * scene.length, y * scene.length], t * period)
            .unwrap();
        let sampled = 2.0 * b[0].hypot(b[1]) * scene.length * std::f64::consts::SQRT_2;
        assert!(w1 >= sampled, "{w1} < {sampled} at ({x}, {y}, {t})");
    }
    // The grid's own samples (X on multiples of L/64, t of T/64) give it exactly.
    let b = |x: f64, y: f64, t: f64| {
        let f = scene.body_force([x, y], t).unwrap();
        f[0].hypot(f[1])
    };
    let mut largest = 0.0f64;
    for i in 0..65 {
        for j in 0..65 {
            for k in 0..65 {
                let at = |n: usize, span: f64| span * n as f64 / 64.0;
                largest = largest.max(b(at(i, scene.length), at(j, scene.length), at(k, period)));
            }
        }
    }
    assert_eq!(w1, 2.0 * largest * scene.length * std::f64::consts::SQRT_2);
}

/// The work bound's samples are kept per parameter set for the process
/// (`AlignedVibration::work_bound`): two sets that differ in one parameter
/// each get their own bound, the one their own 65³ samples give, whichever
/// was asked first, and asking again gives the same bits.
#[test]
fn work_bound_is_sampled_for_each_parameter_set() {
    use hompm::scenes::aligned_vibration::{parameters, SolutionForm};
    let paper = parameters("mls-paper-e1e7").unwrap();
    let axis_aligned = hompm::scenes::aligned_vibration::AlignedVibration {
        solution: SolutionForm::AxisAligned,
        ..paper
    };
    let stiffer = parameters("mls-paper-e1e8").unwrap();
    // A side other than 1 m, a set of its own.
    let smaller = hompm::scenes::aligned_vibration::AlignedVibration {
        length: 2.0,
        ..paper
    };
    let reference = |scene: &hompm::scenes::aligned_vibration::AlignedVibration| {
        let period = 2.0 * scene.length / scene.wave_speed();
        let at = |n: usize, span: f64| span * n as f64 / 64.0;
        let mut largest = 0.0f64;
        for i in 0..65 {
            for j in 0..65 {
                for k in 0..65 {
                    let x0 = [at(i, scene.length), at(j, scene.length)];
                    let f = scene.body_force(x0, at(k, period)).unwrap();
                    largest = largest.max(f[0].hypot(f[1]));
                }
            }
        }
        2.0 * largest * scene.length * std::f64::consts::SQRT_2
    };
    let bounds: Vec<f64> = [paper, axis_aligned, stiffer, axis_aligned, smaller]
        .iter()
        .map(|s| s.work_bound(1.0).unwrap())
        .collect();
    assert_eq!(bounds[1].to_bits(), bounds[3].to_bits());
    assert_ne!(bounds[0], bounds[1]);
    assert_ne!(bounds[0], bounds[2]);
    assert_eq!(bounds[1], reference(&axis_aligned));
    assert_eq!(bounds[2], reference(&stiffer));
    assert_eq!(bounds[4], reference(&smaller));
}
