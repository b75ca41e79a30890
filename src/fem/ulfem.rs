//! # Updated-Lagrangian FEM in 1D
//!
//! The reference the seeds compare large-deformation MPM with (thesis §5.1.2,
//! TLS paper §6.1 with Ref. 26, book §4.5 with 120 DOFs). The mesh moves
//! with the material, so there is no grid crossing and no mapping error:
//! P1 elements, lumped (row-sum) mass fixed by the initial density, one
//! Gauss point per element, and the same Euler–Cromer and constitutive
//! updates as the MPM step (book Eqs. 4.8–4.18):
//!
//! a_i = (f_ext − f_int)_i / m_i, f_int,i = Σ_e σ_e ∂N_i/∂x · h_e,
//! v_i ← v_i + Δt a_i, Δu_i = Δt v_i, x_i ← x_i + Δu_i,
//! Δε_e = (Δu_{e+1} − Δu_e)/h_e, σ_e ← σ_e + E Δε_e or + (E − σ_e) Δε_e,
//! h_e ← h_e (1 + Δε_e).
//!
//! Items: [`UlfemMaterial`], [`Ulfem`].

use crate::error::{finite, Error, Result};
use crate::mpm::musl::{Constitutive, GravityRamp};

/// Material and loading of a ULFEM run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UlfemMaterial {
    /// Initial density ρ.
    pub density: f64,
    /// Young's modulus E.
    pub young: f64,
    /// Small- or large-strain update.
    pub constitutive: Constitutive,
    /// Gravitational acceleration along the axis.
    pub gravity: f64,
    /// If set, gravity ramps as in the MPM step ([`GravityRamp`], read at
    /// the ramp's time level): the dynamic reference of the column
    /// compaction (TLS paper §6.2).
    pub gravity_ramp: Option<GravityRamp>,
}

/// A 1D updated-Lagrangian P1 mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Ulfem {
    /// Initial node positions X_i.
    pub x0: Vec<f64>,
    /// Current node positions x_i.
    pub x: Vec<f64>,
    /// Node velocities.
    pub v: Vec<f64>,
    /// Element stresses σ_e.
    pub stress: Vec<f64>,
    /// Lumped node masses (constant).
    pub mass: Vec<f64>,
    young: f64,
    constitutive: Constitutive,
    gravity: f64,
    gravity_ramp: Option<GravityRamp>,
    fixed: Vec<usize>,
    /// Current time.
    pub time: f64,
}

impl Ulfem {
    /// `elements` equal elements on [0, length] with density ρ; the initial
    /// velocity is given per node; `fixed` lists the Dirichlet nodes.
    pub fn new(
        length: f64,
        elements: usize,
        material: UlfemMaterial,
        initial_velocity: impl Fn(f64) -> f64,
        fixed: Vec<usize>,
    ) -> Result<Self> {
        let UlfemMaterial {
            density,
            young,
            constitutive,
            gravity,
            gravity_ramp,
        } = material;
        if constitutive == Constitutive::NeoHookean {
            return Err(Error::InvalidArgument(
                "the ULFEM reference runs the book's incremental laws (Eqs. 4.15, 4.16), not the neo-Hookean one".into(),
            ));
        }
        finite("length", length)?;
        if length <= 0.0 || elements == 0 || density <= 0.0 || young <= 0.0 {
            return Err(Error::InvalidArgument(
                "ULFEM needs positive length, elements, density and E".into(),
            ));
        }
        let h = length / elements as f64;
        let x0: Vec<f64> = (0..=elements).map(|i| i as f64 * h).collect();
        let mut mass = vec![0.0; elements + 1];
        for e in 0..elements {
            mass[e] += 0.5 * density * h;
            mass[e + 1] += 0.5 * density * h;
        }
        if let Some(&f) = fixed.iter().find(|&&f| f > elements) {
            return Err(Error::InvalidArgument(format!(
                "fixed node {f} outside 0..={elements}"
            )));
        }
        let mut v: Vec<f64> = x0.iter().map(|&x| initial_velocity(x)).collect();
        for &f in &fixed {
            v[f] = 0.0;
        }
        Ok(Self {
            x: x0.clone(),
            x0,
            v,
            stress: vec![0.0; elements],
            mass,
            young,
            constitutive,
            gravity,
            gravity_ramp,
            fixed,
            time: 0.0,
        })
    }

    /// One Euler–Cromer step.
    pub fn step(&mut self, dt: f64) -> Result<()> {
        crate::mpm::check_time_step(dt)?;
        let n = self.x.len();
        let mut f = vec![0.0; n];
        for (e, s) in self.stress.iter().enumerate() {
            // ∫ σ ∂N/∂x dx over the element: −σ for the left node, +σ for the right.
            f[e] += *s;
            f[e + 1] -= *s;
        }
        let g = match self.gravity_ramp {
            Some(ramp) => self.gravity * ramp.fraction_at(ramp.read_time(self.time, dt)),
            None => self.gravity,
        };
        for ((v, fi), m) in self.v.iter_mut().zip(&f).zip(&self.mass) {
            *v += dt * (fi + m * g) / m;
        }
        for &k in &self.fixed {
            self.v[k] = 0.0;
        }
        let du: Vec<f64> = self.v.iter().map(|v| dt * v).collect();
        for e in 0..self.stress.len() {
            let h = self.x[e + 1] - self.x[e];
            let deps = (du[e + 1] - du[e]) / h;
            self.stress[e] += match self.constitutive {
                Constitutive::SmallStrain => self.young * deps,
                Constitutive::LargeStrain => (self.young - self.stress[e]) * deps,
                // Refused by `Ulfem::new`: the reference is incremental.
                Constitutive::NeoHookean => f64::NAN,
            };
        }
        for (x, d) in self.x.iter_mut().zip(&du) {
            *x += d;
        }
        self.time += dt;
        if self.x.windows(2).any(|w| w[1].is_nan() || w[1] <= w[0])
            || self.stress.iter().any(|s| !s.is_finite())
        {
            return Err(Error::BlowUp(format!(
                "ULFEM mesh inverted or non-finite at t = {}",
                self.time
            )));
        }
        Ok(())
    }

    /// The stress at a material point X (initial coordinate): linear
    /// interpolation between element mid-points, constant beyond the outer ones.
    pub fn stress_at(&self, x0: f64) -> f64 {
        let ne = self.stress.len();
        let h = self.x0[1] - self.x0[0];
        let s = (x0 / h - 0.5).clamp(0.0, (ne - 1) as f64);
        let k = (s.floor() as usize).min(ne.saturating_sub(2));
        if ne == 1 {
            return self.stress[0];
        }
        let t = s - k as f64;
        (1.0 - t) * self.stress[k] + t * self.stress[k + 1]
    }

    /// The displacement at a material point X by linear interpolation.
    pub fn displacement_at(&self, x0: f64) -> f64 {
        let h = self.x0[1] - self.x0[0];
        let k = ((x0 / h).floor() as usize).min(self.x0.len() - 2);
        let t = (x0 - self.x0[k]) / h;
        (1.0 - t) * (self.x[k] - self.x0[k]) + t * (self.x[k + 1] - self.x0[k + 1])
    }
}
