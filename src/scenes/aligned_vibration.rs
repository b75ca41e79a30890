//! # The 2D aligned vibration (MLS paper, "Numerical example")
//!
//! A manufactured solution on the unit square (after Sadeghirad et al. 2011):
//!
//! - displacement u = (A sin(2πX/L) sin(cπt/L), A sin(2πY/L) sin(cπt/L + π)),
//!   MLS paper Eq. (38), and its time derivative v, Eq. (39);
//! - F = diag(1 + (2πA/L) cos(2πX/L) sin(cπt/L), 1 + (2πA/L) cos(2πY/L)
//!   sin(cπt/L + π)), and σ from the neo-Hookean law, Eq. (41);
//! - the body force b = ü − ∇_X·P / ρ₀ that makes u a solution. Eq. (42)
//!   prints it with a factor π/L²; the derivation (docs/derivations.md) and a
//!   finite-difference test give **π²/L²**:
//!   b_x = (π² u_x / L²)(4μ/ρ₀ − c² − 4[λ(ln J − 1) − μ]/(ρ₀ F_xx²)), and b_y
//!   likewise with u_y and F_yy. hompm uses the derived force;
//!   [`AlignedVibration::body_force_as_printed`] keeps the printed one for the
//!   test that shows the difference.
//!
//! Parameters: ν = 0.3, ρ₀ = 1000 kg/m³, A = 0.1 m, L = 1 m, T = 0.2 s,
//! Δt = 1e-5 s, c = √(E/ρ₀) (the paper's "√E/γ": the only velocity the listed
//! parameters make). The paper's "E = 10e7 Pa" is ambiguous; both readings
//! are named parameter sets, `mls-paper-e1e7` (the default, c = 100 m/s,
//! T = 10 periods of the time factor) and `mls-paper-e1e8` (c = 316 m/s,
//! 31.6 periods); docs/conventions.md, "2D MPM", gives the evidence.
//!
//! The walls carry zero normal velocity: the exact solution has u_x = 0 at
//! X = 0, L and u_y = 0 at Y = 0, L for all t, and no shear stress.
//!
//! Items: [`AlignedVibration`], [`parameters`], [`PARAMETER_SETS`],
//! [`AlignedMethod`], [`AlignedErrors`], [`AlignedRun`], [`ManufacturedForce`].

use crate::error::{Error, Result};
use crate::mpm::conventions::{BodyForceAt, Conventions};
use crate::mpm2d::step::{Conservation2d, Formulation, Mapping2d, Settings2d, Simulation2d};
use crate::mpm2d::{Basis2d, Grid2d, NeoHookean, Particles2d};
use nalgebra::Matrix2;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

mod force;
mod solution;
pub use force::ManufacturedForce;
pub use solution::SolutionForm;

/// The parameters of the aligned vibration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AlignedVibration {
    /// Young's modulus E \[Pa\].
    pub young: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// Initial density ρ₀ [kg/m³].
    pub density: f64,
    /// Amplitude A \[m\].
    pub amplitude: f64,
    /// Side L of the square \[m\].
    pub length: f64,
    /// Duration T \[s\].
    pub duration: f64,
    /// Time step Δt \[s\].
    pub dt: f64,
    /// The form of the manufactured solution (`--solution`): the MLS
    /// paper's Eq. (38) unless the axis-aligned form is asked for. Not
    /// printed when the paper's.
    #[serde(skip_serializing_if = "SolutionForm::is_mls_paper")]
    pub solution: SolutionForm,
}

/// The named parameter sets.
pub const PARAMETER_SETS: [&str; 2] = ["mls-paper-e1e7", "mls-paper-e1e8"];

/// A named parameter set: `mls-paper-e1e7` or `mls-paper-e1e8`.
pub fn parameters(name: &str) -> Result<AlignedVibration> {
    let young = match name {
        "mls-paper-e1e7" => 1e7,
        "mls-paper-e1e8" => 1e8,
        other => {
            return Err(Error::InvalidArgument(format!(
                "unknown parameter set {other:?} of aligned-vibration; known: {}",
                PARAMETER_SETS.join(", ")
            )))
        }
    };
    Ok(AlignedVibration {
        young,
        poisson: 0.3,
        density: 1000.0,
        amplitude: 0.1,
        length: 1.0,
        duration: 0.2,
        dt: 1e-5,
        solution: SolutionForm::MlsPaper,
    })
}

/// The methods of the aligned vibration: the MLS paper's three (Figures
/// 2–4), B-spline MPM with every other registered [`Mapping2d`], and hompm's
/// reference without grid crossing.
///
/// A new 2D mapping needs nothing here: its registration in
/// [`Mapping2d::info`] names it, labels it and puts `bsmpm-<name>` on the
/// command line.
///
/// JSON: `"mpm"`, `{"bsmpm": {"degree": p}}` for the direct mapping,
/// `{"bsmpm-<mapping>": {"degree": p}}` for the others (`bsmpm-mls`,
/// `bsmpm-mls-phase1`, `bsmpm-tls`, `bsmpm-pu-tls`), `{"total-lagrangian": {"degree": p}}`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AlignedMethod {
    /// Bilinear MPM, direct mapping.
    Mpm,
    /// B-spline MPM of a degree with a mapping: direct (BSMPM), MLS (the
    /// MLS paper), its phase-1 diagnostic ([`Mapping2d::MlsPhase1`]) or TLS
    /// ([`Mapping2d::Tls`]; TLS paper §5.2–5.5 on the cells).
    Bsmpm {
        /// Degree p.
        degree: usize,
        /// The mapping between particles and grid.
        mapping: Mapping2d,
    },
    /// hompm's reference without grid crossing: total-Lagrangian FE with
    /// B-splines of a degree and particle quadrature
    /// ([`Formulation::TotalLagrangian`]).
    TotalLagrangian {
        /// Degree p.
        degree: usize,
    },
}

impl AlignedMethod {
    /// B-spline MPM of degree p with the direct mapping.
    pub const fn bsmpm(degree: usize) -> Self {
        AlignedMethod::Bsmpm {
            degree,
            mapping: Mapping2d::Direct,
        }
    }

    /// B-spline MPM of degree p with a mapping.
    pub const fn bsmpm_with(degree: usize, mapping: Mapping2d) -> Self {
        AlignedMethod::Bsmpm { degree, mapping }
    }

    /// Grid basis and mapping.
    pub fn parts(self) -> (Basis2d, Mapping2d) {
        match self {
            AlignedMethod::Mpm => (Basis2d::Bilinear, Mapping2d::Direct),
            AlignedMethod::TotalLagrangian { degree } => {
                (Basis2d::BSpline { degree }, Mapping2d::Direct)
            }
            AlignedMethod::Bsmpm { degree, mapping } => (Basis2d::BSpline { degree }, mapping),
        }
    }

    /// The polynomial degree of the grid basis (1 for bilinear MPM).
    pub fn degree(self) -> usize {
        match self {
            AlignedMethod::Mpm => 1,
            AlignedMethod::Bsmpm { degree, .. } | AlignedMethod::TotalLagrangian { degree } => {
                degree
            }
        }
    }

    /// A label for tables and charts: `MPM`, `BSMPM-p2`, `BSMPM-p2-MLS`,
    /// `TL-FE-p2` (the mapping's [`crate::mpm2d::step::MappingInfo::label`]).
    pub fn label(self) -> String {
        match self {
            AlignedMethod::Mpm => "MPM".into(),
            AlignedMethod::Bsmpm {
                degree,
                mapping: Mapping2d::Direct,
            } => format!("BSMPM-p{degree}"),
            AlignedMethod::Bsmpm { degree, mapping } => {
                format!("BSMPM-p{degree}-{}", mapping.info().label)
            }
            AlignedMethod::TotalLagrangian { degree } => format!("TL-FE-p{degree}"),
        }
    }

    /// The method's tag in JSON: `mpm`, `bsmpm`, `bsmpm-<mapping name>`,
    /// `total-lagrangian`.
    pub fn tag(self) -> String {
        match self {
            AlignedMethod::Mpm => "mpm".into(),
            AlignedMethod::Bsmpm {
                mapping: Mapping2d::Direct,
                ..
            } => "bsmpm".into(),
            AlignedMethod::Bsmpm { mapping, .. } => format!("bsmpm-{}", mapping.name()),
            AlignedMethod::TotalLagrangian { .. } => "total-lagrangian".into(),
        }
    }

    /// The method of a tag with a degree ([`AlignedMethod::tag`]), if the
    /// tag names one.
    pub fn from_tag(tag: &str, degree: usize) -> Option<Self> {
        match tag {
            "mpm" => Some(AlignedMethod::Mpm),
            "bsmpm" => Some(AlignedMethod::bsmpm(degree)),
            "total-lagrangian" => Some(AlignedMethod::TotalLagrangian { degree }),
            _ => {
                let mapping = Mapping2d::from_name(tag.strip_prefix("bsmpm-")?)?;
                (mapping != Mapping2d::Direct).then_some(AlignedMethod::Bsmpm { degree, mapping })
            }
        }
    }
}

/// The degree inside a tagged [`AlignedMethod`] in JSON.
#[derive(Serialize, Deserialize)]
struct DegreeField {
    degree: usize,
}

impl Serialize for AlignedMethod {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        if *self == AlignedMethod::Mpm {
            return s.serialize_str("mpm");
        }
        let mut map = s.serialize_map(Some(1))?;
        map.serialize_entry(
            &self.tag(),
            &DegreeField {
                degree: self.degree(),
            },
        )?;
        map.end()
    }
}

impl<'de> Deserialize<'de> for AlignedMethod {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Repr {
            Unit(String),
            Tagged(std::collections::BTreeMap<String, DegreeField>),
        }
        let unknown = |tag: &str| serde::de::Error::custom(format!("unknown 2D method {tag:?}"));
        match Repr::deserialize(d)? {
            Repr::Unit(tag) if tag == "mpm" => Ok(AlignedMethod::Mpm),
            Repr::Unit(tag) => Err(unknown(&tag)),
            Repr::Tagged(map) => {
                let mut entries = map.into_iter();
                match (entries.next(), entries.next()) {
                    (Some((tag, field)), None) if tag != "mpm" => {
                        AlignedMethod::from_tag(&tag, field.degree).ok_or_else(|| unknown(&tag))
                    }
                    _ => Err(serde::de::Error::custom(
                        "a 2D method is \"mpm\" or one tag with its degree",
                    )),
                }
            }
        }
    }
}

/// RMS errors (MLS paper Eq. 43) at the particles at one time: ‖·‖ is the
/// Euclidean norm for u and v and the Frobenius norm for σ.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AlignedErrors {
    /// Time t.
    pub time: f64,
    /// RMS of ‖u_p − u(X_p, t)‖.
    pub displacement: f64,
    /// RMS of ‖v_p − v(X_p, t)‖.
    pub velocity: f64,
    /// RMS of ‖σ_p − σ(X_p, t)‖_F.
    pub stress: f64,
}

/// The result of one run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AlignedRun {
    /// Method.
    pub method: AlignedMethod,
    /// Cells per direction.
    pub cells: usize,
    /// Particles per cell.
    pub ppc: usize,
    /// Steps taken.
    pub steps: usize,
    /// Errors at the end.
    pub last: AlignedErrors,
    /// Errors at the recorded times (t = 0 first).
    pub history: Vec<AlignedErrors>,
    /// The largest relative mass and momentum errors of the mappings.
    pub conservation: Conservation2d,
    /// Wall-clock seconds of the time stepping.
    pub seconds: f64,
}

impl AlignedRun {
    /// Wall-clock nanoseconds per particle and step.
    pub fn ns_per_particle_step(&self) -> f64 {
        let n = (self.cells * self.cells * self.ppc * self.steps) as f64;
        1e9 * self.seconds / n
    }
}

impl AlignedVibration {
    /// c = √(E/ρ₀), the speed in the time factor sin(cπt/L).
    pub fn wave_speed(&self) -> f64 {
        (self.young / self.density).sqrt()
    }

    /// The neo-Hookean solid of E and ν.
    pub fn material(&self) -> Result<NeoHookean> {
        NeoHookean::from_young_poisson(self.young, self.poisson)
    }

    /// The dilatational wave speed √((λ + 2μ)/ρ₀) of the linearised solid.
    pub fn dilatational_wave_speed(&self) -> Result<f64> {
        let m = self.material()?;
        Ok(((m.lambda + 2.0 * m.mu) / self.density).sqrt())
    }

    /// The Courant number c_d Δt / h on `cells` cells per side.
    pub fn courant_number(&self, cells: usize) -> Result<f64> {
        Ok(self.dilatational_wave_speed()? * self.dt * cells as f64 / self.length)
    }

    /// Periods of sin(cπt/L) in T: cT/(2L).
    pub fn periods(&self) -> f64 {
        self.wave_speed() * self.duration / (2.0 * self.length)
    }

    /// k = nπ/L, the wavenumber of the form (2π/L for Eq. 38).
    pub fn wavenumber(&self) -> f64 {
        self.solution.waves() * PI / self.length
    }

    fn time_factors(&self, t: f64) -> [f64; 2] {
        let phase = self.wave_speed() * PI * t / self.length;
        [phase.sin(), (phase + PI).sin()]
    }

    /// u(X, t), MLS paper Eq. (38).
    pub fn displacement(&self, x0: [f64; 2], t: f64) -> [f64; 2] {
        let s = self.time_factors(t);
        let k = self.wavenumber();
        [
            self.amplitude * (k * x0[0]).sin() * s[0],
            self.amplitude * (k * x0[1]).sin() * s[1],
        ]
    }

    /// v(X, t) = ∂u/∂t, MLS paper Eq. (39).
    pub fn velocity(&self, x0: [f64; 2], t: f64) -> [f64; 2] {
        let c = self.wave_speed();
        let phase = c * PI * t / self.length;
        let k = self.wavenumber();
        let a = self.amplitude * c * PI / self.length;
        [
            a * (k * x0[0]).sin() * phase.cos(),
            a * (k * x0[1]).sin() * (phase + PI).cos(),
        ]
    }

    /// F(X, t) = I + ∂u/∂X, diagonal.
    pub fn deformation_gradient(&self, x0: [f64; 2], t: f64) -> Matrix2<f64> {
        let s = self.time_factors(t);
        let k = self.wavenumber();
        let a = self.amplitude * k;
        Matrix2::new(
            1.0 + a * (k * x0[0]).cos() * s[0],
            0.0,
            0.0,
            1.0 + a * (k * x0[1]).cos() * s[1],
        )
    }

    /// σ(X, t), MLS paper Eq. (41) at the exact F.
    pub fn stress(&self, x0: [f64; 2], t: f64) -> Result<Matrix2<f64>> {
        self.material()?
            .cauchy_stress(&self.deformation_gradient(x0, t))
    }

    fn body_force_with(&self, x0: [f64; 2], t: f64, factor: f64) -> Result<[f64; 2]> {
        let m = self.material()?;
        let u = self.displacement(x0, t);
        let f = self.deformation_gradient(x0, t);
        let ln_j = NeoHookean::jacobian(&f)?.ln();
        let c2 = self.wave_speed().powi(2);
        let rho = self.density;
        let l2 = self.length * self.length;
        let n2 = self.solution.waves().powi(2);
        let bracket = |fii: f64| {
            n2 * m.mu / rho - c2 - n2 * (m.lambda * (ln_j - 1.0) - m.mu) / (rho * fii * fii)
        };
        Ok([
            factor * u[0] / l2 * bracket(f[(0, 0)]),
            factor * u[1] / l2 * bracket(f[(1, 1)]),
        ])
    }

    /// The body force per unit mass that makes Eq. (38) a solution:
    /// b = ü − ∇_X·P/ρ₀, i.e. Eq. (42) with **π²** (module doc).
    pub fn body_force(&self, x0: [f64; 2], t: f64) -> Result<[f64; 2]> {
        self.body_force_with(x0, t, PI * PI)
    }

    /// Eq. (42) exactly as printed, with π where the derivation gives π².
    pub fn body_force_as_printed(&self, x0: [f64; 2], t: f64) -> Result<[f64; 2]> {
        self.body_force_with(x0, t, PI)
    }

    /// The simulation at t = 0: `per_side`² particles per cell at the
    /// centres of equal sub-cells, v = v(X, 0), F = I, σ = 0, and the
    /// derived body force.
    pub fn simulation(
        &self,
        method: AlignedMethod,
        cells: usize,
        per_side: usize,
        mls_support: f64,
    ) -> Result<Simulation2d> {
        self.simulation_with(method, cells, per_side, mls_support, Conventions::MLS_PAPER)
    }

    /// [`Self::simulation`] with another code's conventions
    /// (`mpm::conventions`); with `--body-force nodes` the force is
    /// evaluated at [`Grid2d::node_positions`].
    pub fn simulation_with(
        &self,
        method: AlignedMethod,
        cells: usize,
        per_side: usize,
        mls_support: f64,
        conventions: Conventions,
    ) -> Result<Simulation2d> {
        let (basis, mapping) = method.parts();
        let grid = Grid2d::with_knots(basis, self.length, cells, conventions.knots)?;
        let particles =
            Particles2d::cell_centred(self.length, cells, per_side, self.density, |x| {
                self.velocity(x, 0.0)
            })?;
        let force = match conventions.body_force {
            BodyForceAt::Particles => ManufacturedForce::new(*self, &particles.x0)?,
            BodyForceAt::Nodes => ManufacturedForce::new(*self, &grid.node_positions())?,
        };
        let formulation = match method {
            AlignedMethod::TotalLagrangian { .. } => Formulation::TotalLagrangian,
            _ => Formulation::UpdatedLagrangian,
        };
        let settings = Settings2d {
            formulation,
            mapping,
            material: self.material()?,
            mls_support,
            conventions,
        };
        Simulation2d::new(grid, particles, settings, Some(Box::new(force)))
    }

    /// RMS errors (Eq. 43) of a simulation's particles at its time.
    pub fn errors(&self, sim: &Simulation2d) -> Result<AlignedErrors> {
        let p = &sim.particles;
        let t = sim.time;
        let (mut eu, mut ev, mut es) = (0.0, 0.0, 0.0);
        for k in 0..p.len() {
            let x0 = p.x0[k];
            let (u, v) = (self.displacement(x0, t), self.velocity(x0, t));
            eu += (p.displacement[k][0] - u[0]).powi(2) + (p.displacement[k][1] - u[1]).powi(2);
            ev += (p.velocity[k][0] - v[0]).powi(2) + (p.velocity[k][1] - v[1]).powi(2);
            es += (p.stress[k] - self.stress(x0, t)?).norm_squared();
        }
        let n = p.len() as f64;
        let e = AlignedErrors {
            time: t,
            displacement: (eu / n).sqrt(),
            velocity: (ev / n).sqrt(),
            stress: (es / n).sqrt(),
        };
        if [e.displacement, e.velocity, e.stress]
            .iter()
            .all(|x| x.is_finite())
        {
            Ok(e)
        } else {
            Err(Error::BlowUp(format!(
                "the RMS errors at t = {t:e} are not finite"
            )))
        }
    }

    /// Runs `steps` steps of Δt and records the errors every `record_every`
    /// steps (and at the end).
    pub fn run(
        &self,
        method: AlignedMethod,
        cells: usize,
        per_side: usize,
        steps: usize,
        record_every: usize,
    ) -> Result<AlignedRun> {
        let (run, stop) = self.run_until_stopped(method, cells, per_side, steps, record_every)?;
        match stop {
            Some(e) => Err(e),
            None => Ok(run),
        }
    }

    /// [`AlignedVibration::run`] that keeps what it recorded when a step
    /// fails: the run (its `steps` and `last` are then those of the last
    /// record before the failure, not of T) and the error that stopped it.
    /// Errors only if the run cannot start.
    pub fn run_until_stopped(
        &self,
        method: AlignedMethod,
        cells: usize,
        per_side: usize,
        steps: usize,
        record_every: usize,
    ) -> Result<(AlignedRun, Option<Error>)> {
        let mut sim = self.simulation(method, cells, per_side, 1.0)?;
        let mut history = vec![self.errors(&sim)?];
        let mut seconds = 0.0;
        let mut done = 0;
        let mut stop = None;
        while done < steps {
            let chunk = if record_every > 0 {
                record_every.min(steps - done)
            } else {
                steps - done
            };
            let start = std::time::Instant::now();
            let stepped = sim.run(self.dt, chunk);
            seconds += start.elapsed().as_secs_f64();
            if let Err(e) = stepped
                .and_then(|()| self.errors(&sim))
                .map(|e| history.push(e))
            {
                stop = Some(e);
                break;
            }
            done += chunk;
        }
        let run = AlignedRun {
            method,
            cells,
            ppc: per_side * per_side,
            steps: done,
            last: *history.last().expect("the initial errors"),
            history,
            conservation: sim.conservation,
            seconds,
        };
        Ok((run, stop))
    }
}
