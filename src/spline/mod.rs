//! # B-splines
//!
//! Knot vectors ([`KnotVector`]), the Cox–de Boor recursion in its literal form
//! and in the span-at-once form ([`bspline`]), and the tensor-product 2D basis
//! ([`tensor`]). Book §4.3, Eqs. (4.19)–(4.23); thesis §6.1–6.2; TLS paper §4;
//! MLS paper Eqs. (1)–(5). Karamelo's boundary-modified uniform B-splines
//! ([`natural`], `--knots natural`; issue #36).
//!
//! Items: [`bspline`], [`knots`], [`natural`], [`tensor`].

pub mod bspline;
pub mod knots;
pub mod natural;
pub mod tensor;

pub use knots::KnotVector;
pub use natural::NaturalSplines;
pub use tensor::TensorBasis2d;
