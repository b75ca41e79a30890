//! # Sums over the lists of the Gauss points
//!
//! A reconstruction is linear in the data (MLS paper Eqs. 18–21 and 31):
//! f̃_g = Σ_p φ_gp f_p over the list (particle, φ_gp) of Gauss point g. Each
//! sum is a function of its own, not inlined into the loop over the Gauss
//! points, so that its accumulators stay in registers (inlined there, the
//! compiler kept them on the stack, a load and a store per value and list
//! entry). The entries are summed in list order.
//!
//! Two Gauss points are summed at once, consecutive in
//! [`storage_order`] ([`storage_pairs`]): each sum still adds its own list's
//! terms in list order from +0, so the values are those of one point at a
//! time, bit for bit, but the two chains of additions are independent, and
//! the processor overlaps them. One point at a time, each entry waited for
//! the previous entry's addition (issue #39).
//!
//! Items: `storage_pairs`, `gauss_point_values`, `gauss_point_momentum`
//! (private to the phases).

use crate::mpm2d::reconstruction::{storage_order, ShapeLists};

/// The Gauss points of [`storage_order`] two at a time, as (gx, gy) pairs:
/// points 0 and 1, then 2 and 3, of each cell (there are four per cell).
pub(super) fn storage_pairs(cells: usize) -> impl Iterator<Item = [(usize, usize); 2]> {
    let mut order = storage_order(cells);
    std::iter::from_fn(move || Some([order.next()?, order.next()?]))
}

/// The particles and φ_gp of Gauss point g's list.
#[inline(always)]
fn list<'a>(lists: ShapeLists<'a>, g: usize) -> (&'a [u32], &'a [f64]) {
    let entries = lists.start[g]..lists.end[g];
    (&lists.particle[entries.clone()], &lists.phi[entries])
}

/// Σ_p over the lists of Gauss points a and b at once: `add(q, φ_gp, d_p)`
/// adds one entry's term to a sum q started at +0, entry by entry in list
/// order for each point. While both lists have entries, one of each is
/// added per round; then the longer list's remaining entries.
#[inline(always)]
fn sum_two_lists<T, const N: usize>(
    lists: ShapeLists,
    [a, b]: [usize; 2],
    values: &[T],
    add: impl Fn([f64; N], f64, &T) -> [f64; N],
) -> [[f64; N]; 2] {
    let ((ka, pa), (kb, pb)) = (list(lists, a), list(lists, b));
    let common = ka.len().min(kb.len());
    let (mut qa, mut qb) = ([0.0; N], [0.0; N]);
    let a_entries = ka[..common].iter().zip(&pa[..common]);
    let b_entries = kb[..common].iter().zip(&pb[..common]);
    for ((&k, &phi), (&l, &psi)) in a_entries.zip(b_entries) {
        qa = add(qa, phi, &values[k as usize]);
        qb = add(qb, psi, &values[l as usize]);
    }
    for (&k, &phi) in ka[common..].iter().zip(&pa[common..]) {
        qa = add(qa, phi, &values[k as usize]);
    }
    for (&l, &psi) in kb[common..].iter().zip(&pb[common..]) {
        qb = add(qb, psi, &values[l as usize]);
    }
    [qa, qb]
}

/// The body of [`gauss_point_values`], inlined into its baseline and AVX2 copies.
#[inline(always)]
fn gauss_point_values_kernel(
    lists: ShapeLists,
    points: [usize; 2],
    values: &[[f64; 8]],
) -> [[f64; 8]; 2] {
    sum_two_lists(lists, points, values, |q, phi, d| {
        std::array::from_fn(|i| q[i] + phi * d[i])
    })
}

crate::dispatch::avx2_when_available! {
    /// Eqs. (18)–(21) at two Gauss points g: Σ_p φ_gp d_p for the eight
    /// values d_p = [ρ, ρv_x, ρv_y, ρb_x, ρb_y, σ_xx, σ_yy, σ_xy] of each
    /// particle. AVX2 where the processor has it ([`crate::dispatch`]).
    #[inline(never)]
    pub(super) fn gauss_point_values(lists: ShapeLists, points: [usize; 2], values: &[[f64; 8]]) -> [[f64; 8]; 2] = gauss_point_values_kernel;
}

/// Eq. (31) at two Gauss points g: (ρv)_g^L = Σ_p (φ_gp ρ_p) v_p^{t+1}
/// from [ρ_p, v_x, v_y] of each particle.
#[inline(never)]
pub(super) fn gauss_point_momentum(
    lists: ShapeLists,
    points: [usize; 2],
    values: &[[f64; 3]],
) -> [[f64; 2]; 2] {
    sum_two_lists(lists, points, values, |q, phi, &[rho, vx, vy]| {
        [q[0] + phi * rho * vx, q[1] + phi * rho * vy]
    })
}
