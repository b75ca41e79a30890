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
use hompm::mpm::musl::{
    Constitutive, GravityRamp, RampTimeLevel, Settings, Simulation, StepObserver, StepPoint,
};
use hompm::mpm::particles::Particles;

const DT: f64 = 0.1;

fn two_particles(constitutive: Constitutive) -> Simulation {
    two_particles_configured(constitutive, |_, _| {})
}

/// The table's two particles before any step (traction not set).
fn table_particles() -> Particles {
    Particles::new(
        vec![0.5, 1.25],
        vec![1.0, 0.5],
        vec![2.0, 4.0],
        vec![1.0, -2.0],
        vec![3.0, -1.0],
    )
    .unwrap()
}

/// The table's two particles after one step, with `configure` applied to
/// the particles and settings before the step.
fn two_particles_configured(
    constitutive: Constitutive,
    configure: impl FnOnce(&mut Particles, &mut Settings),
) -> Simulation {
    two_particles_on(2, constitutive, configure)
}

/// The same on `cells` unit cells [0, cells]: nodes beyond 2 get no mass.
fn two_particles_on(
    cells: usize,
    constitutive: Constitutive,
    configure: impl FnOnce(&mut Particles, &mut Settings),
) -> Simulation {
    let mut sim = before_the_step(cells, constitutive, configure);
    sim.step(DT).unwrap();
    sim
}

/// The table's two particles on `cells` unit cells, configured, before the step.
fn before_the_step(
    cells: usize,
    constitutive: Constitutive,
    configure: impl FnOnce(&mut Particles, &mut Settings),
) -> Simulation {
    let grid = Grid::new(Method::Mpm, 0.0, cells as f64, cells).unwrap();
    let mut p = table_particles();
    p.traction = vec![0.0, 0.5];
    let settings = Settings {
        force_mapping: Mapping::Direct,
        velocity_mapping: Mapping::Direct,
        mass: MassMatrix::Lumped,
        constitutive,
        young: 10.0,
        poisson: 0.0,
        body_force: None,
        gravity: -1.0,
        gravity_ramp: None,
        dirichlet: vec![],
        consistent_acceleration: false,
        tls_density_average: hompm::reconstruct::taylor::CellAverage::Exact,
        conventions: Default::default(),
    };
    let mut settings = settings;
    configure(&mut p, &mut settings);
    Simulation::new(grid, p, settings).unwrap()
}

/// Δε_p (book Eq. 4.14) of the table's step, as the step computes it: read
/// at `StepPoint::Positions`, where `hompm trace` reads it. (A step nobody
/// observes keeps each Δε_p in a register: `StepWorkspace::strain_increment`.)
fn strain_increments_of_the_step() -> Vec<f64> {
    struct AtPositions(Vec<f64>);
    impl StepObserver for AtPositions {
        fn observe(&mut self, point: StepPoint, sim: &mut Simulation) -> hompm::Result<()> {
            if point == StepPoint::Positions {
                self.0 = sim.workspace().strain_increment.clone();
            }
            Ok(())
        }
    }
    let mut sim = before_the_step(2, Constitutive::SmallStrain, |_, _| {});
    let mut seen = AtPositions(Vec::new());
    sim.step_observed(DT, &mut seen).unwrap();
    seen.0
}

fn assert_all(computed: &[f64], expected: &[f64]) {
    assert_eq!(computed.len(), expected.len());
    for (c, e) in computed.iter().zip(expected) {
        assert_relative_eq!(*c, *e, epsilon = 1e-12, max_relative = 1e-12);
    }
}

/// Map rows: book-4.5, book-4.7 — the nodal mass of Eq. (4.7) is the lumped particle mass of Eq. (4.5).
#[test]
fn eq_4_5_lumped_mass_is_the_mass_weighted_basis_sum() {
    // m = [2·½, 2·½ + 2·¾, 2·¼]
    assert_all(
        &two_particles(Constitutive::SmallStrain).workspace().mass,
        &[1.0, 2.5, 0.5],
    );
}

/// Map rows: book-4.6, tls-8 — one equation, printed in two seeds.
#[test]
fn eq_4_6_internal_force_is_stress_times_volume_times_gradient() {
    // σV = 3 and −0.5: f = [3·(−1), 3·1 + (−0.5)(−1), (−0.5)·1]
    let sim = two_particles(Constitutive::SmallStrain);
    assert_all(&sim.workspace().internal_force, &[-3.0, 3.5, -0.5]);
}

/// Map rows: tls-1, thesis-2.4, thesis-2.7, thesis-§3.2-2 — the external force of the governing equation, printed in several seeds; one hand-computed step checks it.
#[test]
fn thesis_3_2_gravity_and_traction_loads() {
    // m g φ: [−1, −1 − 1.5, −0.5]; traction 0.5 φ on particle 1: [0, 0.375, 0.125]
    let sim = two_particles(Constitutive::SmallStrain);
    assert_all(&sim.workspace().gravity_force, &[-1.0, -2.5, -0.5]);
    assert_all(&sim.workspace().traction_force, &[0.0, 0.375, 0.125]);
}

/// Map rows: book-4.1, book-4.8, tls-§3-1, tls-5, thesis-2.6, thesis-2.8, thesis-3.1, thesis-3.2, thesis-§3.2-3 — the momentum balance and its Galerkin form, printed in every 1D seed; the acceleration of one hand-computed step checks them.
#[test]
fn eq_4_8_nodal_acceleration_is_net_force_over_lumped_mass() {
    // a = [(0 − 1 + 3)/1, (0.375 − 2.5 − 3.5)/2.5, (0.125 − 0.5 + 0.5)/0.5]
    let sim = two_particles(Constitutive::SmallStrain);
    assert_all(&sim.workspace().acceleration, &[2.0, -2.25, 0.25]);
}

/// Step 2 with the material-point consistent mass (book Eq. 4.7 before
/// lumping): M^C = Σ_p m_p φ(x_p) φ(x_p)ᵀ
/// = [[½, ½, 0], [½, 1⅝, ⅜], [0, ⅜, ⅛]], singular with two particles on
/// three nodes. With node 0 a Dirichlet DOF, the free DOFs {1, 2} solve
/// [[1⅝, ⅜], [⅜, ⅛]] a = (−5.625, 0.125), the net forces above:
/// a = (−12, 37), and a_0 = 0. On three cells node 3 has no mass: it is
/// left out of the solve too, and its acceleration is 0.
#[test]
fn eq_4_7_consistent_acceleration_solves_the_free_dofs_only() {
    let sim = two_particles_configured(Constitutive::SmallStrain, |_, s| {
        s.consistent_acceleration = true;
        s.dirichlet = vec![0];
    });
    assert_all(&sim.workspace().acceleration, &[0.0, -12.0, 37.0]);
    let sim = two_particles_on(3, Constitutive::SmallStrain, |_, s| {
        s.consistent_acceleration = true;
        s.dirichlet = vec![0];
    });
    assert_all(&sim.workspace().acceleration, &[0.0, -12.0, 37.0, 0.0]);
}

/// Thesis §3.2: traction on every particle, f_i^trac = Σ_p f_p^trac φ_i(x_p):
/// 0.25·(½, ½, 0) + 0.5·(0, ¾, ¼) = (0.125, 0.5, 0.125).
#[test]
fn thesis_3_2_traction_on_every_particle_is_mapped() {
    let sim = two_particles_configured(Constitutive::SmallStrain, |p, _| {
        p.traction = vec![0.25, 0.5];
    });
    assert_all(&sim.workspace().traction_force, &[0.125, 0.5, 0.125]);
}

/// The gravity ramp of the compaction scene: g(t) = g·min(t/t_ramp, 1) for
/// a ramp time t_ramp > 0, and g without a ramp or with t_ramp ≤ 0.
#[test]
fn gravity_ramps_linearly_up_to_its_full_value() {
    let ramped = two_particles_configured(Constitutive::SmallStrain, |_, s| {
        s.gravity_ramp = Some(GravityRamp::over(2.0));
    });
    assert_eq!(ramped.gravity_at(0.5), -0.25);
    assert_eq!(ramped.gravity_at(2.0), -1.0);
    assert_eq!(ramped.gravity_at(3.0), -1.0);
    for ramp in [None, Some(0.0), Some(-0.0), Some(-1.0)] {
        let sim = two_particles_configured(Constitutive::SmallStrain, |_, s| {
            s.gravity_ramp = ramp.map(GravityRamp::over);
        });
        assert_eq!(sim.gravity_at(0.5), -1.0, "{ramp:?}");
    }
}

/// TLS paper Eq. (10) loads the step from tⁿ with (f^ext)^t: a ramp read at
/// the step's start gives the first step no gravity at all, one read at its
/// end gives it g(Δt) = g·Δt/t_ramp, and the nodal gravity force of the
/// step is Σ_p m_p g φ_i with that g.
#[test]
fn a_ramp_loads_the_step_at_its_start_unless_read_at_its_end() {
    let first_step_force = |time_level| {
        let sim = two_particles_configured(Constitutive::SmallStrain, |_, s| {
            s.gravity_ramp = Some(GravityRamp {
                duration: 2.0,
                time_level,
            });
        });
        let total_mass: f64 = sim.particles.mass.iter().sum();
        let force: f64 = sim.workspace().gravity_force.iter().sum();
        (force, total_mass, sim.gravity_in_step(DT))
    };
    let (start, mass, next_start) = first_step_force(RampTimeLevel::StepStart);
    assert_eq!(start, 0.0);
    assert!((next_start - (-DT / 2.0)).abs() < 1e-15, "{next_start}");
    let (end, _, next_end) = first_step_force(RampTimeLevel::StepEnd);
    assert!(
        (end - mass * (-DT / 2.0)).abs() < 1e-14,
        "{end} vs {}",
        mass * -DT / 2.0
    );
    assert!((next_end - (-2.0 * DT / 2.0)).abs() < 1e-15, "{next_end}");
}

/// The particle arrays are public, so a caller may replace the particles
/// between steps: the next step sizes its buffers to the new count and
/// gives what a new simulation of those particles gives.
#[test]
fn a_step_after_the_particles_were_replaced_is_a_fresh_step() {
    let mut sim = two_particles(Constitutive::SmallStrain);
    let three = Particles::new(
        vec![0.2, 0.9, 1.7],
        vec![0.4, 0.5, 0.6],
        vec![1.0, 2.0, 3.0],
        vec![0.5, 0.0, -0.5],
        vec![1.0, -1.0, 2.0],
    )
    .unwrap();
    let grid = Grid::new(Method::Mpm, 0.0, 2.0, 2).unwrap();
    let mut fresh = Simulation::new(grid, three.clone(), sim.settings.clone()).unwrap();
    sim.particles = three;
    sim.step(DT).unwrap();
    fresh.step(DT).unwrap();
    assert_eq!(sim.particles, fresh.particles);
}

/// Map rows: book-4.9, tls-§3.1-1, thesis-§3.1-1, thesis-§3.2-4 — one equation, printed in three seeds.
#[test]
fn eq_4_9_particle_velocity_takes_the_interpolated_acceleration() {
    // v0 = 1 + 0.1(½·2 + ½·(−2.25)), v1 = −2 + 0.1(¾·(−2.25) + ¼·0.25)
    assert_all(
        &two_particles(Constitutive::SmallStrain).particles.velocity,
        &[0.9875, -2.1625],
    );
}

/// Map rows: book-4.10, tls-9, thesis-3.3, thesis-3.4 — one equation, printed in three seeds.
#[test]
fn eq_4_10_nodal_velocity_is_projected_momentum_over_lumped_mass() {
    // p = [2·0.9875·½, 2·0.9875·½ + 2·(−2.1625)·¾, 2·(−2.1625)·¼] over m
    let sim = two_particles(Constitutive::SmallStrain);
    assert_all(
        &sim.workspace().mapping.velocity,
        &[0.9875, -0.9025, -2.1625],
    );
}

/// Map rows: book-4.11, book-4.12, book-4.13, tls-4, thesis-§2.2-1, thesis-§3.2-7 — the three updates of one hand-computed step, printed in three seeds.
#[test]
fn eqs_4_11_to_4_13_displacement_and_position_move_with_the_grid() {
    // Δu_i = 0.1 v_i = [0.09875, −0.09025, −0.21625];
    // Δu_0 = ½(0.09875 − 0.09025), Δu_1 = ¾(−0.09025) + ¼(−0.21625)
    let sim = two_particles(Constitutive::SmallStrain);
    assert_all(&sim.particles.displacement, &[0.00425, -0.12175]);
    assert_all(&sim.particles.x, &[0.50425, 1.12825]);
    assert_all(&sim.particles.x0, &[0.5, 1.25]);
}

/// Map rows: book-4.14, thesis-2.2, thesis-§3.2-5 — one equation, printed in two seeds.
#[test]
fn eq_4_14_strain_increment_is_the_gradient_of_the_displacement_increment() {
    // Δε_0 = −0.09875 − 0.09025, Δε_1 = 0.09025 − 0.21625
    assert_all(&strain_increments_of_the_step(), &[-0.189, -0.126]);
    let sim = two_particles(Constitutive::SmallStrain);
    assert_all(&sim.particles.strain, &[-0.189, -0.126]);
    // The unobserved (fused) step leaves no Δε_p to be taken for its own.
    assert!(sim.step_is_fused() && sim.workspace().strain_increment.is_empty());
}

/// Map rows: book-4.15, tls-2, tls-6 — one equation, printed in two seeds.
#[test]
fn eq_4_15_small_strain_stress_update() {
    // σ = 3 + 10(−0.189), −1 + 10(−0.126)
    assert_all(
        &two_particles(Constitutive::SmallStrain).particles.stress,
        &[1.11, -2.26],
    );
}

/// Map rows: book-4.16, tls-3 — one equation, printed in two seeds.
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

/// Map rows: book-4.18, thesis-2.3 — one equation, printed in two seeds.
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
        poisson: 0.0,
        body_force: None,
        gravity: 0.0,
        ..sim.settings.clone()
    };
    let mut fast = Simulation::new(grid, p, settings).unwrap();
    fast.step(0.1).unwrap();
    assert_relative_eq!(fast.particles.x[0], 1.2, epsilon = 1e-12);
    assert_eq!(fast.diagnostics.grid_crossings, 1);
}

// ---------------------------------------------------------------------------
// The cubic-spline mapping of thesis §7.1–7.2, by hand.
//
// Four P1 cells on [0, 4] (h = 1, ∇φ = ∓1 on the cell's two nodes) and five
// particles given out of order, so that the leftmost is not the first:
//
// | p | x_p  | V_p | σ_p  |
// |---|------|-----|------|
// | 0 | 2.1  | 0.5 | 1    |
// | 1 | 0.9  | 0.6 | −2   |
// | 2 | 3.05 | 0.3 | 0.5  |
// | 3 | 1.6  | 0.5 | 3    |
// | 4 | 2.6  | 0.5 | −1   |
//
// The continuum is Ω_t = [x_1 − V_1/2, x_N + V_N/2] = [0.6, 3.2]. The
// half spans [0, 0.5] and [3.5, 4] miss it and are dropped. The thesis rule
// keeps both Gauss points of [0.5, 1], since 0.5 + 0.25(1 − 1/√3) ≈ 0.606
// lies inside. The rule of `CubicSplineClipped` clips that half span to
// [0.6, 1]. Both rules clip [3, 3.5] to [3, 3.2].

use hompm::mpm::mapping::{internal_force, MappingWorkspace};
use hompm::reconstruct::cubic_spline::{CubicSpline, EndCondition};

fn five_unsorted_particles() -> Particles {
    Particles::new(
        vec![2.1, 0.9, 3.05, 1.6, 2.6],
        vec![0.5, 0.6, 0.3, 0.5, 0.5],
        vec![1.0; 5],
        vec![0.0; 5],
        vec![1.0, -2.0, 0.5, 3.0, -1.0],
    )
    .unwrap()
}

/// Two-point Gauss on [c, d]: (c + d)/2 ± (d − c)/(2√3), weights (d − c)/2.
fn gauss2(c: f64, d: f64) -> [(f64, f64); 2] {
    let (m, r) = (0.5 * (c + d), 0.5 * (d - c));
    [(m - r / 3f64.sqrt(), r), (m + r / 3f64.sqrt(), r)]
}

/// Thesis §7.2's quadrature on the half spans of the unit cells of [0, 4],
/// restricted to Ω_t = [left, right]; `(x, w, cell)`.
fn half_span_rule(left: f64, right: f64, clip_every_half_span: bool) -> Vec<(f64, f64, usize)> {
    let mut rule = Vec::new();
    for e in 0..4 {
        let a = e as f64;
        for (c, d) in [(a, a + 0.5), (a + 0.5, a + 1.0)] {
            let pair = gauss2(c, d);
            let inside = |x: f64| (left..=right).contains(&x);
            let whole = if clip_every_half_span {
                c >= left && d <= right
            } else {
                pair.iter().all(|&(x, _)| inside(x))
            };
            let points = if whole {
                pair.to_vec()
            } else if d.min(right) > c.max(left) {
                gauss2(c.max(left), d.min(right)).to_vec()
            } else {
                vec![]
            };
            rule.extend(points.into_iter().map(|(x, w)| (x, w, e)));
        }
    }
    rule
}

/// Map rows: thesis-§7.2-2, thesis-§7.2-4 — the force integral and its clipping to the continuum are one computation.
#[test]
fn thesis_7_2_spline_force_integrates_the_stress_spline_over_half_spans_clipped_to_the_continuum() {
    let grid = Grid::new(Method::Mpm, 0.0, 4.0, 4).unwrap();
    let p = five_unsorted_particles();
    let stencils = grid.stencils_at(&p.x).unwrap();
    // σ̃: the not-a-knot spline through the particles sorted by position.
    let sorted = [
        (0.9, -2.0),
        (1.6, 3.0),
        (2.1, 1.0),
        (2.6, -1.0),
        (3.05, 0.5),
    ];
    let (xs, ss): (Vec<f64>, Vec<f64>) = sorted.iter().copied().unzip();
    let stress = CubicSpline::new(&xs, &ss, EndCondition::NotAKnot).unwrap();
    for (mapping, clip) in [
        (Mapping::CubicSpline, false),
        (Mapping::CubicSplineClipped, true),
    ] {
        let rule = half_span_rule(0.6, 3.2, clip);
        assert_eq!(
            rule.len(),
            12,
            "three of eight half spans keep no or clipped points"
        );
        // f_i = Σ_q w_q σ̃(x_q) ∇φ_i(x_q), ∇φ = (−1, +1) on the nodes of the cell.
        let mut expected = [0.0; 5];
        for &(x, w, e) in &rule {
            expected[e] -= w * stress.evaluate(x);
            expected[e + 1] += w * stress.evaluate(x);
        }
        let mut ws = MappingWorkspace::new(&grid, 5).unwrap();
        // Twice: the second step must rebuild the points, not add to them.
        for _ in 0..2 {
            ws.begin_step(&grid, &p, &[mapping]).unwrap();
            let mut force = vec![0.0; 5];
            internal_force(&grid, &p, &stencils, mapping, &mut ws, &mut force).unwrap();
            for i in 0..5 {
                assert!(
                    (force[i] - expected[i]).abs() < 1e-13,
                    "{mapping:?}: f_{i} = {} against {}",
                    force[i],
                    expected[i]
                );
            }
        }
        // A force vector that does not match the grid's DOFs is refused.
        let mut short = vec![0.0; 4];
        let refused = internal_force(&grid, &p, &stencils, mapping, &mut ws, &mut short);
        assert!(matches!(refused, Err(hompm::Error::InvalidArgument(_))));
    }
}

/// Book Eq. (4.10)'s mass matrix M_ij = Σ_p m_p φ_i(x_p) φ_j(x_p) has the
/// diagonal M_ii = Σ_p m_p φ_i(x_p)², here (0.5, 1.625, 0.125) (see the
/// table at the top), whichever mass matrix the projection then solves with.
#[test]
fn eq_4_10_projection_diagonal_is_the_mass_weighted_square_of_the_basis() {
    use hompm::mpm::mapping::{project_velocity, ConsistentSolver};
    let grid = &Grid::new(Method::Mpm, 0.0, 2.0, 2).unwrap();
    let p = &table_particles();
    let stencils = grid.stencils_at(&p.x).unwrap();
    for mass in [
        MassMatrix::Lumped,
        MassMatrix::Consistent(ConsistentSolver::Cholesky),
    ] {
        let mut ws = MappingWorkspace::new(grid, 2).unwrap();
        ws.begin_step(grid, p, &[Mapping::Direct]).unwrap();
        let projection =
            project_velocity(grid, p, &stencils, Mapping::Direct, mass, &mut ws).unwrap();
        assert_all(&ws.diagonal, &[0.5, 1.625, 0.125]);
        assert_relative_eq!(
            projection.diagonal_ratio,
            0.125 / 1.625,
            max_relative = 1e-14
        );
    }
}

/// A run document names the ramp's time level only when it is not the
/// text's (TLS paper Eq. 10's tⁿ), as it leaves out every default.
#[test]
fn a_ramp_read_at_the_step_start_prints_only_its_duration() {
    let json = |time_level| {
        serde_json::to_value(GravityRamp {
            duration: 0.5,
            time_level,
        })
        .unwrap()
    };
    assert_eq!(
        json(RampTimeLevel::StepStart),
        serde_json::json!({ "duration": 0.5 })
    );
    assert_eq!(
        json(RampTimeLevel::StepEnd),
        serde_json::json!({ "duration": 0.5, "time_level": "step-end" })
    );
}
