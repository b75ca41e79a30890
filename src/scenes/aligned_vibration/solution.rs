//! # The two forms of the aligned vibration
//!
//! MLS paper Eq. (38) and the Wallstedt–Guilkey form that Uintah, mpmat
//! and the MLS paper's own code run (docs/conventions.md, "Conventions of
//! other codes").
//!
//! Items: [`SolutionForm`].

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// `--solution`: the two forms of the aligned vibration in use,
/// u_x = A sin(nπX/L) sin(cπt/L), u_y = A sin(nπY/L) sin(cπt/L + π) with
/// n waves on the side. Both satisfy the walls; each has its body force
/// b = u (π²/L²) [n²μ/ρ₀ − c² − n²(λ(ln J − 1) − μ)/(ρ₀F_ii²)]
/// (docs/derivations.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SolutionForm {
    /// n = 2: MLS paper Eq. (38) as printed, with the derived π² body force.
    #[default]
    MlsPaper,
    /// n = 1: Wallstedt & Guilkey (2008), Sadeghirad et al. (2011); Uintah's
    /// AxisAligned MMS (`MMS.cc`), mpmat's `impmMMS2D.m`, the MLS paper's
    /// own code (`Vibration2D.m`, which also offsets X by two ghost cells).
    AxisAligned,
}

impl SolutionForm {
    /// Every form, the default first.
    pub const ALL: [SolutionForm; 2] = [SolutionForm::MlsPaper, SolutionForm::AxisAligned];

    /// The command line's word.
    pub fn name(self) -> &'static str {
        match self {
            SolutionForm::MlsPaper => "mls-paper",
            SolutionForm::AxisAligned => "axis-aligned",
        }
    }

    /// The form called `name`, or an error naming the known ones.
    pub fn from_name(name: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|f| f.name() == name)
            .ok_or_else(|| {
                Error::InvalidArgument(format!(
                    "unknown --solution '{name}' (known: mls-paper, axis-aligned)"
                ))
            })
    }

    /// Whether this is the MLS paper's form (the default).
    pub fn is_mls_paper(&self) -> bool {
        *self == SolutionForm::MlsPaper
    }

    /// n, the half-waves on the side: 2 (MLS paper Eq. 38) or 1.
    pub fn waves(self) -> f64 {
        match self {
            SolutionForm::MlsPaper => 2.0,
            SolutionForm::AxisAligned => 1.0,
        }
    }
}
