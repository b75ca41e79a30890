//! The causes of the deviations (golden/deviation-causes.json, issue #11):
//! the file is well formed, every demonstrated cause names an experiment
//! that exists, and the experiments that demonstrate a cause are here.

use hompm::mpm::grid::Method;
use hompm::mpm::mapping::Mapping;
use hompm::report::causes::{causes, CauseKind};
use hompm::scenes::column;
use hompm::studies::tls_paper::{compaction, conservation_errors};
use hompm::tables::Published;

use crate::common;

use common::published;

fn value(p: &Published, row: &str, column: &str) -> f64 {
    let r = p.row_labels.iter().position(|l| l == row).unwrap();
    let c = p.col_labels.iter().position(|l| l == column).unwrap();
    p.values[r][c].unwrap()
}

#[test]
fn every_cause_names_existing_labels_and_every_demonstration_an_existing_experiment() {
    let rules = causes().unwrap();
    assert!(!rules.is_empty());
    for c in &rules {
        let p = published(&c.table);
        assert!(
            c.row == "*" || p.row_labels.contains(&c.row),
            "{}: no row '{}'",
            c.table,
            c.row
        );
        assert!(
            c.column == "*" || p.col_labels.contains(&c.column),
            "{}: no column '{}'",
            c.table,
            c.column
        );
        assert!(!c.cause.trim().is_empty() && !c.evidence.trim().is_empty());
        if c.kind == CauseKind::Demonstrated {
            // `tests/<file>.rs::<test>`: the file has that function.
            let (file, test) = c
                .evidence
                .split_once("::")
                .unwrap_or_else(|| panic!("{}: evidence '{}' names no test", c.table, c.evidence));
            let path = format!("{}/{file}", env!("CARGO_MANIFEST_DIR"));
            let text = std::fs::read_to_string(&path).unwrap_or_else(|_| panic!("{path}"));
            let name = test.split_whitespace().next().unwrap();
            assert!(
                text.contains(&format!("fn {name}(")),
                "{path} has no test {name}"
            );
        }
    }
}

/// tls-3, DDMPM with the cubic spline: the printed Error_M 3.9211e-13
/// appears when DDMPM's node integrals are particle sums, and not with
/// exact node integrals (rounding level, 6.8e-15).
#[test]
fn tls_3_ddmpm_spline_mass_error_appears_with_particle_quadrature_node_integrals() {
    let p = value(&published("tls-3"), "Cubic-spline", "DDMPM Error_M");
    let (particles, _) =
        conservation_errors(Method::DDMPM_PARTICLES, Mapping::CubicSpline, 40, 12).unwrap();
    let (exact, _) = conservation_errors(Method::DDMPM, Mapping::CubicSpline, 40, 12).unwrap();
    assert!((particles - p).abs() <= 0.02 * p, "{particles:e} vs {p:e}");
    assert!(exact < 0.05 * p, "{exact:e}");
}

/// tls-fig10, DDMPM without reconstruction: with particle-quadrature node
/// integrals DDMPM stays in MPM's regime (the paper: "only slightly
/// smoothens"), with exact node integrals it is ten times better.
#[test]
fn particle_quadrature_keeps_ddmpm_near_mpm_in_the_compaction_exact_integrals_do_not() {
    let mpm = compaction(Method::Mpm, Mapping::Direct)
        .unwrap()
        .stress_error;
    let particles = compaction(Method::DDMPM_PARTICLES, Mapping::Direct)
        .unwrap()
        .stress_error;
    let exact = compaction(Method::DDMPM, Mapping::Direct)
        .unwrap()
        .stress_error;
    assert!(
        (0.8..1.25).contains(&(particles / mpm)),
        "{particles:e} vs MPM {mpm:e}"
    );
    assert!(exact < 0.15 * mpm, "{exact:e} vs MPM {mpm:e}");
}

/// tls-8: the ratio column E_subpoints/E_TLS implies the same E_TLS in
/// every row (6.883e-3, within 0.1 %), which is not Figure 10's DDMPM + TLS
/// error (4.7796e-3): Table 8's reference run is not Figure 10's, so no
/// single run can reproduce both the ratio column and Figure 10.
#[test]
fn table_8_ratios_imply_a_reference_that_is_not_figure_10s() {
    let t8 = published("tls-8");
    let implied: Vec<f64> = t8
        .values
        .iter()
        .map(|r| r[0].unwrap() / r[1].unwrap())
        .collect();
    let mean = implied.iter().sum::<f64>() / implied.len() as f64;
    for e in &implied {
        assert!((e - mean).abs() < 1e-3 * mean, "{implied:?}");
    }
    assert!((mean - 6.883e-3).abs() < 1e-5, "{mean:e}");
    let fig10 = value(&published("tls-fig10"), "DDMPM", "TLS");
    assert!(mean / fig10 > 1.4, "{mean:e} vs {fig10:e}");
}

/// thesis-facts, the Courant number of column Table 4.4: the printed 6.5e-2
/// is c Δt/(H/65), the element size taken as H over the 65 DOFs, where
/// 64 elements give 6.4e-2.
#[test]
fn thesis_column_courant_number_divides_by_the_dof_count() {
    let c4 = column::parameters("thesis-table-4.4").unwrap();
    let by_dofs = c4.wave_speed() * 1e-4 / (c4.height / 65.0);
    let by_elements = c4.wave_speed() * 1e-4 / (c4.height / 64.0);
    let p = value(
        &published("thesis-facts"),
        "Courant number, column Table 4.4, 65 DOFs, Δt = 1e-4 (thesis §5.1.4)",
        "value",
    );
    assert!((by_dofs - p).abs() < 1e-12, "{by_dofs}");
    assert!((by_elements - p).abs() > 1e-3);
}

/// The mechanism behind tls-7's spline mass errors: with a uniform density
/// whose body ends inside a half span, beyond its second Gauss point, the
/// thesis' rule keeps the whole half span and integrates the extrapolated
/// spline past the free surface; clipping every half span to Ω_t ends the
/// integral at the surface, and the mapped mass is Σ m_p to rounding.
#[test]
fn clipping_every_half_span_ends_the_spline_integral_at_the_free_surface() {
    use hompm::mpm::grid::Grid;
    use hompm::mpm::mapping::ConsistentSolver;
    use hompm::mpm::mapping::MassMatrix;
    use hompm::mpm::musl::Simulation;
    use hompm::mpm::particles::Particles;
    // Four cells of size 1 on [0, 4]; the body fills [0, 3.45]: the last
    // half span [3, 3.5] has its Gauss points at 3.106 and 3.394.
    let mass_error = |mapping: Mapping| {
        let grid = Grid::new(Method::Bsmpm { degree: 2 }, 0.0, 4.0, 4).unwrap();
        let particles = Particles::uniform(0.0, 3.45, 30, 2.0).unwrap();
        let settings = common::free_settings(
            mapping,
            MassMatrix::Consistent(ConsistentSolver::Cholesky),
            10.0,
        );
        let mut sim = Simulation::new(grid, particles, settings).unwrap();
        sim.step(1e-6).unwrap();
        sim.diagnostics.max_mass_error
    };
    let thesis = mass_error(Mapping::CubicSpline);
    let clipped = mass_error(Mapping::CubicSplineClipped);
    // The thesis' rule integrates [3.45, 3.5] too: 0.05/3.45 of the mass.
    assert!((thesis - 0.05 / 3.45).abs() < 1e-9, "{thesis:e}");
    assert!(clipped < 1e-13, "{clipped:e}");
}

/// tls-7, cubic-spline mass errors: with the thesis' rule all three methods
/// lose 2.1e-3 in the compaction (a whole half span beyond the free surface,
/// 0.106 m of 50 m); with every half span clipped to Ω_t the errors fall to
/// the printed orders (within a factor of 2 of 3.08e-6, 4.76e-7, 1.51e-9).
/// The bar of tls-5, whose BSMPM spline mass error the thesis' rule
/// reproduces to 0.04 %, deviates by 12 % under clipping: no single rule
/// reproduces both tables.
#[test]
fn tls_7_spline_mass_errors_reach_the_printed_orders_when_every_half_span_is_clipped() {
    use hompm::studies::tls_paper::conservation_errors_for;
    let t7 = published("tls-7");
    for (method, column) in [
        (Method::Mpm, "MPM Error_M"),
        (Method::DDMPM, "DDMPM Error_M"),
        (Method::Bsmpm { degree: 2 }, "BSMPM Error_M"),
    ] {
        let p = value(&t7, "Cubic-spline", column);
        let thesis = compaction(method, Mapping::CubicSpline).unwrap().mass_error;
        let clipped = compaction(method, Mapping::CubicSplineClipped)
            .unwrap()
            .mass_error;
        assert!(
            (thesis - 0.1057 / 50.0).abs() < 2e-5,
            "{column}: {thesis:e}"
        );
        assert!(
            (clipped / p).log2().abs() <= 1.0,
            "{column}: {clipped:e} vs {p:e}"
        );
    }
    let p5 = value(&published("tls-5"), "Cubic-spline", "BSMPM Error_M");
    let bar = |mapping| {
        conservation_errors_for(
            "tls-table-4",
            Method::Bsmpm { degree: 2 },
            mapping,
            20,
            8,
            1e-4,
            1000,
        )
        .unwrap()
        .0
    };
    assert!((bar(Mapping::CubicSpline) - p5).abs() < 0.02 * p5);
    assert!((bar(Mapping::CubicSplineClipped) - p5).abs() > 0.05 * p5);
}

/// tls-fig6, BSMPM with a reconstruction: the paper states third-order
/// convergence "for all the considered quantities" with quadratic
/// B-splines. Under each of three stress definitions — the particle stress,
/// E times the derivative of a not-a-knot spline through the particle
/// displacements, and the continuous RMS of a spline through the particle
/// stresses — the fitted order is 2 (p), never 3; cubic B-splines, which
/// the paper excludes ("restrict the analysis to quadratic B-spline basis
/// functions"), give 3.
#[test]
fn fig6_bsmpm_stress_order_is_p_under_every_stress_definition_tried() {
    use hompm::reconstruct::cubic_spline::{CubicSpline, EndCondition};
    use hompm::scenes::{vibrating_bar, Discretisation};
    use hompm::studies::tls_paper::{fitted_order, mass_for};
    let p = vibrating_bar::parameters("tls-table-2").unwrap();
    let rms = |a: &[f64], b: &[f64]| {
        (a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>() / a.len() as f64).sqrt()
    };
    let orders = |degree: usize| {
        let (mut h, mut e) = (vec![], [vec![], vec![], vec![]]);
        for cells in [5, 10, 20, 40] {
            let d = Discretisation::new(
                Method::Bsmpm { degree },
                Mapping::CubicSpline,
                mass_for(Mapping::CubicSpline),
                cells,
                12,
            );
            let mut sim = p.simulation(&d).unwrap();
            sim.run(1e-7, 19).unwrap();
            let (t, q) = (sim.time, &sim.particles);
            let exact: Vec<f64> = q.x0.iter().map(|&x| p.stress(x, t)).collect();
            let u = CubicSpline::new(&q.x0, &q.displacement, EndCondition::NotAKnot).unwrap();
            let dx = 1e-6 * p.length / cells as f64;
            let from_u: Vec<f64> =
                q.x0.iter()
                    .map(|&x| p.young * (u.evaluate(x + dx) - u.evaluate(x - dx)) / (2.0 * dx))
                    .collect();
            let s = CubicSpline::new(&q.x0, &q.stress, EndCondition::NotAKnot).unwrap();
            let (lo, hi) = (q.x0[0], q.x0[q.len() - 1]);
            let xs: Vec<f64> = (0..100 * cells)
                .map(|k| lo + (hi - lo) * (k as f64 + 0.5) / (100 * cells) as f64)
                .collect();
            let field: Vec<f64> = xs.iter().map(|&x| s.evaluate(x)).collect();
            let field_exact: Vec<f64> = xs.iter().map(|&x| p.stress(x, t)).collect();
            h.push(p.length / cells as f64);
            e[0].push(rms(&q.stress, &exact));
            e[1].push(rms(&from_u, &exact));
            e[2].push(rms(&field, &field_exact));
        }
        e.map(|e| fitted_order(&h, &e))
    };
    for order in orders(2) {
        assert!((order - 2.0).abs() < 0.1, "quadratic: {order}");
    }
    for order in orders(3) {
        assert!((order - 3.0).abs() < 0.1, "cubic: {order}");
    }
}

/// thesis-facts, book §4.5's "more than 450" crossings of standard MPM: with
/// the stated 20 elements × 8 PPC over 0.1 s, neither the book's Table 4.1
/// parameters (E = 7e6 Pa) nor the TLS paper's Table 4 (E = 4e4 Pa) come
/// near it (112 and 117 crossings counted as gradient breaks passed); 40
/// elements with the TLS paper's parameters would (463). An experiment,
/// not a demonstration: other counting rules are untried.
#[test]
fn book_450_crossings_are_not_reached_with_the_stated_twenty_elements() {
    use hompm::scenes::{vibrating_bar, Discretisation};
    let crossings = |params: &str, cells: usize| {
        let p = vibrating_bar::parameters(params).unwrap();
        let mut sim = p
            .simulation(&Discretisation::direct(Method::Mpm, cells, 8))
            .unwrap();
        sim.run(1e-5, 10_000).unwrap();
        sim.diagnostics.grid_crossings
    };
    assert_eq!(crossings("book-table-4.1-large", 20), 112);
    assert_eq!(crossings("tls-table-4", 20), 117);
    assert!(crossings("tls-table-4", 40) > 450);
}

/// The cause of tls-5's (and tls-7's) TLS Error_M rows in
/// golden/deviation-causes.json.
#[test]
fn tls_5_mass_errors_are_the_rounding_of_the_tls_authors_cell_average() {
    use hompm::reconstruct::taylor::CellAverage;
    use hompm::studies::tls_paper::{BarRun, TLS_METHODS};
    let p = published("tls-5");
    let bar = BarRun {
        params: "tls-table-4",
        cells: 20,
        ppc: 8,
        dt: 1e-4,
        steps: 1000,
    };
    for method in TLS_METHODS {
        let name = match method {
            Method::Mpm => "MPM",
            Method::Ddmpm { .. } => "DDMPM",
            _ => "BSMPM",
        };
        let printed = value(&p, "TLS", &format!("{name} Error_M"));
        let exact = bar
            .conservation_errors(method, Mapping::Tls, CellAverage::Exact)
            .unwrap()
            .0;
        let author = bar
            .conservation_errors(method, Mapping::Tls, CellAverage::AntiderivativeDifference)
            .unwrap()
            .0;
        // The exact average leaves the mass error a decade and more below
        // the printed one; the antiderivative at the absolute cell ends
        // brings it to within 15 % (2.74, 2.59, 2.55e-14 against 2.91,
        // 2.90, 2.89e-14; the compaction of tls-7 gives 1.0525, 1.0522,
        // 1.0527e-12 against 1.0526, 1.0524, 1.0527e-12, too slow for here).
        assert!(exact < printed / 10.0, "{name}: exact average {exact:e}");
        assert!(
            (author - printed).abs() < 0.15 * printed,
            "{name}: author's average {author:e} against {printed:e}"
        );
    }
}

/// The cause of book-4.5-large's conservation rows in
/// golden/deviation-causes.json: its mass error is tls-5's printed TLS
/// value to every digit (a reprint), and the book's own setup with the TLS
/// author's cell average lands both errors in the printed decade, which the
/// exact average misses.
#[test]
fn book_4_5_large_conservation_errors_reach_the_printed_decade_with_the_tls_authors_cell_average() {
    use hompm::reconstruct::taylor::CellAverage;
    use hompm::studies::tls_paper::BarRun;
    use hompm::tables::Tolerance;
    let book = published("book-4.5-large");
    let row = &book.row_labels[0];
    let mass = value(&book, row, "max relative mass error");
    let momentum = value(&book, row, "max relative momentum error");
    assert_eq!(mass, value(&published("tls-5"), "TLS", "MPM Error_M"));
    let bar = BarRun {
        params: "book-table-4.1-large",
        cells: 20,
        ppc: 8,
        dt: 1e-5,
        steps: 10_000,
    };
    let bsmpm = Method::Bsmpm { degree: 2 };
    let run = |average| {
        bar.conservation_errors(bsmpm, Mapping::Tls, average)
            .unwrap()
    };
    let (exact_m, exact_p) = run(CellAverage::Exact);
    let (author_m, author_p) = run(CellAverage::AntiderivativeDifference);
    let same_decade =
        |published, computed| Tolerance::MachinePrecision.accepts(published, computed);
    assert!(
        !same_decade(mass, exact_m) && !same_decade(momentum, exact_p),
        "{exact_m:e} {exact_p:e}"
    );
    assert!(
        same_decade(mass, author_m) && same_decade(momentum, author_p),
        "{author_m:e} {author_p:e}"
    );
}

/// tls-7, the cubic-spline momentum errors (printed 3.54e-6, 2.04e-6,
/// 1.40e-7; computed 0.29, 0.058, 0.107). Under the ramp the column's total
/// momentum Σ m_p v_p swings between about −33 kg m/s and zero once per
/// period (0.2 s), so the relative error |1ᵀMv − Σ m_p v_p| / |Σ m_p v_p|
/// divides by almost nothing at t ≈ 0.196 s, and the maximum over steps
/// is that spike. Away from it, at the end of the run, the same relative
/// error has the printed orders (MPM within 2 %).
#[test]
fn tls_7_spline_momentum_errors_peak_where_the_columns_momentum_passes_zero() {
    use hompm::mpm::musl::RampTimeLevel;
    use hompm::reconstruct::taylor::CellAverage;
    use hompm::studies::tls_paper::{compaction_start, COMPACTION_DT, COMPACTION_STEPS};
    let t7 = published("tls-7");
    for (method, column, within) in [
        (Method::Mpm, "MPM Error_P", 0.02),
        (Method::DDMPM, "DDMPM Error_P", 0.5),
        (Method::Bsmpm { degree: 2 }, "BSMPM Error_P", 0.5),
    ] {
        let printed = value(&t7, "Cubic-spline", column);
        let mut sim = compaction_start(method, Mapping::CubicSpline).unwrap();
        assert_eq!(sim.settings.tls_density_average, CellAverage::Exact);
        assert_eq!(
            sim.settings.gravity_ramp.unwrap().time_level,
            RampTimeLevel::StepStart
        );
        let (mut largest_momentum, mut momentum_at_max, mut max_error) = (0.0f64, 0.0, 0.0);
        for _ in 0..COMPACTION_STEPS {
            sim.step(COMPACTION_DT).unwrap();
            let momentum = sim.particles.total_momentum().abs();
            largest_momentum = largest_momentum.max(momentum);
            if sim.diagnostics.max_momentum_error > max_error {
                max_error = sim.diagnostics.max_momentum_error;
                momentum_at_max = momentum;
            }
        }
        assert!(largest_momentum > 30.0, "{column}: {largest_momentum}");
        assert!(
            momentum_at_max < 1e-3 * largest_momentum,
            "{column}: the maximum is taken at |P| = {momentum_at_max:e}"
        );
        assert!(max_error > 1e3 * printed, "{column}: {max_error:e}");
        let at_end = sim.diagnostics.last_momentum_error;
        assert!(
            (at_end / printed - 1.0).abs() <= within,
            "{column}: {at_end:e} at the end against {printed:e}"
        );
    }
}

/// tls-fig10: the errors are taken against the quasi-static stress
/// ρ₀b(H − X), and the ramp leaves a dynamic remainder of its own: a
/// converged ULFEM column with the same law and ramp differs from the
/// quasi-static stress by 3.6e-3 (relative L2 at the particles), which is
/// most of BSMPM's error (3.4e-3 against the quasi-static, 5e-4 against the
/// dynamic solution). That remainder depends on when in a step the ramp is
/// read: read at the step's end (tⁿ⁺¹) instead of its start (TLS paper
/// Eq. 10's tⁿ), MPM without reconstruction and DDMPM with either
/// reconstruction reproduce (within 2 %), where at tⁿ they are 5–8 % off.
#[test]
fn fig10_errors_carry_the_ramps_dynamic_remainder_which_the_force_time_level_moves() {
    use hompm::mpm::diagnostics::relative_l2_error;
    use hompm::mpm::musl::RampTimeLevel;
    use hompm::reconstruct::taylor::CellAverage;
    use hompm::studies::tls_paper::{
        as_paper_ran, compaction_dynamic_reference, compaction_simulation, compaction_stress_error,
    };
    let p = column::parameters("tls-table-6").unwrap();
    let fig10 = published("tls-fig10");
    // The dynamic reference, converged in space and time.
    let fine = compaction_dynamic_reference(1000, 2e-5, RampTimeLevel::StepStart).unwrap();
    let coarse = compaction_dynamic_reference(500, 4e-5, RampTimeLevel::StepStart).unwrap();
    let x0: Vec<f64> = (0..1000).map(|k| (k as f64 + 0.5) * 0.05).collect();
    let quasi_static: Vec<f64> = x0.iter().map(|&x| p.equilibrium_stress(x, 0.5)).collect();
    let dynamic: Vec<f64> = x0.iter().map(|&x| fine.stress_at(x)).collect();
    let coarse_dynamic: Vec<f64> = x0.iter().map(|&x| coarse.stress_at(x)).collect();
    let remainder = relative_l2_error(&dynamic, &quasi_static).unwrap();
    assert!((3.3e-3..3.9e-3).contains(&remainder), "{remainder:e}");
    assert!(relative_l2_error(&coarse_dynamic, &dynamic).unwrap() < 0.02 * remainder);
    // BSMPM follows the dynamic solution far more closely than either
    // follows the quasi-static one.
    let bsmpm = compaction_simulation(
        Method::Bsmpm { degree: 2 },
        Mapping::Direct,
        CellAverage::Exact,
        RampTimeLevel::StepStart,
    )
    .unwrap();
    let at_particles = |stress: &dyn Fn(f64) -> f64| -> Vec<f64> {
        bsmpm.particles.x0.iter().map(|&x| stress(x)).collect()
    };
    let against_dynamic = relative_l2_error(
        &bsmpm.particles.stress,
        &at_particles(&|x| fine.stress_at(x)),
    )
    .unwrap();
    let against_static = relative_l2_error(
        &bsmpm.particles.stress,
        &at_particles(&|x| p.equilibrium_stress(x, 0.5)),
    )
    .unwrap();
    assert!(
        against_dynamic < 0.2 * against_static,
        "{against_dynamic:e} {against_static:e}"
    );
    // The time level of the ramp: three rows move into 2 % of the figure.
    for (method, mapping, row, column) in [
        (Method::Mpm, Mapping::Direct, "MPM", "no reconstruction"),
        (Method::DDMPM, Mapping::CubicSpline, "DDMPM", "cubic spline"),
        (Method::DDMPM, Mapping::Tls, "DDMPM", "TLS"),
    ] {
        let printed = value(&fig10, row, column);
        let error_at = |level| {
            let sim = compaction_simulation(
                as_paper_ran(method, mapping),
                mapping,
                CellAverage::Exact,
                level,
            )
            .unwrap();
            compaction_stress_error(&sim).unwrap()
        };
        let start = compaction(as_paper_ran(method, mapping), mapping)
            .unwrap()
            .stress_error;
        let end = error_at(RampTimeLevel::StepEnd);
        assert!(
            (start / printed - 1.0).abs() > 0.05,
            "{row} {column}: {start:e}"
        );
        assert!(
            (end / printed - 1.0).abs() < 0.02,
            "{row} {column}: {end:e} vs {printed:e}"
        );
    }
}
