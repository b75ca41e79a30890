//! # Exact and manufactured fields at any point and time
//!
//! `hompm exact` evaluates what another code compares its particles with:
//!
//! - the vibrating bar, thesis Eq. (4.1), book Eqs. (4.50)–(4.52):
//!   u, v, ε = ∂u/∂X and σ = E ε (the linear, small-strain solution; for a
//!   large-strain set it is labelled as the linear reference);
//! - the column, thesis Eq. (4.2): the series summed to infinity in closed
//!   form ([`column_closed_form`]), u = u_s(y) − ½[Ũ(y − ct) + Ũ(y + ct)]
//!   with u_s the static solution and Ũ its extension, odd about y = 0 and
//!   even about y = H (period 4H); each term cos(ckt) sin(ky) of the series
//!   is ½[sin k(y + ct) + sin k(y − ct)], so the two agree term by term
//!   (tests compare them). A ramped set (TLS paper §6.2) has the
//!   quasi-static equilibrium instead, ramped in time;
//! - the aligned vibration, MLS paper Eqs. (38)–(42): u, v, F, J, the
//!   first Piola stress P, the Cauchy stress σ and the body force b, with
//!   π² (the derivation) or π (Eq. 42 as printed).
//!
//! Items: [`Exact1d`], [`Exact2d`], [`exact_1d`], [`exact_2d`],
//! [`column_closed_form`], [`reference_kind`], [`formulas_1d`],
//! [`formulas_2d`], [`ExactTable`], [`exact_table`].

use super::setup::{Scene1d, Setup, Setup1d};
use crate::error::{Error, Result};
use crate::mpm::musl::Constitutive;
use crate::mpm::particles::Particles;
use crate::mpm2d::NeoHookean;
use crate::mpm2d::Particles2d;
use crate::scenes::aligned_vibration::AlignedVibration;
use crate::scenes::column::ColumnParameters;
use serde::Serialize;

/// The exact 1D fields at one point X and time t.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Exact1d {
    /// Initial position X.
    pub x0: f64,
    /// Displacement u(X, t).
    pub u: f64,
    /// Velocity v(X, t).
    pub v: f64,
    /// Strain ε = ∂u/∂X.
    pub strain: f64,
    /// Stress σ = E ε (plus the top load's share where it applies).
    pub stress: f64,
}

/// t reduced to [0, period) when it exceeds a million periods: the fields
/// are periodic in t, and a time so large that ω t overflows would
/// otherwise give NaN (times below that are used as given, so ordinary
/// runs see no rounding from the reduction).
fn within_period(t: f64, period: f64) -> f64 {
    if t.abs() > 1e6 * period && period > 0.0 && period.is_finite() {
        t.rem_euclid(period)
    } else {
        t
    }
}

/// The exact fields of a 1D scene at X and t. The bar and the unramped
/// column are periodic in t (periods 2L/c and 4H/c), and t is reduced to
/// one period first.
pub fn exact_1d(scene: &Scene1d, x0: f64, t: f64) -> Exact1d {
    match scene {
        Scene1d::VibratingBar(p) => {
            let t = within_period(t, 2.0 * p.length / p.wave_speed());
            exact_bar(p, x0, t)
        }
        Scene1d::Column(p) => match p.ramp_time {
            Some(tr) if tr > 0.0 => {
                let ramp = (t / tr).min(1.0);
                let (u, strain) = column_static(p, x0);
                Exact1d {
                    x0,
                    u: ramp * u,
                    v: 0.0,
                    strain: ramp * strain,
                    stress: p.equilibrium_stress(x0, t),
                }
            }
            _ => column_closed_form(p, x0, within_period(t, 4.0 * p.height / p.wave_speed())),
        },
        Scene1d::ManufacturedStrip(p) => {
            let t = within_period(t, 2.0 * p.length / p.wave_speed());
            let f = p.deformation(x0, t);
            Exact1d {
                x0,
                u: p.displacement(x0, t),
                v: p.velocity(x0, t),
                strain: f - 1.0,
                stress: p.stress(x0, t),
            }
        }
    }
}

/// The bar's fields, thesis Eq. (4.1) and book Eqs. (4.50)–(4.52).
fn exact_bar(p: &crate::scenes::vibrating_bar::BarParameters, x0: f64, t: f64) -> Exact1d {
    Exact1d {
        x0,
        u: p.displacement(x0, t),
        v: p.velocity(x0, t),
        strain: p.stress(x0, t) / p.young,
        stress: p.stress(x0, t),
    }
}

/// The static solution u_s(y) = ρgy²/(2E) + (p₀ − ρgH)y/E and its
/// derivative, g the magnitude of the (downward) gravity.
fn column_static(p: &ColumnParameters, y: f64) -> (f64, f64) {
    let (h, e, rho, p0) = (p.height, p.young, p.density, p.top_load);
    let g = -p.gravity;
    (
        0.5 * rho * g * y * y / e + (p0 - rho * g * h) * y / e,
        rho * g * y / e + (p0 - rho * g * h) / e,
    )
}

/// The extension Ũ of u_s (odd about 0, even about H, period 4H) and its
/// derivative at s.
fn column_extension(p: &ColumnParameters, s: f64) -> (f64, f64) {
    let h = p.height;
    let period = 4.0 * h;
    // s into [−2H, 2H).
    let mut r = (s + 2.0 * h).rem_euclid(period) - 2.0 * h;
    let odd = r < 0.0;
    if odd {
        r = -r;
    }
    let (u, du) = if r <= h {
        column_static(p, r)
    } else {
        let (u, du) = column_static(p, 2.0 * h - r);
        (u, -du)
    };
    if odd {
        (-u, du)
    } else {
        (u, du)
    }
}

/// The column's linear solution, thesis Eq. (4.2) summed to infinity: the
/// static part plus the free vibration −½[Ũ(y − ct) + Ũ(y + ct)] that
/// starts the column at rest and unstrained (module docs).
pub fn column_closed_form(p: &ColumnParameters, y: f64, t: f64) -> Exact1d {
    let c = p.wave_speed();
    let (us, dus) = column_static(p, y);
    let (minus, dminus) = column_extension(p, y - c * t);
    let (plus, dplus) = column_extension(p, y + c * t);
    let strain = dus - 0.5 * (dminus + dplus);
    Exact1d {
        x0: y,
        u: us - 0.5 * (minus + plus),
        v: 0.5 * c * (dminus - dplus),
        strain,
        stress: p.young * strain,
    }
}

/// What the 1D exact fields are: the analytic solution of the run's own
/// model, or the linear solution a large-strain run is compared with, or
/// the quasi-static equilibrium of a ramped column.
pub fn reference_kind(scene: &Scene1d) -> &'static str {
    let ramped = matches!(scene, Scene1d::Column(p) if p.ramp_time.is_some_and(|t| t > 0.0));
    if ramped {
        "quasi-static equilibrium of the ramped body force (TLS paper §6.2); not a solution of the dynamic problem"
    } else if matches!(scene, Scene1d::ManufacturedStrip(_)) {
        "manufactured solution of the run's own (neo-Hookean) model, exact with its body force"
    } else if scene.constitutive() == Constitutive::LargeStrain {
        "linear analytic solution (small strain); this set uses the large-strain update (book Eq. 4.16), so the error includes the difference of the models"
    } else {
        "analytic solution of the run's own (small-strain) model"
    }
}

/// The formulas of the 1D exact fields, for the JSON metadata.
pub fn formulas_1d(scene: &Scene1d) -> serde_json::Value {
    match scene {
        Scene1d::VibratingBar(_) => serde_json::json!({
            "source": "thesis Eq. (4.1), book Eqs. (4.50)-(4.52)",
            "omega": "ω = π √(E/ρ) / L",
            "u": "u = v0/ω sin(ωt) sin(πX/L)",
            "v": "v = v0 cos(ωt) sin(πX/L)",
            "strain": "ε = v0/√(E/ρ) sin(ωt) cos(πX/L)",
            "stress": "σ = v0 √(Eρ) sin(ωt) cos(πX/L)",
        }),
        Scene1d::Column(p) if p.ramp_time.is_some_and(|t| t > 0.0) => serde_json::json!({
            "source": "TLS paper §6.2 (quasi-static)",
            "u": "u = r(t) u_s(X), r(t) = min(t/t_ramp, 1)",
            "v": "v = 0",
            "stress": "σ = ρ g r(t) (H − X) + p0",
        }),
        Scene1d::Column(_) => serde_json::json!({
            "source": "thesis Eq. (4.2), summed in closed form",
            "static": "u_s(y) = ρ g y²/(2E) + (p0 − ρ g H) y/E, g = |gravity|",
            "u": "u = u_s(y) − ½[Ũ(y − ct) + Ũ(y + ct)], Ũ: u_s extended odd about 0 and even about H, c = √(E/ρ)",
            "v": "v = (c/2)[Ũ'(y − ct) − Ũ'(y + ct)]",
            "strain": "ε = u_s'(y) − ½[Ũ'(y − ct) + Ũ'(y + ct)]",
            "stress": "σ = E ε",
        }),
        Scene1d::ManufacturedStrip(p) => serde_json::json!({
            "source": "the MLS paper's code, Vibration.m (f30bc24); MLS paper Eq. (37) in 1D",
            "u": "u = A sin(π(X − a)/L) sin(cπt/L), c = √(E/ρ0)",
            "v": "v = ∂u/∂t",
            "F": "F = 1 + ∂u/∂X",
            "strain": "ε = F − 1",
            "stress": "σ = (λ ln F + μ(F² − 1))/F",
            "body_force": "b = (π²u/(ρ0 L²))(λ(1 − ln F)/F² + μ(F² + 1)/F² − E)",
            "a": p.left_end,
        }),
    }
}

/// The manufactured 2D fields at one point X and time t (MLS paper
/// Eqs. 38–42). Matrices are rows [xx, xy, yx, yy].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Exact2d {
    /// Initial position X.
    pub x0: [f64; 2],
    /// Displacement u, Eq. (38).
    pub u: [f64; 2],
    /// Velocity v, Eq. (39).
    pub v: [f64; 2],
    /// Deformation gradient F = I + ∂u/∂X.
    #[serde(rename = "F")]
    pub deformation: [f64; 4],
    /// J = det F.
    #[serde(rename = "J")]
    pub jacobian: f64,
    /// First Piola stress P = μ(F − F⁻ᵀ) + λ ln J F⁻ᵀ, Eq. (40).
    #[serde(rename = "P")]
    pub first_piola: [f64; 4],
    /// Cauchy stress σ, Eq. (41).
    pub stress: [f64; 4],
    /// Body force per unit mass b, Eq. (42).
    pub body_force: [f64; 2],
}

fn rows(m: &nalgebra::Matrix2<f64>) -> [f64; 4] {
    [m[(0, 0)], m[(0, 1)], m[(1, 0)], m[(1, 1)]]
}

/// The manufactured fields of the aligned vibration at X and t; with
/// `as_printed` the body force is Eq. (42) as printed (π, not π²).
pub fn exact_2d(
    scene: &AlignedVibration,
    x0: [f64; 2],
    t: f64,
    as_printed: bool,
) -> Result<Exact2d> {
    let t = within_period(t, 2.0 * scene.length / scene.wave_speed());
    let f = scene.deformation_gradient(x0, t);
    let material = scene.material()?;
    Ok(Exact2d {
        x0,
        u: scene.displacement(x0, t),
        v: scene.velocity(x0, t),
        deformation: rows(&f),
        jacobian: NeoHookean::jacobian(&f)?,
        first_piola: rows(&material.first_piola(&f)?),
        stress: rows(&scene.stress(x0, t)?),
        body_force: if as_printed {
            scene.body_force_as_printed(x0, t)?
        } else {
            scene.body_force(x0, t)?
        },
    })
}

/// The formulas of the 2D fields, for the JSON metadata.
pub fn formulas_2d(as_printed: bool) -> serde_json::Value {
    serde_json::json!({
        "source": "MLS paper Eqs. (38)-(42)",
        "c": "c = √(E/ρ0)",
        "u": "u = (A sin(2πX/L) sin(cπt/L), A sin(2πY/L) sin(cπt/L + π))",
        "v": "v = ∂u/∂t",
        "F": "F = I + ∂u/∂X (diagonal)",
        "P": "P = μ(F − F⁻ᵀ) + λ ln(J) F⁻ᵀ",
        "stress": "σ = (λ ln J / J) I + (μ/J)(F Fᵀ − I)",
        "body_force": if as_printed {
            "Eq. (42) as printed: b_x = (π u_x/L²)(4μ/ρ0 − c² − 4[λ(ln J − 1) − μ]/(ρ0 F_xx²)), b_y likewise"
        } else {
            "b = ü − ∇_X·P/ρ0: b_x = (π² u_x/L²)(4μ/ρ0 − c² − 4[λ(ln J − 1) − μ]/(ρ0 F_xx²)), b_y likewise (Eq. 42 prints π; docs/derivations.md)"
        },
    })
}

/// The exact fields of a setup at its particles' initial positions (or at
/// `at`, 2D as x, y pairs), at time t: the columns `hompm exact` prints
/// and what they are (`meta`: scene, kind, formulas).
#[derive(Debug, Clone, PartialEq)]
pub struct ExactTable {
    /// The fields by name, one value per point: 1D x0, u, v, strain,
    /// stress; 2D x0, u, v (pairs), F, J, P, stress (rows) and b.
    pub columns: Vec<(String, Vec<f64>)>,
    /// The scene, the kind of solution and its formulas.
    pub meta: serde_json::Value,
}

/// [`ExactTable`] of `setup` at time `time`: 1D thesis Eq. (4.1) / (4.2),
/// book Eqs. (4.50)–(4.52); 2D MLS paper Eqs. (38)–(42) (`as_printed`:
/// Eq. 42 with π). A point outside [0, L] (1D) or [0, L]² (2D) is
/// [`Error::OutsideDomain`], a non-finite field [`Error::NonFinite`].
pub fn exact_table(
    setup: &Setup,
    at: Option<&[f64]>,
    time: f64,
    as_printed: bool,
) -> Result<ExactTable> {
    let mut columns: Vec<(String, Vec<f64>)> = Vec::new();
    let mut push = |name: &str, v: f64| match columns.iter_mut().find(|(k, _)| k == name) {
        Some((_, c)) => c.push(v),
        None => columns.push((name.to_string(), vec![v])),
    };
    let meta = match setup {
        Setup::OneD(s1) => {
            let x0 = match at {
                None => layout_1d(s1)?,
                Some(at) => at.to_vec(),
            };
            let (lo, hi) = s1.scene.domain();
            for &x in &x0 {
                if !(lo..=hi).contains(&x) {
                    return Err(Error::OutsideDomain { x, a: lo, b: hi });
                }
                let e = exact_1d(&s1.scene, x, time);
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
            if !at.map_or(0, <[f64]>::len).is_multiple_of(2) {
                return Err(Error::InvalidArgument(format!(
                    "--at takes x,y pairs in 2D; got {} numbers",
                    at.map_or(0, <[f64]>::len)
                )));
            }
            let x0: Vec<[f64; 2]> = if at.is_none() {
                Particles2d::cell_centred(
                    s2.scene.length,
                    s2.cells,
                    s2.per_side,
                    s2.scene.density,
                    |_| [0.0; 2],
                )?
                .x0
            } else {
                at.unwrap_or_default()
                    .chunks(2)
                    .map(|c| [c[0], c[1]])
                    .collect()
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
                let e = exact_2d(&s2.scene, *x, time, as_printed)?;
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
                "formulas": formulas_2d(as_printed),
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
            what: format!("the exact {name} at t = {time:e}"),
            value: bad,
        });
    }
    Ok(ExactTable { columns, meta })
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
    if let Scene1d::ManufacturedStrip(p) = &s.scene {
        return Ok(p.initial_positions(d.cells, d.ppc));
    }
    Ok(Particles::uniform(0.0, s.scene.length(), count, 1.0)?.x0)
}
