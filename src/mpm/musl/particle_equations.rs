//! # One particle's update: the equations of steps 3 and 5–8
//!
//! Book Eqs. (4.9), (4.12)–(4.18) for one material point, written once and
//! called by both shapes of [`super::Simulation::step`]: the pass per
//! equation that `hompm trace` observes, and the fused particle loops of
//! [`super::fused`]. Each function is the formula and nothing else; the
//! loops around them decide which particles and in which order.
//!
//! Items: `flip_velocity`, `displacement_and_strain_increment`,
//! `small_strain_stress`, `large_strain_stress`,
//! `update_volume_density_strain`.

/// Book Eq. (4.9), FLIP: v_p + Δt Σ_i φ_i(x_p) a_i, given the interpolated
/// acceleration Σ_i φ_i(x_p) a_i ([`crate::basis::interpolate_row`]).
#[inline(always)]
pub(super) fn flip_velocity(velocity: f64, dt: f64, interpolated_acceleration: f64) -> f64 {
    velocity + dt * interpolated_acceleration
}

/// Book Eqs. (4.11)–(4.14) at one particle: with Δu_i = Δt v_i, the
/// displacement increment Σ_i φ_i(x_p) Δu_i and the strain increment
/// Δε_p = Σ_i ∇φ_i(x_p) Δu_i, over its stencil (`values`, `gradients`)
/// and the projected nodal velocity from its first function on.
#[inline(always)]
pub(super) fn displacement_and_strain_increment(
    values: &[f64],
    gradients: &[f64],
    nodal_velocity_from_first: &[f64],
    dt: f64,
) -> (f64, f64) {
    let mut du = 0.0;
    let mut deps = 0.0;
    for ((phi, grad), vi) in values.iter().zip(gradients).zip(nodal_velocity_from_first) {
        let dui = dt * vi;
        du += phi * dui;
        deps += grad * dui;
    }
    (du, deps)
}

/// Book Eq. (4.15), small strain: σ_p + E Δε_p.
#[inline(always)]
pub(super) fn small_strain_stress(stress: f64, young: f64, strain_increment: f64) -> f64 {
    stress + young * strain_increment
}

/// Book Eq. (4.16), large strain: σ_p + (E − σ_p) Δε_p.
#[inline(always)]
pub(super) fn large_strain_stress(stress: f64, young: f64, strain_increment: f64) -> f64 {
    stress + (young - stress) * strain_increment
}

/// Book Eqs. (4.17)–(4.18): V_p ← (1 + Δε_p) V_p, ρ_p ← ρ_p / (1 + Δε_p),
/// and the accumulated strain ε_p ← ε_p + Δε_p.
#[inline(always)]
pub(super) fn update_volume_density_strain(
    volume: &mut f64,
    density: &mut f64,
    strain: &mut f64,
    strain_increment: f64,
) {
    *volume *= 1.0 + strain_increment;
    *density /= 1.0 + strain_increment;
    *strain += strain_increment;
}
