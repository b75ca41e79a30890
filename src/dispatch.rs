//! # One kernel, compiled twice: AVX2 when the processor has it
//!
//! hompm is built for the x86-64 baseline (SSE2), so that one binary runs
//! on every x86-64 processor. A few inner loops of the 2D step (the MLS
//! moment sums and shape functions, the Gauss-point sums of MLS paper
//! Eqs. 18–21) run about a third faster when the compiler may use the
//! 256-bit registers and three-operand forms of AVX2. `avx2_when_available!`
//! compiles one body twice, for the baseline and with AVX2 enabled, and
//! calls the AVX2 copy when the running processor has AVX2.
//!
//! The two copies compute the same bits. They are the same Rust source;
//! IEEE 754 fixes the result of every +, −, ×, ÷ and √ whatever the
//! instruction width; Rust never contracts a × b + c into a fused
//! multiply-add unless the source calls `mul_add`, and FMA is not among
//! the enabled features; and without `-ffast-math` the compiler may not
//! reorder a floating-point sum, so wider registers only hold independent
//! lanes. tests/spec/speed/dispatch.rs runs MLS steps both ways and
//! compares every bit (docs/conventions.md, "Floating-point determinism").
//!
//! [`force_portable`] makes every kernel take the baseline copy (for that
//! test, and for a user who wants to see the difference in time).
//!
//! The call of the AVX2 copy is one of the crate's two places with `unsafe`
//! code (the other is the allocator of [`crate::placement`]): calling a
//! function compiled for a feature the processor may lack is undefined, so
//! the macro calls it only after `is_x86_feature_detected!` has read the
//! feature from the processor.
//!
//! Items: [`force_portable`], [`avx2_in_use`] (and the crate's macro
//! `avx2_when_available!`).

use std::sync::atomic::{AtomicBool, Ordering};

/// Set by [`force_portable`].
static PORTABLE_ONLY: AtomicBool = AtomicBool::new(false);

/// From now on, every kernel of `avx2_when_available!` takes its
/// baseline copy (`true`), or its AVX2 copy where the processor has AVX2
/// (`false`, the default). Process-wide; the results are the same bits
/// either way, only the time differs.
pub fn force_portable(portable: bool) {
    PORTABLE_ONLY.store(portable, Ordering::Relaxed);
}

/// Whether the kernels of `avx2_when_available!` take their AVX2 copy:
/// the processor has AVX2 and [`force_portable`] is off.
#[inline]
pub fn avx2_in_use() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        !PORTABLE_ONLY.load(Ordering::Relaxed) && std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Defines a free function `name` that runs the kernel `kernel` (a function
/// of the same module with the same signature, marked `#[inline(always)]`),
/// compiled twice: for the target's baseline and, on x86-64, with AVX2
/// enabled; a call runs the AVX2 copy when [`avx2_in_use`] (module docs:
/// the same bits either way). The kernel stays an ordinary function, which
/// rustfmt formats and cargo-mutants mutates. The arguments must be plain
/// names; const generic parameters are passed on to the kernel.
///
/// ```ignore
/// #[inline(always)]
/// fn dot_kernel(a: &[f64], b: &[f64]) -> f64 {
///     a.iter().zip(b).fold(0.0, |s, (x, y)| s + x * y)
/// }
/// crate::dispatch::avx2_when_available! {
///     /// Σ_k a_k b_k, in index order.
///     fn dot(a: &[f64], b: &[f64]) -> f64 = dot_kernel;
/// }
/// ```
macro_rules! avx2_when_available {
    (
        $(#[$attr:meta])*
        $vis:vis fn $name:ident $(<$(const $g:ident: $gt:ty),*>)?
            ($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)? = $kernel:ident;
    ) => {
        $(#[$attr])*
        $vis fn $name $(<$(const $g: $gt),*>)? ($($arg: $ty),*) $(-> $ret)? {
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx2")]
                fn with_avx2 $(<$(const $g: $gt),*>)? ($($arg: $ty),*) $(-> $ret)? {
                    $kernel $(::<$($g),*>)? ($($arg),*)
                }
                if $crate::dispatch::avx2_in_use() {
                    // SAFETY: `with_avx2` needs AVX2, and avx2_in_use has
                    // just read it from the processor (CPUID).
                    return unsafe { with_avx2 $(::<$($g),*>)? ($($arg),*) };
                }
            }
            $kernel $(::<$($g),*>)? ($($arg),*)
        }
    };
}
pub(crate) use avx2_when_available;
