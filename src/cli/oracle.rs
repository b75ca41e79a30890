//! # `hompm exact`, `hompm trace`, `hompm check`
//!
//! The commands of the oracle (docs/oracle.md): they parse, call
//! [`crate::oracle`] and print. `check` exits 0 when the other code agrees,
//! 1 when it differs (the report is printed first), 2 when its input is
//! unusable. Bad arguments to `exact`, `trace` and `check` (a NaN time, an
//! unknown parameter set, an override a scene lacks, …) are usage errors:
//! one line, exit 2. A refusal by the limits and a run that fails exit 1.
//!
//! Items: [`ExactArgs`], [`TraceArgs`], [`CheckArgs`], [`MatchArg`],
//! [`exact`], [`trace`], [`check`].

use super::args::SceneArg;
use super::limits::Limits;
use super::setup_args::SetupArgs;
use super::{json, Output};
use crate::error::{Error, Result};
use crate::mpm::particles::Particles;
use crate::mpm2d::Particles2d;
use crate::oracle::check::{check as compare, CheckOptions, MatchBy};
use crate::oracle::compare::sci;
use crate::oracle::convergence::convergence;
use crate::oracle::exact::{exact_1d, exact_2d, formulas_1d, formulas_2d, reference_kind};
use crate::oracle::input::{parse_input, read_input, ColumnMap, Input};
use crate::oracle::run::{reference, trace_1d, trace_2d};
use crate::oracle::setup::{Setup, Setup1d};
use crate::oracle::trace::{header_1d, header_2d, Trace, EQUATIONS_1D, EQUATIONS_2D};
use crate::oracle::visibility::time_resolution;
use clap::ValueEnum;
use std::path::PathBuf;

/// Arguments of `hompm exact`.
#[derive(clap::Args, Debug)]
pub struct ExactArgs {
    /// The scene, its parameters and (with --cells and --ppc) its particle
    /// layout; the method options are ignored.
    #[command(flatten)]
    setup: SetupArgs,
    /// The time t.
    #[arg(long, allow_negative_numbers = true)]
    time: f64,
    /// Initial positions X (2D: x,y pairs, flattened); default: the
    /// particles of --cells and --ppc.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    at: Vec<f64>,
    /// The body force as MLS paper Eq. (42) prints it (π, not π²).
    #[arg(long)]
    as_printed: bool,
    /// Print JSON.
    #[arg(long, conflicts_with = "csv")]
    json: bool,
    /// Print CSV.
    #[arg(long)]
    csv: bool,
}

/// Arguments of `hompm trace`.
#[derive(clap::Args, Debug)]
pub struct TraceArgs {
    /// The run's setup (as `hompm run`); --steps is the number of steps run.
    #[command(flatten)]
    setup: SetupArgs,
    /// Trace steps 1, 1 + N, 1 + 2N, … and the last.
    #[arg(long, default_value_t = 1, value_parser = super::args::count)]
    every: usize,
    /// Print JSON.
    #[arg(long, conflicts_with = "csv")]
    json: bool,
    /// Print CSV (`step,time,equation,index,value`).
    #[arg(long)]
    csv: bool,
}

/// `--match`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MatchArg {
    /// By the `id` column if present, else by initial position.
    Auto,
    /// By the `id` column (0-based; 1..=n read as 1-based).
    Id,
    /// By initial position, nearest within a quarter spacing.
    X0,
    /// Row k is hompm's particle k (a file with neither id nor x0).
    Order,
}

/// Arguments of `hompm check`.
#[derive(clap::Args, Debug)]
pub struct CheckArgs {
    /// The run's setup, as the other code ran it.
    #[command(flatten)]
    setup: SetupArgs,
    /// The other code's particles at the end (CSV with a header, or JSON),
    /// or its trace in `hompm trace`'s schema.
    #[arg(long, required_unless_present = "convergence")]
    input: Option<PathBuf>,
    /// Several resolutions of the other code: the observed order per field
    /// (cells from each file's `# cells:` line or JSON `cells`, or --cells).
    #[arg(long, num_args = 1.., conflicts_with = "input")]
    convergence: Vec<PathBuf>,
    /// Column names: ours=theirs,… (e.g. x0_x=X0,u_x=ux).
    #[arg(long, default_value = "")]
    columns: String,
    /// How particles are matched.
    #[arg(long = "match", value_enum, default_value_t = MatchArg::Auto)]
    match_by: MatchArg,
    /// Relative tolerance (a value fails only if both tolerances fail).
    #[arg(long, default_value_t = crate::oracle::check::DEFAULT_RTOL, allow_negative_numbers = true)]
    rtol: f64,
    /// Absolute tolerance.
    #[arg(long, default_value_t = crate::oracle::check::DEFAULT_ATOL, allow_negative_numbers = true)]
    atol: f64,
    /// Print JSON.
    #[arg(long)]
    json: bool,
}

/// An error in the arguments of an oracle command is a usage error (exit
/// 2, docs/oracle.md); a refusal by the limits, an input-file error and the
/// failures of a run keep their own kind.
fn as_usage(e: Error) -> Error {
    match e {
        Error::OverLimit { .. } | Error::Input(_) | Error::Usage(_) => e,
        other => Error::Usage(other.to_string()),
    }
}

/// `hompm exact`: every failure is in its arguments (exit 2) but a
/// refusal by the limits.
pub fn exact(a: ExactArgs, limits: &Limits) -> Result<Output> {
    exact_fields(a, limits).map_err(as_usage)
}

fn exact_fields(a: ExactArgs, limits: &Limits) -> Result<Output> {
    crate::error::finite("--time", a.time)?;
    let scene = a.setup.scene()?;
    let mut setup = a.setup.clone();
    // The method options do not matter for the exact solution; a 2D scene
    // builds its layout with any method.
    setup.method = if scene == SceneArg::AlignedVibration {
        super::args::MethodArg::MPM
    } else {
        setup.method
    };
    let s = setup.setup()?;
    let points = match &s {
        Setup::OneD(_) => a.at.len(),
        Setup::TwoD(_) => a.at.len() / 2,
    };
    let n = if a.at.is_empty() {
        let c = setup.cells()? as f64;
        match &s {
            Setup::OneD(_) => c * setup.ppc() as f64,
            Setup::TwoD(_) => c * c * setup.ppc() as f64,
        }
    } else {
        points as f64
    };
    limits.check_memory(
        || format!("the exact fields at {n:.0} points"),
        n * 400.0,
        "columns",
    )?;
    let mut columns: Vec<(String, Vec<f64>)> = Vec::new();
    let mut push = |name: &str, v: f64| match columns.iter_mut().find(|(k, _)| k == name) {
        Some((_, c)) => c.push(v),
        None => columns.push((name.to_string(), vec![v])),
    };
    let meta = match &s {
        Setup::OneD(s1) => {
            let x0 = if a.at.is_empty() {
                layout_1d(s1)?
            } else {
                a.at.clone()
            };
            let (lo, hi) = (0.0, s1.scene.length());
            for &x in &x0 {
                if !(lo..=hi).contains(&x) {
                    return Err(Error::OutsideDomain { x, a: lo, b: hi });
                }
                let e = exact_1d(&s1.scene, x, a.time);
                for (k, v) in [
                    ("x0", x),
                    ("u", e.u),
                    ("v", e.v),
                    ("strain", e.strain),
                    ("stress", e.stress),
                ] {
                    push(k, v);
                }
            }
            serde_json::json!({
                "scene": s1.scene,
                "kind": reference_kind(&s1.scene),
                "formulas": formulas_1d(&s1.scene),
            })
        }
        Setup::TwoD(s2) => {
            if !a.at.len().is_multiple_of(2) {
                return Err(Error::InvalidArgument(format!(
                    "--at takes x,y pairs in 2D; got {} numbers",
                    a.at.len()
                )));
            }
            let x0: Vec<[f64; 2]> = if a.at.is_empty() {
                Particles2d::cell_centred(
                    s2.scene.length,
                    s2.cells,
                    s2.per_side,
                    s2.scene.density,
                    |_| [0.0; 2],
                )?
                .x0
            } else {
                a.at.chunks(2).map(|c| [c[0], c[1]]).collect()
            };
            let l = s2.scene.length;
            for x in &x0 {
                crate::error::finite("--at", x[0])?;
                crate::error::finite("--at", x[1])?;
                // The square [0, L]², as 1D refuses a point outside [0, L].
                for &c in x {
                    if !(0.0..=l).contains(&c) {
                        return Err(Error::OutsideDomain { x: c, a: 0.0, b: l });
                    }
                }
                let e = exact_2d(&s2.scene, *x, a.time, a.as_printed)?;
                let m = |name: &str, v: [f64; 4]| {
                    [
                        (format!("{name}_xx"), v[0]),
                        (format!("{name}_xy"), v[1]),
                        (format!("{name}_yx"), v[2]),
                        (format!("{name}_yy"), v[3]),
                    ]
                };
                let mut all = vec![
                    ("x0_x".to_string(), x[0]),
                    ("x0_y".into(), x[1]),
                    ("u_x".into(), e.u[0]),
                    ("u_y".into(), e.u[1]),
                    ("v_x".into(), e.v[0]),
                    ("v_y".into(), e.v[1]),
                ];
                all.extend(m("F", e.deformation));
                all.push(("J".into(), e.jacobian));
                all.extend(m("P", e.first_piola));
                all.extend(m("stress", e.stress));
                all.push(("b_x".into(), e.body_force[0]));
                all.push(("b_y".into(), e.body_force[1]));
                for (k, v) in all {
                    push(&k, v);
                }
            }
            serde_json::json!({
                "scene": s2.scene,
                "params_set": s2.set_name,
                "kind": "manufactured solution (MLS paper Eqs. 38-42)",
                "formulas": formulas_2d(a.as_printed),
            })
        }
    };
    if let Some((name, values)) = columns
        .iter()
        .find(|(_, v)| v.iter().any(|x| !x.is_finite()))
    {
        let bad = values
            .iter()
            .copied()
            .find(|x| !x.is_finite())
            .unwrap_or(f64::NAN);
        return Err(Error::NonFinite {
            what: format!("the exact {name} at t = {:e}", a.time),
            value: bad,
        });
    }
    if a.json {
        let mut doc = serde_json::Map::new();
        doc.insert("time".into(), serde_json::json!(a.time));
        doc.insert("exact_solution".into(), meta);
        let cols: serde_json::Map<String, serde_json::Value> = columns
            .into_iter()
            .map(|(k, v)| (k, serde_json::json!(v)))
            .collect();
        doc.insert("fields".into(), serde_json::Value::Object(cols));
        return Ok(Output::text(json::strict(&doc)?));
    }
    let mut out = format!(
        "# time: {:e}\n# kind: {}\n",
        a.time,
        meta["kind"].as_str().unwrap_or("")
    );
    if !a.csv {
        if let Some(f) = meta["formulas"].as_object() {
            for (k, v) in f {
                out.push_str(&format!("# {k}: {}\n", v.as_str().unwrap_or("")));
            }
        }
    }
    out.push_str(
        &columns
            .iter()
            .map(|(k, _)| k.as_str())
            .collect::<Vec<_>>()
            .join(","),
    );
    out.push('\n');
    let rows = columns.first().map_or(0, |(_, c)| c.len());
    for r in 0..rows {
        let line: Vec<String> = columns.iter().map(|(_, c)| format!("{:e}", c[r])).collect();
        out.push_str(&line.join(","));
        out.push('\n');
    }
    Ok(Output::text(out))
}

/// The initial particle positions of a 1D setup.
fn layout_1d(s: &Setup1d) -> Result<Vec<f64>> {
    let d = &s.discretisation;
    let count = d.cells.checked_mul(d.ppc).ok_or_else(|| {
        Error::InvalidArgument(format!(
            "{} cells × {} PPC overflow a count",
            d.cells, d.ppc
        ))
    })?;
    Ok(Particles::uniform(0.0, s.scene.length(), count, 1.0)?.x0)
}

/// Bytes of a trace of `steps` traced steps: 8 particle and 9 DOF
/// quantities per step in 1D; 14 per particle, 11 per node and 8 per
/// Gauss point in 2D; each kept twice (values and text) and doubled for
/// the formatting.
fn trace_bytes(setup: &Setup, steps: usize) -> f64 {
    let per_step = match setup {
        Setup::OneD(s) => {
            let d = &s.discretisation;
            let particles = d.cells as f64 * d.ppc as f64;
            let dofs = 2.0 * d.cells as f64 + 8.0;
            8.0 * particles + 9.0 * dofs
        }
        Setup::TwoD(s) => {
            let c = s.cells as f64;
            let particles = c * c * (s.per_side as f64).powi(2);
            let nodes = (c + 5.0) * (c + 5.0);
            14.0 * particles + 11.0 * nodes + 32.0 * c * c
        }
    };
    steps as f64 * per_step * 8.0 * 4.0
}

/// `hompm trace`.
pub fn trace(a: TraceArgs, limits: &Limits) -> Result<Output> {
    if a.every == 0 {
        return Err(Error::Usage("--every must be at least 1".into()));
    }
    let setup = a.setup.setup().map_err(as_usage)?;
    let traced = if setup.steps() == 0 {
        0
    } else {
        (setup.steps() - 1) / a.every + 2
    };
    a.setup
        .check_limits(&setup, limits, trace_bytes(&setup, traced))?;
    let trace = match &setup {
        Setup::OneD(s) => trace_1d(s, a.every, None)?.0,
        Setup::TwoD(s) => trace_2d(s, a.every, None)?.0,
    };
    let stdout = if a.json {
        json::strict(&trace)?
    } else if a.csv {
        trace.to_csv()
    } else {
        trace_summary(&trace)
    };
    Ok(Output::text(stdout))
}

/// A readable summary: per traced step and equation, the count and range.
fn trace_summary(t: &Trace) -> String {
    let mut out = format!(
        "hompm trace, {} traced steps (--json or --csv for every value; docs/oracle.md)\n",
        t.steps.len()
    );
    for s in &t.steps {
        out.push_str(&format!("step {} (t = {:e})\n", s.step, s.time));
        for e in EQUATIONS_1D.iter().chain(EQUATIONS_2D.iter()) {
            if let Some(v) = s.equations.get(e.key) {
                let (lo, hi) = v
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                        (a.min(*x), b.max(*x))
                    });
                out.push_str(&format!(
                    "  {:<17} {:<24} {:>5} values in [{lo:.6e}, {hi:.6e}]  {}\n",
                    e.key,
                    e.citation,
                    v.len(),
                    e.symbol
                ));
            }
        }
    }
    out
}

/// Reads and parses one input file.
fn read(path: &std::path::Path, a: &CheckArgs, limits: &Limits) -> Result<(Input, Vec<String>)> {
    let text = read_input(path, limits.max_memory)?;
    parse_input(&text, &ColumnMap::parse(&a.columns)?, a.setup.two_d())
}

/// `hompm check`.
pub fn check(a: CheckArgs, limits: &Limits) -> Result<Output> {
    let options = CheckOptions {
        rtol: a.rtol,
        atol: a.atol,
        match_by: match a.match_by {
            MatchArg::Auto => MatchBy::Auto,
            MatchArg::Id => MatchBy::Id,
            MatchArg::X0 => MatchBy::X0,
            MatchArg::Order => MatchBy::Order,
        },
    };
    for (name, v) in [("--rtol", a.rtol), ("--atol", a.atol)] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(Error::Usage(format!(
                "{name} must be finite and at least 0, got {v}"
            )));
        }
    }
    if !a.convergence.is_empty() {
        return check_convergence(&a, &options, limits);
    }
    let Some(path) = a.input.as_deref() else {
        return Err(Error::Usage(
            "--input FILE or --convergence FILE… is required".into(),
        ));
    };
    let setup = a.setup.setup().map_err(as_usage)?;
    a.setup.check_limits(&setup, limits, 0.0)?;
    let (input, ignored) = read(path, &a, limits)?;
    let only = match &input {
        Input::Trace(t) => {
            let ours = match &setup {
                Setup::OneD(s) => header_1d(s)?,
                Setup::TwoD(s) => header_2d(s)?,
            };
            crate::oracle::check::check_header(&t.header, &ours)?;
            Some(t.steps.iter().map(|s| s.step).collect())
        }
        Input::Particles(_) => None,
    };
    let (state, ours) = reference(&setup, only)?;
    let mut report = compare(&setup, &state, &input, ours.as_ref(), &options)?;
    if report.agrees && matches!(input, Input::Particles(_)) {
        let compared = report.compared_columns();
        if let Some(r) = time_resolution(&setup, &state, &compared, &options.tolerance())? {
            report = report.with_time_resolution(r);
        }
    }
    let mut warnings = Vec::new();
    if !ignored.is_empty() {
        let shown: Vec<&str> = ignored.iter().take(10).map(String::as_str).collect();
        let more = ignored.len().saturating_sub(shown.len());
        warnings.push(format!(
            "ignored columns that are not hompm's: {}{} (map them with --columns ours=theirs)",
            shown.join(", "),
            if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            }
        ));
    }
    let stdout = if a.json {
        json::strict(&report)?
    } else {
        report_text(&report)
    };
    let failure = (!report.agrees).then(|| {
        Error::Differs(
            report
                .verdict
                .lines()
                .next()
                .unwrap_or("differs from hompm")
                .to_string(),
        )
    });
    Ok(Output {
        stdout,
        warnings,
        failure,
    })
}

/// The report in words and a table of fields, in the order compared.
fn report_text(r: &crate::oracle::check::CheckReport) -> String {
    let mut out = format!(
        "{}\n\nhompm: {}; {} particles matched by {}; exact solution at t = {:e}\n",
        r.verdict, r.method, r.particles, r.matched_by, r.time
    );
    out.push_str(&format!(
        "{:<8} {:>10} {:>10} {:>10} {:>9} {:>9} {:>12} {:>12}\n",
        "field", "max abs", "max rel", "tol abs", "particle", "failures", "RMS yours", "RMS hompm"
    ));
    for name in &r.compared_fields {
        let Some(f) = r.fields.get(name) else {
            continue;
        };
        let (ry, rh) = f.rms_exact.map_or(("-".into(), "-".into()), |p| {
            (sci(p.yours, 4), sci(p.hompm, 4))
        });
        out.push_str(&format!(
            "{name:<8} {:>10} {:>10} {:>10} {:>9} {:>9} {ry:>12} {rh:>12}\n",
            sci(f.max_abs, 3),
            sci(f.max_rel, 3),
            sci(f.atol_abs, 3),
            f.worst_particle,
            f.failures
        ));
    }
    if let Some(d) = &r.first_difference {
        out.push_str(&format!(
            "first difference: step {}, {} ({}), {} {} (absolute tolerance there {:.3e})\n",
            d.step, d.equation, d.citation, d.index_kind, d.index, d.atol_abs
        ));
    }
    out
}

/// `hompm check --convergence`.
fn check_convergence(a: &CheckArgs, o: &CheckOptions, limits: &Limits) -> Result<Output> {
    let mut runs = Vec::new();
    let listed = &a.setup.cells;
    if listed.len() > 1 && listed.len() != a.convergence.len() {
        return Err(Error::Usage(format!(
            "--cells lists {} resolutions for {} files; give one per file, in the files' order",
            listed.len(),
            a.convergence.len()
        )));
    }
    let explicit = listed.len() == a.convergence.len() && listed.len() > 1;
    for (k, path) in a.convergence.iter().enumerate() {
        let (input, _) = read(path, a, limits)?;
        let Input::Particles(table) = &input else {
            return Err(Error::Input(format!(
                "{}: --convergence reads final particles, not traces",
                path.display()
            )));
        };
        let cells = if explicit {
            listed[k]
        } else {
            let text = table.metadata.get("cells").ok_or_else(|| {
                Error::Input(format!(
                    "{} names no cells (a '# cells: N' line or a JSON 'cells'); or list them with --cells N1,N2,…",
                    path.display()
                ))
            })?;
            super::args::count(text.trim_matches('"'))
                .map_err(|e| Error::Input(format!("{}: cells {e}", path.display())))?
        };
        let setup = a.setup.setup_with_cells(cells).map_err(as_usage)?;
        a.setup.check_limits(&setup, limits, 0.0)?;
        let length = match &setup {
            Setup::OneD(s) => s.scene.length(),
            Setup::TwoD(s) => s.scene.length,
        };
        let (state, _) = reference(&setup, None)?;
        runs.push((setup, state, input, cells, length));
    }
    runs.sort_by_key(|r| r.3);
    let report = convergence(&runs, o)?;
    let stdout = if a.json {
        json::strict(&report)?
    } else {
        format!("{}\n", report.verdict)
    };
    let not_held: Vec<String> = report
        .fields
        .iter()
        .filter(|(_, f)| f.verdict != crate::oracle::convergence::HOLDS)
        .map(|(name, f)| format!("{name} {}", f.verdict))
        .collect();
    Ok(Output {
        stdout,
        warnings: Vec::new(),
        failure: (!not_held.is_empty()).then(|| {
            Error::Differs(format!(
                "the observed order does not hold in every field: {}",
                not_held.join("; ")
            ))
        }),
    })
}
