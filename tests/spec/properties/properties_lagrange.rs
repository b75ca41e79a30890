//! Lagrange P1/P2 (thesis §5.1–5.2). (The 2D tensor B-spline basis, MLS
//! paper Eqs. 4–5, is tested with the other B-spline properties in
//! properties_bspline.rs.)

use approx::assert_relative_eq;
use hompm::basis::Basis1d;
use hompm::lagrange::{reference_shape_functions, LagrangeBasis, LagrangeOrder};
use hompm::spline::KnotVector;
use proptest::prelude::*;

/// N̂_i(ξ_j) = δ_ij at the reference nodes (thesis §5.1 and §5.2).
#[test]
fn reference_shape_functions_are_nodal() {
    for (order, nodes) in [
        (LagrangeOrder::Linear, vec![0.0, 1.0]),
        (LagrangeOrder::Quadratic, vec![0.0, 0.5, 1.0]),
    ] {
        for (j, &xi) in nodes.iter().enumerate() {
            let n = reference_shape_functions(order, xi);
            for (i, v) in n.iter().enumerate() {
                assert_eq!(*v, if i == j { 1.0 } else { 0.0 });
            }
        }
    }
}

/// Thesis §5.2: the P2 end-node functions are negative inside the element,
/// with minimum −1/8 at ξ = 1/4 (and 3/4 for N̂_3).
#[test]
fn quadratic_end_functions_take_negative_values() {
    let n = reference_shape_functions(LagrangeOrder::Quadratic, 0.75);
    assert_relative_eq!(n[0], -0.125, epsilon = 1e-15);
    let n = reference_shape_functions(LagrangeOrder::Quadratic, 0.25);
    assert_relative_eq!(n[2], -0.125, epsilon = 1e-15);
    let min = (0..=1000)
        .map(|k| reference_shape_functions(LagrangeOrder::Quadratic, k as f64 / 1000.0)[0])
        .fold(f64::INFINITY, f64::min);
    assert_relative_eq!(min, -0.125, epsilon = 1e-15);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Partition of unity, zero-sum gradients and finite-difference gradients
    /// for P1 and P2 meshes (thesis §5.1–5.2).
    ///
    /// Map rows: tls-§3.2-1, thesis-§5.1-2 — one basis, printed in two seeds.
    #[test]
    fn lagrange_partition_of_unity_and_gradients(elements in 1usize..20, quadratic in any::<bool>(),
                                                 a in -3.0f64..3.0, len in 0.5f64..5.0, t in 0.0f64..=1.0) {
        let order = if quadratic { LagrangeOrder::Quadratic } else { LagrangeOrder::Linear };
        let basis = LagrangeBasis::new(a, a + len, elements, order).unwrap();
        let x = a + t * len;
        let loc = basis.local(x, 1).unwrap();
        prop_assert!((loc.values().iter().sum::<f64>() - 1.0).abs() < 1e-13);
        let gscale = loc.gradients().iter().map(|g| g.abs()).fold(1.0, f64::max);
        prop_assert!(loc.gradients().iter().sum::<f64>().abs() < 1e-12 * gscale);
        let h = 1e-7 * len;
        let k = basis.element_of(x).unwrap();
        let (lo, hi) = basis.cells()[k];
        if x - h > lo && x + h < hi {
            let up = basis.local(x + h, 0).unwrap();
            let dn = basis.local(x - h, 0).unwrap();
            for j in 0..loc.values().len() {
                let fd = (up.values()[j] - dn.values()[j]) / (2.0 * h);
                prop_assert!((fd - loc.gradients()[j]).abs() < 1e-5 * gscale);
            }
        }
    }

}

#[test]
fn lagrange_rejects_bad_input() {
    assert!(LagrangeBasis::new(0.0, 0.0, 3, LagrangeOrder::Linear).is_err());
    assert!(LagrangeBasis::new(0.0, 1.0, 0, LagrangeOrder::Linear).is_err());
    // Element sizes double precision cannot divide by, or that overflow.
    assert!(LagrangeBasis::new(0.0, 5e-324, 1, LagrangeOrder::Linear).is_err());
    assert!(LagrangeBasis::new(-1e308, 1e308, 4, LagrangeOrder::Linear).is_err());
    let b = LagrangeBasis::new(0.0, 1.0, 3, LagrangeOrder::Quadratic).unwrap();
    assert!(b.local(1.01, 0).is_err());
    assert!(b.local(f64::NAN, 0).is_err());
    let (mut v, mut g) = ([0.0; 3], [0.0; 3]);
    assert!(matches!(
        b.evaluate_fixed::<3>(1.01, &mut v, &mut g),
        Some(Err(_))
    ));
    assert!(matches!(
        b.evaluate_fixed::<3>(f64::NAN, &mut v, &mut g),
        Some(Err(_))
    ));
    assert_eq!(b.num_basis(), 7);
    assert_eq!(
        KnotVector::open_uniform(0.0, 1.0, 3, 2)
            .unwrap()
            .num_basis(),
        5
    );
}

proptest! {
    /// Thesis §5.1–5.2 as the engine evaluates them: `evaluate_into` gives
    /// bitwise the numbers of `Basis1d::local` (N_i(x) = N̂_i(T⁻¹(x)),
    /// ∇N_i = N̂_i'(ξ)/h), on a shifted domain, and the global functions are
    /// nodal at `nodes()`: N_i(x_j) = δ_ij.
    #[test]
    fn engine_evaluation_is_the_specification_and_nodal_on_any_domain(
        elements in 1usize..12,
        quadratic in any::<bool>(),
        a in -3.0..3.0f64,
        length in 0.5..4.0f64,
        t in 0.0..=1.0f64,
    ) {
        let order = if quadratic { LagrangeOrder::Quadratic } else { LagrangeOrder::Linear };
        let basis = LagrangeBasis::new(a, a + length, elements, order).unwrap();
        prop_assert_eq!(basis.elements(), elements);
        prop_assert_eq!(basis.degree(), if quadratic { 2 } else { 1 });
        let x = a + t * length;
        let h = length / elements as f64;
        let k = (((x - a) / h) as usize).min(elements - 1);
        prop_assert_eq!(basis.element_of(x).unwrap(), k);
        let local = basis.local(x, 1).unwrap();
        let (mut values, mut gradients) = ([0.0; 3], [0.0; 3]);
        let first = basis.evaluate_into(x, &mut values, &mut gradients).unwrap();
        let w = basis.degree() + 1;
        prop_assert_eq!(first, local.first);
        // The step's batch fill: the width fixed at compile time, the same
        // bits; a width the basis does not have is declined.
        let (mut v2, mut g2, mut v3, mut g3) = ([0.0; 2], [0.0; 2], [0.0; 3], [0.0; 3]);
        let fixed2 = basis.evaluate_fixed::<2>(x, &mut v2, &mut g2);
        let fixed3 = basis.evaluate_fixed::<3>(x, &mut v3, &mut g3);
        let (fixed, other, fv, fg) = if quadratic {
            (fixed3, fixed2, &v3[..], &g3[..])
        } else {
            (fixed2, fixed3, &v2[..], &g2[..])
        };
        prop_assert!(other.is_none());
        prop_assert_eq!(fixed.unwrap().unwrap(), first);
        prop_assert_eq!(fv.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), values[..w].iter().map(|v| v.to_bits()).collect::<Vec<_>>());
        prop_assert_eq!(fg.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), gradients[..w].iter().map(|v| v.to_bits()).collect::<Vec<_>>());
        prop_assert_eq!(&values[..w], local.values());
        prop_assert_eq!(&gradients[..w], &local.derivatives[1][..]);
        // Second derivatives: N̂'' = (4, −8, 4) for P2 and 0 for P1, over h²,
        // against a central difference of the gradients inside the element.
        let second = basis.local(x, 2).unwrap().derivatives[2].clone();
        let (lo, hi) = (a + k as f64 * h, a + (k + 1) as f64 * h);
        let (y, d) = (lo + 0.5 * (hi - lo), 1e-4 * h);
        let (mut g_minus, mut g_plus) = ([0.0; 3], [0.0; 3]);
        basis.evaluate_into(y - d, &mut values, &mut g_minus).unwrap();
        basis.evaluate_into(y + d, &mut values, &mut g_plus).unwrap();
        for i in 0..w {
            let fd = (g_plus[i] - g_minus[i]) / (2.0 * d);
            prop_assert!((second[i] - fd).abs() <= 1e-6 * (1.0 + fd.abs()), "N''_{i} = {} vs {fd}", second[i]);
        }
        // The gradient jumps at every interior element boundary a + k h.
        let breaks = basis.gradient_breaks();
        prop_assert_eq!(breaks.len(), elements - 1);
        for (j, b) in breaks.iter().enumerate() {
            prop_assert!((b - (a + (j + 1) as f64 * h)).abs() <= 1e-12 * (1.0 + a.abs() + length));
        }
        let nodes = basis.nodes();
        prop_assert_eq!(nodes.len(), basis.num_basis());
        for (j, &xj) in nodes.iter().enumerate() {
            let first = basis.evaluate_into(xj, &mut values, &mut gradients).unwrap();
            for (i, v) in values[..w].iter().enumerate() {
                let delta = if first + i == j { 1.0 } else { 0.0 };
                prop_assert!((v - delta).abs() < 1e-12, "N_{}({xj}) = {v}", first + i);
            }
        }
    }
}

proptest! {
    /// Bilinear MPM's paired basis (MLS paper Eqs. 4–5): at a 2D point,
    /// `evaluate_pair_of_width` gives each axis bit for bit what
    /// `evaluate_of_width` gives that coordinate, for P1 (paired lanes) and
    /// P2 (axis by axis), ends and nodes included; a coordinate outside
    /// [a, b] is the scalar path's error.
    #[test]
    fn the_paired_basis_is_each_axis_basis_bit_for_bit(
        elements in 1usize..40,
        quadratic in any::<bool>(),
        a in -3.0..3.0f64,
        length in 0.5..4.0f64,
        t in prop_oneof![0.0..=1.0f64, Just(0.0), Just(1.0)],
        s in prop_oneof![0.0..=1.0f64, Just(0.0), Just(1.0)],
        outside in 0usize..3,
    ) {
        let order = if quadratic { LagrangeOrder::Quadratic } else { LagrangeOrder::Linear };
        let basis = LagrangeBasis::new(a, a + length, elements, order).unwrap();
        let at = |t: f64| (a + t * length).min(a + length);
        let mut x = [at(t), at(s)];
        if outside < 2 {
            x[outside] = a + length * 1.5;
        }
        fn both<const W: usize>(basis: &LagrangeBasis, x: [f64; 2]) -> (String, String) {
            let (mut v, mut g) = ([[0.0; W]; 2], [[0.0; W]; 2]);
            let paired = basis.evaluate_pair_of_width::<W>(x, &mut v, &mut g);
            let paired = format!("{paired:?} {:?} {:?}", v.map(|r| r.map(f64::to_bits)), g.map(|r| r.map(f64::to_bits)));
            let (mut v, mut g) = ([[0.0; W]; 2], [[0.0; W]; 2]);
            let scalar = basis
                .evaluate_of_width::<W>(x[0], &mut v[0], &mut g[0])
                .and_then(|fx| basis.evaluate_of_width::<W>(x[1], &mut v[1], &mut g[1]).map(|fy| [fx, fy]));
            let scalar = format!("{scalar:?} {:?} {:?}", v.map(|r| r.map(f64::to_bits)), g.map(|r| r.map(f64::to_bits)));
            (paired, scalar)
        }
        let (paired, scalar) = if quadratic { both::<3>(&basis, x) } else { both::<2>(&basis, x) };
        prop_assert_eq!(paired, scalar);
    }
}
