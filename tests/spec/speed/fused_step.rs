//! Issue #39: `Simulation::step` runs the book's step in three fused
//! particle loops (src/mpm/musl/fused.rs) whenever nobody observes it; an
//! observed step (`hompm trace`, the planted defects of `hompm check`)
//! runs one pass per equation. Both must compute the same bits.

use hompm::mpm::grid::Method;
use hompm::mpm::monitor::StabilityMonitor;
use hompm::mpm::musl::{Simulation, StepObserver, StepPoint};
use hompm::scenes::{column, vibrating_bar, Discretisation};
use hompm::Result;

/// An observer that looks at every point of the step and changes nothing:
/// it makes `step_observed` take the pass per equation.
struct Looks;

impl StepObserver for Looks {
    fn observe(&mut self, _: StepPoint, _: &mut Simulation) -> Result<()> {
        Ok(())
    }
}

/// Everything a step leaves, with every bit (`{:?}` prints each f64 so
/// that it reads back to the same bits, −0.0 included).
fn state(sim: &Simulation) -> String {
    format!(
        "{:?}\n{:?}\n{:?}\n{:?}",
        sim.time,
        sim.particles,
        sim.diagnostics,
        sim.workspace()
    )
}

/// `steps` steps both ways from the same start; the fused run's first
/// differing line, if any, is in the panic message.
fn assert_same_bits(fused: &mut Simulation, passes: &mut Simulation, dt: f64, steps: usize) {
    for k in 0..steps {
        let a = fused.step(dt);
        let b = passes.step_observed(dt, &mut Looks);
        assert_eq!(
            format!("{a:?}"),
            format!("{b:?}"),
            "step {k}: results differ"
        );
        if a.is_err() {
            break;
        }
    }
    // The fused step keeps Δε_p in a register and leaves none in the
    // workspace (`StepWorkspace::strain_increment`); the passes' Δε_p shows
    // in σ_p, V_p, ρ_p and ε_p, compared below.
    if fused.step_is_fused() {
        assert!(fused.workspace().strain_increment.is_empty());
        passes.workspace_mut().strain_increment.clear();
    }
    let (a, b) = (state(fused), state(passes));
    if a != b {
        let line = a.lines().zip(b.lines()).position(|(x, y)| x != y);
        panic!("the fused and the observed step differ (line {line:?} of the state)");
    }
}

fn bar(set: &str, method: Method, cells: usize) -> Simulation {
    let p = vibrating_bar::parameters(set).unwrap();
    p.simulation(&Discretisation::direct(method, cells, 4))
        .unwrap()
}

fn column_of(set: &str, method: Method, cells: usize) -> Simulation {
    let p = column::parameters(set).unwrap();
    p.simulation(&Discretisation::direct(method, cells, 3))
        .unwrap()
}

/// Book Eqs. (4.5)–(4.18), fused and pass by pass, on the vibrating bar
/// with P1, P2 and B-splines of degree 2 and 3 (stencil widths 2, 3, 3, 4):
/// the particles, every monitor and the step's buffers agree to the bit
/// after 400 steps, and the step taken is the fused one (it is not
/// observed).
#[test]
fn the_fused_step_computes_the_bits_of_the_step_pass_by_pass_on_the_bar() {
    for method in [
        Method::Mpm,
        Method::MpmP2,
        Method::Bsmpm { degree: 2 },
        Method::Bsmpm { degree: 3 },
    ] {
        let mut fused = bar("thesis-table-4.1", method, 16);
        let mut passes = bar("thesis-table-4.1", method, 16);
        assert!(fused.step_is_fused(), "{method:?}");
        assert_same_bits(&mut fused, &mut passes, 1e-5, 400);
        assert!(fused.particles.displacement.iter().any(|u| u.abs() > 1e-9));
    }
}

/// The loads and laws of the columns, fused and pass by pass: gravity
/// (thesis Table 4.3), the large-strain law (Table 4.4), a traction on the
/// top (Table 8.1) and the TLS paper's ramped gravity (Table 6), each
/// with P1 and quadratic B-splines and Dirichlet DOFs; the same bits.
#[test]
fn the_fused_step_computes_the_bits_of_the_step_pass_by_pass_under_loads_and_laws() {
    for set in [
        "thesis-table-4.3",
        "thesis-table-4.4",
        "thesis-table-8.1",
        "tls-table-6",
    ] {
        for method in [Method::Mpm, Method::Bsmpm { degree: 2 }] {
            let mut fused = column_of(set, method, 8);
            let mut passes = column_of(set, method, 8);
            assert!(fused.step_is_fused(), "{set} {method:?}");
            assert_same_bits(&mut fused, &mut passes, 1e-4, 300);
            assert!(fused.diagnostics.max_abs_strain > 0.0, "{set}");
        }
    }
}

/// Gravity at the nodes, f_i = m_i g (the other codes' convention,
/// `BodyForceAt::Nodes`), fused and pass by pass on the gravity column with
/// P1 and quadratic B-splines: the same bits, and the body force is there
/// (the particles fall further than under half of it).
#[test]
fn the_fused_step_computes_the_bits_of_the_passes_with_gravity_at_the_nodes() {
    use hompm::mpm::conventions::BodyForceAt;
    for method in [Method::Mpm, Method::Bsmpm { degree: 2 }] {
        let at_nodes = |s: &mut Simulation| s.settings.conventions.body_force = BodyForceAt::Nodes;
        let mut fused = column_of("thesis-table-4.3", method, 8);
        let mut passes = column_of("thesis-table-4.3", method, 8);
        at_nodes(&mut fused);
        at_nodes(&mut passes);
        assert!(fused.step_is_fused(), "{method:?}");
        assert_same_bits(&mut fused, &mut passes, 1e-4, 300);
        let sag: f64 = fused.particles.displacement.iter().sum();
        assert!(sag < 0.0, "{method:?}: the column does not sag ({sag})");
    }
}

/// The crossing monitor counts from where a particle was, also when
/// something moved it between two steps (a user, an oracle's planted
/// state): the fused step recounts the breaks below a particle it did not
/// move itself, as the pass per equation does; the same crossings.
#[test]
fn the_fused_step_counts_the_crossings_of_particles_moved_between_steps() {
    let mut fused = bar("thesis-table-4.1", Method::Mpm, 16);
    let mut passes = bar("thesis-table-4.1", Method::Mpm, 16);
    assert_same_bits(&mut fused, &mut passes, 1e-5, 20);
    let (h, (lo, hi)) = (fused.grid.cell_size(), fused.grid.domain());
    let mut moved_across = 0;
    for sim in [&mut fused, &mut passes] {
        // Inner particles moved by ±0.3 cells, across a break for some.
        moved_across = 0;
        for (k, x) in sim.particles.x.iter_mut().enumerate() {
            if *x > lo + h && *x < hi - h {
                let before = sim.grid.breaks_at_or_below(*x);
                *x += 0.3 * h * ((k % 3) as f64 - 1.0);
                moved_across += sim.grid.breaks_at_or_below(*x).abs_diff(before);
            }
        }
    }
    // Those moves are not the step's crossings: a count from the stale
    // positions would include them.
    assert!(moved_across > 0);
    let before = fused.diagnostics.grid_crossings;
    assert_same_bits(&mut fused, &mut passes, 1e-5, 20);
    assert_eq!(
        fused.diagnostics.grid_crossings,
        passes.diagnostics.grid_crossings
    );
    assert!(fused.diagnostics.grid_crossings < before + moved_across);
}

/// Thesis §3.3's crossing monitor in both shapes of the step, where
/// particles do cross: given v_p = c sin(π (x_p − a)/(b − a)), c = 0.3 cells
/// per step, the middle particles cross a break every few steps. Both
/// shapes count the same crossings (`assert_same_bits` compares every
/// `RunDiagnostics` entry), and there are some.
#[test]
fn both_shapes_of_the_step_count_the_same_crossings_of_moving_particles() {
    let dt = 1e-5;
    let mut fused = bar("thesis-table-4.1", Method::Mpm, 16);
    let mut passes = bar("thesis-table-4.1", Method::Mpm, 16);
    let (h, (a, b)) = (fused.grid.cell_size(), fused.grid.domain());
    for sim in [&mut fused, &mut passes] {
        let p = &mut sim.particles;
        for (v, &x) in p.velocity.iter_mut().zip(&p.x) {
            *v = 0.3 * h / dt * (std::f64::consts::PI * (x - a) / (b - a)).sin();
        }
    }
    let before = passes.diagnostics.grid_crossings;
    assert_same_bits(&mut fused, &mut passes, dt, 8);
    assert!(passes.diagnostics.grid_crossings > before);
}

/// With the diagnostics off the fused step records nothing either, and the
/// particles still agree with the pass-by-pass step.
#[test]
fn the_fused_step_without_diagnostics_moves_the_particles_as_the_passes_do() {
    let mut fused = bar("thesis-table-4.1", Method::Bsmpm { degree: 2 }, 16).without_diagnostics();
    let mut passes = bar("thesis-table-4.1", Method::Bsmpm { degree: 2 }, 16).without_diagnostics();
    assert_same_bits(&mut fused, &mut passes, 1e-5, 200);
    assert_eq!(fused.diagnostics.max_abs_strain, 0.0);
}

/// A step that fails fails the same way fused and pass by pass: a particle
/// thrown out of the grid (`ParticleLeftGrid`), one with a NaN stress and
/// one with a zero volume (`NonPhysicalParticle`: the screen asks V_p > 0,
/// not ≥), with the same error, step and particle.
#[test]
fn the_fused_step_fails_where_and_as_the_step_pass_by_pass_fails() {
    let planted: [fn(&mut Simulation); 3] = [
        |sim| sim.particles.velocity[5] = 1e7,
        |sim| sim.particles.stress[9] = f64::NAN,
        |sim| sim.particles.volume[7] = 0.0,
    ];
    for plant in planted {
        let mut fused = bar("thesis-table-4.1", Method::Mpm, 16);
        let mut passes = bar("thesis-table-4.1", Method::Mpm, 16);
        plant(&mut fused);
        plant(&mut passes);
        let a = fused.step(1e-5);
        let b = passes.step_observed(1e-5, &mut Looks);
        assert!(a.is_err(), "{a:?}");
        assert_eq!(format!("{a:?}"), format!("{b:?}"));
    }
}

/// The steps map the traction only when some particle carries one
/// (`Particles::has_traction`, a scan without an early exit): ±0 are
/// none; a subnormal, a NaN or a value on the last particle alone is one,
/// and so are two.
#[test]
fn a_traction_is_mapped_when_any_particle_carries_a_non_zero_one() {
    let mut p = hompm::mpm::particles::Particles::uniform(0.0, 1.0, 37, 1000.0).unwrap();
    assert!(!p.has_traction());
    p.traction[3] = -0.0;
    assert!(!p.has_traction(), "−0 is no traction");
    for value in [f64::from_bits(1), -1e300, f64::NAN, f64::INFINITY] {
        let mut q = p.clone();
        q.traction[36] = value;
        assert!(q.has_traction(), "{value:e} on the last particle");
        let mut q = p.clone();
        q.traction[0] = value;
        assert!(q.has_traction(), "{value:e} on the first particle");
        q.traction[20] = -1.0;
        assert!(q.has_traction(), "{value:e} and −1 on two particles");
    }
}

/// `step_summarised` reports the energy and the largest strain that a pass
/// over the particles finds after the step (`Simulation::energy`, the same
/// bits), and the monitor's verdict on it is `check`'s.
#[test]
fn the_step_summary_holds_the_energy_and_strain_a_pass_over_the_particles_finds() {
    let mut sim = column_of("thesis-table-4.4", Method::Bsmpm { degree: 2 }, 8);
    let mut monitor = StabilityMonitor::new(&sim, 1e-4).unwrap();
    let mut other = monitor.clone();
    for _ in 0..200 {
        let summary = sim.step_summarised(1e-4).unwrap();
        assert_eq!(summary.energy.to_bits(), sim.energy().to_bits());
        let largest = sim
            .particles
            .strain
            .iter()
            .map(|e| e.abs())
            .fold(0.0, f64::max);
        assert_eq!(summary.max_abs_strain.to_bits(), largest.to_bits());
        assert_eq!(
            format!("{:?}", monitor.check_step(&sim, &summary)),
            format!("{:?}", other.check(&sim))
        );
    }
    assert!(sim.energy() > 0.0);
}

/// The fused loops serve the book's step only: another code's conventions,
/// a reconstruction, a consistent mass, DDMPM's dual domain or the
/// neo-Hookean law take the pass per equation.
#[test]
fn only_the_book_s_direct_lumped_step_is_fused() {
    use hompm::mpm::conventions::{Positions, Scheme, Transfer};
    use hompm::mpm::grid::NodeIntegrals;
    use hompm::mpm::mapping::{ConsistentSolver, Mapping, MassMatrix};
    use hompm::mpm::musl::Constitutive;
    use hompm::scenes::manufactured_strip;
    let p = vibrating_bar::parameters("thesis-table-4.1").unwrap();
    let sim = |d: &Discretisation| p.simulation(d).unwrap();
    assert!(sim(&Discretisation::direct(Method::Mpm, 8, 2)).step_is_fused());
    let tls = Discretisation::new(Method::Mpm, Mapping::Tls, MassMatrix::Lumped, 8, 2);
    assert!(!sim(&tls).step_is_fused());
    let consistent = MassMatrix::Consistent(ConsistentSolver::Cholesky);
    let spline = Discretisation::new(
        Method::Bsmpm { degree: 2 },
        Mapping::Direct,
        consistent,
        8,
        2,
    );
    assert!(!sim(&spline).step_is_fused());
    let ddmpm = Method::Ddmpm {
        node_integrals: NodeIntegrals::Exact,
    };
    assert!(!sim(&Discretisation::direct(ddmpm, 8, 2)).step_is_fused());
    let book = || sim(&Discretisation::direct(Method::Mpm, 8, 2));
    let changed: [fn(&mut Simulation); 7] = [
        |s| s.settings.conventions.scheme = Scheme::Usl,
        |s| s.settings.conventions.transfer = Transfer::Pic,
        |s| s.settings.conventions.positions = Positions::Grid,
        |s| s.settings.force_mapping = Mapping::Tls,
        |s| s.settings.consistent_acceleration = true,
        |s| s.settings.constitutive = Constitutive::NeoHookean,
        |s| s.settings.mass = MassMatrix::Consistent(ConsistentSolver::Cholesky),
    ];
    for change in changed {
        let mut s = book();
        change(&mut s);
        assert!(!s.step_is_fused(), "{:?}", s.settings);
    }
    let strip = manufactured_strip::parameters("mls-paper-code")
        .unwrap()
        .placed(8);
    let field = strip.simulation(&Discretisation::direct(Method::Bsmpm { degree: 2 }, 8, 5));
    let mut with_field = book();
    with_field.settings.body_force = field.unwrap().settings.body_force;
    assert!(with_field.settings.body_force.is_some());
    assert!(!with_field.step_is_fused());
}

/// The monitor's verdict from a step summary is `check`'s when the run
/// diverges too: an energy above the budget stops the run with the same
/// error, and a largest strain at the limit (1) sends the check to the
/// particles, which names the first one there; below the limit the
/// summary answers for every particle.
#[test]
fn the_monitor_stops_a_summarised_step_where_check_stops_it() {
    use hompm::mpm::monitor::STRAIN_LIMIT;
    use hompm::mpm::musl::StepSummary;
    let mut sim = bar("thesis-table-4.1", Method::Mpm, 16);
    let summary = sim.step_summarised(1e-5).unwrap();
    let tight = StabilityMonitor::with_budget(0.5 * summary.energy, Vec::new());
    let (mut a, mut b) = (tight.clone(), tight);
    let by_summary = a.check_step(&sim, &summary);
    assert!(by_summary.is_err());
    assert_eq!(format!("{by_summary:?}"), format!("{:?}", b.check(&sim)));
    let roomy = StabilityMonitor::with_budget(1e30, Vec::new());
    sim.particles.strain[3] = -1.5;
    let at_limit = StepSummary {
        energy: summary.energy,
        max_abs_strain: STRAIN_LIMIT,
    };
    let (mut a, mut b) = (roomy.clone(), roomy.clone());
    let by_summary = a.check_step(&sim, &at_limit);
    assert!(
        format!("{by_summary:?}").contains("particle: Some(3)"),
        "{by_summary:?}"
    );
    assert_eq!(format!("{by_summary:?}"), format!("{:?}", b.check(&sim)));
    let below = StepSummary {
        max_abs_strain: 0.5,
        ..at_limit
    };
    assert!(roomy.clone().check_step(&sim, &below).is_ok());
}

/// The lumped projection's record with no active DOF (no mass reached
/// any node): the diagonal ratio is 0, not min/max of an empty set (book
/// Eq. 4.10's diagnostics, thesis §7.2.4).
#[test]
fn a_projection_that_reaches_no_node_records_a_diagonal_ratio_of_zero() {
    use hompm::mpm::mapping::{
        diagnose_projection, solve_projection, MappingWorkspace, MassMatrix,
    };
    let sim = bar("thesis-table-4.1", Method::Mpm, 4);
    let mut ws = MappingWorkspace::new(&sim.grid, 0).unwrap();
    let iterations = solve_projection(None, MassMatrix::Lumped, &mut ws).unwrap();
    let record = diagnose_projection(None, iterations, &mut ws);
    assert_eq!(record.diagonal_ratio, 0.0);
    assert_eq!(record.grid_mass, 0.0);
}

/// A lumped projection whose momenta or lumped masses are fewer than its
/// DOFs is an error naming the counts, not a panic (book Eq. 4.10).
#[test]
fn a_lumped_projection_with_too_few_masses_is_an_error() {
    use hompm::mpm::mapping::{solve_projection, MappingWorkspace, MassMatrix};
    let sim = bar("thesis-table-4.1", Method::Mpm, 4);
    let mut ws = MappingWorkspace::new(&sim.grid, 0).unwrap();
    ws.diagonal = vec![1.0; 3];
    ws.momentum = vec![2.0; 3];
    ws.lumped = vec![4.0; 3];
    solve_projection(None, MassMatrix::Lumped, &mut ws).unwrap();
    assert_eq!(ws.velocity, [0.5; 3]);
    ws.lumped.truncate(2);
    let e = solve_projection(None, MassMatrix::Lumped, &mut ws).unwrap_err();
    assert!(
        e.to_string()
            .contains("3 DOFs but 3 momenta and 2 lumped masses"),
        "{e}"
    );
}

use proptest::prelude::*;

proptest! {
    /// The fused loops and the projection's diagnosis keep their running
    /// extremes by one comparison (`running_max`, `running_min`); for a
    /// running value that is not NaN and anything it meets (NaN, ±∞,
    /// subnormals; zeros of one sign, as |v| and M_ii ≠ 0 are) they are
    /// `f64::max` and `f64::min` bit for bit.
    #[test]
    fn running_extremes_are_f64_max_and_min(
        running in proptest::num::f64::ANY.prop_filter("not NaN", |r| !r.is_nan()),
        x in proptest::num::f64::ANY,
    ) {
        use hompm::mpm::mapping::{running_max, running_min};
        // Zeros of opposite signs are the one case f64::max leaves open.
        prop_assume!(!(running == 0.0 && x == 0.0 && running.is_sign_negative() != x.is_sign_negative()));
        prop_assert_eq!(running_max(running, x).to_bits(), f64::max(running, x).to_bits());
        prop_assert_eq!(running_min(running, x).to_bits(), f64::min(running, x).to_bits());
    }

    /// The fused step's physical screen tests finiteness by arithmetic
    /// (`both_finite`: (a − a) + (b − b) = 0); for every pair of doubles,
    /// ±∞, NaN, subnormals and both zeros among them, it is
    /// `a.is_finite() && b.is_finite()`.
    #[test]
    fn both_finite_is_is_finite_of_both(
        a in prop_oneof![proptest::num::f64::ANY, Just(f64::INFINITY), Just(f64::NEG_INFINITY), Just(f64::NAN), Just(f64::MAX), Just(-0.0)],
        b in prop_oneof![proptest::num::f64::ANY, Just(f64::INFINITY), Just(f64::NEG_INFINITY), Just(f64::NAN), Just(f64::MAX), Just(-0.0)],
    ) {
        use hompm::mpm::mapping::both_finite;
        prop_assert_eq!(both_finite(a, b), a.is_finite() && b.is_finite(), "a = {}, b = {}", a, b);
    }

    /// The fused step takes P1's lumped mass M^L_i = Σ m_p φ_i Σ_j φ_j as
    /// the nodal mass m_i = Σ m_p φ_i: it needs Σ_j φ_j = 1 exactly, i.e.
    /// fl(fl(1 − ξ) + ξ) = 1, for the shape functions P1 elements evaluate,
    /// at any point of any mesh (and for ξ itself anywhere in [0, 1],
    /// subnormals and the ties at 2⁻⁵⁴ included).
    #[test]
    fn p1_shape_functions_sum_to_exactly_one(
        xi in prop_oneof![0.0..=1.0f64, (0u64..=1u64 << 62).prop_map(|b| f64::from_bits(b).min(1.0))],
        a in -1e3..1e3f64,
        length in 1e-6..1e4f64,
        elements in 1usize..5000,
        t in 0.0..=1.0f64,
    ) {
        use hompm::lagrange::{LagrangeBasis, LagrangeOrder};
        prop_assert_eq!((1.0 - xi) + xi, 1.0);
        let basis = LagrangeBasis::new(a, a + length, elements, LagrangeOrder::Linear).unwrap();
        let x = (a + t * length).min(a + length);
        let (mut values, mut gradients) = ([0.0; 2], [0.0; 2]);
        basis.evaluate_of_width::<2>(x, &mut values, &mut gradients).unwrap();
        prop_assert_eq!(values[0] + values[1], 1.0, "x = {}", x);
    }
}
