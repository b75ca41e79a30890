//! # The manufactured body force at fixed points, and its largest work
//!
//! MLS paper Eq. (42) with the derived π² (module doc of the parent), for
//! the particles' X_p or, with `--body-force nodes`, the nodes' X_i; and
//! the bound on the work it can do that the 2D stability monitor budgets
//! (`AlignedVibration::work_bound`).
//!
//! Items: [`ManufacturedForce`].

use super::AlignedVibration;
use crate::error::Result;
use crate::mpm2d::step::BodyForce2d;
use crate::mpm2d::NeoHookean;
use std::f64::consts::PI;
use std::sync::Mutex;

/// The largest sampled |b| of each parameter set met so far in this
/// process ([`AlignedVibration::work_bound`]), keyed by the bits of the
/// parameters that b depends on. Its 65³ samples, each with its sines,
/// cosines and logarithm, cost ~40 ms; a stability scan starts hundreds of
/// simulations of one set (`hompm reproduce`: about 6 s of processor time
/// before the samples were kept).
static LARGEST_SAMPLED_FORCE: Mutex<Vec<(String, f64)>> = Mutex::new(Vec::new());

impl AlignedVibration {
    /// The most work the manufactured body force can do on the particles,
    /// the loads' share of the 2D stability monitor's budget
    /// (`mpm2d::monitor`), as 1D's (Σ m_p |g|) × L: the total mass ×
    /// max |b| × L√2 (no particle moves farther than the square's
    /// diagonal). max |b| is taken over a 65 × 65 grid of X on the square
    /// and 65 times of one period 2L/c, and doubled for what the samples
    /// miss between them; it is sampled once per parameter set and process.
    pub fn work_bound(&self, total_mass: f64) -> Result<f64> {
        let largest = self.largest_sampled_force()?;
        Ok(total_mass * 2.0 * largest * self.length * std::f64::consts::SQRT_2)
    }

    /// max |b| over the samples of [`AlignedVibration::work_bound`], from
    /// [`LARGEST_SAMPLED_FORCE`] when this set was sampled before.
    fn largest_sampled_force(&self) -> Result<f64> {
        let bits = [
            self.young,
            self.poisson,
            self.density,
            self.amplitude,
            self.length,
        ]
        .map(f64::to_bits);
        let key = format!("{bits:?} {:?}", self.solution);
        let known = |cache: &[(String, f64)]| cache.iter().find(|(k, _)| *k == key).map(|e| e.1);
        if let Some(largest) = LARGEST_SAMPLED_FORCE.lock().ok().and_then(|c| known(&c)) {
            return Ok(largest);
        }
        const SAMPLES: usize = 65;
        let period = 2.0 * self.length / self.wave_speed();
        let at = |k: usize, span: f64| span * k as f64 / (SAMPLES - 1) as f64;
        let mut largest = 0.0f64;
        for i in 0..SAMPLES {
            for j in 0..SAMPLES {
                let x0 = [at(i, self.length), at(j, self.length)];
                for k in 0..SAMPLES {
                    let b = self.body_force(x0, at(k, period))?;
                    largest = largest.max(b[0].hypot(b[1]));
                }
            }
        }
        if let Ok(mut cache) = LARGEST_SAMPLED_FORCE.lock() {
            if known(&cache).is_none() {
                cache.push((key, largest));
            }
        }
        Ok(largest)
    }
}

/// The derived body force of Eq. (42) (with π²) at fixed particles, with
/// the products that do not depend on t precomputed per particle, so that
/// a step pays one logarithm and a few products per particle.
pub struct ManufacturedForce {
    scene: AlignedVibration,
    material: NeoHookean,
    /// [A k cos kX, A k cos kY, (π²/L²) A sin kX, (π²/L²) A sin kY] per
    /// particle, k = nπ/L, each the left operand
    /// of the products of Eq. (42) as [`BodyForce2d::fill`] forms them, in
    /// the same order, so the same bits.
    terms: Vec<[f64; 4]>,
}

impl ManufacturedForce {
    /// For the particles with initial positions `x0`.
    pub fn new(scene: AlignedVibration, x0: &[[f64; 2]]) -> Result<Self> {
        let k = scene.wavenumber();
        let ak = scene.amplitude * scene.solution.waves() * PI / scene.length;
        let pa = PI * PI / (scene.length * scene.length) * scene.amplitude;
        Ok(Self {
            material: scene.material()?,
            scene,
            terms: x0
                .iter()
                .map(|x| {
                    [
                        ak * (k * x[0]).cos(),
                        ak * (k * x[1]).cos(),
                        pa * (k * x[0]).sin(),
                        pa * (k * x[1]).sin(),
                    ]
                })
                .collect(),
        })
    }
}

impl BodyForce2d for ManufacturedForce {
    fn fill(&self, time: f64, _x0: &[[f64; 2]], out: &mut [[f64; 2]]) {
        let sc = &self.scene;
        let s = sc.time_factors(time);
        let n2 = sc.solution.waves().powi(2);
        let (lambda, mu, rho) = (self.material.lambda, self.material.mu, sc.density);
        let c2 = sc.wave_speed().powi(2);
        let head = n2 * mu / rho - c2;
        for (o, t) in out.iter_mut().zip(&self.terms) {
            let fxx = 1.0 + t[0] * s[0];
            let fyy = 1.0 + t[1] * s[1];
            let ln_j = (fxx * fyy).ln();
            let numerator = n2 * (lambda * (ln_j - 1.0) - mu);
            let bracket = |fii: f64| head - numerator / (rho * fii * fii);
            *o = [t[2] * s[0] * bracket(fxx), t[3] * s[1] * bracket(fyy)];
        }
    }
}
