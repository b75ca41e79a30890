//! # The 2D material point method of the MLS paper
//!
//! Bilinear MPM, B-spline MPM and B-spline MPM with moving least squares on
//! the unit square, as far as the MLS paper's aligned vibration needs and no
//! further: MLS paper Eqs. (4)–(5) (the tensor-product basis, [`grid`]),
//! (10)–(17) at the Gauss points ([`mls`]), the TLS paper's §5.2–5.5 on
//! rectangular cells ([`tls`], its normal matrices inverted by [`lu`]) and
//! hompm's partition-of-unity blend of it ([`pu_tls`]), all behind one interface
//! ([`reconstruction`]) and registered as mappings ([`mapping`]),
//! (18)–(37) (one step, [`step`], its phases in [`phases`], its buffers in
//! [`workspace`]), watched by the 1D run's stability monitor ([`monitor`]),
//! (40)–(41) (the neo-Hookean solid, [`material`]). The particles are a
//! struct of arrays ([`particles`]).
//!
//! Everything one-dimensional is reused from the 1D engine: each axis of the
//! grid is a [`crate::mpm::grid::Grid`] (P1 Lagrange or open-uniform
//! B-splines), and the 2D functions are products of two 1D stencils.

pub mod grid;
pub mod lu;
pub mod mapping;
pub mod material;
pub mod mls;
pub mod monitor;
pub mod particles;
pub mod phases;
pub mod pu_tls;
pub mod reconstruction;
pub mod step;
pub mod tls;
pub mod workspace;

pub use grid::{Basis2d, Grid2d};
pub use material::NeoHookean;
pub use particles::Particles2d;
pub use step::{BodyForce2d, Conservation2d, Formulation, Mapping2d, Settings2d, Simulation2d};
