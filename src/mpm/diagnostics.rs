//! # Diagnostics
//!
//! The error measures and monitors of the seeds:
//! - RMS error over particles, thesis §4.3 and MLS paper Eq. (43):
//!   e = √(Σ_p (f_p − f̄(X_p))² / N_p);
//! - relative L2 error ‖f − f̄‖₂/‖f̄‖₂ over particles (TLS paper §6, Figs. 9–10);
//! - maximal relative errors of total mass and momentum over all steps, before
//!   and after the velocity projection (TLS paper §6, Tables 3, 5, 7);
//! - grid crossings: particles passing a point where a basis gradient jumps
//!   (thesis §3.3, §6.2);
//! - maximal strain, lumped-mass sign, and energy.
//!
//! Items: [`rms_error`], [`relative_l2_error`], [`compensated_sum`],
//! [`CompensatedSum`], [`RunDiagnostics`], [`LumpedMassScan`].

use super::mapping::{running_max, running_min, Projection};
use crate::error::{Error, Result};
use serde::Serialize;

/// RMS error between computed values and a reference, thesis §4.3.
pub fn rms_error(computed: &[f64], reference: &[f64]) -> Result<f64> {
    check(computed, reference)?;
    let s: f64 = computed
        .iter()
        .zip(reference)
        .map(|(a, b)| (a - b) * (a - b))
        .sum();
    Ok((s / computed.len() as f64).sqrt())
}

/// Σ values by Neumaier's compensated summation: the rounding of the sum
/// itself stays at about one ulp of the result, whatever the count, so a
/// conservation monitor that subtracts two such sums sees the mapping's
/// rounding, not its own (the 2D step's mass and momentum monitor; a naive
/// sum of the 36 864 equal particle masses of 64 × 64 cells at 9 PPC errs
/// by 6.7e-13 relative, the largest "mapping error" the convergence study
/// had measured).
pub fn compensated_sum(values: impl IntoIterator<Item = f64>) -> f64 {
    let (mut sum, mut correction) = (0.0f64, 0.0f64);
    for v in values {
        let t = sum + v;
        correction += if sum.abs() >= v.abs() {
            (sum - t) + v
        } else {
            (v - t) + sum
        };
        sum = t;
    }
    sum + correction
}

/// [`compensated_sum`] one term at a time, so that one pass over the
/// particles can keep several sums: the same sums in the same order, so
/// the same bits as [`compensated_sum`] of the same terms. Each step's
/// rounding error is taken by Knuth's TwoSum, without Neumaier's branch on
/// |sum| ≥ |v|: both give the exact error fl(sum + v) − (sum + v) of finite
/// terms whose sum does not overflow, and an exact error is one number.
/// Without the branch the processor keeps four such sums side by side in
/// one vector register (the 2D step's conservation record, issue #39).
#[derive(Debug, Clone, Copy, Default)]
pub struct CompensatedSum {
    sum: f64,
    correction: f64,
}

impl CompensatedSum {
    /// Adds v (one step of Neumaier's summation).
    #[inline(always)]
    pub fn add(&mut self, v: f64) {
        let t = self.sum + v;
        let v_rounded = t - self.sum;
        let sum_rounded = t - v_rounded;
        self.correction += (self.sum - sum_rounded) + (v - v_rounded);
        self.sum = t;
    }

    /// The sum of the terms added so far.
    #[inline(always)]
    pub fn total(self) -> f64 {
        self.sum + self.correction
    }
}

/// Relative L2 error ‖c − r‖₂ / ‖r‖₂.
pub fn relative_l2_error(computed: &[f64], reference: &[f64]) -> Result<f64> {
    check(computed, reference)?;
    let num: f64 = computed
        .iter()
        .zip(reference)
        .map(|(a, b)| (a - b) * (a - b))
        .sum();
    let den: f64 = reference.iter().map(|b| b * b).sum();
    if den == 0.0 {
        return Err(Error::InvalidArgument(
            "relative error against a zero reference".into(),
        ));
    }
    Ok((num / den).sqrt())
}

fn check(a: &[f64], b: &[f64]) -> Result<()> {
    if a.len() != b.len() || a.is_empty() {
        return Err(Error::InvalidArgument(format!(
            "cannot compare {} values with {}",
            a.len(),
            b.len()
        )));
    }
    for (k, (&x, &y)) in a.iter().zip(b).enumerate() {
        crate::error::finite_named(x, || format!("computed value {k}"))?;
        crate::error::finite_named(y, || format!("reference value {k}"))?;
    }
    Ok(())
}

/// A minimum over steps that no step has recorded yet is +∞; JSON has no
/// number for it, so the key is left out rather than written as `null`.
fn no_value_yet(x: &f64) -> bool {
    x.is_infinite()
}

/// Monitors accumulated over a run.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct RunDiagnostics {
    /// Steps taken.
    pub steps: usize,
    /// max over steps of |Σ_ij M_ij − Σ m_p| / Σ m_p for the projection's mass.
    pub max_mass_error: f64,
    /// max over steps of |1ᵀMv − Σ m_p v_p| / |Σ m_p v_p| (before boundary
    /// velocities are zeroed).
    pub max_momentum_error: f64,
    /// The relative momentum error of the last projection whose particle
    /// momentum was non-zero, for a caller that follows it step by step (tls-7: the maximum over steps
    /// is attained where Σ m_p v_p passes near zero). Not in JSON.
    #[serde(skip)]
    pub last_momentum_error: f64,
    /// Number of times a particle crossed a gradient discontinuity.
    pub grid_crossings: usize,
    /// max over particles and steps of |ε_p|.
    pub max_abs_strain: f64,
    /// Steps in which some active lumped mass was negative (P2, thesis §5.2).
    pub negative_mass_steps: usize,
    /// Smallest active lumped mass seen (+∞ before the first step; absent
    /// from JSON until a step has recorded one).
    #[serde(skip_serializing_if = "no_value_yet")]
    pub min_lumped_mass: f64,
    /// Total iterations of a consistent iterative solver.
    pub solver_iterations: usize,
    /// min over steps of min_i M_ii / max_i M_ii of the projection's mass
    /// matrix over active DOFs (near-zero entries, thesis §7.2.4); +∞ before
    /// the first step and absent from JSON until then.
    #[serde(skip_serializing_if = "no_value_yet")]
    pub min_mass_diagonal_ratio: f64,
    /// max over steps of max_i |v_i| of the projected nodal velocities.
    pub max_nodal_velocity: f64,
    /// max over steps of max_p |v_p|.
    pub max_particle_velocity: f64,
    /// Kinetic plus strain energy at the start.
    pub initial_energy: f64,
    /// Kinetic plus strain energy at the end.
    pub final_energy: f64,
}

/// What [`RunDiagnostics::record_lumped_masses`] records of one step's
/// lumped masses, node by node: the smallest non-zero one in a running
/// minimum (one comparison each, `running_min`; merged into the record by
/// `f64::min`) and whether one is negative.
#[derive(Debug, Clone, Copy)]
pub struct LumpedMassScan {
    negative: bool,
    smallest: f64,
}

impl Default for LumpedMassScan {
    fn default() -> Self {
        Self {
            negative: false,
            smallest: f64::INFINITY,
        }
    }
}

impl LumpedMassScan {
    /// Takes in the lumped mass m_i of one node (zero masses are skipped).
    #[inline(always)]
    pub fn add(&mut self, m: f64) {
        if m != 0.0 {
            self.negative |= m < 0.0;
            self.smallest = running_min(self.smallest, m);
        }
    }
}

/// The recorder: every monitor of a run is updated here, by the step
/// functions of `mpm::musl`, after the physics of the step is done.
impl RunDiagnostics {
    /// Step 2's lumped masses m_i: the smallest non-zero one, and one more
    /// step with a negative mass if any is (P2, thesis §5.2).
    pub fn record_lumped_masses(&mut self, masses: &[f64]) {
        let mut scan = LumpedMassScan::default();
        masses.iter().for_each(|&m| scan.add(m));
        self.record_lumped_mass_scan(scan);
    }

    /// [`RunDiagnostics::record_lumped_masses`] from a scan that a loop over
    /// the nodes has already made (the step's Eq. 4.8 loop).
    pub fn record_lumped_mass_scan(&mut self, scan: LumpedMassScan) {
        self.min_lumped_mass = self.min_lumped_mass.min(scan.smallest);
        if scan.negative {
            self.negative_mass_steps += 1;
        }
    }

    /// Step 4's projection: solver iterations, the smallest diagonal ratio,
    /// the largest nodal (before boundary conditions) and particle speeds,
    /// and the relative mass and momentum errors of the grid against the
    /// particles (TLS paper Tables 3, 5, 7).
    pub fn record_projection(
        &mut self,
        projection: &Projection,
        nodal_velocity: &[f64],
        particle_velocity: &[f64],
        total_mass: f64,
        total_momentum: f64,
    ) {
        let pmax = particle_velocity
            .iter()
            .map(|v| v.abs())
            .fold(0.0, f64::max);
        self.record_projection_totals(projection, nodal_velocity, pmax, total_mass, total_momentum);
    }

    /// [`RunDiagnostics::record_projection`] with the largest particle
    /// speed max_p |v_p| already found (the fused 1D step finds it in the
    /// loop that updates the velocities).
    pub fn record_projection_totals(
        &mut self,
        projection: &Projection,
        nodal_velocity: &[f64],
        fastest_particle_speed: f64,
        total_mass: f64,
        total_momentum: f64,
    ) {
        self.solver_iterations += projection.solver_iterations;
        self.min_mass_diagonal_ratio = self.min_mass_diagonal_ratio.min(projection.diagonal_ratio);
        let vmax = nodal_velocity
            .iter()
            .map(|v| v.abs())
            .fold(0.0, running_max);
        self.max_nodal_velocity = self.max_nodal_velocity.max(vmax);
        self.max_particle_velocity = self.max_particle_velocity.max(fastest_particle_speed);
        self.max_mass_error = self
            .max_mass_error
            .max((projection.grid_mass - total_mass).abs() / total_mass);
        if total_momentum != 0.0 {
            let e = (projection.grid_momentum - total_momentum).abs() / total_momentum.abs();
            self.max_momentum_error = self.max_momentum_error.max(e);
            self.last_momentum_error = e;
        }
    }

    /// Steps 5–8's particles: the largest accumulated |ε_p| and this step's
    /// grid crossings.
    pub fn record_particles(&mut self, strain: &[f64], crossings: usize) {
        let largest = strain.iter().map(|e| e.abs()).fold(0.0, f64::max);
        self.record_particle_extremes(largest, crossings);
    }

    /// [`RunDiagnostics::record_particles`] with max_p |ε_p| already found
    /// (the fused 1D step finds it in the loop that updates the strains).
    pub fn record_particle_extremes(&mut self, max_abs_strain: f64, crossings: usize) {
        self.max_abs_strain = self.max_abs_strain.max(max_abs_strain);
        self.grid_crossings += crossings;
    }
}
