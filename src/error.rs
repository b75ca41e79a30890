//! # Errors
//!
//! Every failure a user can cause is a variant of [`Error`]: malformed knot
//! vectors, degrees that do not fit, points outside a domain, non-finite input,
//! singular systems, solvers that do not converge and runs that blow up.
//! Public functions return `Result<_, Error>`; none of them panics on bad input
//! and none returns a silent NaN.
//!
//! Items: [`Error`], [`DivergenceCause`], [`Result`], [`finite`], [`finite_named`].

/// The one error type of hompm. Each message names the offending value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// A knot vector that is empty, not non-decreasing, or has a knot of too high
    /// multiplicity (book §4.3, thesis §6.1).
    #[error("invalid knot vector: {0}")]
    InvalidKnots(String),
    /// A knot vector that decreases: ξ_index < ξ_{index−1} (book §4.3 asks
    /// for a non-decreasing sequence).
    #[error("invalid knot vector: knots must be non-decreasing, but knot {index} = {knot} < knot {} = {previous}", index - 1)]
    DecreasingKnot {
        /// Index of the first knot below its predecessor (≥ 1).
        index: usize,
        /// Its value ξ_index.
        knot: f64,
        /// The value ξ_{index−1} before it.
        previous: f64,
    },
    /// A polynomial degree that does not fit the knot vector or the element type.
    #[error("invalid degree: {0}")]
    InvalidDegree(String),
    /// A NaN or infinite number where a finite one is required.
    #[error("non-finite input: {what} = {value}")]
    NonFinite {
        /// What the number was meant to be (e.g. "knot 3", "evaluation point").
        what: String,
        /// The offending value.
        value: f64,
    },
    /// An evaluation point (or particle) outside the domain of a basis.
    #[error("point {x} lies outside the domain [{a}, {b}]")]
    OutsideDomain {
        /// The point.
        x: f64,
        /// Left end of the domain.
        a: f64,
        /// Right end of the domain.
        b: f64,
    },
    /// Any other argument out of its documented range (zero spans, …),
    /// for a person to read.
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
    /// Two inputs that go together have different lengths: values and their
    /// points, particle arrays, a right-hand side and its system.
    #[error("{what}: {got} given, {expected} needed")]
    LengthMismatch {
        /// The shorter or longer input, and what its length must match.
        what: String,
        /// The length it must have.
        expected: usize,
        /// The length it has.
        got: usize,
    },
    /// A quantity that must be positive and finite is not: Δt, a density,
    /// a volume, the length of a cell or domain, a support scale.
    #[error("{what} must be positive and finite, got {value}")]
    NotPositive {
        /// The quantity.
        what: String,
        /// Its value.
        value: f64,
    },
    /// An input that needs at least one item has none (particles, cells).
    #[error("no {0}")]
    Empty(String),
    /// A linear system that cannot be solved (singular or not positive definite).
    #[error("singular system: {0}")]
    Singular(String),
    /// A system whose condition number exceeds what double precision
    /// resolves: its smallest eigenvalue is below the rounding of the largest.
    #[error("{what} has κ ≥ {kappa_at_least:.1e}: its smallest eigenvalue is below the rounding n·ε·λ_max of the largest, so κ exceeds what double precision resolves")]
    IllConditioned {
        /// The system.
        what: String,
        /// A lower bound on κ = λ_max/λ_min.
        kappa_at_least: f64,
    },
    /// An iterative method that did not meet its stopping rule.
    #[error("did not converge: {0}")]
    NotConverged(String),
    /// A time-stepping run whose state became non-finite or unphysical.
    #[error("the run blew up: {0}")]
    BlowUp(String),
    /// An MPM run in which a particle's position, velocity or stress became
    /// non-finite, or its volume non-positive (a diverged run).
    #[error(
        "the run blew up: particle {particle} became non-physical at step {step} (t = {time:e}): x = {x:e}, v = {velocity:e}, σ = {stress:e}, V = {volume:e}{}",
        if *.negative_masses { "; negative lumped masses were seen" } else { "" }
    )]
    NonPhysicalParticle {
        /// Index of the first such particle.
        particle: usize,
        /// Steps taken, including the one that failed.
        step: usize,
        /// Time reached.
        time: f64,
        /// Its position.
        x: f64,
        /// Its velocity.
        velocity: f64,
        /// Its stress.
        stress: f64,
        /// Its volume.
        volume: f64,
        /// Whether negative lumped masses were seen earlier in the run.
        negative_masses: bool,
    },
    /// An MPM run in which a particle left the grid.
    #[error(
        "the run blew up: particle {particle} left the grid [{a}, {b}] at step {step}: x = {x:e}"
    )]
    ParticleLeftGrid {
        /// Index of the first such particle.
        particle: usize,
        /// Steps taken, including the one that failed.
        step: usize,
        /// Its position.
        x: f64,
        /// Left end of the grid.
        a: f64,
        /// Right end of the grid.
        b: f64,
    },
    /// A deformation gradient F with J = det F ≤ 0 or not finite: a material
    /// turned inside out, where the neo-Hookean law (MLS paper Eqs. 40–41)
    /// and V = J V⁰ (Eq. 36) need J > 0. The 2D engine fills in the particle,
    /// the step and the time; the material alone knows only F.
    #[error("the run blew up: {}det F = {jacobian:e} ≤ 0 or not finite, the material turned inside out (F = [{:e}, {:e}; {:e}, {:e}])", where_in_run(*.particle, *.step, *.time), .deformation[0], .deformation[1], .deformation[2], .deformation[3])]
    InvertedDeformation {
        /// The particle, when the check ran in a time step.
        particle: Option<usize>,
        /// Steps taken, including the one that failed, when known.
        step: Option<usize>,
        /// Time reached, when known.
        time: Option<f64>,
        /// J = det F.
        jacobian: f64,
        /// F row by row: [F₁₁, F₁₂, F₂₁, F₂₂].
        deformation: [f64; 4],
    },
    /// A 2D particle whose velocity is not finite at the end of a step
    /// (MLS paper Eq. 29 produced NaN or ∞). The step fills in its number
    /// and time.
    #[error("the run blew up: {}velocity ({:e}, {:e}) is not finite", where_in_run(Some(*.particle), *.step, *.time), .velocity[0], .velocity[1])]
    NonFiniteVelocity {
        /// The particle.
        particle: usize,
        /// Steps taken, including the one that failed, when known.
        step: Option<usize>,
        /// Time reached, when known.
        time: Option<f64>,
        /// Its velocity.
        velocity: [f64; 2],
    },
    /// A TLS cell whose data cannot determine its fit (TLS paper §5.3), when
    /// degenerate cells are errors.
    #[error(
        "singular system: TLS on cell {} [{}]: {detail}",
        index_text(cell),
        cell_text(lower, upper)
    )]
    SingularCell {
        /// Index of the cell per axis: (e) in 1D, (e_x, e_y) in 2D.
        cell: Vec<usize>,
        /// Lower corner: the left end in 1D, (x₀, y₀) in 2D.
        lower: Vec<f64>,
        /// Upper corner: the right end in 1D, (x₁, y₁) in 2D.
        upper: Vec<f64>,
        /// Why the fit failed (too few points, or κ(D) with its value).
        detail: String,
    },
    /// An MLS moment matrix A (MLS paper Eq. 10) at an evaluation point that
    /// is singular or whose condition number exceeds its limit
    /// (`MLS_MAX_CONDITION` of the MLS reconstruction): too few data points
    /// (particles) in the weight's support, or all of them on a line in 2D.
    #[error("singular system: MLS moment matrix A at {} is singular or has κ = {condition_number:e} > {limit:e}: {points_in_support} points in its support", point_text(point))]
    SingularMoments {
        /// The evaluation point: (x) in 1D, (x, y) in 2D (a Gauss point in
        /// the 2D engine).
        point: Vec<f64>,
        /// How many data points (particles) have a positive weight there.
        points_in_support: usize,
        /// κ(A), or ∞ where A cannot be inverted.
        condition_number: f64,
        /// The largest κ accepted.
        limit: f64,
    },
    /// A run that the stability monitor (`mpm::monitor`) stopped: the energy
    /// grew beyond its bound, or a strain reached ±1.
    #[error("the run diverged at step {step} (t = {time:e}){}: {cause}", match particle { Some(p) => format!(", particle {p}"), None => String::new() })]
    Diverged {
        /// Steps taken, including the one that failed.
        step: usize,
        /// Time reached.
        time: f64,
        /// The particle that shows it, where one does.
        particle: Option<usize>,
        /// What diverged, with the numbers.
        cause: DivergenceCause,
    },
    /// A command whose estimated memory or run time exceeds a limit: refused
    /// before any work is done.
    #[error("{what} needs {needed}; the limit is {limit} ({flag})")]
    OverLimit {
        /// What was asked for ("--condition on 100001 DOFs").
        what: String,
        /// The estimate ("a dense 80 GB matrix").
        needed: String,
        /// The limit in force ("4 GiB").
        limit: String,
        /// The flag that raises it.
        flag: &'static str,
    },
    /// Command-line arguments that do not parse (exit code 2).
    #[error("{0}")]
    Usage(String),
    /// Another code's output that `hompm check` cannot use: an empty or
    /// unparsable file, a missing, unknown or duplicated column, a
    /// non-finite value, a particle that matches none or two of hompm's, a
    /// trace of other settings, a file over the memory limit (exit code 2).
    #[error("input: {0}")]
    Input(String),
    /// `hompm check` compared another code's output with hompm's and
    /// found a difference beyond the tolerance (exit code 1); the report
    /// is printed before it.
    #[error("{0}")]
    Differs(String),
    /// A table id that is not registered.
    #[error("unknown table id '{0}' (see `hompm table --list`)")]
    UnknownTable(String),
    /// A file that cannot be written or read (report output, baselines).
    #[error("i/o: {0}")]
    Io(String),
    /// A published-number file that cannot be read.
    #[error("published data {id}: {message}")]
    Published {
        /// The table id.
        id: String,
        /// What is wrong with it.
        message: String,
    },
}

/// Why the stability monitor (`mpm::monitor`) stopped a run: the fields of
/// [`Error::Diverged`]'s cause, so a caller matches the kind and its numbers,
/// not the message.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DivergenceCause {
    /// The energy grew beyond `bound` × (initial energy + work of the loads)
    /// = `budget`; the particle named is the fastest.
    #[error("the energy {energy:e} exceeds {bound} × (initial energy + work of the loads) = {budget:e} (the particle named is the fastest)")]
    EnergyGrowth {
        /// The energy after the step.
        energy: f64,
        /// The allowed growth factor.
        bound: f64,
        /// bound × (E₀ + W).
        budget: f64,
    },
    /// A strain reached |ε| ≥ 1 (a Jacobian 1 + ε ≤ 0 or ≥ 2).
    #[error("strain {strain:e} has |ε| ≥ 1 (Jacobian {:e})", 1.0 + .strain)]
    StrainLimit {
        /// The particle's strain.
        strain: f64,
    },
    /// The run failed with Δt above the measured critical step; `failure`
    /// is the error it failed with.
    #[error("dt = {dt:e} is above the critical step {critical_dt:e} (Courant number {critical_courant} measured by hompm's CFL study); {failure}")]
    TimeStepAboveCritical {
        /// The time step of the run.
        dt: f64,
        /// C_crit h / c_max.
        critical_dt: f64,
        /// The measured critical Courant number C_crit.
        critical_courant: f64,
        /// The error the run failed with.
        failure: Box<Error>,
    },
}

/// Shorthand used throughout the crate.
pub type Result<T> = std::result::Result<T, Error>;

/// Returns `Ok(x)` if `x` is finite, otherwise [`Error::NonFinite`] naming `what`.
pub fn finite(what: &str, x: f64) -> Result<f64> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(Error::NonFinite {
            what: what.to_string(),
            value: x,
        })
    }
}

/// [`finite`] for a quantity whose name has to be formatted (an index, a
/// particle): the name is built only when the check fails, so checking a
/// long array in a time step does not format a string per entry.
pub fn finite_named(x: f64, what: impl FnOnce() -> String) -> Result<f64> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(Error::NonFinite {
            what: what(),
            value: x,
        })
    }
}

/// "particle 3 at step 5 (t = 1e-3): ", as much of it as is known, for
/// [`Error::InvertedDeformation`] and [`Error::NonFiniteVelocity`].
fn where_in_run(particle: Option<usize>, step: Option<usize>, time: Option<f64>) -> String {
    let mut text = String::new();
    if let Some(k) = particle {
        text += &format!("particle {k} ");
    }
    if let Some(s) = step {
        text += &format!("at step {s} ");
    }
    if let Some(t) = time {
        text += &format!("(t = {t:e}) ");
    }
    if text.is_empty() {
        text
    } else {
        text.pop();
        text + ": "
    }
}

/// "(0.300000, 0.200000)": an evaluation point in an error message.
fn point_text(point: &[f64]) -> String {
    let coordinates: Vec<String> = point.iter().map(|c| format!("{c:.6}")).collect();
    format!("({})", coordinates.join(", "))
}

/// A cell index: `3` in 1D, `(2, 5)` in 2D.
fn index_text(cell: &[usize]) -> String {
    match cell {
        [e] => e.to_string(),
        _ => {
            let parts: Vec<String> = cell.iter().map(|e| e.to_string()).collect();
            format!("({})", parts.join(", "))
        }
    }
}

/// A cell's extent: `0.25, 0.5` in 1D, `0, 0.5] × [0.5, 1` in 2D (inside
/// the brackets of the message).
fn cell_text(lower: &[f64], upper: &[f64]) -> String {
    let sides: Vec<String> = lower
        .iter()
        .zip(upper)
        .map(|(a, b)| format!("{a}, {b}"))
        .collect();
    sides.join("] × [")
}
