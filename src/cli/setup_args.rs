//! # The options of a run, shared by `run`, `trace` and `check`
//!
//! [`SetupArgs`] is every option that decides a run: the scene and its
//! named set, each physical parameter as an override (`--young`,
//! `--density`, `--length`, `--v0`, `--poisson`, `--amplitude`,
//! `--gravity`, `--top-load`, `--constitutive`), the discretisation, the
//! Richardson stopping rule (`--tol`, `--residual`) and the time stepping.
//! It converts into the library's [`Setup`]; the up-front limits of a run
//! are estimated here.
//!
//! Items: [`SetupArgs`], [`ConstitutiveArg`], [`ResidualArg`].

use super::args::{count, name, node_integrals, MappingArg, MassArg, MethodArg, SceneArg};
use super::limits::Limits;
use crate::error::{Error, Result};
use crate::mpm::conventions::{
    registered, BodyForceAt, Conventions, Gradient, Knots, Positions, Scheme, Transfer,
};
use crate::mpm::grid::NodeIntegrals;
use crate::mpm::mapping::{ConsistentSolver, Mapping, MassMatrix};
use crate::mpm::musl::Constitutive;
use crate::oracle::setup::{Overrides, Scene1d, Setup, Setup1d, Setup2d};
use crate::scenes::aligned_vibration::{AlignedMethod, SolutionForm};
use crate::scenes::Discretisation;
use crate::solve::richardson::ResidualNorm;
use clap::ValueEnum;

/// `--constitutive`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ConstitutiveArg {
    /// σ ← σ + E Δε (book Eq. 4.15).
    Small,
    /// σ ← σ + (E − σ) Δε (book Eq. 4.16).
    Large,
}

/// `--residual`: what Richardson divides its residual by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ResidualArg {
    /// ‖P‖₂, the right-hand side: hompm's rule (stop at ≤ tol).
    Rhs,
    /// ‖v‖₂, the iterate: the thesis author's code (stop at < tol).
    Solution,
}

impl From<ResidualArg> for ResidualNorm {
    /// The one place the command line's word becomes the stopping rule.
    fn from(arg: ResidualArg) -> Self {
        match arg {
            ResidualArg::Rhs => ResidualNorm::Rhs,
            ResidualArg::Solution => ResidualNorm::Solution,
        }
    }
}

/// The options of a run.
#[derive(clap::Args, Debug, Clone)]
pub struct SetupArgs {
    /// The scene (vibrating-bar, column-self-weight, column-top-load,
    /// aligned-vibration).
    #[arg(value_enum)]
    pub scene: Option<SceneArg>,
    /// Named parameter set (default: the thesis' set of the scene; `hompm
    /// run --list-params` prints every set with its values).
    #[arg(long)]
    pub params: Option<String>,
    /// Override Young's modulus E of the set.
    #[arg(long, allow_negative_numbers = true)]
    pub young: Option<f64>,
    /// Override the density ρ (ρ₀ in 2D).
    #[arg(long, allow_negative_numbers = true)]
    pub density: Option<f64>,
    /// Override the length L of the bar, the height H of the column, the
    /// side L of the square.
    #[arg(long, allow_negative_numbers = true)]
    pub length: Option<f64>,
    /// Override the bar's initial velocity amplitude v₀.
    #[arg(long, allow_negative_numbers = true)]
    pub v0: Option<f64>,
    /// Override Poisson's ratio ν (aligned-vibration).
    #[arg(long, allow_negative_numbers = true)]
    pub poisson: Option<f64>,
    /// Override the amplitude A (aligned-vibration).
    #[arg(long, allow_negative_numbers = true)]
    pub amplitude: Option<f64>,
    /// Override the column's gravity along the axis (signed; −9.81 points down).
    #[arg(long, allow_negative_numbers = true)]
    pub gravity: Option<f64>,
    /// Override the column's top load p₀ (signed; negative compresses).
    #[arg(long, allow_negative_numbers = true)]
    pub top_load: Option<f64>,
    /// The 1D stress update: small (book Eq. 4.15) or large (Eq. 4.16);
    /// default: the set's.
    #[arg(long, value_enum)]
    pub constitutive: Option<ConstitutiveArg>,
    /// The MPM variant.
    #[arg(long, value_enum, default_value_t = MethodArg::MPM)]
    pub method: MethodArg,
    /// DDMPM's node integrals V_j and ∫φ_j∇φ_i: exact, particles (particle
    /// quadrature) or subpoints:N (N subpoints per particle).
    #[arg(long, default_value = "exact", value_parser = node_integrals)]
    pub node_integrals: NodeIntegrals,
    /// B-spline degree for bsmpm.
    #[arg(long, default_value_t = 2, value_parser = count, allow_negative_numbers = true)]
    pub degree: usize,
    /// How particle data reaches the grid.
    #[arg(long, value_enum, default_value_t = MappingArg::DIRECT)]
    pub mapping: MappingArg,
    /// The mass matrix of the velocity projection.
    #[arg(long, value_enum, default_value_t = MassArg::Lumped)]
    pub mass: MassArg,
    /// Richardson's tolerance ε (--mass richardson; default 1e-9, thesis §7.2).
    #[arg(long, allow_negative_numbers = true)]
    pub tol: Option<f64>,
    /// Richardson's residual: rhs (‖P − Mv‖/‖P‖ ≤ ε, hompm) or solution
    /// (‖P − Mv‖/‖v‖ < ε, the thesis author's code).
    #[arg(long, value_enum)]
    pub residual: Option<ResidualArg>,
    /// Elements or knot spans (per side in 2D); `check --convergence` takes
    /// a comma-separated list.
    #[arg(long, default_value = "16", value_parser = count, value_delimiter = ',', allow_negative_numbers = true)]
    pub cells: Vec<usize>,
    /// Particles per cell [default: 4 in 1D, 9 (3 × 3) in aligned-vibration,
    /// where it must be a square].
    #[arg(long, value_parser = count, allow_negative_numbers = true)]
    pub ppc: Option<usize>,
    /// Time step.
    #[arg(long, default_value_t = 1e-5, allow_negative_numbers = true)]
    pub dt: f64,
    /// Number of steps.
    #[arg(long, default_value_t = 100, value_parser = count, allow_negative_numbers = true)]
    pub steps: usize,
    /// Another code's update scheme (docs/conventions.md, "Conventions of
    /// other codes"); default musl.
    #[arg(long, value_parser = convention::<Scheme>, help = convention_help("scheme"))]
    pub scheme: Option<Scheme>,
    /// Another code's velocity transfer; default flip.
    #[arg(long, value_parser = convention::<Transfer>, help = convention_help("transfer"))]
    pub transfer: Option<Transfer>,
    /// The velocity that moves the particles; default projected in 1D,
    /// grid in 2D (the seeds').
    #[arg(long, value_parser = convention::<Positions>, help = convention_help("positions"))]
    pub positions: Option<Positions>,
    /// Where the body force is evaluated; default particles.
    #[arg(long = "body-force", value_parser = convention::<BodyForceAt>, help = convention_help("body-force"))]
    pub body_force: Option<BodyForceAt>,
    /// The B-spline knots (padded: 2D; natural: 1D); default open.
    #[arg(long, value_parser = convention::<Knots>, help = convention_help("knots"))]
    pub knots: Option<Knots>,
    /// The velocity gradient and internal force (2D); default basis.
    #[arg(long, value_parser = convention::<Gradient>, help = convention_help("gradient"))]
    pub gradient: Option<Gradient>,
    /// The form of the aligned vibration's manufactured solution.
    #[arg(long, value_parser = solution_form, help = "mls-paper: u = A sin(2πX/L) sin(cπt/L), MLS paper Eq. (38) (default); axis-aligned: u = A sin(πX/L) sin(cπt/L), Wallstedt & Guilkey (2008), Uintah's AxisAligned MMS, mpmat, the MLS paper's own code")]
    pub solution: Option<SolutionForm>,
}

/// A convention flag's value, parsed by its registration.
fn convention<T: FromConventionName>(text: &str) -> std::result::Result<T, String> {
    T::from_convention_name(text.trim()).map_err(|e| e.to_string())
}

/// `--solution`.
fn solution_form(text: &str) -> std::result::Result<SolutionForm, String> {
    SolutionForm::from_name(text.trim()).map_err(|e| e.to_string())
}

/// The `--help` of a convention flag: its registered values, one line each.
fn convention_help(flag: &str) -> String {
    registered(flag)
        .map(|c| format!("{}: {} [{}]", c.value, c.help, c.citation))
        .collect::<Vec<_>>()
        .join("; ")
}

/// A convention parsed from its registered word.
trait FromConventionName: Sized + Clone + Send + Sync + 'static {
    fn from_convention_name(name: &str) -> Result<Self>;
}

impl FromConventionName for Scheme {
    fn from_convention_name(name: &str) -> Result<Self> {
        Scheme::from_name(name)
    }
}

impl FromConventionName for Transfer {
    fn from_convention_name(name: &str) -> Result<Self> {
        Transfer::from_name(name)
    }
}

impl FromConventionName for Positions {
    fn from_convention_name(name: &str) -> Result<Self> {
        Positions::from_name(name)
    }
}

impl FromConventionName for Knots {
    fn from_convention_name(name: &str) -> Result<Self> {
        Knots::from_name(name)
    }
}

impl FromConventionName for Gradient {
    fn from_convention_name(name: &str) -> Result<Self> {
        Gradient::from_name(name)
    }
}

impl FromConventionName for BodyForceAt {
    fn from_convention_name(name: &str) -> Result<Self> {
        BodyForceAt::from_name(name)
    }
}

impl SetupArgs {
    /// The scene, which is required outside `--list-params`.
    pub fn scene(&self) -> Result<SceneArg> {
        self.scene.ok_or_else(|| {
            Error::Usage(
                "a scene is required: vibrating-bar, column-self-weight, column-top-load or aligned-vibration".into(),
            )
        })
    }

    /// Whether the scene is the 2D one.
    pub fn two_d(&self) -> bool {
        self.scene == Some(SceneArg::AlignedVibration)
    }

    /// --ppc, or its default: 4 in 1D, 9 in 2D.
    pub fn ppc(&self) -> usize {
        self.ppc.unwrap_or(if self.two_d() { 9 } else { 4 })
    }

    /// The one value of --cells (a list only for `check --convergence`).
    pub fn cells(&self) -> Result<usize> {
        match self.cells.as_slice() {
            [n] => Ok(*n),
            other => Err(Error::InvalidArgument(format!(
                "--cells takes one count here, got {} ({}); a list is for check --convergence",
                other.len(),
                other
                    .iter()
                    .map(|c| c.to_string())
                    .collect::<Vec<_>>()
                    .join(",")
            ))),
        }
    }

    /// The overrides given.
    pub fn overrides(&self) -> Overrides {
        Overrides {
            young: self.young,
            density: self.density,
            length: self.length,
            v0: self.v0,
            poisson: self.poisson,
            amplitude: self.amplitude,
            gravity: self.gravity,
            top_load: self.top_load,
            constitutive: self.constitutive.map(|c| match c {
                ConstitutiveArg::Small => Constitutive::SmallStrain,
                ConstitutiveArg::Large => Constitutive::LargeStrain,
            }),
            solution: self.solution,
        }
    }

    /// The conventions of the step: the dimension's default with every
    /// flag given on top, checked.
    pub fn conventions(&self) -> Result<Conventions> {
        let mut c = Conventions::default_for(if self.two_d() { 2 } else { 1 });
        // APIC is Taichi's update-stress-last step unless --scheme says
        // otherwise (and is refused).
        let apic = self.transfer == Some(Transfer::Apic);
        c.scheme = self
            .scheme
            .unwrap_or(if apic { Scheme::Usl } else { c.scheme });
        c.knots = self.knots.unwrap_or(c.knots);
        c.gradient = self.gradient.unwrap_or(c.gradient);
        c.transfer = self.transfer.unwrap_or(c.transfer);
        // USL and USF project nothing: they move the particles with the
        // grid velocity unless --positions says otherwise (and is refused).
        let moved = if c.scheme == Scheme::Musl {
            c.positions
        } else {
            Positions::Grid
        };
        c.positions = self.positions.unwrap_or(moved);
        c.body_force = self.body_force.unwrap_or(c.body_force);
        c.validate()?;
        Ok(c)
    }

    /// The mass matrix with its solver and stopping rule.
    fn mass_matrix(&self) -> Result<MassMatrix> {
        if self.mass != MassArg::Richardson && (self.tol.is_some() || self.residual.is_some()) {
            return Err(Error::InvalidArgument(format!(
                "--tol and --residual apply to --mass richardson, not {}",
                name(&self.mass)
            )));
        }
        if self.mass != MassArg::Richardson {
            return Ok(self.mass.into());
        }
        let tolerance = self.tol.unwrap_or(1e-9);
        if !(tolerance.is_finite() && tolerance >= f64::EPSILON) {
            return Err(Error::InvalidArgument(format!(
                "--tol must be finite and at least ε = {:e}, got {tolerance}",
                f64::EPSILON
            )));
        }
        let residual = self
            .residual
            .map_or(ResidualNorm::default(), ResidualNorm::from);
        Ok(MassMatrix::Consistent(ConsistentSolver::Richardson {
            tolerance,
            residual,
        }))
    }

    /// Refuses counts, time steps and combinations that cannot run.
    fn validate(&self, cells: usize) -> Result<()> {
        if cells == 0 || self.ppc() == 0 {
            return Err(Error::InvalidArgument(format!(
                "--cells and --ppc must be at least 1, got {cells} and {}",
                self.ppc()
            )));
        }
        if !(self.dt > 0.0 && self.dt.is_finite()) {
            return Err(Error::InvalidArgument(format!(
                "--dt must be positive and finite, got {}",
                self.dt
            )));
        }
        if !(self.dt * self.steps as f64).is_finite() {
            return Err(Error::InvalidArgument(format!(
                "--dt {:e} × --steps {} overflows the time t = n·Δt in double precision",
                self.dt, self.steps
            )));
        }
        Ok(())
    }

    /// The setup of these options with `cells` cells.
    pub fn setup_with_cells(&self, cells: usize) -> Result<Setup> {
        let scene = self.scene()?;
        self.validate(cells)?;
        let overrides = self.overrides();
        if scene == SceneArg::AlignedVibration {
            let (params, set_name) = Setup2d::scene(
                self.params.as_deref().unwrap_or("mls-paper-e1e7"),
                &overrides,
            )?;
            let method = self.aligned_method()?;
            let conventions = self.conventions()?;
            let (basis, mapping) = method.parts();
            conventions.check_2d(
                basis == crate::mpm2d::Basis2d::BSpline { degree: 2 },
                mapping == crate::mpm2d::step::Mapping2d::Direct,
                matches!(method, AlignedMethod::TotalLagrangian { .. }),
            )?;
            return Ok(Setup::TwoD(Setup2d {
                scene: params,
                set_name,
                method,
                cells,
                per_side: per_side(self.ppc())?,
                dt: self.dt,
                steps: self.steps,
                conventions,
            }));
        }
        let method = self.method.method(self.degree, self.node_integrals)?;
        let mapping = Mapping::from(self.mapping);
        let mut discretisation =
            Discretisation::new(method, mapping, self.mass_matrix()?, cells, self.ppc());
        discretisation.conventions = self.conventions()?;
        discretisation.conventions.check_1d(
            Mapping::takes_other_conventions(
                discretisation.force_mapping,
                discretisation.velocity_mapping,
                discretisation.mass,
            ),
            method,
        )?;
        let scene = match scene {
            SceneArg::VibratingBar => Scene1d::bar(
                self.params.as_deref().unwrap_or("thesis-table-4.1"),
                &overrides,
            )?,
            SceneArg::ColumnSelfWeight => Scene1d::column(
                self.params.as_deref().unwrap_or("thesis-table-4.3"),
                &overrides,
            )?,
            SceneArg::ManufacturedStrip => Scene1d::strip(
                self.params.as_deref().unwrap_or("mls-paper-code"),
                &overrides,
                cells,
            )?,
            _ => Scene1d::column(
                self.params.as_deref().unwrap_or("thesis-table-8.1"),
                &overrides,
            )?,
        };
        Ok(Setup::OneD(Setup1d {
            scene,
            discretisation,
            dt: self.dt,
            steps: self.steps,
        }))
    }

    /// The setup of these options.
    pub fn setup(&self) -> Result<Setup> {
        self.setup_with_cells(self.cells()?)
    }

    /// The 2D method of --method and --degree.
    fn aligned_method(&self) -> Result<AlignedMethod> {
        if self.mass != MassArg::Lumped || self.mapping != MappingArg::DIRECT {
            return Err(Error::InvalidArgument(
                "aligned-vibration runs with the lumped mass; its mapping follows --method (bsmpm-mls maps by MLS)".into(),
            ));
        }
        self.method.aligned(self.degree)
    }

    /// Refuses a run whose estimated memory or time exceeds the limits;
    /// `extra_bytes` is what the command keeps besides the run (a trace).
    pub fn check_limits(&self, setup: &Setup, limits: &Limits, extra_bytes: f64) -> Result<()> {
        match setup {
            Setup::OneD(s) => check_limits_1d(self, s, limits, extra_bytes),
            Setup::TwoD(s) => check_limits_2d(s, limits, extra_bytes),
        }
    }
}

/// 9 PPC is 3 per side; a PPC that is not a square has no layout.
fn per_side(ppc: usize) -> Result<usize> {
    let side = (ppc as f64).sqrt().round() as usize;
    if side * side == ppc {
        Ok(side)
    } else {
        Err(Error::InvalidArgument(format!(
            "aligned-vibration places --ppc particles on a square lattice in each cell, so --ppc must be a square (4, 9, 16, …), got {ppc}"
        )))
    }
}

/// Memory: about 200 bytes plus 16 per stencil entry for each particle,
/// the same per DOF, and 600 bytes of JSON per particle (7 numbers of
/// about 30 characters of pretty JSON, in a string that grows by
/// doubling, and the columns' copies; measured in docs/conventions.md,
/// "Up-front limits"). Time: about
/// 45 + 4 w² ns per particle-step for a stencil of width w (the divan
/// benchmark measures 24–50 ns for w ≤ 3), 200 ns more for TLS or
/// cubic-spline mappings, and a banded solve per step for a consistent mass.
fn check_limits_1d(a: &SetupArgs, s: &Setup1d, limits: &Limits, extra: f64) -> Result<()> {
    let d = &s.discretisation;
    let particles = d.cells as f64 * d.ppc as f64;
    let width = d.method.functions_per_particle() as f64;
    let dofs = 2.0 * d.cells as f64 + width;
    let what = || format!("a run of {particles:.0} particles × {} steps", s.steps);
    let bytes = (particles + dofs) * (200.0 + 16.0 * width) + particles * 600.0 + extra;
    limits.check_memory(what, bytes, "particle and grid storage")?;
    let mapping = a.mapping.0.info().extra_ns_per_particle_step;
    let solve = if a.mass == MassArg::Lumped {
        20.0
    } else {
        40.0 * width * width
    };
    let per_step = (particles * (45.0 + 4.0 * width * width + mapping) + dofs * solve) * 1e-9;
    limits.check_time(what, per_step * s.steps as f64)
}

/// Memory: about 400 bytes per particle, 100 per node, and for MLS 12
/// bytes per (Gauss point, particle) pair, about 40 per particle (up to 7
/// times that where the material is compressed); 1500 bytes of JSON per
/// particle (18 numbers, as in 1D). Time: the divan benchmark's 60 (MPM), 110 (BSMPM p = 2),
/// 500 (MLS) and 250 (TLS) ns per particle-step, doubled for the compressed states and
/// scaled by (p + 1)²/9 for other degrees.
fn check_limits_2d(s: &Setup2d, limits: &Limits, extra: f64) -> Result<()> {
    let degree = s.method.degree();
    let mapping = s.method.parts().1.info();
    let particles = (s.cells as f64).powi(2) * (s.per_side as f64).powi(2);
    let nodes = (s.cells as f64 + degree as f64).powi(2);
    let what = || format!("a 2D run of {particles:.0} particles × {} steps", s.steps);
    let bytes = particles * (1900.0 + mapping.bytes_per_particle) + nodes * 100.0 + extra;
    limits.check_memory(what, bytes, "particle, grid and MLS storage")?;
    let width2 = (degree as f64 + 1.0).powi(2) / 9.0;
    let ns = match s.method {
        AlignedMethod::Mpm => 60.0,
        _ => mapping.ns_per_particle_step * width2,
    };
    limits.check_time(what, 2.0 * ns * 1e-9 * particles * s.steps as f64)
}
