//! # The hompm command line
//!
//! Reviewers check published numbers (`hompm table <id>`, `hompm reproduce`);
//! authors of faster MPM codes use the oracle commands (`hompm basis`, …) with
//! `--json`. Bad input gives one line on stderr and a non-zero exit code.

use clap::{Parser, Subcommand};
use hompm::error::{Error, Result};
use hompm::spline::KnotVector;
use hompm::tables::{self, RunOptions};
use serde::Serialize;
use std::io::Write;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "hompm",
    version,
    about = "An executable specification of the high-order Material Point Method"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// B-spline basis values (and derivatives) at points: book Eqs. (4.19)-(4.23).
    Basis {
        /// Polynomial degree p.
        #[arg(long)]
        degree: usize,
        /// Comma-separated knots, non-decreasing.
        #[arg(long, allow_hyphen_values = true)]
        knots: String,
        /// Comma-separated evaluation points inside the domain.
        #[arg(long, allow_hyphen_values = true)]
        at: String,
        /// Also print first derivatives.
        #[arg(long)]
        derivatives: bool,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Mass matrix of degree p on N uniform spans of [0,1] (ρ = 1): size, spectrum and a
    /// solve of M a = M·(−9.81·1). Book Eqs. (4.2), (4.53)–(4.62); thesis §7.2.
    Mass(MassArgs),
    /// Reconstruct a function from scattered data: TLS (book Eqs. 4.26-4.37), cubic splines
    /// (thesis §7.1) or MLS (MLS paper Eqs. 6-17). Prints values at --at, cell integrals and κ(D).
    Reconstruct(ReconstructArgs),
    /// Run a 1D MPM scene and print the final particle state and diagnostics (MUSL,
    /// book §4.2.2). Scenes: vibrating-bar, column-self-weight, column-top-load.
    Run(RunArgs),
    /// Published and computed values of one table, with deviation and status.
    Table {
        /// Table id (see --list).
        id: Option<String>,
        /// List the registered table ids.
        #[arg(long)]
        list: bool,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Run every registered table and the studies; write report.md, report.json,
    /// reproduction.md and charts; exit non-zero if a number marked reproduced in
    /// golden/reproduced.json no longer reproduces.
    Reproduce {
        /// Output directory.
        #[arg(long, default_value = "target/hompm-report")]
        out: std::path::PathBuf,
        /// Only these table ids (studies and charts are skipped).
        #[arg(long, num_args = 1..)]
        only: Vec<String>,
        /// Reduced sizes (smoke test).
        #[arg(long)]
        quick: bool,
        /// Also write the generated reproduction status to this path
        /// (docs/reproduction.md in the repository).
        #[arg(long)]
        docs: Option<std::path::PathBuf>,
        /// Write the reproduced cells to golden/reproduced.json (a reviewed change).
        #[arg(long)]
        update_baseline: bool,
    },
}

/// Arguments of `hompm run`.
#[derive(clap::Args)]
struct RunArgs {
    /// Scene id.
    scene: String,
    /// Named parameter set (default: the thesis' set of the scene).
    #[arg(long)]
    params: Option<String>,
    /// mpm, mpm-p2, ddmpm or bsmpm.
    #[arg(long, default_value = "mpm")]
    method: String,
    /// B-spline degree for bsmpm.
    #[arg(long, default_value_t = 2)]
    degree: usize,
    /// direct, tls or cubic-spline.
    #[arg(long, default_value = "direct")]
    mapping: String,
    /// lumped, consistent (Cholesky) or richardson (thesis §7.2, 1e-9).
    #[arg(long, default_value = "lumped")]
    mass: String,
    /// Elements or knot spans.
    #[arg(long, default_value_t = 16)]
    cells: usize,
    /// Particles per cell.
    #[arg(long, default_value_t = 4)]
    ppc: usize,
    /// Time step.
    #[arg(long, default_value_t = 1e-5, allow_hyphen_values = true)]
    dt: f64,
    /// Number of steps.
    #[arg(long, default_value_t = 100)]
    steps: usize,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

/// Arguments of `hompm mass`.
#[derive(clap::Args)]
struct MassArgs {
    /// Polynomial degree p.
    #[arg(long)]
    degree: usize,
    /// Number of knot spans per direction.
    #[arg(long)]
    spans: usize,
    /// Dimension: 1, or 2 for the tensor-product matrix.
    #[arg(long, default_value_t = 1)]
    dim: usize,
    /// Remove the first and last function per direction.
    #[arg(long)]
    dirichlet: bool,
    /// Compute λ_min, λ_max and κ.
    #[arg(long)]
    condition: bool,
    /// Solve with cg, pmg, richardson or direct.
    #[arg(long)]
    solve: Option<String>,
    /// Relative tolerance of the iterative solvers.
    #[arg(long, default_value_t = 1e-8)]
    tol: f64,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

/// Arguments of `hompm reconstruct`.
#[derive(clap::Args)]
struct ReconstructArgs {
    /// tls, tls-conservative, cubic-spline (not-a-knot), cubic-spline-natural or mls.
    #[arg(long)]
    method: String,
    /// Cell boundaries a,b,c,... (consecutive cells [a,b], [b,c], ...).
    #[arg(long, allow_hyphen_values = true)]
    cells: String,
    /// Data abscissae.
    #[arg(long, allow_hyphen_values = true)]
    points: String,
    /// Data values.
    #[arg(long, allow_hyphen_values = true)]
    values: String,
    /// Integral to conserve in each cell (tls-conservative).
    #[arg(long, allow_hyphen_values = true)]
    integrals: Option<String>,
    /// Number of Taylor basis functions n_b.
    #[arg(long, default_value_t = 3)]
    order: usize,
    /// Query points.
    #[arg(long, allow_hyphen_values = true)]
    at: String,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

fn parse_list(what: &str, text: &str) -> Result<Vec<f64>> {
    text.split(',')
        .map(|s| {
            let s = s.trim();
            s.parse::<f64>()
                .map_err(|_| Error::InvalidArgument(format!("{what}: '{s}' is not a number")))
        })
        .collect()
}

#[derive(Serialize)]
struct BasisJson {
    degree: usize,
    knots: Vec<f64>,
    points: Vec<f64>,
    values: Vec<Vec<f64>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    derivatives: Option<Vec<Vec<f64>>>,
}

fn print(out: &str) {
    let mut stdout = std::io::stdout().lock();
    let _ = stdout.write_all(out.as_bytes());
    let _ = stdout.flush();
}

fn to_json<T: Serialize>(value: &T) -> Result<String> {
    serde_json::to_string_pretty(value)
        .map(|s| s + "\n")
        .map_err(|e| Error::InvalidArgument(format!("cannot write JSON: {e}")))
}

fn basis(degree: usize, knots: &str, at: &str, derivatives: bool, json: bool) -> Result<String> {
    let knots = parse_list("--knots", knots)?;
    let points = parse_list("--at", at)?;
    let kv = KnotVector::new(knots.clone(), degree)?;
    let mut values = Vec::new();
    let mut ders = Vec::new();
    for &x in &points {
        values.push(kv.dense_values(x)?);
        if derivatives {
            ders.push(kv.dense_derivatives(x)?);
        }
    }
    let doc = BasisJson {
        degree,
        knots,
        points,
        values,
        derivatives: derivatives.then_some(ders),
    };
    if json {
        return to_json(&doc);
    }
    let mut s = format!(
        "degree {} on {} knots: {} basis functions, domain [{}, {}]\n",
        degree,
        doc.knots.len(),
        kv.num_basis(),
        kv.domain().0,
        kv.domain().1
    );
    for (k, x) in doc.points.iter().enumerate() {
        let row: Vec<String> = doc.values[k].iter().map(|v| format!("{v:.12}")).collect();
        s.push_str(&format!("x = {x}: phi = [{}]\n", row.join(", ")));
        if let Some(d) = &doc.derivatives {
            let row: Vec<String> = d[k].iter().map(|v| format!("{v:.12}")).collect();
            s.push_str(&format!("        dphi = [{}]\n", row.join(", ")));
        }
    }
    Ok(s)
}

/// Analytic (u, v, σ) at (X, t), where known.
type Reference = Box<dyn Fn(f64, f64) -> [Option<f64>; 3]>;

#[derive(Serialize)]
struct ParticleJson {
    x0: Vec<f64>,
    x: Vec<f64>,
    u: Vec<f64>,
    v: Vec<f64>,
    stress: Vec<f64>,
    volume: Vec<f64>,
    density: Vec<f64>,
}

#[derive(Serialize)]
struct RunJson {
    scene: String,
    params: serde_json::Value,
    method: String,
    mapping: String,
    mass: String,
    cells: usize,
    ppc: usize,
    dt: f64,
    steps: usize,
    time: f64,
    particles: ParticleJson,
    diagnostics: serde_json::Value,
}

fn run_scene(args: RunArgs) -> Result<String> {
    use hompm::mpm::diagnostics::rms_error;
    use hompm::mpm::grid::Method;
    use hompm::mpm::mapping::{ConsistentSolver, Mapping, MassMatrix};
    use hompm::scenes::{column, vibrating_bar, Discretisation};
    let method = Method::parse(&args.method, args.degree)?;
    let mapping = Mapping::parse(&args.mapping)?;
    let mass = match args.mass.as_str() {
        "lumped" => MassMatrix::Lumped,
        "consistent" => MassMatrix::Consistent(ConsistentSolver::Cholesky),
        "richardson" => MassMatrix::Consistent(ConsistentSolver::Richardson { tolerance: 1e-9 }),
        other => {
            return Err(Error::InvalidArgument(format!(
                "--mass must be lumped, consistent or richardson, got '{other}'"
            )))
        }
    };
    if args.dt.is_nan() || args.dt <= 0.0 || args.dt.is_infinite() {
        return Err(Error::InvalidArgument(format!(
            "--dt must be positive and finite, got {}",
            args.dt
        )));
    }
    let d = Discretisation {
        method,
        force_mapping: mapping,
        velocity_mapping: mapping,
        mass,
        cells: args.cells,
        ppc: args.ppc,
    };
    let (mut sim, params_json, reference): (_, serde_json::Value, Reference) =
        match args.scene.as_str() {
            "vibrating-bar" => {
                let p = vibrating_bar::parameters(
                    args.params.as_deref().unwrap_or("thesis-table-4.1"),
                )?;
                let small = p.constitutive == hompm::mpm::musl::Constitutive::SmallStrain;
                (
                    p.simulation(&d)?,
                    serde_json::to_value(p).unwrap_or_default(),
                    Box::new(move |x, t| {
                        if small {
                            [
                                Some(p.displacement(x, t)),
                                Some(p.velocity(x, t)),
                                Some(p.stress(x, t)),
                            ]
                        } else {
                            [None, None, None]
                        }
                    }),
                )
            }
            "column-self-weight" | "column-top-load" => {
                let default = if args.scene == "column-self-weight" {
                    "thesis-table-4.3"
                } else {
                    "thesis-table-8.1"
                };
                let p = column::parameters(args.params.as_deref().unwrap_or(default))?;
                let small = p.constitutive == hompm::mpm::musl::Constitutive::SmallStrain;
                (
                    p.simulation(&d)?,
                    serde_json::to_value(p).unwrap_or_default(),
                    Box::new(move |x, t| {
                        if small {
                            [Some(p.displacement(x, t, 200)), None, None]
                        } else {
                            [None, None, None]
                        }
                    }),
                )
            }
            other => {
                return Err(Error::InvalidArgument(format!(
                "scene must be vibrating-bar, column-self-weight or column-top-load, got '{other}' \
                 (column-compaction is not implemented yet)"
            )))
            }
        };
    sim.run(args.dt, args.steps)?;
    let pt = &sim.particles;
    let mut diagnostics = serde_json::to_value(&sim.diagnostics).unwrap_or_default();
    let refs: Vec<[Option<f64>; 3]> = pt.x0.iter().map(|&x| reference(x, sim.time)).collect();
    for (k, (name, field)) in [
        ("rms_displacement", &pt.u),
        ("rms_velocity", &pt.v),
        ("rms_stress", &pt.stress),
    ]
    .into_iter()
    .enumerate()
    {
        let exact: Option<Vec<f64>> = refs.iter().map(|r| r[k]).collect();
        if let (Some(exact), Some(obj)) = (exact, diagnostics.as_object_mut()) {
            obj.insert(name.into(), serde_json::json!(rms_error(field, &exact)?));
        }
    }
    let doc = RunJson {
        scene: args.scene.clone(),
        params: params_json,
        method: args.method.clone(),
        mapping: args.mapping.clone(),
        mass: args.mass.clone(),
        cells: args.cells,
        ppc: args.ppc,
        dt: args.dt,
        steps: args.steps,
        time: sim.time,
        particles: ParticleJson {
            x0: pt.x0.clone(),
            x: pt.x.clone(),
            u: pt.u.clone(),
            v: pt.v.clone(),
            stress: pt.stress.clone(),
            volume: pt.volume.clone(),
            density: pt.density.clone(),
        },
        diagnostics,
    };
    if args.json {
        return to_json(&doc);
    }
    let mut s = format!(
        "{} ({}), {} with {} mapping and {} mass, {} cells × {} PPC, {} steps of {:e} s (t = {:e} s)\n",
        doc.scene, sim.settings.young, doc.method, doc.mapping, doc.mass, doc.cells, doc.ppc, doc.steps, doc.dt, doc.time
    );
    s.push_str(&format!("diagnostics: {}\n", doc.diagnostics));
    Ok(s)
}

#[derive(Serialize)]
struct ReconstructJson {
    method: String,
    values: Vec<f64>,
    cell_integrals: Vec<f64>,
    condition_numbers: Option<Vec<f64>>,
}

fn reconstruct(args: ReconstructArgs) -> Result<String> {
    use hompm::quadrature::gauss_on_cells;
    use hompm::reconstruct::{cubic_spline, mls, taylor};
    let edges = parse_list("--cells", &args.cells)?;
    if edges.len() < 2 {
        return Err(Error::InvalidArgument(
            "--cells needs at least two boundaries".into(),
        ));
    }
    let cells: Vec<(f64, f64)> = edges.windows(2).map(|w| (w[0], w[1])).collect();
    if let Some(&(a, b)) = cells.iter().find(|(a, b)| b.is_nan() || b <= a) {
        return Err(Error::InvalidArgument(format!(
            "cell [{a}, {b}] is empty: --cells must increase"
        )));
    }
    let points = parse_list("--points", &args.points)?;
    let values = parse_list("--values", &args.values)?;
    let at = parse_list("--at", &args.at)?;
    let integrals = args
        .integrals
        .as_deref()
        .map(|t| parse_list("--integrals", t))
        .transpose()?;
    let eval: Box<dyn Fn(f64) -> Result<f64>>;
    let mut kappas = None;
    match args.method.as_str() {
        "tls" | "tls-conservative" => {
            let ints = if args.method == "tls-conservative" {
                Some(integrals.clone().ok_or_else(|| {
                    Error::InvalidArgument("tls-conservative needs --integrals".into())
                })?)
            } else {
                None
            };
            let options = taylor::TlsOptions { order: args.order, ..Default::default() };
            let r = taylor::reconstruct(&cells, &points, &values, ints.as_deref(), options)?;
            kappas = Some(r.condition_numbers());
            eval = Box::new(move |x| Ok(r.evaluate(x)));
        }
        "cubic-spline" | "cubic-spline-natural" => {
            let end = if args.method == "cubic-spline" {
                cubic_spline::EndCondition::NotAKnot
            } else {
                cubic_spline::EndCondition::Natural
            };
            let mut pairs: Vec<(f64, f64)> = points.iter().copied().zip(values.iter().copied()).collect();
            if points.len() != values.len() {
                return Err(Error::InvalidArgument("--points and --values differ in length".into()));
            }
            pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
            let (x, y): (Vec<f64>, Vec<f64>) = pairs.into_iter().unzip();
            let s = cubic_spline::CubicSpline::new(&x, &y, end)?;
            eval = Box::new(move |z| Ok(s.evaluate(z)));
        }
        "mls" => {
            let cells_c = cells.clone();
            let (points, values) = (points.clone(), values.clone());
            eval = Box::new(move |z| {
                let (a, b) = cells_c
                    .iter()
                    .copied()
                    .find(|&(a, b)| a <= z && z <= b)
                    .ok_or(Error::OutsideDomain { x: z, a: edges[0], b: edges[edges.len() - 1] })?;
                mls::reconstruct_1d(z, &points, &values, b - a)
            });
        }
        other => {
            return Err(Error::InvalidArgument(format!(
                "--method must be tls, tls-conservative, cubic-spline, cubic-spline-natural or mls, got '{other}'"
            )))
        }
    }
    let out_values: Vec<f64> = at.iter().map(|&x| eval(x)).collect::<Result<_>>()?;
    // Cell integrals: 10 Gauss points on each sub-interval between data points
    // (exact for TLS of order ≤ 20 and for cubic-spline pieces).
    let mut cell_integrals = Vec::new();
    for &(a, b) in &cells {
        let mut cuts: Vec<f64> = points.iter().copied().filter(|&x| x > a && x < b).collect();
        cuts.push(a);
        cuts.push(b);
        cuts.sort_by(|p, q| p.total_cmp(q));
        cuts.dedup();
        let subs: Vec<(f64, f64)> = cuts.windows(2).map(|w| (w[0], w[1])).collect();
        let q = gauss_on_cells(&subs, 10)?;
        let mut sum = 0.0;
        for p in q {
            sum += p.weight * eval(p.x)?;
        }
        cell_integrals.push(sum);
    }
    if let Some(v) = out_values
        .iter()
        .chain(&cell_integrals)
        .find(|v| !v.is_finite())
    {
        return Err(Error::Singular(format!("the reconstruction produced {v}")));
    }
    let doc = ReconstructJson {
        method: args.method.clone(),
        values: out_values,
        cell_integrals,
        condition_numbers: kappas,
    };
    if args.json {
        return to_json(&doc);
    }
    let mut s = format!("{} reconstruction\n", doc.method);
    for (x, v) in at.iter().zip(&doc.values) {
        s.push_str(&format!("f({x}) = {v:.12e}\n"));
    }
    for (e, c) in doc.cell_integrals.iter().enumerate() {
        s.push_str(&format!("cell {e}: integral {c:.12e}"));
        if let Some(k) = &doc.condition_numbers {
            s.push_str(&format!(", condition number of D {:.3e}", k[e]));
        }
        s.push('\n');
    }
    Ok(s)
}

#[derive(Serialize)]
struct MassJson {
    size: usize,
    lambda_min: Option<f64>,
    lambda_max: Option<f64>,
    condition_number: Option<f64>,
    solver: Option<String>,
    iterations: Option<usize>,
    residuals: Option<Vec<f64>>,
}

fn mass(args: MassArgs) -> Result<String> {
    use hompm::solve::{cg, direct, pmultigrid, richardson, spectrum};
    use hompm::tables::book::{gravity_rhs, unit_mass_1d, unit_mass_2d};
    if args.dim != 1 && args.dim != 2 {
        return Err(Error::InvalidArgument(format!(
            "--dim must be 1 or 2, got {}",
            args.dim
        )));
    }
    if args.spans == 0 {
        return Err(Error::InvalidArgument("--spans must be at least 1".into()));
    }
    let k = unit_mass_2d(args.spans, args.degree, args.dirichlet)?;
    let m1 = unit_mass_1d(args.spans, args.degree, args.dirichlet)?;
    if m1.rows() == 0 {
        return Err(Error::InvalidArgument(
            "no degrees of freedom remain".into(),
        ));
    }
    let matrix = if args.dim == 1 {
        m1.clone()
    } else {
        k.assemble()
    };
    let mut doc = MassJson {
        size: matrix.rows(),
        lambda_min: None,
        lambda_max: None,
        condition_number: None,
        solver: args.solve.clone(),
        iterations: None,
        residuals: None,
    };
    if args.condition {
        let s = if args.dim == 1 {
            spectrum::spectrum_1d(&m1)?
        } else {
            spectrum::spectrum_kronecker(&k)?
        };
        doc.lambda_min = Some(s.lambda_min);
        doc.lambda_max = Some(s.lambda_max);
        doc.condition_number = Some(s.condition_number());
    }
    if let Some(method) = &args.solve {
        let f = gravity_rhs(&matrix);
        let result = match method.as_str() {
            "cg" => {
                cg::conjugate_gradient(&matrix, &f, args.tol, 100_000, cg::CgVariant::Recursive)?
            }
            "pmg" => {
                let mg = pmultigrid::PMultigrid::unit_mass(
                    args.spans,
                    args.degree,
                    args.dim,
                    args.dirichlet,
                    pmultigrid::PMultigridOptions::default(),
                )?;
                mg.solve(&f, args.tol, 10_000)?
            }
            "richardson" => {
                let ml = matrix.row_sums();
                richardson::richardson(&matrix, &ml, &f, args.tol, 1_000_000)?
            }
            "direct" => {
                let x = direct::cholesky_solve(&matrix, &f)?;
                let mut ax = vec![0.0; x.len()];
                matrix.mul_vec(&x, &mut ax);
                let r =
                    hompm::solve::norm(&f.iter().zip(&ax).map(|(a, b)| a - b).collect::<Vec<_>>());
                hompm::solve::IterativeResult {
                    solution: x,
                    iterations: 0,
                    residuals: vec![r / hompm::solve::norm(&f)],
                }
            }
            other => {
                return Err(Error::InvalidArgument(format!(
                    "--solve must be cg, pmg, richardson or direct, got '{other}'"
                )))
            }
        };
        doc.iterations = (method != "direct").then_some(result.iterations);
        doc.residuals = Some(result.residuals);
    }
    if args.json {
        return to_json(&doc);
    }
    let mut s = format!("size {}\n", doc.size);
    if let (Some(a), Some(b), Some(c)) = (doc.lambda_min, doc.lambda_max, doc.condition_number) {
        s.push_str(&format!(
            "lambda_min {a:.6e}\nlambda_max {b:.6e}\ncondition number {c:.6e}\n"
        ));
    }
    if let Some(r) = &doc.residuals {
        s.push_str(&format!(
            "{}: {} iterations, final relative residual {:.3e}\n",
            doc.solver.clone().unwrap_or_default(),
            doc.iterations.map_or("-".into(), |i| i.to_string()),
            r.last().copied().unwrap_or(f64::NAN)
        ));
    }
    Ok(s)
}

fn table(id: Option<String>, list: bool, json: bool) -> Result<String> {
    if list || id.is_none() {
        let mut s = String::new();
        for spec in tables::registry() {
            let p = tables::Published::parse(spec.id, spec.published_json)?;
            s.push_str(&format!("{:<20} {}\n", spec.id, p.title));
        }
        return Ok(s);
    }
    let id = id.unwrap_or_default();
    let spec = tables::find(&id)?;
    let report = tables::run(&spec, &RunOptions::default())?;
    if json {
        to_json(&report)
    } else {
        Ok(report.render_text())
    }
}

fn reproduce(
    out: std::path::PathBuf,
    only: Vec<String>,
    quick: bool,
    docs: Option<std::path::PathBuf>,
    update_baseline: bool,
) -> Result<String> {
    use hompm::report;
    use std::io::IsTerminal;
    let options = RunOptions { quick };
    for o in &only {
        tables::find(o)?;
    }
    let ids: Vec<&str> = tables::ids()
        .into_iter()
        .filter(|id| only.is_empty() || only.iter().any(|o| o == id))
        .collect();
    let terminal = std::io::stderr().is_terminal();
    let bar = indicatif::ProgressBar::new(ids.len() as u64);
    if terminal {
        bar.set_style(
            indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} tables  {msg}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
    } else {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let done = std::sync::atomic::AtomicUsize::new(0);
    let progress = |id: &str, secs: f64| {
        let k = done.fetch_add(1, std::sync::atomic::Ordering::SeqCst) + 1;
        if terminal {
            bar.set_message(format!("{id} ({secs:.1} s)"));
            bar.inc(1);
        } else {
            eprintln!("[{k}/{}] {id} ({secs:.1} s)", ids.len());
        }
    };
    let reports = report::run_tables(&ids, options, &progress)?;
    bar.finish_and_clear();
    let mut studies = std::collections::BTreeMap::new();
    let charts = out.join("charts");
    if only.is_empty() {
        for (name, step) in [
            ("convergence", 0),
            ("work-precision", 1),
            ("solvers", 2),
            ("stability", 3),
            ("speed", 4),
        ] {
            let t = std::time::Instant::now();
            match step {
                0 => report::convergence_charts(&charts, &mut studies)?,
                1 => report::work_precision_chart(&charts, quick, &mut studies)?,
                2 => report::solver_charts(&charts, &reports, quick, &mut studies)?,
                3 => report::stability_chart(&charts, quick, &mut studies)?,
                _ => report::speed_chart(&charts, quick, &mut studies)?,
            }
            eprintln!("study {name} ({:.1} s)", t.elapsed().as_secs_f64());
        }
    }
    let built = report::build(
        reports,
        &report::ReproduceOptions {
            out: out.clone(),
            only: only.clone(),
            quick,
        },
        studies,
    )?;
    if let Some(path) = docs {
        report::write_file(
            &path,
            &report::reproduction_markdown(
                &built,
                include_str!("../../docs/reproduction-notes.md"),
            ),
        )?;
    }
    let baseline: report::Baseline =
        serde_json::from_str(include_str!("../../golden/reproduced.json")).map_err(|e| {
            Error::Published {
                id: "reproduced.json".into(),
                message: e.to_string(),
            }
        })?;
    if update_baseline {
        let mut merged = baseline.clone();
        merged.extend(report::baseline_of(&built.tables));
        let text = serde_json::to_string_pretty(&merged).map_err(|e| Error::Io(e.to_string()))?;
        report::write_file(
            std::path::Path::new("golden/reproduced.json"),
            &(text + "\n"),
        )?;
    }
    let mut s = String::new();
    for r in &built.tables {
        let (rep, total) = r.counts();
        s.push_str(&format!("{:<20} {rep:>4} of {total:>4} reproduced\n", r.id));
    }
    s.push_str(&format!("report written to {}\n", out.display()));
    s.push_str(&format!(
        "{} of {} published numbers reproduced\n",
        built.reproduced, built.published_in_computed_tables
    ));
    // With --quick, cells that are not computed are skipped, not regressions.
    let tables_for_check: Vec<tables::TableReport> = built
        .tables
        .iter()
        .cloned()
        .map(|mut r| {
            if quick {
                for (i, row) in r.computed.iter().enumerate() {
                    for (j, v) in row.iter().enumerate() {
                        if v.is_none() {
                            r.status[i][j] = tables::Status::Reproduced;
                        }
                    }
                }
            }
            r
        })
        .collect();
    let regressed = report::regressions(&tables_for_check, &baseline);
    if !regressed.is_empty() && !update_baseline {
        print(&s);
        return Err(Error::InvalidArgument(format!(
            "{} published numbers marked reproduced no longer reproduce: {}",
            regressed.len(),
            regressed.join("; ")
        )));
    }
    Ok(s)
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(
                e.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            ) {
                print(&e.to_string());
                return if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
                    ExitCode::from(2)
                } else {
                    ExitCode::SUCCESS
                };
            }
            let text = e.to_string();
            let first = text.lines().next().unwrap_or("error: invalid arguments");
            eprintln!("{first}");
            return ExitCode::from(2);
        }
    };
    let result = match cli.command {
        Command::Basis {
            degree,
            knots,
            at,
            derivatives,
            json,
        } => basis(degree, &knots, &at, derivatives, json),
        Command::Table { id, list, json } => table(id, list, json),
        Command::Run(args) => run_scene(args),
        Command::Reconstruct(args) => reconstruct(args),
        Command::Mass(args) => mass(args),
        Command::Reproduce {
            out,
            only,
            quick,
            docs,
            update_baseline,
        } => reproduce(out, only, quick, docs, update_baseline),
    };
    match result {
        Ok(out) => {
            print(&out);
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
