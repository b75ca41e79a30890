//! # The setup of a run another code can match
//!
//! A [`Setup`] is everything a run depends on: the scene with its named
//! parameter set and any physical parameter the caller overrides
//! ([`Overrides`]: E, ρ, L, v₀, g, p₀, ν, A, the constitutive update), the
//! discretisation (method, mapping, mass and its solver, cells, PPC) and
//! the time stepping (Δt, steps). `hompm run`, `trace` and `check` build
//! their runs from it, so a check runs exactly the setup a run prints.
//!
//! The time of a run is reported as steps × Δt ([`Setup::end_time`]), not
//! as the sum the step accumulates (1999 steps of 1e-5 s sum to
//! 0.019989999999999356 s); the step's own clock is unchanged.
//!
//! Items: [`Overrides`], [`Scene1d`], [`Setup1d`], [`Setup2d`], [`Setup`],
//! [`parameter_sets`].

use crate::error::{Error, Result};
use crate::mpm::conventions::Conventions;
use crate::mpm::musl::{Constitutive, Simulation};
use crate::scenes::aligned_vibration::{self, AlignedMethod, AlignedVibration, SolutionForm};
use crate::scenes::column::{self, ColumnParameters};
use crate::scenes::manufactured_strip::{self, StripParameters};
use crate::scenes::vibrating_bar::{self, BarParameters};
use crate::scenes::Discretisation;
use serde::Serialize;

/// Physical parameters that override a named set. A `None` keeps the
/// set's value; a parameter the scene does not have is an error.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Overrides {
    /// Young's modulus E.
    pub young: Option<f64>,
    /// Density ρ (ρ₀ in 2D).
    pub density: Option<f64>,
    /// Length L of the bar, height H of the column, side L of the square.
    pub length: Option<f64>,
    /// The bar's initial velocity amplitude v₀.
    pub v0: Option<f64>,
    /// Poisson's ratio ν (2D).
    pub poisson: Option<f64>,
    /// The aligned vibration's amplitude A (2D).
    pub amplitude: Option<f64>,
    /// The column's gravitational acceleration along the axis (signed).
    pub gravity: Option<f64>,
    /// The column's top load p₀ (signed; negative compresses).
    pub top_load: Option<f64>,
    /// The 1D constitutive update: small (book Eq. 4.15) or large strain
    /// (Eq. 4.16).
    pub constitutive: Option<Constitutive>,
    /// The form of the aligned vibration's manufactured solution.
    pub solution: Option<SolutionForm>,
}

impl Overrides {
    /// The names of the parameters that are set, as the command line
    /// spells them.
    pub fn names(&self) -> Vec<&'static str> {
        let mut out = Vec::new();
        let set = [
            ("young", self.young.is_some()),
            ("density", self.density.is_some()),
            ("length", self.length.is_some()),
            ("v0", self.v0.is_some()),
            ("poisson", self.poisson.is_some()),
            ("amplitude", self.amplitude.is_some()),
            ("gravity", self.gravity.is_some()),
            ("top-load", self.top_load.is_some()),
            ("constitutive", self.constitutive.is_some()),
            ("solution", self.solution.is_some()),
        ];
        for (name, is_set) in set {
            if is_set {
                out.push(name);
            }
        }
        out
    }

    /// Refuses the overrides a scene does not have, naming them.
    fn allow_only(&self, scene: &str, allowed: &[&str]) -> Result<()> {
        let extra: Vec<&str> = self
            .names()
            .into_iter()
            .filter(|n| !allowed.contains(n))
            .collect();
        if extra.is_empty() {
            Ok(())
        } else {
            Err(Error::InvalidArgument(format!(
                "{scene} has no parameter {} (it takes: {})",
                extra
                    .iter()
                    .map(|n| format!("--{n}"))
                    .collect::<Vec<_>>()
                    .join(", "),
                allowed
                    .iter()
                    .map(|n| format!("--{n}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            )))
        }
    }
}

/// A positive, finite physical parameter.
fn positive(name: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::InvalidArgument(format!(
            "--{name} must be positive and finite, got {value}"
        )))
    }
}

/// A finite physical parameter of either sign.
fn finite(name: &str, value: f64) -> Result<f64> {
    crate::error::finite_named(value, || format!("--{name}"))?;
    Ok(value)
}

/// Sets `target` to `value` if one is given, after `check` accepts it
/// under the option's `name`.
fn override_with(
    target: &mut f64,
    value: Option<f64>,
    name: &str,
    check: fn(&str, f64) -> Result<f64>,
) -> Result<()> {
    if let Some(v) = value {
        *target = check(name, v)?;
    }
    Ok(())
}

/// A 1D scene with its (possibly overridden) parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "scene", rename_all = "kebab-case")]
pub enum Scene1d {
    /// The vibrating bar (thesis §4.1).
    VibratingBar(BarParameters),
    /// The column under self-weight or a top load (thesis §4.2, §8.1).
    Column(ColumnParameters),
    /// The manufactured strip of the MLS paper's code (issue #40), placed
    /// for the run's cells.
    ManufacturedStrip(StripParameters),
}

impl Scene1d {
    /// The bar with set `name` and the overrides.
    pub fn bar(name: &str, o: &Overrides) -> Result<Self> {
        o.allow_only(
            "vibrating-bar",
            &["young", "density", "length", "v0", "constitutive"],
        )?;
        let mut p = vibrating_bar::parameters(name)?;
        override_with(&mut p.young, o.young, "young", positive)?;
        override_with(&mut p.density, o.density, "density", positive)?;
        override_with(&mut p.length, o.length, "length", positive)?;
        override_with(&mut p.v0, o.v0, "v0", finite)?;
        p.constitutive = o.constitutive.unwrap_or(p.constitutive);
        Ok(Scene1d::VibratingBar(p))
    }

    /// The column with set `name` and the overrides.
    pub fn column(name: &str, o: &Overrides) -> Result<Self> {
        o.allow_only(
            "the column",
            &[
                "young",
                "density",
                "length",
                "gravity",
                "top-load",
                "constitutive",
            ],
        )?;
        let mut p = column::parameters(name)?;
        override_with(&mut p.young, o.young, "young", positive)?;
        override_with(&mut p.density, o.density, "density", positive)?;
        override_with(&mut p.height, o.length, "length", positive)?;
        override_with(&mut p.gravity, o.gravity, "gravity", finite)?;
        override_with(&mut p.top_load, o.top_load, "top-load", finite)?;
        p.constitutive = o.constitutive.unwrap_or(p.constitutive);
        Ok(Scene1d::Column(p))
    }

    /// The strip with set `name` and the overrides, placed for `cells`.
    pub fn strip(name: &str, o: &Overrides, cells: usize) -> Result<Self> {
        o.allow_only(
            "manufactured-strip",
            &["young", "density", "poisson", "amplitude"],
        )?;
        let mut p = manufactured_strip::parameters(name)?;
        override_with(&mut p.young, o.young, "young", positive)?;
        override_with(&mut p.density, o.density, "density", positive)?;
        override_with(&mut p.poisson, o.poisson, "poisson", finite)?;
        override_with(&mut p.amplitude, o.amplitude, "amplitude", finite)?;
        if !(p.poisson > -1.0 && p.poisson < 0.5) {
            return Err(Error::InvalidArgument(format!(
                "the neo-Hookean strip needs −1 < ν < 0.5, got {}",
                p.poisson
            )));
        }
        Ok(Scene1d::ManufacturedStrip(p.placed(cells.max(1))))
    }

    /// The simulation of a discretisation at t = 0.
    pub fn simulation(&self, d: &Discretisation) -> Result<Simulation> {
        match self {
            Scene1d::VibratingBar(p) => p.simulation(d),
            Scene1d::Column(p) => p.simulation(d),
            Scene1d::ManufacturedStrip(p) => p.simulation(d),
        }
    }

    /// The body's initial extent [a, a + L]: a = 0 but for the strip,
    /// which sits two ghost cells from the origin as its code's does.
    pub fn domain(&self) -> (f64, f64) {
        match self {
            Scene1d::ManufacturedStrip(p) => (p.left_end, p.left_end + p.length),
            _ => (0.0, self.length()),
        }
    }

    /// The named set the parameters started from.
    pub fn set_name(&self) -> &'static str {
        match self {
            Scene1d::VibratingBar(p) => p.name,
            Scene1d::Column(p) => p.name,
            Scene1d::ManufacturedStrip(p) => p.name,
        }
    }

    /// The length of the domain [0, L].
    pub fn length(&self) -> f64 {
        match self {
            Scene1d::VibratingBar(p) => p.length,
            Scene1d::Column(p) => p.height,
            Scene1d::ManufacturedStrip(p) => p.length,
        }
    }

    /// The constitutive update.
    pub fn constitutive(&self) -> Constitutive {
        match self {
            Scene1d::VibratingBar(p) => p.constitutive,
            Scene1d::Column(p) => p.constitutive,
            Scene1d::ManufacturedStrip(_) => Constitutive::NeoHookean,
        }
    }
}

/// A 1D run: scene, discretisation and time stepping.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Setup1d {
    /// The scene and its parameters.
    pub scene: Scene1d,
    /// Method, mappings, mass, cells and PPC.
    pub discretisation: Discretisation,
    /// Time step Δt.
    pub dt: f64,
    /// Number of steps.
    pub steps: usize,
}

/// A 2D run of the aligned vibration (MLS paper §4).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Setup2d {
    /// The manufactured solution's parameters.
    pub scene: AlignedVibration,
    /// The set the parameters started from.
    pub set_name: &'static str,
    /// Method (basis and mapping).
    pub method: AlignedMethod,
    /// Cells per side.
    pub cells: usize,
    /// Particles per cell per side (PPC = per_side²).
    pub per_side: usize,
    /// Time step Δt.
    pub dt: f64,
    /// Number of steps.
    pub steps: usize,
    /// Scheme, transfer, positions and body force (the MLS paper's unless
    /// another code's are asked for; not printed then).
    #[serde(skip_serializing_if = "Conventions::is_mls_paper")]
    pub conventions: Conventions,
}

impl Setup2d {
    /// The aligned vibration with set `name` and the overrides.
    pub fn scene(name: &str, o: &Overrides) -> Result<(AlignedVibration, &'static str)> {
        o.allow_only(
            "aligned-vibration",
            &[
                "young",
                "density",
                "length",
                "poisson",
                "amplitude",
                "solution",
            ],
        )?;
        let set = aligned_vibration::PARAMETER_SETS
            .iter()
            .copied()
            .find(|s| *s == name);
        let mut p = aligned_vibration::parameters(name)?;
        override_with(&mut p.young, o.young, "young", positive)?;
        override_with(&mut p.density, o.density, "density", positive)?;
        override_with(&mut p.length, o.length, "length", positive)?;
        override_with(&mut p.poisson, o.poisson, "poisson", finite)?;
        override_with(&mut p.amplitude, o.amplitude, "amplitude", finite)?;
        p.solution = o.solution.unwrap_or(p.solution);
        p.material()?;
        Ok((p, set.unwrap_or("custom")))
    }
}

/// A run of either dimension.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Setup {
    /// A 1D scene.
    OneD(Setup1d),
    /// The 2D aligned vibration.
    TwoD(Setup2d),
}

impl Setup {
    /// Δt.
    pub fn dt(&self) -> f64 {
        match self {
            Setup::OneD(s) => s.dt,
            Setup::TwoD(s) => s.dt,
        }
    }

    /// Steps.
    pub fn steps(&self) -> usize {
        match self {
            Setup::OneD(s) => s.steps,
            Setup::TwoD(s) => s.steps,
        }
    }

    /// The time at the end of the run, steps × Δt.
    pub fn end_time(&self) -> f64 {
        self.steps() as f64 * self.dt()
    }

    /// The scene names on the command line that give this setup's scene
    /// (the column answers to both of its loads).
    pub fn scene_names(&self) -> &'static [&'static str] {
        match self {
            Setup::OneD(s) => match s.scene {
                Scene1d::VibratingBar(_) => &["vibrating-bar"],
                Scene1d::Column(_) => &["column-self-weight", "column-top-load"],
                Scene1d::ManufacturedStrip(_) => &["manufactured-strip"],
            },
            Setup::TwoD(_) => &["aligned-vibration"],
        }
    }

    /// The conventions of the step.
    pub fn conventions(&self) -> Conventions {
        match self {
            Setup::OneD(s) => s.discretisation.conventions,
            Setup::TwoD(s) => s.conventions,
        }
    }

    /// The dimension, 1 or 2.
    pub fn dimension(&self) -> usize {
        match self {
            Setup::OneD(_) => 1,
            Setup::TwoD(_) => 2,
        }
    }

    /// Cells per side and particles per cell (2D: per cell, the square of
    /// the particles per side), as `hompm run --json` writes them.
    pub fn cells_and_ppc(&self) -> (usize, usize) {
        match self {
            Setup::OneD(s) => (s.discretisation.cells, s.discretisation.ppc),
            Setup::TwoD(s) => (s.cells, s.per_side * s.per_side),
        }
    }
}

/// Every named parameter set of every scene with its values, as JSON
/// (`hompm run --list-params`).
pub fn parameter_sets() -> Result<serde_json::Value> {
    let aligned: Result<Vec<serde_json::Value>> = aligned_vibration::PARAMETER_SETS
        .iter()
        .map(|name| {
            let p = aligned_vibration::parameters(name)?;
            let mut v = to_json(&p)?;
            if let Some(o) = v.as_object_mut() {
                o.insert("name".into(), serde_json::json!(name));
            }
            Ok(v)
        })
        .collect();
    Ok(serde_json::json!({
        "vibrating-bar": to_json(&vibrating_bar::PARAMETER_SETS)?,
        "column-self-weight": to_json(&column::PARAMETER_SETS)?,
        "column-top-load": to_json(&column::PARAMETER_SETS)?,
        "manufactured-strip": to_json(&manufactured_strip::PARAMETER_SETS)?,
        "aligned-vibration": aligned?,
    }))
}

/// A value as JSON, or an error naming why not.
pub(crate) fn to_json<T: Serialize + ?Sized>(v: &T) -> Result<serde_json::Value> {
    serde_json::to_value(v).map_err(|e| Error::InvalidArgument(format!("cannot write JSON: {e}")))
}
