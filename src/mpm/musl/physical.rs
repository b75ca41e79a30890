//! # The end of a 1D step: are the particles physical?
//!
//! What [`super::Simulation::step`] checks last, after recording the
//! per-particle monitors: that every particle's position, velocity and
//! stress are finite, its volume positive, and that it is inside the grid
//! (a typed error otherwise, never a silent NaN).

use super::Simulation;
use crate::error::{Error, Result};

impl Simulation {
    /// A typed [`Error::NonPhysicalParticle`] if a particle's position,
    /// velocity or stress is non-finite or its volume non-positive (the
    /// first such particle); else [`Error::ParticleLeftGrid`] for the first
    /// particle outside the grid. [`Simulation::step`] ends with this check;
    /// it is public so that a caller who edits the particles between steps
    /// can run it too.
    pub fn check_particles_are_physical(&self) -> Result<()> {
        let p = &self.particles;
        let (lo, hi) = self.grid.domain();
        // One pass without an early exit, which the compiler vectorises:
        // whether any particle fails either check. Only then the loop below
        // finds the first one, so the errors are the same.
        let mut suspect = false;
        for (((&x, &v), &s), &volume) in p.x.iter().zip(&p.velocity).zip(&p.stress).zip(&p.volume) {
            let finite = x.is_finite() & v.is_finite() & s.is_finite();
            suspect |= !finite | (volume <= 0.0) | (x < lo) | (x > hi);
        }
        if !suspect {
            return Ok(());
        }
        let mut outside = None;
        for k in 0..p.len() {
            let finite = p.x[k].is_finite() && p.velocity[k].is_finite() && p.stress[k].is_finite();
            if !finite || p.volume[k] <= 0.0 {
                return Err(Error::NonPhysicalParticle {
                    particle: k,
                    step: self.diagnostics.steps,
                    time: self.time,
                    x: p.x[k],
                    velocity: p.velocity[k],
                    stress: p.stress[k],
                    volume: p.volume[k],
                    negative_masses: self.diagnostics.negative_mass_steps > 0,
                });
            }
            if outside.is_none() && (p.x[k] < lo || p.x[k] > hi) {
                outside = Some(k);
            }
        }
        if let Some(k) = outside {
            return Err(Error::ParticleLeftGrid {
                particle: k,
                step: self.diagnostics.steps,
                x: p.x[k],
                a: lo,
                b: hi,
            });
        }
        Ok(())
    }
}
