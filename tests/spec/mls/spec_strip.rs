//! The manufactured strip, the 1D vibration the MLS paper's own code runs
//! for its figures (issue #40; `scenes::manufactured_strip`): the 1D
//! neo-Hookean law, the body force that makes the displacement exact, the
//! code's time loop and particle layout, and the code's own output files
//! (tests/fixtures/tran, written by `scripts/tran_code_check.sh` from
//! `Vibration('MPM', 8)` and `Vibration('BSMPM', 8)` of commit f30bc24
//! under GNU Octave 7.3) checked with one `hompm check` line each.

use approx::assert_relative_eq;
use hompm::mpm::grid::{Grid, Method};
use hompm::mpm::musl::{neo_hookean_1d, Constitutive, Simulation};
use hompm::mpm::particles::Particles;
use hompm::scenes::manufactured_strip::{parameters, StripParameters};
use hompm::scenes::Discretisation;
use std::path::PathBuf;

fn strip(cells: usize) -> StripParameters {
    parameters("mls-paper-code").unwrap().placed(cells)
}

#[test]
fn the_1d_neo_hookean_stress_is_eq_37_with_unit_transverse_stretches() {
    // λ = 2, μ = 3, F = 1.1: (2 ln 1.1 + 3·0.21)/1.1, worked by hand.
    let by_hand = (2.0 * 0.095_310_179_804_324_87 + 0.63) / 1.1;
    assert_relative_eq!(neo_hookean_1d(2.0, 3.0, 1.1), by_hand, max_relative = 1e-15);
    assert_eq!(neo_hookean_1d(2.0, 3.0, 1.0), 0.0);
}

#[test]
fn the_strip_s_body_force_makes_its_displacement_exact() {
    // b = ü − (1/ρ₀) ∂P/∂X, P = λ ln F/F + μ(F − 1/F), by central
    // differences of the exact u, at ν = 0.3 so that every term counts.
    let mut p = strip(8);
    p.poisson = 0.3;
    p.amplitude = 0.05;
    let (lambda, mu) = p.lame();
    let piola = |x: f64, t: f64| {
        let f = p.deformation(x, t);
        lambda * f.ln() / f + mu * (f - 1.0 / f)
    };
    let (x, t, h, k) = (p.left_end + 0.37, 0.0031, 1e-4, 1e-7);
    let acceleration = (p.displacement(x, t + k) - 2.0 * p.displacement(x, t)
        + p.displacement(x, t - k))
        / (k * k);
    let divergence = (piola(x + h, t) - piola(x - h, t)) / (2.0 * h);
    let b = acceleration - divergence / p.density;
    assert_relative_eq!(p.body_force(x, t), b, max_relative = 1e-5);
}

#[test]
fn the_code_s_time_loop_ends_just_past_0_02_s() {
    // `while t < 0.02 + 1e-7`: 41 steps to 0.0205 s on 8 cells, 321 to
    // 0.0200625 s on 64 (docs/reproduction-notes.md).
    let (dt, steps) = strip(8).code_time_steps(8);
    assert_eq!((dt, steps), (5e-4, 41));
    let (dt, steps) = strip(64).code_time_steps(64);
    assert_eq!(steps, 321);
    assert_relative_eq!(steps as f64 * dt, 0.0200625, max_relative = 1e-12);
}

/// A file of the MLS paper's code's runs (tests/fixtures/tran).
pub(super) fn fixture(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/tran")
        .join(name)
        .to_str()
        .unwrap()
        .to_string()
}

#[test]
fn the_strip_s_particles_sit_where_the_code_puts_them_two_ghost_cells_right() {
    let text = std::fs::read_to_string(fixture("strip-MPM-8.csv")).unwrap();
    let theirs: Vec<f64> = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("id"))
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    let ours = strip(8).initial_positions(8, 5);
    assert_eq!(ours, theirs);
    assert_eq!(ours[0], 0.25 + 0.0125);
}

fn check(file: &str, method: &[&str]) -> hompm::cli::Output {
    let input = fixture(file);
    let mut args = vec!["check", "manufactured-strip"];
    args.extend_from_slice(method);
    args.extend_from_slice(&[
        "--cells", "8", "--ppc", "5", "--dt", "5e-4", "--steps", "41", "--input", &input,
    ]);
    hompm::cli::run(&args).unwrap()
}

#[test]
fn the_mls_paper_code_s_strip_files_agree_under_its_conventions_and_only_under_them() {
    // MPM: MUSL with particles moved by the updated grid momentum
    // (Update_Particle_Position.m). BSMPM: USL (BSMPM_solvertest.m).
    for (file, method, conventions) in [
        ("strip-MPM-8.csv", &["--method", "mpm"][..], "--positions"),
        (
            "strip-BSMPM-8.csv",
            &["--method", "bsmpm", "--degree", "2"][..],
            "--scheme",
        ),
    ] {
        let matched = if conventions == "--positions" {
            vec!["--positions", "grid"]
        } else {
            vec!["--scheme", "usl"]
        };
        let flags: Vec<&str> = method.iter().copied().chain(matched).collect();
        let out = check(file, &flags);
        assert!(out.stdout.starts_with("agrees"), "{file}: {}", out.stdout);
        assert!(
            out.stdout.contains("in u, v, stress, x0, x"),
            "{}",
            out.stdout
        );
        let out = check(file, method);
        assert!(out.stdout.starts_with("differs"), "{file}: {}", out.stdout);
    }
}

#[test]
fn the_manufactured_body_force_is_refused_at_the_nodes() {
    let e = hompm::cli::run([
        "run",
        "manufactured-strip",
        "--method",
        "mpm",
        "--cells",
        "4",
        "--ppc",
        "5",
        "--steps",
        "2",
        "--body-force",
        "nodes",
    ])
    .unwrap_err();
    assert!(e.to_string().contains("mapped from the particles"), "{e}");
}

#[test]
fn origin_moves_a_file_whose_body_starts_elsewhere_onto_hompm_s() {
    // The MLS paper's Vibration2D.m puts its square at [2h, 1 + 2h]²; its
    // files check with --origin 2h,2h. Here: hompm's own 2D run, moved by
    // (0.25, 0.25) in x0 and x.
    let setup = crate::common::SETUP_2D;
    let mut args = vec!["run"];
    args.extend_from_slice(setup);
    args.push("--json");
    let mut doc: serde_json::Value =
        serde_json::from_str(&hompm::cli::run(&args).unwrap().stdout).unwrap();
    for column in ["x0", "x"] {
        for pair in doc["particles"][column].as_array_mut().unwrap() {
            for v in pair.as_array_mut().unwrap() {
                *v = serde_json::json!(v.as_f64().unwrap() + 0.25);
            }
        }
    }
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("origin");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("moved.json");
    std::fs::write(&path, doc.to_string()).unwrap();
    let input = path.to_str().unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["check"];
        args.extend_from_slice(setup);
        args.extend_from_slice(&["--input", input]);
        args.extend_from_slice(extra);
        hompm::cli::run(&args)
    };
    let out = run(&["--origin", "0.25,0.25"]).unwrap();
    assert!(out.stdout.starts_with("agrees"), "{}", out.stdout);
    assert!(run(&[]).is_err_and(|e| e
        .to_string()
        .contains("no particle of the setup starts within")));
    let e = run(&["--origin", "0.25"]).unwrap_err();
    assert_eq!(hompm::cli::exit_code(&e), 2, "{e}");
    assert!(e.to_string().contains("--origin takes 2"), "{e}");
}

/// The code's own RMS errors, from the `# rms (code):` line of its file.
pub(super) fn code_rms(file: &str) -> [f64; 3] {
    let text = std::fs::read_to_string(fixture(file)).unwrap();
    let line = text
        .lines()
        .find(|l| l.starts_with("# rms (code):"))
        .unwrap();
    let numbers: Vec<f64> = line
        .split([' ', ','])
        .filter_map(|w| w.parse().ok())
        .collect();
    [numbers[0], numbers[1], numbers[2]]
}

#[test]
fn under_its_code_s_setup_mpm_and_bsmpm_both_converge_at_order_two() {
    // hompm's strip study (table mls-aligned-code) gives the code's own RMS
    // errors at 8 cells (Vibration.m's Eq. 43, printed by the code) and
    // order 2 in u for both methods from 32 to 64 cells, MPM the more
    // accurate: the paper's "lack of convergence" and "considerably lower"
    // do not hold on the setup its code runs.
    let study = hompm::studies::mls_code::strip_study(&[8, 16, 32, 64]).unwrap();
    for (runs, file) in [
        (&study.mpm, "strip-MPM-8.csv"),
        (&study.bsmpm, "strip-BSMPM-8.csv"),
    ] {
        let theirs = code_rms(file);
        let ours = [runs[0].displacement, runs[0].velocity, runs[0].stress];
        for (a, b) in ours.iter().zip(theirs) {
            assert_relative_eq!(*a, b, max_relative = 1e-8);
        }
        let order = (runs[2].displacement / runs[3].displacement).log2();
        assert!((order - 2.0).abs() < 0.05, "{file}: order {order}");
    }
    assert!(study.bsmpm[3].displacement > 1.5 * study.mpm[3].displacement);
}

/// A one-particle run on two cells of [0, 1] with the given law, E and ν.
fn one_particle(constitutive: Constitutive, young: f64, poisson: f64) -> hompm::Result<Simulation> {
    let grid = Grid::new(Method::Mpm, 0.0, 1.0, 2).unwrap();
    let p = Particles::new(vec![0.25], vec![0.5], vec![1.0], vec![0.0], vec![0.0]).unwrap();
    let mut s =
        Discretisation::direct(Method::Mpm, 2, 1).settings(constitutive, young, 0.0, None, vec![]);
    s.poisson = poisson;
    Simulation::new(grid, p, s)
}

#[test]
fn a_run_refuses_a_young_s_modulus_that_is_not_positive() {
    for young in [0.0, -1.0, f64::NAN] {
        for law in [Constitutive::SmallStrain, Constitutive::NeoHookean] {
            let e = one_particle(law, young, 0.0).err().unwrap().to_string();
            assert!(
                e.contains("Young's modulus must be positive"),
                "{young}: {e}"
            );
        }
    }
    assert!(one_particle(Constitutive::SmallStrain, f64::MIN_POSITIVE, 0.0).is_ok());
}

#[test]
fn the_neo_hookean_law_needs_poisson_s_ratio_strictly_between_minus_one_and_one_half() {
    // λ = Eν/((1 + ν)(1 − 2ν)) and μ = E/(2(1 + ν)) are finite and μ > 0
    // only for −1 < ν < 1/2: both ends are refused, points just inside
    // accepted.
    for nu in [-1.0, 0.5, -1.5, 0.7] {
        let e = one_particle(Constitutive::NeoHookean, 1.0, nu)
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("−1 < ν < 0.5"), "{nu}: {e}");
    }
    for nu in [-0.999, 0.0, 0.3, 0.499] {
        assert!(
            one_particle(Constitutive::NeoHookean, 1.0, nu).is_ok(),
            "{nu}"
        );
    }
    // The small-strain laws do not read ν: any value is accepted there.
    for nu in [-1.0, 0.5, 0.7] {
        assert!(
            one_particle(Constitutive::SmallStrain, 1.0, nu).is_ok(),
            "{nu}"
        );
    }
}

#[test]
fn a_neo_hookean_step_updates_f_then_sigma_v_rho_and_the_strain_of_each_particle() {
    // Steps 7 and 8 under the 1D neo-Hookean law, particle by particle and
    // bit for bit: F ← (1 + Δε)F, σ = (λ ln F + μ(F² − 1))/F, V = V⁰F,
    // ρ = m/V and ε ← ε + Δε, with Δε the step's strain increment. ν = 0.3
    // so that λ counts.
    let mut p = strip(8);
    p.poisson = 0.3;
    let (lambda, mu) = p.lame();
    let mut sim = p
        .simulation(&Discretisation::direct(Method::Mpm, 8, 5))
        .unwrap();
    let (dt, _) = p.code_time_steps(8);
    for step in 1..=3 {
        let before = sim.particles.clone();
        sim.step(dt).unwrap();
        let (q, de) = (&sim.particles, &sim.workspace().strain_increment);
        assert!(de.iter().all(|&d| d != 0.0), "step {step}");
        for (k, &de_k) in de.iter().enumerate().take(q.len()) {
            let f = before.deformation[k] * (1.0 + de_k);
            assert_eq!(q.deformation[k], f, "step {step}, particle {k}");
            assert_eq!(q.stress[k], neo_hookean_1d(lambda, mu, f));
            assert_eq!(q.volume[k], q.initial_volume[k] * f);
            assert_eq!(q.density[k], q.mass[k] / q.volume[k]);
            assert_eq!(q.strain[k], before.strain[k] + de_k);
        }
    }
    // After the first steps F differs from 1 by the order of A π/L.
    let f = &sim.particles.deformation;
    assert!(f.iter().any(|&f| (f - 1.0).abs() > 1e-6), "{f:?}");
}

#[test]
fn the_strip_s_body_force_bound_holds_and_the_monitor_counts_its_work() {
    // |b(X, t)| ≤ bound over the body and a period, and the bound is
    // within a factor 2 (u and F − 1 peak at different X: |sin cos| ≤ ½,
    // which the bound does not use): the stability monitor
    // counts the work Σ m_p·bound·L among the loads' (docs/conventions.md,
    // "The stability monitor"). ν = 0.3 so that λ counts too.
    for poisson in [0.0, 0.3] {
        let mut p = strip(8);
        p.poisson = poisson;
        let bound = p.body_force_bound();
        let period = 2.0 / p.wave_speed();
        let mut largest: f64 = 0.0;
        for i in 0..=200 {
            for j in 0..=200 {
                let x = p.left_end + i as f64 / 200.0;
                largest = largest.max(p.body_force(x, period * j as f64 / 200.0).abs());
            }
        }
        assert!(largest <= bound, "ν = {poisson}: {largest:e} > {bound:e}");
        assert!(
            largest >= 0.45 * bound,
            "ν = {poisson}: {largest:e} ≪ {bound:e}"
        );
    }
    // With it the code's MLS_BSMPM, whose energy ½σεV grows because its
    // forces are h/2 too weak, runs to the code's end under `hompm run`
    // (the monitor stopped it at step 24 of 41 without the body force's work).
    let mut args = super::spec_strip_mls::mls_code_args("run", "mls-code-weights", 8, 5e-4, 41);
    args.push("--json".into());
    let out = hompm::cli::run(&args);
    assert!(out.is_ok(), "{:?}", out.err());
}
