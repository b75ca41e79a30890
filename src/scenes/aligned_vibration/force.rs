//! # The manufactured body force at fixed points
//!
//! MLS paper Eq. (42) with the derived π² (module doc of the parent), for
//! the particles' X_p or, with `--body-force nodes`, the nodes' X_i.
//!
//! Items: [`ManufacturedForce`].

use super::AlignedVibration;
use crate::error::Result;
use crate::mpm2d::step::BodyForce2d;
use crate::mpm2d::NeoHookean;
use std::f64::consts::PI;

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
