//! Issue #39: the lean steps that hompm's speed is measured against
//! compute bit for bit what hompm's step computes, so a ratio of their
//! times is a ratio of the same work; and the fixed-size inverse of the
//! TLS normal matrix gives nalgebra's bits (small_lu.rs); the kernels
//! compiled for AVX2 give the baseline's bits (dispatch.rs); the
//! reconstructed 2D step's sums two Gauss points at a time give the bits of
//! one at a time (reconstructed_2d.rs); the allocator that staggers large
//! arrays within the page changes where they start, not what the binary
//! computes (placement.rs).

mod dispatch;
mod fused_step;
mod lean_2d;
mod lean_p1;
#[path = "../../../benches/lean/mpm2d.rs"]
#[allow(dead_code)]
mod mpm2d;
#[path = "../../../benches/lean/p1.rs"]
#[allow(dead_code)]
mod p1;
mod placement;
mod reconstructed_2d;
mod small_lu;
mod step_2d;
