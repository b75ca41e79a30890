//! # Sums over the list of one Gauss point
//!
//! A reconstruction is linear in the data (MLS paper Eqs. 18–21 and 31):
//! f̃_g = Σ_p φ_gp f_p over the list (particle, φ_gp) of Gauss point g. Each
//! sum is a function of its own, not inlined into the loop over the Gauss
//! points, so that its accumulators stay in registers (inlined there, the
//! compiler kept them on the stack, a load and a store per value and list
//! entry). The entries are summed in list order.
//!
//! Items: `gauss_point_values`, `gauss_point_momentum` (private to the
//! phases).

use crate::mpm2d::reconstruction::ShapeLists;

/// The entries (particle, φ_gp) of Gauss point g's list.
#[inline(always)]
fn list<'a>(lists: ShapeLists<'a>, g: usize) -> impl Iterator<Item = (&'a u32, &'a f64)> {
    let entries = lists.start[g]..lists.end[g];
    lists.particle[entries.clone()]
        .iter()
        .zip(&lists.phi[entries])
}

/// The body of [`gauss_point_values`], inlined into its baseline and AVX2 copies.
#[inline(always)]
fn gauss_point_values_kernel(lists: ShapeLists, g: usize, values: &[[f64; 8]]) -> [f64; 8] {
    let mut q = [0.0; 8];
    for (&k, &phi) in list(lists, g) {
        let d = &values[k as usize];
        q = std::array::from_fn(|i| q[i] + phi * d[i]);
    }
    q
}

crate::dispatch::avx2_when_available! {
    /// Eqs. (18)–(21) at Gauss point g: Σ_p φ_gp d_p for the eight values
    /// d_p = [ρ, ρv_x, ρv_y, ρb_x, ρb_y, σ_xx, σ_yy, σ_xy] of each particle.
    /// AVX2 where the processor has it ([`crate::dispatch`]).
    #[inline(never)]
    pub(super) fn gauss_point_values(lists: ShapeLists, g: usize, values: &[[f64; 8]]) -> [f64; 8] = gauss_point_values_kernel;
}

/// Eq. (31) at Gauss point g: (ρv)_g^L = Σ_p (φ_gp ρ_p) v_p^{t+1} from
/// [ρ_p, v_x, v_y] of each particle.
#[inline(never)]
pub(super) fn gauss_point_momentum(lists: ShapeLists, g: usize, values: &[[f64; 3]]) -> [f64; 2] {
    let mut q = [0.0; 2];
    for (&k, &phi) in list(lists, g) {
        let [rho, vx, vy] = values[k as usize];
        q[0] += phi * rho * vx;
        q[1] += phi * rho * vy;
    }
    q
}
