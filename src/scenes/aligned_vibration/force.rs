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
/// sin and cos of 2πX/L and 2πY/L precomputed per particle so that a step
/// pays one logarithm per particle.
pub struct ManufacturedForce {
    scene: AlignedVibration,
    material: NeoHookean,
    /// [sin 2πX/L, cos 2πX/L, sin 2πY/L, cos 2πY/L] per particle.
    trig: Vec<[f64; 4]>,
}

impl ManufacturedForce {
    /// For the particles with initial positions `x0`.
    pub fn new(scene: AlignedVibration, x0: &[[f64; 2]]) -> Result<Self> {
        let k = scene.wavenumber();
        Ok(Self {
            material: scene.material()?,
            scene,
            trig: x0
                .iter()
                .map(|x| {
                    [
                        (k * x[0]).sin(),
                        (k * x[0]).cos(),
                        (k * x[1]).sin(),
                        (k * x[1]).cos(),
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
        let a = sc.amplitude;
        let ak = a * sc.solution.waves() * PI / sc.length;
        let n2 = sc.solution.waves().powi(2);
        let (lambda, mu, rho) = (self.material.lambda, self.material.mu, sc.density);
        let c2 = sc.wave_speed().powi(2);
        let pre = PI * PI / (sc.length * sc.length);
        for (o, t) in out.iter_mut().zip(&self.trig) {
            let fxx = 1.0 + ak * t[1] * s[0];
            let fyy = 1.0 + ak * t[3] * s[1];
            let ln_j = (fxx * fyy).ln();
            let bracket = |fii: f64| {
                n2 * mu / rho - c2 - n2 * (lambda * (ln_j - 1.0) - mu) / (rho * fii * fii)
            };
            *o = [
                pre * a * t[0] * s[0] * bracket(fxx),
                pre * a * t[2] * s[1] * bracket(fyy),
            ];
        }
    }
}
