//! # The combinations of conventions the study runs (issue #38)
//!
//! hompm's BSMPM (MLS paper Eqs. 18–37 with MUSL and FLIP, open knots),
//! one convention of another code switched at a time
//! (`mpm::conventions`, docs/conventions.md "Conventions of other codes");
//! the Taichi-style step (APIC, the affine gradient, padded knots, USL; Hu
//! et al. 2018) with one switched back at a time; the MLS paper's
//! reconstruction (Eqs. 14–21), conservative 2D TLS (TLS paper §5.2–5.5)
//! and hompm's partition-of-unity TLS (`mpm2d::pu_tls`) alone and under
//! USL or FLIP 0.99; and the total-Lagrangian
//! reference, which never crosses cells. Each is named by the flags of
//! `hompm run aligned-vibration` that give it.
//!
//! Items: [`Combination`], [`combinations`], [`BSMPM`], [`TAICHI`], [`REFERENCE`].

use crate::mpm::conventions::{BodyForceAt, Conventions, Gradient, Knots, Positions};
use crate::mpm::conventions::{Scheme, Transfer};
use crate::mpm2d::Mapping2d;
use crate::scenes::aligned_vibration::{AlignedMethod, AlignedVibration, SolutionForm};
use serde::Serialize;

/// One combination of conventions of the step (docs/conventions.md,
/// "Conventions of other codes") and, for one row, of the manufactured
/// solution's form (MLS paper Eq. 38 or Wallstedt & Guilkey's), as the
/// command line names it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Combination {
    /// The row's name in the table.
    pub label: &'static str,
    /// The flags of `hompm run aligned-vibration` that give it (method,
    /// degree and every convention that is not the MLS paper's).
    pub flags: &'static str,
    /// The method: quadratic B-spline MPM with the direct mapping, or the
    /// total-Lagrangian reference without grid crossing.
    pub method: AlignedMethod,
    /// The step's conventions (`mpm::conventions`).
    pub conventions: Conventions,
    /// The manufactured solution (`--solution`; MLS paper Eq. 38 unless
    /// the axis-aligned form).
    pub solution: SolutionForm,
}

impl Combination {
    /// The scene with this combination's solution form.
    pub fn scene(&self, base: &AlignedVibration) -> AlignedVibration {
        AlignedVibration {
            solution: self.solution,
            ..*base
        }
    }
}

/// The label of hompm's BSMPM, the first combination (MLS paper Eqs.
/// 18–37 with MUSL and FLIP, book §4.2.2).
pub const BSMPM: &str = "BSMPM";
/// The label of the Taichi-style step (APIC, affine gradient, padded
/// knots, USL; Hu et al. 2018, Jiang et al. 2015).
pub const TAICHI: &str = "Taichi-style (apic, affine, padded)";
/// The label of the control without grid crossing: the total-Lagrangian
/// reference on the same quadratic B-splines (`Formulation::TotalLagrangian`).
pub const REFERENCE: &str = "TL-FE reference (no grid crossing)";

const fn with(scheme: Scheme, transfer: Transfer, knots: Knots, gradient: Gradient) -> Conventions {
    Conventions {
        scheme,
        transfer,
        knots,
        gradient,
        ..Conventions::MLS_PAPER
    }
}

/// The combinations of the study, hompm's BSMPM first: from it one
/// convention switched at a time (APIC runs with USL, which
/// `Conventions::validate` requires), then the Taichi-style step and one
/// convention switched back at a time (the affine gradient needs APIC, so
/// replacing APIC drops it too; APIC cannot go back to MUSL); then MLS,
/// conservative TLS and PU-TLS alone and under USL or FLIP 0.99; last, the
/// total-Lagrangian reference, which separates what grid crossing does
/// from what the manufactured solution does.
pub fn combinations() -> Vec<Combination> {
    use Gradient::{Affine, Basis};
    use Knots::{Open, Padded};
    use Scheme::{Musl, Usl};
    let mls = Conventions::MLS_PAPER;
    let paper = SolutionForm::MlsPaper;
    let c = |label, flags, conventions| Combination {
        label,
        flags,
        method: AlignedMethod::bsmpm(2),
        conventions,
        solution: paper,
    };
    let r = |mapping, label, flags, conventions| Combination {
        method: AlignedMethod::bsmpm_with(2, mapping),
        ..c(label, flags, conventions)
    };
    vec![
        c(BSMPM, "--method bsmpm --degree 2", mls),
        c(
            "BSMPM + usl",
            "--method bsmpm --degree 2 --scheme usl",
            with(Usl, Transfer::Flip, Open, Basis),
        ),
        c(
            "BSMPM + pic",
            "--method bsmpm --degree 2 --transfer pic",
            with(Musl, Transfer::Pic, Open, Basis),
        ),
        c(
            "BSMPM + flip:0.99",
            "--method bsmpm --degree 2 --transfer flip:0.99",
            with(Musl, Transfer::Blend(0.99), Open, Basis),
        ),
        c(
            "BSMPM + apic (usl)",
            "--method bsmpm --degree 2 --transfer apic",
            with(Usl, Transfer::Apic, Open, Basis),
        ),
        c(
            "BSMPM + padded knots",
            "--method bsmpm --degree 2 --knots padded",
            with(Musl, Transfer::Flip, Padded, Basis),
        ),
        c(
            "BSMPM + projected positions",
            "--method bsmpm --degree 2 --positions projected",
            Conventions {
                positions: Positions::Projected,
                ..mls
            },
        ),
        c(
            "BSMPM + body force at nodes",
            "--method bsmpm --degree 2 --body-force nodes",
            Conventions {
                body_force: BodyForceAt::Nodes,
                ..mls
            },
        ),
        Combination {
            label: "BSMPM + axis-aligned solution",
            flags: "--method bsmpm --degree 2 --solution axis-aligned",
            method: AlignedMethod::bsmpm(2),
            conventions: mls,
            solution: SolutionForm::AxisAligned,
        },
        c(
            TAICHI,
            "--method bsmpm --degree 2 --transfer apic --gradient affine --knots padded",
            with(Usl, Transfer::Apic, Padded, Affine),
        ),
        c(
            "Taichi-style - affine",
            "--method bsmpm --degree 2 --transfer apic --knots padded",
            with(Usl, Transfer::Apic, Padded, Basis),
        ),
        c(
            "Taichi-style - padded knots",
            "--method bsmpm --degree 2 --transfer apic --gradient affine",
            with(Usl, Transfer::Apic, Open, Affine),
        ),
        c(
            "Taichi-style, pic for apic",
            "--method bsmpm --degree 2 --transfer pic --scheme usl --knots padded",
            with(Usl, Transfer::Pic, Padded, Basis),
        ),
        c(
            "Taichi-style, flip for apic",
            "--method bsmpm --degree 2 --scheme usl --knots padded",
            with(Usl, Transfer::Flip, Padded, Basis),
        ),
        // The reconstructions of the MLS paper (Eqs. 14-21) and of 2D TLS
        // (TLS paper §5.2-5.5, conservative) under the two switches that
        // restore BSMPM to 32 cells; APIC, the affine gradient and padded
        // knots run with the direct mapping only (Conventions::check_2d).
        r(Mapping2d::Mls, "BSMPM + MLS", "--method bsmpm-mls", mls),
        r(
            Mapping2d::Mls,
            "BSMPM + MLS + usl",
            "--method bsmpm-mls --scheme usl",
            with(Usl, Transfer::Flip, Open, Basis),
        ),
        r(
            Mapping2d::Mls,
            "BSMPM + MLS + flip:0.99",
            "--method bsmpm-mls --transfer flip:0.99",
            with(Musl, Transfer::Blend(0.99), Open, Basis),
        ),
        r(Mapping2d::Tls, "BSMPM + TLS", "--method bsmpm-tls", mls),
        r(
            Mapping2d::Tls,
            "BSMPM + TLS + usl",
            "--method bsmpm-tls --scheme usl",
            with(Usl, Transfer::Flip, Open, Basis),
        ),
        r(
            Mapping2d::Tls,
            "BSMPM + TLS + flip:0.99",
            "--method bsmpm-tls --transfer flip:0.99",
            with(Musl, Transfer::Blend(0.99), Open, Basis),
        ),
        // hompm's partition-of-unity TLS (src/mpm2d/pu_tls.rs): conservative
        // as TLS and continuous as MLS, under the same switches.
        r(
            Mapping2d::PuTls,
            "BSMPM + PU-TLS",
            "--method bsmpm-pu-tls",
            mls,
        ),
        r(
            Mapping2d::PuTls,
            "BSMPM + PU-TLS + usl",
            "--method bsmpm-pu-tls --scheme usl",
            with(Usl, Transfer::Flip, Open, Basis),
        ),
        r(
            Mapping2d::PuTls,
            "BSMPM + PU-TLS + flip:0.99",
            "--method bsmpm-pu-tls --transfer flip:0.99",
            with(Musl, Transfer::Blend(0.99), Open, Basis),
        ),
        Combination {
            label: REFERENCE,
            flags: "--method tl-fe --degree 2",
            method: AlignedMethod::TotalLagrangian { degree: 2 },
            conventions: mls,
            solution: paper,
        },
    ]
}
