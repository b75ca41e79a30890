//! Properties of the MPM mappings and bases: book Eq. (4.24), TLS paper §3.3
//! and §5.5.

use hompm::mpm::diagnostics::relative_l2_error;
use hompm::mpm::grid::{Grid, Method};
use hompm::mpm::mapping::{
    project_velocity, ConsistentSolver, Mapping, MappingWorkspace, MassMatrix,
};
use hompm::mpm::particles::Particles;
use proptest::prelude::*;

use crate::common;

fn method_strategy() -> impl Strategy<Value = Method> {
    prop_oneof![
        Just(Method::Mpm),
        Just(Method::DDMPM),
        (1usize..=4).prop_map(|degree| Method::Bsmpm { degree })
    ]
}

/// Random particles: `ppc` per cell, jittered inside their sub-interval.
fn particles(cells: usize, ppc: usize, jitter: &[f64], vel: &[f64]) -> Particles {
    let n = cells * ppc;
    let dx = 1.0 / n as f64;
    let x0: Vec<f64> = (0..n)
        .map(|k| (k as f64 + 0.5 + 0.8 * (jitter[k % jitter.len()] - 0.5)) * dx)
        .collect();
    let v: Vec<f64> = (0..n).map(|k| vel[k % vel.len()]).collect();
    let rho: Vec<f64> = (0..n)
        .map(|k| 1.0 + 0.5 * jitter[(3 * k) % jitter.len()])
        .collect();
    Particles::new(x0, vec![dx; n], rho, v, vec![0.0; n]).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Book Eq. (4.24): the direct mapping preserves total mass and momentum
    /// for any partition-of-unity basis; TLS does too (TLS paper §5.5), with
    /// lumped or consistent mass.
    ///
    /// Map rows: book-4.24, tls-§5-1 — one property, stated in two seeds.
    #[test]
    fn mappings_conserve_mass_and_momentum(method in method_strategy(), cells in 2usize..10, ppc in 3usize..6,
                                           jitter in proptest::collection::vec(0.0f64..1.0, 7),
                                           vel in proptest::collection::vec(0.1f64..1.0, 5),
                                           tls in any::<bool>(), consistent in any::<bool>()) {
        let grid = Grid::new(method, 0.0, 1.0, cells).unwrap();
        let p = particles(cells, ppc, &jitter, &vel);
        let stencils = grid.stencils_at(&p.x).unwrap();
        let mapping = if tls { Mapping::Tls } else { Mapping::Direct };
        let mass = if consistent { MassMatrix::Consistent(ConsistentSolver::Cholesky) } else { MassMatrix::Lumped };
        // With two Gauss points per element the TLS consistent mass has rank
        // ≤ 2·cells; below the DOF count it is singular, a typed error.
        let rank_deficient = tls && consistent && 2 * cells < grid.num_dofs();
        let mut ws = MappingWorkspace::new(&grid, p.len()).unwrap();
        ws.begin_step(&grid, &p, &[mapping]).unwrap();
        let proj = match project_velocity(&grid, &p, &stencils, mapping, mass, &mut ws) {
            Err(hompm::Error::Singular(_)) if rank_deficient => return Ok(()),
            other => other.unwrap(),
        };
        let m = p.total_mass();
        let q = p.total_momentum();
        prop_assert!((proj.grid_mass - m).abs() <= 1e-12 * m);
        prop_assert!((proj.grid_momentum - q).abs() <= 1e-10 * q.abs().max(m));
    }

    /// TLS paper §3.3: the DDMPM gradients sum to zero (a rigid translation
    /// produces no strain), like the P1 gradients they blend.
    #[test]
    fn ddmpm_gradients_sum_to_zero(cells in 2usize..20, t in 0.0f64..=1.0) {
        let grid = Grid::new(Method::DDMPM, 0.0, 2.0, cells).unwrap();
        let s = grid.shape(2.0 * t).unwrap();
        let sum: f64 = s.gradients.iter().sum();
        let scale = s.gradients.iter().map(|g| g.abs()).fold(1.0, f64::max);
        prop_assert!(sum.abs() < 1e-12 * scale);
        prop_assert!((s.values.iter().sum::<f64>() - 1.0).abs() < 1e-14);
    }
}

/// A uniform velocity field is a rigid translation: one MUSL step moves every
/// particle by v Δt and creates no stress, for every method and mapping. The
/// body sits inside a larger grid, except for DDMPM, whose grid-domain
/// smoothing sees the empty DOFs beyond a free surface (docs/conventions.md).
#[test]
fn rigid_translation_creates_no_stress() {
    use hompm::mpm::musl::Simulation;
    for method in [
        Method::Mpm,
        Method::DDMPM,
        Method::Bsmpm { degree: 2 },
        Method::Bsmpm { degree: 3 },
        // Width 5: the step's loops with the width read at run time.
        Method::Bsmpm { degree: 4 },
    ] {
        for mapping in Mapping::ALL {
            let grid = if method == Method::DDMPM {
                Grid::new(method, 0.0, 1.0, 4).unwrap()
            } else {
                Grid::new(method, -1.0, 2.0, 12).unwrap()
            };
            let mut p = Particles::uniform(0.0, 1.0, 16, 1.0).unwrap();
            p.velocity = vec![0.3; 16];
            let settings = common::free_settings(
                mapping,
                MassMatrix::Consistent(ConsistentSolver::Cholesky),
                10.0,
            );
            let mut sim = Simulation::new(grid, p, settings).unwrap();
            sim.step(1e-3).unwrap();
            for k in 0..16 {
                assert!(
                    sim.particles.stress[k].abs() < 1e-9,
                    "{method:?} {mapping:?}: σ = {}",
                    sim.particles.stress[k]
                );
                assert!(
                    (sim.particles.displacement[k] - 3e-4).abs() < 1e-12,
                    "{method:?} {mapping:?}: u = {}",
                    sim.particles.displacement[k]
                );
            }
        }
    }
}

#[test]
fn relative_l2_error_definition() {
    let e = relative_l2_error(&[1.0, 2.0], &[1.0, 1.0]).unwrap();
    assert!((e - (0.5f64).sqrt()).abs() < 1e-15);
    assert!(relative_l2_error(&[1.0], &[0.0]).is_err());
    assert!(relative_l2_error(&[], &[]).is_err());
    // Both measures refuse what they cannot compare: unequal lengths,
    // nothing at all, or a non-finite value on either side (issue #13).
    use hompm::mpm::diagnostics::rms_error;
    for (c, r) in [
        (&[1.0][..], &[1.0, 2.0][..]),
        (&[][..], &[][..]),
        (&[f64::NAN][..], &[1.0][..]),
        (&[1.0][..], &[f64::INFINITY][..]),
    ] {
        assert!(rms_error(c, r).is_err(), "{c:?} against {r:?}");
        assert!(relative_l2_error(c, r).is_err(), "{c:?} against {r:?}");
    }
    assert_eq!(rms_error(&[1.0, 3.0], &[1.0, 1.0]).unwrap(), 2.0f64.sqrt());
}

/// Book Eqs. (4.39)–(4.44), TLS paper §5.4: the TLS mapping fits ρv (not
/// ρ or v alone) per cell and integrates it against φ_i. With ρ = 1 + x and
/// v = 1 − x, ρv = 1 − x² is quadratic, so quadratic TLS reproduces it up
/// to the constant that conserves the particles' cell momentum (a
/// midpoint-rule error of O(h²)), and p_i = ∫ρv φ_i follows.
#[test]
fn tls_projection_integrates_the_product_of_density_and_velocity() {
    use hompm::mpm::mapping::assemble_projection;
    use hompm::quadrature::gauss_on_cells;
    let grid = Grid::new(Method::Bsmpm { degree: 2 }, 0.0, 1.0, 8).unwrap();
    let n = 8 * 16;
    let x0: Vec<f64> = (0..n).map(|k| (k as f64 + 0.5) / n as f64).collect();
    let volume = vec![1.0 / n as f64; n];
    let density: Vec<f64> = x0.iter().map(|x| 1.0 + x).collect();
    let velocity: Vec<f64> = x0.iter().map(|x| 1.0 - x).collect();
    let particles = Particles::new(x0, volume, density, velocity, vec![0.0; n]).unwrap();
    let stencils = grid.stencils_at(&particles.x).unwrap();
    let mut ws = MappingWorkspace::new(&grid, n).unwrap();
    ws.begin_step(&grid, &particles, &[Mapping::Tls]).unwrap();
    assemble_projection(&grid, &particles, &stencils, Mapping::Tls, false, &mut ws).unwrap();
    let mut exact = vec![0.0; grid.num_dofs()];
    for q in gauss_on_cells(&grid.cells(), 6).unwrap() {
        let s = grid.shape(q.x).unwrap();
        for (j, phi) in s.values.iter().enumerate() {
            exact[s.first + j] += q.weight * (1.0 - q.x * q.x) * phi;
        }
    }
    for (i, (p, e)) in ws.momentum.iter().zip(&exact).enumerate() {
        assert!((p - e).abs() < 2e-4, "p_{i} = {p}, ∫ρvφ_{i} = {e}");
    }
}

/// The run monitors of `RunDiagnostics` by hand (TLS paper Tables 3, 5, 7;
/// thesis §5.2): each recorder keeps a running maximum, minimum or count.
#[test]
fn run_diagnostics_keep_the_extremes_and_counts_of_each_step() {
    use hompm::mpm::diagnostics::RunDiagnostics;
    use hompm::mpm::mapping::Projection;
    let mut d = RunDiagnostics {
        min_lumped_mass: f64::INFINITY,
        min_mass_diagonal_ratio: f64::INFINITY,
        ..Default::default()
    };
    // Before any step the two minima are +∞ and JSON leaves them out.
    let json = serde_json::to_value(&d).unwrap();
    assert!(json.get("min_lumped_mass").is_none());
    assert!(json.get("min_mass_diagonal_ratio").is_none());
    assert_eq!(json["steps"], 0);

    // Lumped masses: zeros are inactive nodes and ignored; a negative mass
    // counts the step once, however many nodes are negative.
    d.record_lumped_masses(&[0.0, 2.0, 0.5, 3.0]);
    assert_eq!((d.min_lumped_mass, d.negative_mass_steps), (0.5, 0));
    d.record_lumped_masses(&[-0.25, -0.5, 4.0]);
    assert_eq!((d.min_lumped_mass, d.negative_mass_steps), (-0.5, 1));
    d.record_lumped_masses(&[1.0, -0.125]);
    assert_eq!((d.min_lumped_mass, d.negative_mass_steps), (-0.5, 2));
    let json = serde_json::to_value(&d).unwrap();
    assert_eq!(json["min_lumped_mass"], -0.5);

    // Projection: grid mass 10.5 against particle mass 10 is 5 %; grid
    // momentum −3 against −4 is 25 %; a zero particle momentum is skipped.
    let projection = Projection {
        grid_mass: 10.5,
        grid_momentum: -3.0,
        solver_iterations: 7,
        diagonal_ratio: 0.25,
    };
    d.record_projection(&projection, &[1.0, -6.0, 2.0], &[-3.0, 2.0], 10.0, -4.0);
    assert_eq!(d.solver_iterations, 7);
    assert_eq!(d.min_mass_diagonal_ratio, 0.25);
    assert_eq!(d.max_nodal_velocity, 6.0);
    assert_eq!(d.max_particle_velocity, 3.0);
    assert!((d.max_mass_error - 0.05).abs() < 1e-15);
    assert_eq!(d.max_momentum_error, 0.25);
    let quieter = Projection {
        grid_mass: 9.9,
        grid_momentum: 1.0,
        solver_iterations: 3,
        diagonal_ratio: 0.5,
    };
    d.record_projection(&quieter, &[1.0], &[1.0], 10.0, 0.0);
    assert_eq!(d.solver_iterations, 10);
    assert_eq!(d.min_mass_diagonal_ratio, 0.25);
    assert_eq!((d.max_nodal_velocity, d.max_particle_velocity), (6.0, 3.0));
    assert!((d.max_mass_error - 0.05).abs() < 1e-15);
    assert_eq!(d.max_momentum_error, 0.25);
    let json = serde_json::to_value(&d).unwrap();
    assert_eq!(json["min_mass_diagonal_ratio"], 0.25);

    // Particles: the largest |ε_p| and the sum of crossings.
    d.record_particles(&[0.01, -0.03, 0.02], 2);
    d.record_particles(&[0.001], 3);
    assert_eq!((d.max_abs_strain, d.grid_crossings), (0.03, 5));
}

/// Thesis §3.3 and §6.1: a particle crosses the grid where a basis gradient
/// jumps. P1 and P2 gradients jump at every interior cell boundary, linear
/// B-splines too (they are P1), and B-splines of degree ≥ 2 on an open
/// uniform knot vector have continuous gradients, so nothing to cross.
#[test]
fn gradient_breaks_are_the_interior_boundaries_of_c0_bases_and_none_of_smooth_splines() {
    let interior = vec![0.5, 1.0, 1.5];
    for method in [Method::Mpm, Method::MpmP2, Method::Bsmpm { degree: 1 }] {
        let grid = Grid::new(method, 0.0, 2.0, 4).unwrap();
        assert_eq!(grid.gradient_breaks(), interior, "{method:?}");
    }
    for degree in [2, 3] {
        let grid = Grid::new(Method::Bsmpm { degree }, 0.0, 2.0, 4).unwrap();
        assert!(grid.gradient_breaks().is_empty(), "degree {degree}");
        // Debug names the method and the cell count.
        let shown = format!("{grid:?}");
        assert!(
            shown.contains("4 cells") && shown.contains("Bsmpm"),
            "{shown}"
        );
    }
}

/// How often the uniform guess ⌊(x − a)·cells/(b − a)⌋ of a search was
/// below and above the answer: a test of the search's correction loops
/// must make both happen.
#[derive(Default)]
struct GuessTally {
    low: usize,
    high: usize,
}

impl GuessTally {
    fn count(&mut self, guess: usize, answer: usize) {
        self.low += usize::from(guess < answer);
        self.high += usize::from(guess > answer);
    }

    fn assert_both_ways(&self) {
        let (low, high) = (self.low, self.high);
        assert!(
            low > 0 && high > 0,
            "guess too low {low}×, too high {high}×"
        );
    }
}

/// The half-open cell assignment c_e ≤ x < c_{e+1}, the last cell closed
/// (book Eq. 4.38's cells, thesis §7.2): `Grid::cell_of` against a search of
/// the cell boundaries, at every boundary and its floating-point
/// neighbours. `cell_of` starts from the guess ⌊(x − a)·cells/(b − a)⌋; the
/// grids here are chosen so that rounding makes that guess one too low at
/// some boundaries and one too high at others, so both corrections run.
#[test]
fn cell_of_is_the_half_open_cell_even_where_the_uniform_guess_rounds_wrong() {
    let mut tally = GuessTally::default();
    for (a, b) in [(0.1, 0.7), (0.0, 1.0), (-0.3, 2.9), (1.0 / 3.0, 5.0)] {
        for cells in 1..40 {
            let grid = Grid::new(Method::Mpm, a, b, cells).unwrap();
            let bounds: Vec<f64> = std::iter::once(grid.cells()[0].0)
                .chain(grid.cells().iter().map(|c| c.1))
                .collect();
            let (a0, b0) = grid.domain();
            let per_length = cells as f64 / (b0 - a0);
            for &c in &bounds {
                for x in [c.next_down(), c, c.next_up()] {
                    if !(a0..=b0).contains(&x) {
                        assert!(grid.cell_of(x).is_err(), "{x} outside [{a0}, {b0}]");
                        continue;
                    }
                    let expected = (0..cells)
                        .find(|&e| bounds[e] <= x && x < bounds[e + 1])
                        .unwrap_or(cells - 1);
                    assert_eq!(grid.cell_of(x).unwrap(), expected, "x = {x}, {cells} cells");
                    tally.count((((x - a0) * per_length) as usize).min(cells - 1), expected);
                }
            }
        }
    }
    tally.assert_both_ways();
}

/// Thesis §3.3: a particle moving from x to y crosses |N(y) − N(x)|
/// gradient breaks, N(x) = #{b ≤ x}. `Grid::breaks_at_or_below` against a
/// count, at every break and its floating-point neighbours, at both ends and
/// at points in between; `breaks_at_or_below_is(n, x)` is N(x) = n.
#[test]
fn breaks_at_or_below_counts_the_gradient_breaks_up_to_x() {
    let mut tally = GuessTally::default();
    for method in [Method::Mpm, Method::MpmP2, Method::Bsmpm { degree: 2 }] {
        for (a, b) in [(0.1, 0.7), (-0.3, 2.9), (1.0 / 3.0, 5.0)] {
            for cells in 1..30 {
                let grid = Grid::new(method, a, b, cells).unwrap();
                let breaks = grid.gradient_breaks();
                let (a0, b0) = grid.domain();
                let per_length = cells as f64 / (b0 - a0);
                let mut xs = vec![a0, b0, 0.5 * (a0 + b0), a0 + 0.37 * (b0 - a0)];
                for &c in &breaks {
                    xs.extend([c.next_down(), c, c.next_up()]);
                }
                for x in xs {
                    let expected = breaks.iter().filter(|&&c| c <= x).count();
                    let n = grid.breaks_at_or_below(x);
                    assert_eq!(n, expected, "{method:?}, x = {x}, {cells} cells");
                    for m in 0..=breaks.len() + 1 {
                        assert_eq!(
                            grid.breaks_at_or_below_is(m, x),
                            m == expected,
                            "{m} at {x}"
                        );
                    }
                    if !breaks.is_empty() {
                        let guess = (((x - a0) * per_length) as usize).min(breaks.len());
                        tally.count(guess, expected);
                    }
                }
            }
        }
    }
    tally.assert_both_ways();
}

/// Thesis §3.2: particles "initially equally distributed", each at the
/// centre of its sub-interval, x_p = a + (p − ½)(b − a)/n (p from 1) and
/// V_p = (b − a)/n, m_p = ρ V_p; on [1, 3] with n = 4: x = 1.25, 1.75, …
#[test]
fn uniform_particles_sit_at_the_centres_of_equal_sub_intervals() {
    let p = Particles::uniform(1.0, 3.0, 4, 2.0).unwrap();
    assert_eq!(p.x, vec![1.25, 1.75, 2.25, 2.75]);
    assert_eq!(p.x0, p.x);
    assert_eq!(p.volume, vec![0.5; 4]);
    assert_eq!(p.mass, vec![1.0; 4]);
    assert_eq!((p.len(), p.is_empty(), p.total_mass()), (4, false, 4.0));
    assert!(Particles::uniform(1.0, 3.0, 0, 2.0).is_err());
}

/// What a 1D reconstruction reports of its last step, the `Reconstruction`
/// trait that 1D shares with 2D (book Eqs. 4.26–4.29, TLS paper §5.3): TLS
/// reports the largest κ of its cells' fits and the cells that took virtual
/// points, from zero again at every step; a cubic spline solves no small
/// system; the direct mapping has no reconstruction.
#[test]
fn a_1d_reconstruction_reports_the_condition_and_the_repairs_of_its_last_step() {
    use hompm::mpm::mapping::internal_force;
    use hompm::reconstruct::taylor::{reconstruct, Assignment, TlsOptions};
    let grid = Grid::new(Method::Mpm, 0.0, 4.0, 4).unwrap();
    // Three particles in each of cells 0–2 and one in cell 3: quadratic
    // TLS needs three, so cell 3 takes virtual points from cell 2.
    let x = vec![0.2, 0.5, 0.9, 1.1, 1.4, 1.8, 2.3, 2.5, 2.7, 3.5];
    let n = x.len();
    let stress: Vec<f64> = x.iter().map(|x| 1.0 + x * x).collect();
    let p = Particles::new(
        x.clone(),
        vec![0.4; n],
        vec![1.0; n],
        vec![0.1; n],
        stress.clone(),
    )
    .unwrap();
    let stencils = grid.stencils_at(&p.x).unwrap();
    let mut ws = MappingWorkspace::new(&grid, n).unwrap();
    assert!(ws.reconstruction(Mapping::Direct).is_none());
    ws.begin_step(&grid, &p, &[Mapping::Tls]).unwrap();
    let mut force = vec![0.0; grid.num_dofs()];
    internal_force(&grid, &p, &stencils, Mapping::Tls, &mut ws, &mut force).unwrap();
    let options = TlsOptions {
        assignment: Assignment::HalfOpen,
        ..TlsOptions::default()
    };
    let fit = reconstruct(&grid.cells(), &x, &stress, None, options).unwrap();
    let kappa = fit.condition_numbers().into_iter().fold(0.0, f64::max);
    let repaired = fit.cells.iter().flatten();
    let repaired = repaired.filter(|c| c.virtual_points > 0).count();
    assert_eq!(repaired, 1);
    assert!(kappa > 1.0);
    let tls = ws.reconstruction(Mapping::Tls).unwrap();
    assert_eq!(
        (tls.name(), tls.largest_condition(), tls.repaired()),
        ("TLS", kappa, repaired)
    );
    // The projection's two fits add theirs; the next step starts from zero.
    let lumped = MassMatrix::Lumped;
    project_velocity(&grid, &p, &stencils, Mapping::Tls, lumped, &mut ws).unwrap();
    let tls = ws.reconstruction(Mapping::Tls).unwrap();
    assert!(tls.largest_condition() >= kappa && tls.repaired() == 1);
    ws.begin_step(&grid, &p, &[Mapping::Tls]).unwrap();
    let tls = ws.reconstruction(Mapping::Tls).unwrap();
    assert_eq!((tls.largest_condition(), tls.repaired()), (0.0, 0));
    for m in [Mapping::CubicSpline, Mapping::CubicSplineClipped] {
        ws.begin_step(&grid, &p, &[m]).unwrap();
        project_velocity(&grid, &p, &stencils, m, lumped, &mut ws).unwrap();
        let spline = ws.reconstruction(m).unwrap();
        assert_eq!(
            (spline.name(), spline.largest_condition(), spline.repaired()),
            (m.info().legend, 0.0, 0)
        );
    }
}

/// Each registered mapping keeps its own quadrature (thesis §7.2): the
/// thesis' spline rule for the internal force and the clipped rule for
/// the velocity in one step give what each gives alone.
#[test]
fn the_force_and_the_velocity_mapping_keep_their_own_quadratures() {
    use hompm::mpm::mapping::internal_force;
    let grid = Grid::new(Method::Bsmpm { degree: 2 }, 0.0, 1.0, 6).unwrap();
    let mut p = particles(6, 3, &[0.1, 0.9, 0.4, 0.7, 0.2, 0.6, 0.5], &[0.3, 0.5, 0.2]);
    p.stress = p.x.clone();
    let stencils = grid.stencils_at(&p.x).unwrap();
    let (force_mapping, velocity_mapping) = (Mapping::CubicSpline, Mapping::CubicSplineClipped);
    let mass = MassMatrix::Consistent(ConsistentSolver::Cholesky);
    // The force, then the velocity, of a step that began with `mappings`.
    let run = |mappings: &[Mapping], velocity: bool| {
        let mut ws = MappingWorkspace::new(&grid, p.len()).unwrap();
        ws.begin_step(&grid, &p, mappings).unwrap();
        let mut force = vec![0.0; grid.num_dofs()];
        internal_force(&grid, &p, &stencils, force_mapping, &mut ws, &mut force).unwrap();
        if !velocity {
            return force;
        }
        project_velocity(&grid, &p, &stencils, velocity_mapping, mass, &mut ws).unwrap();
        ws.velocity
    };
    let both = [force_mapping, velocity_mapping];
    let (force, velocity) = (run(&both, false), run(&both, true));
    assert_eq!(force, run(&[force_mapping], false));
    assert_eq!(velocity, run(&[velocity_mapping], true));
    assert!(force.iter().any(|&f| f != 0.0) && velocity.iter().any(|&v| v != 0.0));
}

/// The TLS fit of the density averages (x − x_c)² the way the simulation
/// says (`Settings::tls_density_average`, docs/conventions.md, "The TLS
/// author's cell average"): the averages are equal in exact arithmetic, so
/// on a bar far from the origin the projections differ only by the
/// antiderivative's rounding, about |x|³ε/(b − a) ≈ 7e-8 against
/// Δx²/3 ≈ 0.08 at x = 1000 (about 1e-6 relative), and they do differ.
#[test]
fn the_tls_density_fit_uses_the_cell_average_it_is_given_and_it_changes_only_rounding() {
    use hompm::reconstruct::taylor::CellAverage;
    let grid = Grid::new(Method::Bsmpm { degree: 2 }, 1000.0, 1004.0, 4).unwrap();
    let p0 = particles(4, 3, &[0.1, 0.9, 0.4, 0.7, 0.2, 0.6, 0.5], &[0.3, 0.5, 0.2]);
    let x = p0.x.iter().map(|x| 1000.0 + 4.0 * x).collect();
    let volume = p0.volume.iter().map(|v| 4.0 * v).collect();
    let p = Particles::new(
        x,
        volume,
        p0.density.clone(),
        p0.velocity.clone(),
        p0.stress,
    )
    .unwrap();
    let stencils = grid.stencils_at(&p.x).unwrap();
    let mass = MassMatrix::Consistent(ConsistentSolver::Cholesky);
    let velocity = |average: CellAverage| {
        let mut ws = MappingWorkspace::new(&grid, p.len()).unwrap();
        ws.begin_step_with(&grid, &p, &[Mapping::Tls], average)
            .unwrap();
        project_velocity(&grid, &p, &stencils, Mapping::Tls, mass, &mut ws).unwrap();
        ws.velocity
    };
    let exact = velocity(CellAverage::Exact);
    for average in [
        CellAverage::AntiderivativeDifference,
        CellAverage::AntiderivativeSixTerms,
    ] {
        let other = velocity(average);
        assert_ne!(other, exact, "{average:?}");
        assert!(
            relative_l2_error(&other, &exact).unwrap() < 1e-5,
            "{average:?}"
        );
    }
}

/// A workspace sized for n particles serves a step of m particles: the
/// spline mappings (thesis §7.2) sort what the step hands them, not what
/// the workspace was built for.
#[test]
fn a_spline_mapping_sorts_every_particle_of_the_step_whatever_the_workspace_was_built_for() {
    let grid = Grid::new(Method::Bsmpm { degree: 2 }, 0.0, 1.0, 6).unwrap();
    let p = particles(6, 3, &[0.1, 0.9, 0.4, 0.7, 0.2, 0.6, 0.5], &[0.3, 0.5, 0.2]);
    let stencils = grid.stencils_at(&p.x).unwrap();
    let velocity = |built_for: usize| {
        let mut ws = MappingWorkspace::new(&grid, built_for).unwrap();
        ws.begin_step(&grid, &p, &[Mapping::CubicSpline]).unwrap();
        project_velocity(
            &grid,
            &p,
            &stencils,
            Mapping::CubicSpline,
            MassMatrix::Lumped,
            &mut ws,
        )
        .unwrap();
        ws.velocity
    };
    assert_eq!(velocity(5), velocity(p.len()));
}

/// `Grid::fill_stencils` at every stencil width, 2 (P1) to 6 (B-splines of
/// degree 5, whose width the step dispatches at run time): each point's
/// row and first function are `Grid::evaluate`'s at that point (book
/// Eqs. 4.5–4.6), for points across the whole domain.
#[test]
fn fill_stencils_writes_each_point_s_basis_at_every_width() {
    use hompm::spline::bspline::SpanScratch;
    for method in [
        Method::Mpm,
        Method::MpmP2,
        Method::Bsmpm { degree: 2 },
        Method::Bsmpm { degree: 3 },
        Method::Bsmpm { degree: 4 },
        Method::Bsmpm { degree: 5 },
    ] {
        let grid = Grid::new(method, -0.5, 2.0, 7).unwrap();
        let w = grid.stencil_width();
        let xs: Vec<f64> = (0..=40).map(|k| -0.5 + 2.5 * k as f64 / 40.0).collect();
        let mut scratch = SpanScratch::default();
        let mut stencils = grid.stencils(0);
        grid.fill_stencils(&xs, |x| *x, &mut stencils, &mut scratch)
            .unwrap();
        for (k, &x) in xs.iter().enumerate() {
            let (mut values, mut gradients) = (vec![0.0; w], vec![0.0; w]);
            let first = grid
                .evaluate(x, &mut scratch, &mut values, &mut gradients)
                .unwrap();
            assert_eq!(stencils.first[k], first, "{method:?} at {x}");
            assert_eq!(stencils.values_of(k), &values[..], "{method:?} at {x}");
            assert_eq!(
                stencils.gradients_of(k),
                &gradients[..],
                "{method:?} at {x}"
            );
            assert!(values.iter().any(|&v| v > 0.0));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// `CompensatedSum` takes each rounding error by Knuth's branch-free
    /// TwoSum, `compensated_sum` by Neumaier's branch; for finite terms
    /// whose sums do not overflow both errors are exact, so the two totals
    /// agree bit for bit, over terms of every sign and of magnitudes 2⁻⁶⁰
    /// to 2⁶⁰ (where cancellation and absorption both happen).
    #[test]
    fn the_running_compensated_sum_is_neumaier_s_bit_for_bit(
        terms in prop::collection::vec(
            (-1.0f64..1.0, -60i32..60).prop_map(|(m, e)| m * 2f64.powi(e)),
            0..200,
        )
    ) {
        use hompm::mpm::diagnostics::{compensated_sum, CompensatedSum};
        let mut running = CompensatedSum::default();
        for &t in &terms {
            running.add(t);
        }
        prop_assert_eq!(
            running.total().to_bits(),
            compensated_sum(terms.iter().copied()).to_bits()
        );
    }
}

/// Thesis §3.3: a particle moving from x to y crosses |N(y) − N(x)|
/// gradient breaks. `Grid::crossings_between` is given the count kept from
/// the last step; whatever it holds (right, stale, or beyond the breaks),
/// the crossings are counted from N(x), and the count becomes N(y).
#[test]
fn crossings_between_counts_from_x_whatever_count_it_is_given() {
    // P1 on [0, 4]: breaks at 1, 2, 3.
    let grid = Grid::new(Method::Mpm, 0.0, 4.0, 4).unwrap();
    for (x, y) in [(2.5, 3.5), (3.5, 0.5), (1.5, 1.75), (0.0, 4.0), (2.0, 1.0)] {
        let expected = grid
            .breaks_at_or_below(y)
            .abs_diff(grid.breaks_at_or_below(x));
        for kept in 0..6 {
            let mut count = kept;
            assert_eq!(
                grid.crossings_between(&mut count, x, y),
                expected,
                "{x} → {y}, count {kept}"
            );
            assert_eq!(count, grid.breaks_at_or_below(y));
        }
    }
}
