//! `hompm exact`, `trace` and `check` as an author of another MPM code meets
//! them (issue #24): the exact fields are the seeds' solutions, a traced run
//! is the run, and `check` names the step, equation and particle of a defect
//! planted in an otherwise correct code.

use hompm::mpm::grid::Method;
use hompm::mpm::mapping::{ConsistentSolver, Mapping, MassMatrix};
use hompm::mpm::musl::{NoObserver, Simulation, StepObserver, StepPoint};
use hompm::mpm2d::Mapping2d;
use hompm::oracle::check::{check, CheckOptions, DEFAULT_ATOL, DEFAULT_RTOL};
use hompm::oracle::exact::{column_closed_form, exact_1d};
use hompm::oracle::input::{parse_input, ColumnMap, Input};
use hompm::oracle::run::{reference, run_1d, trace_1d};
use hompm::oracle::setup::{Overrides, Scene1d, Setup, Setup1d};
use hompm::oracle::trace::{header_1d, Trace, TraceObserver};
use hompm::scenes::column;
use hompm::scenes::Discretisation;
use hompm::solve::richardson::{richardson, richardson_with, ResidualNorm};
use hompm::sparse::SparseMatrix;
use hompm::Error;

/// The thesis' bar (Table 4.1) on 8 cells × 2 PPC for `steps` steps of
/// 1e-3 s (Courant number 0.32).
fn bar(method: Method, mapping: Mapping, mass: MassMatrix, steps: usize) -> Setup1d {
    Setup1d {
        scene: Scene1d::bar("thesis-table-4.1", &Overrides::default()).unwrap(),
        discretisation: Discretisation::new(method, mapping, mass, 8, 2),
        dt: 1e-3,
        steps,
    }
}

fn quadratic_bar(steps: usize) -> Setup1d {
    bar(
        Method::Bsmpm { degree: 2 },
        Mapping::Direct,
        MassMatrix::Lumped,
        steps,
    )
}

/// A code that is hompm with one defect: `plant` alters the simulation at
/// a point of a step, and the trace is recorded after it.
struct Defective<F: FnMut(StepPoint, usize, &mut Simulation)> {
    plant: F,
    trace: TraceObserver,
}

impl<F: FnMut(StepPoint, usize, &mut Simulation)> StepObserver for Defective<F> {
    fn observe(&mut self, point: StepPoint, sim: &mut Simulation) -> hompm::Result<()> {
        let step = hompm::mpm::monitor::Watched::steps_done(sim) + 1;
        (self.plant)(point, step, sim);
        self.trace.observe(point, sim)
    }
}

/// The other code's trace, with `plant` inside its steps.
fn defective_trace(s: &Setup1d, plant: impl FnMut(StepPoint, usize, &mut Simulation)) -> Trace {
    let mut code = Defective {
        plant,
        trace: TraceObserver::new(s.dt, 1, s.steps, s.scene.constitutive()),
    };
    run_1d(s, &mut code, &mut |_| {}).unwrap();
    code.trace.into_trace(header_1d(s).unwrap())
}

/// `hompm check` of a trace against hompm's run of `s`.
fn check_trace(s: &Setup1d, theirs: Trace) -> hompm::oracle::check::CheckReport {
    let setup = Setup::OneD(*s);
    let only = theirs.steps.iter().map(|t| t.step).collect();
    let (state, ours) = reference(&setup, Some(only)).unwrap();
    check(
        &setup,
        &state,
        &Input::Trace(theirs),
        ours.as_ref(),
        &CheckOptions::default(),
    )
    .unwrap()
}

/// The first index of `values` whose change by `delta(v)` fails the
/// default tolerance rule: where the checker must point.
fn first_visible(values: &[f64], delta: impl Fn(f64) -> f64) -> usize {
    values
        .iter()
        .position(|&v| {
            let d = delta(v).abs();
            d > DEFAULT_ATOL && d > DEFAULT_RTOL * v.abs()
        })
        .expect("the defect is visible somewhere")
}

#[test]
fn a_traced_run_is_bit_identical_to_an_untraced_one() {
    for s in [
        quadratic_bar(20),
        bar(
            Method::Bsmpm { degree: 2 },
            Mapping::CubicSpline,
            MassMatrix::Consistent(ConsistentSolver::richardson(1e-9)),
            20,
        ),
    ] {
        let plain = run_1d(&s, &mut NoObserver, &mut |_| {}).unwrap();
        let (trace, traced) = trace_1d(&s, 1, None).unwrap();
        assert_eq!(plain.simulation.particles, traced.simulation.particles);
        assert_eq!(trace.steps.len(), 20);
        // The trace's last u_p and σ_p are the run's final state.
        let last = &trace.steps[19].equations;
        assert_eq!(last["book-4.12"], traced.simulation.particles.displacement);
        assert_eq!(last["book-4.15"], traced.simulation.particles.stress);
    }
}

#[test]
fn every_n_traces_steps_one_one_plus_n_and_the_last() {
    let (trace, _) = trace_1d(&quadratic_bar(10), 4, None).unwrap();
    let steps: Vec<usize> = trace.steps.iter().map(|s| s.step).collect();
    assert_eq!(steps, [1, 5, 9, 10]);
    assert_eq!(trace.steps[1].time, 5.0 * 1e-3);
}

#[test]
fn the_trace_holds_the_equations_as_the_step_computes_them() {
    let s = quadratic_bar(3);
    let (trace, _) = trace_1d(&s, 1, None).unwrap();
    let e = &trace.steps[2].equations;
    let dt = s.dt;
    // Eq. (4.8): a_i = (f_ext − f_int)_i / m_i where m_i ≠ 0.
    for (i, m) in e["book-4.5"].iter().enumerate() {
        let a = (e["thesis-3.2"][i] - e["book-4.6"][i]) / m;
        assert_eq!(e["book-4.8"][i], a, "DOF {i}");
    }
    // The boundary conditions zero the end DOFs only.
    let last = e["book-4.8"].len() - 1;
    assert_eq!(e["book-4.8-bc"][0], 0.0);
    assert_eq!(e["book-4.8-bc"][last], 0.0);
    assert_eq!(e["book-4.8-bc"][1..last], e["book-4.8"][1..last]);
    // Eq. (4.10) with the lumped mass: v_i = p_i / m_i (m_i the row sum,
    // equal to the lumped mass of Eq. 4.5 at the same positions).
    for (i, m) in e["book-4.5"].iter().enumerate() {
        let v = e["book-4.10-rhs"][i] / m;
        assert!(
            (e["book-4.10"][i] - v).abs() <= 1e-15 * v.abs().max(1e-300),
            "DOF {i}"
        );
    }
    // Eq. (4.11): Δu_i = Δt v_i with the boundary conditions.
    for (du, v) in e["book-4.11"].iter().zip(&e["book-4.10-bc"]) {
        assert_eq!(*du, dt * v);
    }
    // Eqs. (4.15), (4.17), (4.18) from step 2's state.
    let before = &trace.steps[1].equations;
    for k in 0..e["book-4.14"].len() {
        let de = e["book-4.14"][k];
        assert_eq!(e["book-4.15"][k], before["book-4.15"][k] + 100.0 * de);
        assert_eq!(e["book-4.17"][k], before["book-4.17"][k] * (1.0 + de));
        assert_eq!(e["book-4.18"][k], before["book-4.18"][k] / (1.0 + de));
    }
    // The lumped solve takes no iterations.
    assert_eq!(e["book-4.10-solver"], [0.0, 0.0]);
}

#[test]
fn check_names_step_3_and_eq_4_8_for_a_one_per_cent_acceleration_defect() {
    let s = quadratic_bar(5);
    let theirs = defective_trace(&s, |point, step, sim| {
        if point == StepPoint::Acceleration && step == 3 {
            for a in &mut sim.workspace_mut().acceleration {
                *a *= 1.01;
            }
        }
    });
    let (ours, _) = trace_1d(&s, 1, None).unwrap();
    let expected = first_visible(&ours.steps[2].equations["book-4.8"], |a| 0.01 * a);
    let r = check_trace(&s, theirs);
    assert!(!r.agrees);
    let d = r.first_difference.expect("a first difference");
    assert_eq!(
        (d.step, d.equation.as_str(), d.index),
        (3, "book-4.8", expected)
    );
    assert_eq!(d.citation, "book Eq. (4.8)");
    assert!(
        r.verdict
            .starts_with(&format!("differs from step 3 at book Eq. (4.8), the nodal acceleration before the boundary conditions a_i, DOF {expected}")),
        "{}",
        r.verdict
    );
}

#[test]
fn check_names_eq_4_14_and_the_particle_for_a_sign_error_in_the_strain_increment() {
    let s = quadratic_bar(5);
    let theirs = defective_trace(&s, |point, _, sim| {
        if point == StepPoint::Positions {
            for de in &mut sim.workspace_mut().strain_increment {
                *de = -*de;
            }
        }
    });
    let (ours, _) = trace_1d(&s, 1, None).unwrap();
    let expected = first_visible(&ours.steps[0].equations["book-4.14"], |de| 2.0 * de);
    let d = check_trace(&s, theirs).first_difference.unwrap();
    assert_eq!((d.step, d.equation.as_str()), (1, "book-4.14"));
    assert_eq!((d.index_kind.as_str(), d.index), ("particle", expected));
}

#[test]
fn check_names_eq_4_18_for_a_density_multiplied_where_it_should_be_divided() {
    let s = quadratic_bar(5);
    let theirs = defective_trace(&s, |point, _, sim| {
        if point == StepPoint::VolumeAndDensity {
            let de = sim.workspace().strain_increment.clone();
            for (rho, d) in sim.particles.density.iter_mut().zip(de) {
                // ρ(1 + Δε) instead of ρ/(1 + Δε).
                *rho *= (1.0 + d) * (1.0 + d);
            }
        }
    });
    let (ours, _) = trace_1d(&s, 1, None).unwrap();
    let expected = first_visible(&ours.steps[0].equations["book-4.14"], |de| 2.0 * de);
    let d = check_trace(&s, theirs).first_difference.unwrap();
    assert_eq!(
        (d.step, d.equation.as_str(), d.index),
        (1, "book-4.18", expected)
    );
    assert_eq!(d.citation, "book Eq. (4.18)");
}

#[test]
fn check_names_the_fixed_dof_when_the_velocity_boundary_condition_is_missing() {
    let s = quadratic_bar(5);
    let theirs = defective_trace(&s, |point, _, sim| {
        if point == StepPoint::NodalVelocityConditions {
            let m = &mut sim.workspace_mut().mapping;
            // v_0 as projected, not zeroed.
            m.velocity[0] = m.momentum[0] / m.lumped[0];
        }
    });
    let d = check_trace(&s, theirs).first_difference.unwrap();
    assert_eq!((d.step, d.equation.as_str()), (1, "book-4.10-bc"));
    assert_eq!((d.index_kind.as_str(), d.index), ("DOF", 0));
    assert_eq!(d.values.hompm, 0.0);
    assert!(d.values.yours > 0.0);
}

#[test]
fn check_names_eq_4_10_at_step_1_for_richardson_stopped_at_1e_6() {
    let spline = |tolerance| {
        bar(
            Method::Bsmpm { degree: 2 },
            Mapping::CubicSpline,
            MassMatrix::Consistent(ConsistentSolver::richardson(tolerance)),
            5,
        )
    };
    let (mut theirs, _) = trace_1d(&spline(1e-6), 1, None).unwrap();
    // The other code's trace carries no hompm header.
    theirs.header.clear();
    let r = check_trace(&spline(1e-9), theirs);
    let d = r.first_difference.unwrap();
    assert_eq!((d.step, d.equation.as_str()), (1, "book-4.10"));
    assert_ne!(d.values.yours, d.values.hompm);
    let (ours, _) = trace_1d(&spline(1e-9), 1, None).unwrap();
    let solver = &ours.steps[0].equations["book-4.10-solver"];
    assert!(solver[0] >= 1.0 && solver[1] <= 1e-9, "{solver:?}");
}

#[test]
fn a_trace_of_other_settings_is_refused_by_its_header() {
    let s = quadratic_bar(3);
    let (mut theirs, _) = trace_1d(&s, 1, None).unwrap();
    theirs.header.insert("dt".into(), serde_json::json!(2e-3));
    let ours = hompm::oracle::trace::header_1d(&s).unwrap();
    match hompm::oracle::check::check_header(&theirs.header, &ours) {
        Err(Error::Input(m)) => assert!(m.contains("dt: yours 0.002, hompm's 0.001"), "{m}"),
        other => panic!("{other:?}"),
    }
}

/// hompm's final particles as CSV rows in a shuffled order, with the
/// columns named `names` (ours → theirs) and without `drop`.
fn shuffled_csv(s: &Setup1d, names: &[(&str, &str)], drop: &[&str]) -> String {
    let (state, _) = reference(&Setup::OneD(*s), None).unwrap();
    let t = &state.particles;
    let n = t.rows();
    let mut order: Vec<usize> = (0..n).collect();
    let mut rng = hompm::rng::SplitMix64::new(24);
    for i in (1..n).rev() {
        let j = (rng.next_u64() % (i as u64 + 1)) as usize;
        order.swap(i, j);
    }
    let cols: Vec<&(String, Vec<f64>)> = t
        .columns
        .iter()
        .filter(|(c, _)| !drop.contains(&c.as_str()))
        .collect();
    let rename = |c: &str| -> String {
        names
            .iter()
            .find(|(o, _)| *o == c)
            .map_or(c.to_string(), |(_, t)| t.to_string())
    };
    let mut out = cols
        .iter()
        .map(|(c, _)| rename(c))
        .collect::<Vec<_>>()
        .join(",")
        + "\n";
    for &k in &order {
        let row: Vec<String> = cols.iter().map(|(_, v)| format!("{:e}", v[k])).collect();
        out.push_str(&(row.join(",") + "\n"));
    }
    out
}

fn check_text(
    s: &Setup1d,
    text: &str,
    map: &str,
) -> hompm::Result<hompm::oracle::check::CheckReport> {
    let (input, _) = parse_input(text, &ColumnMap::parse(map)?, false)?;
    let setup = Setup::OneD(*s);
    let (state, _) = reference(&setup, None)?;
    check(&setup, &state, &input, None, &CheckOptions::default())
}

#[test]
fn a_shuffled_but_correct_output_agrees_matched_by_id_or_by_initial_position() {
    let s = quadratic_bar(20);
    let by_id = check_text(&s, &shuffled_csv(&s, &[], &[]), "").unwrap();
    assert!(by_id.agrees, "{}", by_id.verdict);
    assert_eq!(by_id.matched_by, "id");
    assert!(
        by_id.verdict.starts_with("agrees with hompm's BSMPM-p2"),
        "{}",
        by_id.verdict
    );
    let renamed = shuffled_csv(&s, &[("x0", "X"), ("u", "disp")], &["id"]);
    let by_x0 = check_text(&s, &renamed, "x0=X,u=disp").unwrap();
    assert!(by_x0.agrees, "{}", by_x0.verdict);
    assert_eq!(by_x0.matched_by, "x0");
    assert_eq!(by_x0.fields["u"].max_abs, 0.0);
    // Both codes' errors against the exact solution are the same numbers.
    let u = by_x0.fields["u"].rms_exact.unwrap();
    assert_eq!(u.yours, u.hompm);
    assert_eq!(by_x0.error_ratio, Some(1.0));
}

#[test]
fn the_rms_error_against_the_exact_solution_is_the_thesis_rms_at_the_initial_positions() {
    let s = quadratic_bar(20);
    let r = check_text(&s, &shuffled_csv(&s, &[], &[]), "").unwrap();
    let run = run_1d(&s, &mut NoObserver, &mut |_| {}).unwrap();
    let p = &run.simulation.particles;
    let t = 20.0 * 1e-3;
    let Scene1d::VibratingBar(bar) = s.scene else {
        unreachable!()
    };
    // u = v0/ω sin(ωt) sin(πX/L), written out here.
    let omega = std::f64::consts::PI * (bar.young / bar.density).sqrt() / bar.length;
    let sum: f64 = p
        .x0
        .iter()
        .zip(&p.displacement)
        .map(|(x, u)| {
            let exact =
                bar.v0 / omega * (omega * t).sin() * (std::f64::consts::PI * x / bar.length).sin();
            (u - exact).powi(2)
        })
        .sum();
    let rms = (sum / p.len() as f64).sqrt();
    let got = r.fields["u"].rms_exact.unwrap().yours;
    assert!((got - rms).abs() <= 1e-15 * rms, "{got} {rms}");
}

/// `text` with the cell at `row` (0: the header) and `column` replaced.
fn with_cell(text: &str, row: usize, column: usize, value: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let mut cells: Vec<&str> = lines[row].split(',').collect();
    cells[column] = value;
    lines[row] = cells.join(",");
    lines.join("\n")
}

#[test]
fn bad_input_files_are_refused_with_one_sentence() {
    let s = quadratic_bar(2);
    let good = shuffled_csv(&s, &[], &[]);
    let cases: Vec<(String, &str, &str)> = vec![
        (String::new(), "", "empty"),
        ("x0,u\n".into(), "", "no rows"),
        (
            good.replacen("id,", "id,id2,", 1),
            "",
            "values but the header names",
        ),
        (good.replace("x0,x,", "x0,x0,"), "", "appears twice"),
        (with_cell(&good, 1, 1, "NaN"), "", "must be finite"),
        (with_cell(&good, 2, 3, "inf"), "", "must be finite"),
        (good.replacen("\n0e0,", "\nzero,", 1), "", "is not a number"),
        (
            good.lines().take(5).collect::<Vec<_>>().join("\n"),
            "",
            "particles, the setup has 16",
        ),
        (good.clone(), "weird=x0", "not a column of hompm's"),
        (good.clone(), "u=nope", "does not have"),
        ("a,b\n1,2\n".into(), "", "none of hompm's columns"),
    ];
    for (text, map, needle) in cases {
        match check_text(&s, &text, map) {
            Err(e @ Error::Input(_)) => {
                assert!(e.to_string().contains(needle), "{needle}: {e}");
                assert_eq!(hompm::cli::exit_code(&e), 2);
            }
            other => panic!("{needle}: {other:?}"),
        }
    }
    // A duplicated particle names both rows.
    let dup = good.replacen("\n1e0,", "\n0e0,", 1);
    match check_text(&s, &dup, "") {
        Err(Error::Input(m)) => assert!(m.contains("both have id 0"), "{m}"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn richardson_with_the_solution_rule_divides_the_residual_by_the_iterate() {
    // A 3 × 3 mass-like matrix whose solution is small: ‖v‖ < ‖P‖, so the
    // solution rule is the stricter one and needs more iterations.
    let m = SparseMatrix::from_triplets(
        3,
        3,
        &[
            (0, 0, 4.0),
            (0, 1, 1.0),
            (1, 0, 1.0),
            (1, 1, 4.0),
            (1, 2, 1.0),
            (2, 1, 1.0),
            (2, 2, 4.0),
        ],
    )
    .unwrap();
    let lumped = m.row_sums();
    let p = [1.0, 2.0, 3.0];
    let rhs = richardson(&m, &lumped, &p, 1e-9, 1000).unwrap();
    let sol = richardson_with(&m, &lumped, &p, 1e-9, ResidualNorm::Solution, 1000).unwrap();
    assert!(
        sol.iterations > rhs.iterations,
        "{} {}",
        sol.iterations,
        rhs.iterations
    );
    let residual_over = |v: &[f64]| {
        let mut mv = vec![0.0; 3];
        m.mul_vec(v, &mut mv);
        let r: f64 = p
            .iter()
            .zip(&mv)
            .map(|(a, b)| (a - b).powi(2))
            .sum::<f64>()
            .sqrt();
        let vn: f64 = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let pn: f64 = p.iter().map(|x| x * x).sum::<f64>().sqrt();
        (r / vn, r / pn)
    };
    let (over_v, _) = residual_over(&sol.solution);
    assert_eq!(*sol.residuals.last().unwrap(), over_v);
    assert!(over_v < 1e-9);
    // The iterate before the last did not meet the rule.
    assert!(sol.residuals[sol.residuals.len() - 2] >= 1e-9);
    let (_, over_p) = residual_over(&rhs.solution);
    assert!(over_p <= 1e-9);
    // At a tolerance equal to the first iterate's ratio, the ‖P‖ rule
    // (≤) stops there and the ‖v‖ rule (<, as the author's `while … >= tol`)
    // does not.
    let v0: Vec<f64> = p.iter().zip(&lumped).map(|(a, l)| a / l).collect();
    let mut mv = vec![0.0; 3];
    m.mul_vec(&v0, &mut mv);
    let r: Vec<f64> = p.iter().zip(&mv).map(|(a, b)| a - b).collect();
    let (rn, vn, pn) = (
        hompm::solve::norm(&r),
        hompm::solve::norm(&v0),
        hompm::solve::norm(&p),
    );
    let at_rhs = richardson_with(&m, &lumped, &p, rn / pn, ResidualNorm::Rhs, 1000).unwrap();
    assert_eq!(at_rhs.iterations, 0);
    let at_sol = richardson_with(&m, &lumped, &p, rn / vn, ResidualNorm::Solution, 1000).unwrap();
    assert!(at_sol.iterations >= 1, "{}", at_sol.iterations);
}

#[test]
fn the_column_closed_form_is_the_limit_of_the_thesis_series() {
    for name in ["thesis-table-4.3", "thesis-table-8.1"] {
        let p = column::parameters(name).unwrap();
        let scale = column_closed_form(&p, p.height, 0.0).u.abs().max(
            column_closed_form(&p, p.height, p.height / p.wave_speed())
                .u
                .abs(),
        );
        for (y, t) in [(0.3, 0.1), (0.7, 0.37), (0.95, 1.3), (0.5, 2.9)] {
            let (y, t) = (y * p.height, t * p.height / p.wave_speed());
            let closed = column_closed_form(&p, y, t).u;
            let far = (p.displacement(y, t, 4000) - closed).abs();
            let near = (p.displacement(y, t, 40) - closed).abs();
            assert!(
                far <= 1e-6 * scale,
                "{name} y={y} t={t}: {far:e} vs {scale:e}"
            );
            assert!(far < near, "{name}: the series approaches the closed form");
        }
    }
}

#[test]
fn the_column_exact_fields_meet_the_boundary_conditions_and_the_wave_equation() {
    let p = column::parameters("thesis-table-8.1").unwrap();
    let (h, c) = (p.height, p.wave_speed());
    // The top load acts from t > 0 (at t = 0 the column is unstrained).
    for t in [0.21 * h / c, 1.7 * h / c, 5.3 * h / c] {
        assert_eq!(column_closed_form(&p, 0.0, t).u, 0.0);
        let top = column_closed_form(&p, h, t).stress;
        assert!((top - p.top_load).abs() <= 1e-9 * p.top_load.abs(), "{top}");
    }
    // v = ∂u/∂t and ε = ∂u/∂y by central differences, away from the kinks.
    let (y, t) = (0.43 * h, 0.61 * h / c);
    let e = column_closed_form(&p, y, t);
    let (dt, dy) = (1e-6 * h / c, 1e-6 * h);
    let dudt =
        (column_closed_form(&p, y, t + dt).u - column_closed_form(&p, y, t - dt).u) / (2.0 * dt);
    let dudy =
        (column_closed_form(&p, y + dy, t).u - column_closed_form(&p, y - dy, t).u) / (2.0 * dy);
    assert!(
        (dudt - e.v).abs() <= 1e-6 * e.v.abs().max(1e-12),
        "{dudt} {}",
        e.v
    );
    assert!(
        (dudy - e.strain).abs() <= 1e-6 * e.strain.abs(),
        "{dudy} {}",
        e.strain
    );
    // At rest and unstrained at t = 0.
    let start = column_closed_form(&p, y, 0.0);
    let static_scale = (p.top_load / p.young).abs();
    assert!(
        start.u.abs() <= 1e-14 * static_scale * h
            && start.v == 0.0
            && start.strain.abs() <= 1e-14 * static_scale,
        "{start:?}"
    );
    // The exact fields of a 1D scene are this closed form.
    let scene = Scene1d::Column(p);
    assert_eq!(exact_1d(&scene, y, t), e);
}

#[test]
fn overrides_change_only_the_named_parameters_and_refuse_what_a_scene_lacks() {
    let o = Overrides {
        young: Some(60.0),
        constitutive: Some(hompm::mpm::musl::Constitutive::SmallStrain),
        ..Overrides::default()
    };
    let Scene1d::VibratingBar(p) = Scene1d::bar("thesis-table-4.2", &o).unwrap() else {
        unreachable!()
    };
    let base = hompm::scenes::vibrating_bar::parameters("thesis-table-4.2").unwrap();
    assert_eq!(
        (p.young, p.density, p.length, p.v0),
        (60.0, base.density, base.length, base.v0)
    );
    assert_eq!(p.constitutive, hompm::mpm::musl::Constitutive::SmallStrain);
    let bad = Overrides {
        poisson: Some(0.3),
        ..Overrides::default()
    };
    match Scene1d::bar("thesis-table-4.1", &bad) {
        Err(Error::InvalidArgument(m)) => assert!(m.contains("no parameter --poisson"), "{m}"),
        other => panic!("{other:?}"),
    }
    let negative = Overrides {
        young: Some(-1.0),
        ..Overrides::default()
    };
    assert!(matches!(
        Scene1d::column("thesis-table-4.3", &negative),
        Err(Error::InvalidArgument(m)) if m.contains("--young must be positive")
    ));
}

/// The 2D aligned vibration on 4 × 4 cells × 4 PPC, 5 steps.
fn aligned(amplitude: f64, young: f64) -> Setup {
    let o = Overrides {
        amplitude: Some(amplitude),
        young: Some(young),
        ..Overrides::default()
    };
    let (scene, set_name) = hompm::oracle::setup::Setup2d::scene("mls-paper-e1e7", &o).unwrap();
    Setup::TwoD(hompm::oracle::setup::Setup2d {
        scene,
        set_name,
        method: hompm::scenes::aligned_vibration::AlignedMethod::bsmpm(2),
        cells: 4,
        per_side: 2,
        dt: 1e-5,
        steps: 5,
        conventions: hompm::mpm::conventions::Conventions::MLS_PAPER,
    })
}

#[test]
fn a_2d_code_with_its_own_column_names_and_parameters_is_checked_with_its_error_computed_independently(
) {
    let setup = aligned(0.05, 2e7);
    let (state, _) = reference(&setup, None).unwrap();
    let t = &state.particles;
    // The other code writes X, Y, its own names, and its rows reversed.
    let theirs = [
        ("x0_x", "X"),
        ("x0_y", "Y"),
        ("u_x", "ux"),
        ("u_y", "uy"),
        ("stress_xx", "sxx"),
        ("stress_yy", "syy"),
        ("stress_xy", "sxy"),
    ];
    let mut csv = theirs.iter().map(|(_, b)| *b).collect::<Vec<_>>().join(",") + ",extra\n";
    for k in (0..t.rows()).rev() {
        let row: Vec<String> = theirs
            .iter()
            .map(|(a, _)| format!("{:e}", t.column(a).unwrap()[k]))
            .collect();
        csv.push_str(&(row.join(",") + ",7\n"));
    }
    let map = theirs
        .iter()
        .map(|(a, b)| format!("{a}={b}"))
        .collect::<Vec<_>>()
        .join(",");
    let (input, ignored) = parse_input(&csv, &ColumnMap::parse(&map).unwrap(), true).unwrap();
    assert_eq!(ignored, ["extra"]);
    let r = check(&setup, &state, &input, None, &CheckOptions::default()).unwrap();
    assert!(r.agrees, "{}", r.verdict);
    assert_eq!(r.particles, 64);
    assert_eq!(r.matched_by, "x0");
    // MLS paper Eq. (43) for u, written out: A sin(2πX/L) sin(cπt/L) and
    // A sin(2πY/L) sin(cπt/L + π), c = √(E/ρ0), t = 5 Δt.
    let (a, c, time) = (0.05, (2e7f64 / 1000.0).sqrt(), 5.0 * 1e-5);
    let pi = std::f64::consts::PI;
    let (x, y) = (t.column("x0_x").unwrap(), t.column("x0_y").unwrap());
    let (ux, uy) = (t.column("u_x").unwrap(), t.column("u_y").unwrap());
    let mut sum = 0.0;
    for k in 0..t.rows() {
        let ex = a * (2.0 * pi * x[k]).sin() * (c * pi * time).sin();
        let ey = a * (2.0 * pi * y[k]).sin() * (c * pi * time + pi).sin();
        sum += (ux[k] - ex).powi(2) + (uy[k] - ey).powi(2);
    }
    let independent = (sum / t.rows() as f64).sqrt();
    let got = r.fields["u"].rms_exact.unwrap().yours;
    assert!(
        (got - independent).abs() <= 1e-14 * independent,
        "{got} {independent}"
    );
    // A symmetric stress given as xx, yy, xy has the full tensor's RMS.
    let s = r.fields["stress"].rms_exact.unwrap();
    assert!((s.yours - s.hompm).abs() <= 1e-12 * s.hompm, "{s:?}");
}

#[test]
fn the_observed_order_of_hompm_s_own_output_holds_against_hompm() {
    let runs: Vec<_> = [4usize, 8, 16]
        .into_iter()
        .map(|cells| {
            let mut s = quadratic_bar(25);
            s.discretisation.cells = cells;
            let setup = Setup::OneD(s);
            let (state, _) = reference(&setup, None).unwrap();
            let input = Input::Particles(state.particles.clone());
            (setup, state, input, cells, 25.0)
        })
        .collect();
    let r = hompm::oracle::convergence::convergence(&runs, &CheckOptions::default()).unwrap();
    for (name, f) in &r.fields {
        assert_eq!(f.yours, f.hompm, "{name}");
        assert_ne!(f.verdict, "falls short", "{name}");
    }
    let fit =
        hompm::oracle::convergence::fit_order(&[1.0, 0.5, 0.25], &[3.0, 0.75, 0.1875]).unwrap();
    assert!((fit.order - 2.0).abs() < 1e-12 && fit.spread < 1e-12);
    assert_eq!(fit.pairwise.len(), 2);
}

#[test]
fn check_names_eq_27_and_the_node_component_for_a_2d_acceleration_defect() {
    use hompm::mpm2d::step::{Simulation2d, StepObserver2d, StepPoint2d};
    use hompm::oracle::trace::{header_2d, Recorder, TraceObserver2d};
    struct Defective2d(TraceObserver2d);
    impl StepObserver2d for Defective2d {
        fn observe(&mut self, point: StepPoint2d, sim: &mut Simulation2d) -> hompm::Result<()> {
            if point == StepPoint2d::NodalUpdate && sim.steps + 1 == 2 {
                for a in &mut sim.workspace.acceleration {
                    a[1] *= 1.01;
                }
            }
            self.0.observe(point, sim)
        }
    }
    let setup = aligned(0.1, 1e7);
    let Setup::TwoD(s) = setup else {
        unreachable!()
    };
    let mut code = Defective2d(TraceObserver2d {
        recorder: Recorder::new(s.dt, 1, s.steps),
    });
    hompm::oracle::run::run_2d_observed(&s, &mut code, &mut |_| {}).unwrap();
    let theirs = code.0.recorder.into_trace(header_2d(&s).unwrap());
    let (ours, _) = hompm::oracle::run::trace_2d(&s, 1, None).unwrap();
    // The first node whose a_y changes visibly under the factor 1.01.
    let a = &ours.steps[1].equations["mls-27"];
    let flat = (0..a.len())
        .filter(|i| i % 2 == 1)
        .find(|&i| {
            let d = (0.01 * a[i]).abs();
            d > DEFAULT_ATOL && d > DEFAULT_RTOL * a[i].abs()
        })
        .unwrap();
    let only = theirs.steps.iter().map(|t| t.step).collect();
    let (state, ours) = reference(&setup, Some(only)).unwrap();
    let r = check(
        &setup,
        &state,
        &Input::Trace(theirs),
        ours.as_ref(),
        &CheckOptions::default(),
    )
    .unwrap();
    let d = r.first_difference.unwrap();
    assert_eq!(
        (d.step, d.equation.as_str(), d.index),
        (2, "mls-27", flat / 2)
    );
    assert_eq!(d.component.as_deref(), Some("y"));
    assert_eq!(d.index_kind, "node");
}

#[test]
fn cg_with_the_solution_rule_stops_on_the_residual_over_the_iterate() {
    use hompm::solve::cg::{conjugate_gradient_observed, CgVariant};
    // Quartic B-spline mass on 64 spans: CG converges gradually, so the
    // two rules stop at different iterations of the same iterates.
    let m = hompm::mass::unit_density_mass(64, 4, false).unwrap();
    let b = hompm::solve::gravity_rhs(&m);
    let r0: f64 = b.iter().map(|x| x * x).sum::<f64>().sqrt();
    let mut x_norms = Vec::new();
    let rhs = conjugate_gradient_observed(
        &m,
        &b,
        1e-14,
        ResidualNorm::Rhs,
        10_000,
        CgVariant::Recursive,
        &mut |_, x| x_norms.push(x.iter().map(|v| v * v).sum::<f64>().sqrt()),
    )
    .unwrap();
    let plain = hompm::solve::cg::conjugate_gradient(&m, &b, 1e-14, 10_000, CgVariant::Recursive);
    assert_eq!(
        rhs,
        plain.unwrap(),
        "the rhs rule is Eq. (4.53), plain CG's"
    );
    let tol = 1e-10;
    let sol = conjugate_gradient_observed(
        &m,
        &b,
        tol,
        ResidualNorm::Solution,
        10_000,
        CgVariant::Recursive,
        &mut |_, _| {},
    )
    .unwrap();
    // The same iterates, each residual divided by ‖x_k‖ instead of ‖r_0‖.
    let pairs = rhs.residuals.iter().zip(&x_norms).enumerate();
    for (k, (rel, x_norm)) in pairs.skip(1).take(sol.iterations) {
        let expected = rel * r0 / x_norm;
        assert!(
            (sol.residuals[k] - expected).abs() <= 1e-12 * expected,
            "iteration {k}: {} vs {expected}",
            sol.residuals[k]
        );
    }
    let first_below = (1..rhs.residuals.len())
        .find(|&k| rhs.residuals[k] * r0 / x_norms[k] < tol)
        .unwrap();
    assert_eq!(sol.iterations, first_below);
    let rhs_stop = (1..rhs.residuals.len())
        .find(|&k| rhs.residuals[k] < tol)
        .unwrap();
    assert_ne!(
        sol.iterations, rhs_stop,
        "the rules stop at different iterations"
    );
}

#[test]
fn a_traced_2d_run_is_bit_identical_to_an_untraced_one() {
    for method in [
        hompm::scenes::aligned_vibration::AlignedMethod::bsmpm(2),
        hompm::scenes::aligned_vibration::AlignedMethod::bsmpm_with(2, Mapping2d::Mls),
        hompm::scenes::aligned_vibration::AlignedMethod::bsmpm_with(2, Mapping2d::Tls),
    ] {
        let Setup::TwoD(mut s) = aligned(0.1, 1e7) else {
            unreachable!()
        };
        s.method = method;
        s.per_side = 3;
        let plain = hompm::oracle::run::run_2d(&s).unwrap();
        let (trace, traced) = hompm::oracle::run::trace_2d(&s, 2, None).unwrap();
        assert_eq!(plain.particles.displacement, traced.particles.displacement);
        assert_eq!(plain.particles.stress, traced.particles.stress);
        assert_eq!(plain.particles.deformation, traced.particles.deformation);
        let steps: Vec<usize> = trace.steps.iter().map(|t| t.step).collect();
        assert_eq!(steps, [1, 3, 5]);
        let gauss = trace.steps[0].equations.get("mls-18-21").map(Vec::len);
        // Every reconstruction (MLS or TLS) records its Gauss-point values.
        let reconstructed = method.parts().1 != Mapping2d::Direct;
        assert_eq!(
            gauss,
            reconstructed.then_some(8 * 8 * 8),
            "8 values at 8 × 8 Gauss points"
        );
    }
}

/// A directory of this test binary's scratch space.
fn scratch_dir(name: &str) -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn a_file_over_the_memory_limit_is_refused_by_its_size_before_it_is_read() {
    let dir = scratch_dir("oracle-size");
    let path = dir.join("big.csv");
    // About 2 000 bytes of a valid header and rows: 4 bytes of memory per
    // byte read is about 8 000, over 4 KiB.
    let mut text = String::from("x0,u\n");
    while text.len() < 2000 {
        text.push_str("1.0,0.0\n");
    }
    std::fs::write(&path, &text).unwrap();
    let args = [
        "--max-memory",
        "4KiB",
        "check",
        "vibrating-bar",
        "--cells",
        "1",
        "--ppc",
        "1",
        "--steps",
        "1",
        "--input",
        path.to_str().unwrap(),
    ];
    match hompm::cli::run(args) {
        Err(e @ Error::Input(_)) => {
            let m = e.to_string();
            assert!(
                m.contains("needs about 8") && m.contains("over the memory limit of 4096 bytes"),
                "{m}"
            );
            assert_eq!(hompm::cli::exit_code(&e), 2);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn exact_fields_stay_finite_at_times_where_omega_t_overflows() {
    let bar = Scene1d::bar("thesis-table-4.1", &Overrides::default()).unwrap();
    let column = Scene1d::column("thesis-table-8.1", &Overrides::default()).unwrap();
    for scene in [bar, column] {
        let e = exact_1d(&scene, 0.3 * scene.length(), 1e308);
        assert!(
            [e.u, e.v, e.strain, e.stress].iter().all(|x| x.is_finite()),
            "{e:?}"
        );
    }
    let (aligned, _) =
        hompm::oracle::setup::Setup2d::scene("mls-paper-e1e7", &Overrides::default()).unwrap();
    let e = hompm::oracle::exact::exact_2d(&aligned, [0.3, 0.6], 1e308, false).unwrap();
    assert!(e
        .u
        .iter()
        .chain(&e.stress)
        .chain(&e.body_force)
        .all(|x| x.is_finite()));
    // Reduced by whole periods: the bar at 2·10⁶ periods + 1 s is the bar at 1 s.
    let period = 50.0 / 10.0;
    let far = exact_1d(&bar, 7.0, 2e6 * period + 1.0);
    let near = exact_1d(&bar, 7.0, 1.0);
    assert!(
        (far.u - near.u).abs() <= 1e-9 * near.u.abs(),
        "{far:?} {near:?}"
    );
}

#[test]
fn bad_arguments_to_exact_trace_and_check_are_one_line_and_exit_2() {
    let dir = scratch_dir("oracle-args");
    let good = dir.join("good.csv");
    std::fs::write(&good, "x0,u\n1,0\n").unwrap();
    let missing = dir.join("missing.csv");
    let g = good.to_str().unwrap();
    let m = missing.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["exact", "vibrating-bar", "--time", "nan"], "--time"),
        (
            vec!["exact", "vibrating-bar", "--time", "0", "--at", "30"],
            "outside",
        ),
        (
            vec!["exact", "aligned-vibration", "--time", "0", "--at", "0.1"],
            "x,y pairs",
        ),
        (
            vec!["exact", "vibrating-bar", "--time", "0", "--poisson", "0.3"],
            "no parameter --poisson",
        ),
        (
            vec!["exact", "vibrating-bar", "--time", "0", "--params", "nope"],
            "unknown",
        ),
        (vec!["trace", "vibrating-bar", "--every", "0"], "--every"),
        (vec!["trace", "vibrating-bar", "--dt", "-1"], "--dt"),
        (
            vec!["trace", "column-self-weight", "--young", "-5"],
            "--young must be positive",
        ),
        (
            vec!["check", "vibrating-bar", "--input", g, "--rtol", "nan"],
            "--rtol",
        ),
        (
            vec![
                "check",
                "vibrating-bar",
                "--input",
                g,
                "--mass",
                "lumped",
                "--tol",
                "1e-9",
            ],
            "--tol",
        ),
        (vec!["check", "vibrating-bar", "--input", m], "cannot read"),
        (
            vec!["check", "vibrating-bar", "--input", g],
            "particles, the setup has",
        ),
        (vec!["check", "vibrating-bar"], "--input"),
    ];
    for (args, needle) in cases {
        match hompm::cli::run(&args) {
            Err(e) => {
                let line = hompm::cli::one_line(&e.to_string());
                assert!(line.contains(needle), "{args:?}: {line}");
                assert_eq!(hompm::cli::exit_code(&e), 2, "{args:?}: {line}");
            }
            Ok(out) => panic!("{args:?} was accepted: {}", out.stdout),
        }
    }
}

/// Issue #37: the oracle's columns are declared once
/// (`oracle::columns::QUANTITIES`). hompm's own state has exactly the known
/// columns of its dimension, in their order; every compared field's columns
/// are known; the physical fields are the schema's physical quantities; and
/// x0's columns are the schema's.
#[test]
fn hompm_s_own_state_has_exactly_the_schema_s_columns_in_1d_and_2d() {
    use hompm::oracle::columns::{
        field_columns, known_columns, x0_columns, PHYSICAL_FIELDS, QUANTITIES,
    };
    let one = Setup::OneD(bar(Method::Mpm, Mapping::Direct, MassMatrix::Lumped, 2));
    for (setup, two_d) in [(one, false), (aligned(0.01, 1e7), true)] {
        let (state, _) = reference(&setup, None).unwrap();
        assert_eq!(state.two_d, two_d);
        let names: Vec<&str> = state
            .particles
            .columns
            .iter()
            .map(|(n, _)| n.as_str())
            .collect();
        assert_eq!(names, known_columns(two_d));
        for (field, columns) in field_columns(two_d) {
            assert!(
                columns.iter().all(|c| known_columns(two_d).contains(c)),
                "{field}"
            );
        }
        assert_eq!(
            x0_columns(two_d),
            QUANTITIES
                .iter()
                .find(|q| q.name == "x0")
                .unwrap()
                .columns(two_d)
        );
    }
    let physical: Vec<&str> = QUANTITIES
        .iter()
        .filter(|q| q.physical)
        .map(|q| q.name)
        .collect();
    assert_eq!(physical, PHYSICAL_FIELDS);
    assert_eq!(
        known_columns(false),
        ["id", "x0", "x", "u", "v", "stress", "volume", "density"]
    );
    assert_eq!(known_columns(true).len(), 19);
    let order: Vec<&str> = field_columns(true).iter().map(|(f, _)| *f).collect();
    assert_eq!(
        order,
        ["u", "v", "stress", "F", "x0", "x", "volume", "density"]
    );
    let order: Vec<&str> = field_columns(false).iter().map(|(f, _)| *f).collect();
    assert_eq!(order, ["u", "v", "stress", "x0", "x", "volume", "density"]);
}
