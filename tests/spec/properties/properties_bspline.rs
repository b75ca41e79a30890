//! Property tests of the B-spline basis: book Eqs. (4.19)–(4.23), thesis §6.1.

use crate::common;

use approx::assert_relative_eq;
use common::{general_knots, open_knots, sample_points};
use hompm::basis::Basis1d;
use hompm::spline::bspline::{cox_de_boor, cox_de_boor_derivative};
use hompm::spline::{KnotVector, TensorBasis2d};
use proptest::prelude::*;

fn fractions() -> impl Strategy<Value = Vec<f64>> {
    proptest::collection::vec(0.0f64..=1.0, 1..8)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Book Eq. (4.21) and (4.22): Σ φ_i = 1 and φ_i ≥ 0 on the domain,
    /// for the literal recursion and for the span evaluator.
    ///
    /// Map rows: book-4.19, book-4.21, book-4.22, tls-§4-3, thesis-§6.1-2 — the B-spline properties of three seeds, checked on random knot vectors.
    #[test]
    fn partition_of_unity_and_non_negativity(kv in general_knots(), f in fractions()) {
        for x in sample_points(&kv, &f) {
            let fast = kv.dense_values(x).unwrap();
            let literal: Vec<f64> = (0..kv.num_basis())
                .map(|i| cox_de_boor(&kv, i, kv.degree(), x).unwrap())
                .collect();
            prop_assert!((fast.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            prop_assert!((literal.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            prop_assert!(fast.iter().all(|&v| v >= -1e-15));
            prop_assert!(literal.iter().all(|&v| v >= 0.0));
        }
    }

    /// The span evaluator equals the literal Cox–de Boor recursion, values and
    /// first derivatives (Eq. 4.23), on open knots with repeated interior knots.
    ///
    /// Map rows: book-4.20, tls-§4-1, thesis-§6.1-1, mls-1, mls-2 — the Cox–de Boor recursion, printed in four seeds.
    #[test]
    fn span_evaluator_matches_literal_recursion(kv in open_knots(6, 0.02), f in fractions()) {
        let p = kv.degree();
        for x in sample_points(&kv, &f) {
            let local = kv.local_basis(x, 1).unwrap();
            let values = local.dense(0, kv.num_basis());
            let ders = local.dense(1, kv.num_basis());
            for i in 0..kv.num_basis() {
                let v = cox_de_boor(&kv, i, p, x).unwrap();
                let d = cox_de_boor_derivative(&kv, i, p, x).unwrap();
                prop_assert!((values[i] - v).abs() < 1e-12, "value {i} at {x}: {} vs {v}", values[i]);
                prop_assert!((ders[i] - d).abs() < 1e-9 * (1.0 + d.abs()), "derivative {i} at {x}: {} vs {d}", ders[i]);
            }
        }
    }

    /// The MPM step's evaluator (values and gradients into slices, NURBS
    /// A2.2 with A2.3 at k = 1) gives bit for bit the numbers of the general
    /// span evaluator, on any knots, also when its scratch was last used for
    /// another degree or point (A2.2 writes every entry before reading it);
    /// so does its fixed-width copy for p = 1, 2, 3, the step's hot path.
    #[test]
    fn mpm_evaluator_is_bitwise_the_span_evaluator(kv in general_knots(), other in open_knots(6, 0.02),
                                                   f in fractions()) {
        let mut scratch = hompm::spline::bspline::SpanScratch::default();
        for basis in [&other, &kv, &other] {
            let w = basis.degree() + 1;
            for x in sample_points(basis, &f) {
                let (mut v, mut g) = (vec![f64::NAN; w], vec![f64::NAN; w]);
                let first = basis.values_and_gradients_into(x, &mut scratch, &mut v, &mut g).unwrap();
                let local = basis.local_basis(x, 1).unwrap();
                prop_assert_eq!(first, local.first);
                for j in 0..w {
                    prop_assert_eq!(v[j].to_bits(), local.values()[j].to_bits(), "value {} at {}", j, x);
                    prop_assert_eq!(g[j].to_bits(), local.gradients()[j].to_bits(), "gradient {} at {}", j, x);
                }
                // The fixed-width copy the step runs for p = 1, 2, 3.
                let fixed = match w {
                    2 => Some(fixed_width::<2>(basis, x)),
                    3 => Some(fixed_width::<3>(basis, x)),
                    4 => Some(fixed_width::<4>(basis, x)),
                    _ => None,
                };
                if let Some((first_fixed, vf, gf)) = fixed {
                    prop_assert_eq!(first_fixed, local.first);
                    for j in 0..w {
                        prop_assert_eq!(vf[j].to_bits(), v[j].to_bits(), "fixed value {} at {}", j, x);
                        prop_assert_eq!(gf[j].to_bits(), g[j].to_bits(), "fixed gradient {} at {}", j, x);
                    }
                }
            }
        }
    }

    /// Property 2 of book §4.3: φ_{i,p} vanishes outside [ξ_i, ξ_{i+p+1}].
    #[test]
    fn compact_support(kv in general_knots(), f in fractions()) {
        let t = kv.knots().to_vec();
        let p = kv.degree();
        for x in sample_points(&kv, &f) {
            for i in 0..kv.num_basis() {
                if x < t[i] || x > t[i + p + 1] {
                    prop_assert_eq!(cox_de_boor(&kv, i, p, x).unwrap(), 0.0);
                }
            }
            let local = kv.local_basis(x, 0).unwrap();
            for j in 0..=p {
                let i = local.first + j;
                prop_assert!(t[i] <= x && x <= t[i + p + 1]);
            }
        }
    }

    /// Σ φ_i' = 0 (derivative of the partition of unity), and φ_i' matches a
    /// central difference away from the knots.
    #[test]
    fn derivatives_sum_to_zero_and_match_finite_differences(kv in open_knots(6, 0.05), f in fractions()) {
        let (a, b) = kv.domain();
        let h = 1e-6 * (b - a);
        for x in sample_points(&kv, &f) {
            let d = kv.dense_derivatives(x).unwrap();
            let scale = d.iter().map(|v| v.abs()).fold(1.0, f64::max);
            prop_assert!(d.iter().sum::<f64>().abs() < 1e-10 * scale);
            let near_knot = kv.knots().iter().any(|k| (x - k).abs() < 1e3 * h);
            if near_knot { continue; }
            let plus = kv.dense_values(x + h).unwrap();
            let minus = kv.dense_values(x - h).unwrap();
            for i in 0..kv.num_basis() {
                let fd = (plus[i] - minus[i]) / (2.0 * h);
                prop_assert!((fd - d[i]).abs() < 1e-5 * scale, "fd {fd} vs {}", d[i]);
            }
        }
    }

    /// Thesis §6.1 and Fig. 6.2: across an interior knot of multiplicity k ≤ p,
    /// the basis is C^{p−k}: derivatives of order 0..=p−k have equal one-sided limits.
    #[test]
    fn continuity_across_repeated_knots(kv in open_knots(6, 0.05)) {
        let p = kv.degree();
        let (a, b) = kv.domain();
        for (knot, k) in kv.breakpoints() {
            if knot <= a || knot >= b || k > p { continue; }
            let order = p - k;
            // One-sided limits: the polynomial piece of the span ending at the
            // knot, evaluated at the knot, against the span starting there.
            let right_span = kv.find_span(knot).unwrap();
            let left_span = (0..right_span).rev().find(|&s| kv.knots()[s] < kv.knots()[s + 1]).unwrap();
            let left = kv.local_basis_on_span(left_span, knot, order).unwrap();
            let right = kv.local_basis(knot, order).unwrap();
            for j in 0..=order {
                let l = left.dense(j, kv.num_basis());
                let r = right.dense(j, kv.num_basis());
                let scale = r.iter().chain(&l).map(|v| v.abs()).fold(1.0, f64::max);
                for i in 0..kv.num_basis() {
                    prop_assert!((l[i] - r[i]).abs() < 1e-9 * scale,
                        "derivative {j} of φ_{i} jumps at knot {knot} (multiplicity {k}, p = {p}): {} vs {}", l[i], r[i]);
                }
            }
            // …and no smoother: derivative p−k+1 jumps for some function.
            let j = order + 1;
            let l = kv.local_basis_on_span(left_span, knot, j).unwrap().dense(j, kv.num_basis());
            let r = kv.local_basis(knot, j).unwrap().dense(j, kv.num_basis());
            let scale = r.iter().chain(&l).map(|v| v.abs()).fold(1.0, f64::max);
            prop_assert!(l.iter().zip(&r).any(|(u, v)| (u - v).abs() > 1e-6 * scale),
                "derivative {j} is continuous at a knot of multiplicity {k}, p = {p}");
        }
    }

    /// An open knot vector interpolates at both ends: φ_1(a) = 1, φ_n(b) = 1.
    #[test]
    fn open_knots_interpolate_at_both_ends(kv in open_knots(6, 0.02)) {
        let (a, b) = kv.domain();
        let n = kv.num_basis();
        let left = kv.dense_values(a).unwrap();
        let right = kv.dense_values(b).unwrap();
        // Exactly 1 up to one rounding of a·(1/a) in the triangular scheme.
        prop_assert!((left[0] - 1.0).abs() <= 4.0 * f64::EPSILON);
        prop_assert!((right[n - 1] - 1.0).abs() <= 4.0 * f64::EPSILON);
    }
}

/// Book Eq. (4.23) has a minus between its terms; the MLS paper's Eq. (3)
/// prints a plus. Central differences decide for the minus
/// (docs/conventions.md, "Sign of the derivative").
///
/// Map rows: book-4.23, tls-§4-2, mls-3 — one derivative, printed in three seeds (one with the wrong sign).
#[test]
fn derivative_sign_is_minus() {
    let kv = KnotVector::new(vec![0.0, 0.0, 0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0, 1.0, 1.0], 2).unwrap();
    let t = kv.knots();
    let p = 2.0;
    let (x, h) = (0.5, 1e-6);
    for i in 0..kv.num_basis() {
        let fd = (cox_de_boor(&kv, i, 2, x + h).unwrap() - cox_de_boor(&kv, i, 2, x - h).unwrap())
            / (2.0 * h);
        let a = if t[i + 2] > t[i] {
            p / (t[i + 2] - t[i])
        } else {
            0.0
        };
        let b = if t[i + 3] > t[i + 1] {
            p / (t[i + 3] - t[i + 1])
        } else {
            0.0
        };
        let lo = cox_de_boor(&kv, i, 1, x).unwrap();
        let hi = cox_de_boor(&kv, i + 1, 1, x).unwrap();
        let minus = a * lo - b * hi;
        let plus = a * lo + b * hi;
        assert_relative_eq!(minus, fd, epsilon = 1e-6);
        if hi != 0.0 {
            assert!(
                (plus - fd).abs() > 0.1,
                "the '+' form would also fit for φ_{i}"
            );
        }
    }
}

/// Thesis §6.1: for p = 1 on an open uniform knot vector, the B-splines are the
/// P1 hat functions of thesis §5.1.
#[test]
fn linear_bsplines_are_hat_functions() {
    use hompm::lagrange::{LagrangeBasis, LagrangeOrder};
    let kv = KnotVector::open_uniform(0.0, 2.0, 5, 1).unwrap();
    let p1 = LagrangeBasis::new(0.0, 2.0, 5, LagrangeOrder::Linear).unwrap();
    for k in 0..=40 {
        let x = 2.0 * k as f64 / 40.0;
        let a = kv.local(x, 1).unwrap();
        let b = p1.local(x, 1).unwrap();
        for (u, v) in a.dense(0, 6).iter().zip(b.dense(0, 6)) {
            assert_relative_eq!(*u, v, epsilon = 1e-14);
        }
        for (u, v) in a.dense(1, 6).iter().zip(b.dense(1, 6)) {
            assert_relative_eq!(*u, v, epsilon = 1e-12);
        }
    }
}

/// Validation: every malformed input is a typed error, never a panic.
#[test]
fn malformed_knot_vectors_are_rejected() {
    use hompm::Error;
    let bad = [
        (vec![], 0),
        (vec![0.0, 1.0, 0.5, 2.0], 1),
        (vec![0.0, f64::NAN, 1.0], 0),
        (vec![0.0, f64::INFINITY], 0),
        (vec![0.0, 0.0, 1.0, 1.0], 3),
        (vec![0.0, 0.0, 0.0, 0.0], 1),
        (vec![0.0, 0.0, 0.5, 0.5, 0.5, 1.0, 1.0], 1),
        (vec![0.0, 0.0, 0.0, 1.0, 1.0], 1),
    ];
    for (knots, p) in bad {
        let r = KnotVector::new(knots.clone(), p);
        assert!(r.is_err(), "{knots:?} with p = {p} was accepted");
    }
    // Knots that double precision cannot divide by (the reciprocal of a
    // subnormal span overflows) or whose domain length overflows are refused
    // rather than evaluated to inf/NaN (issue #13's reproducers); a tiny but
    // normal span is fine.
    for (knots, p) in [
        (vec![0.0, 0.0, 5e-324, 5e-324], 1),
        (vec![-1e308, -1e308, 1e308, 1e308], 1),
        (vec![0.0, 1e308, 1.7e308, 1.7e308], 0),
    ] {
        assert!(
            matches!(
                KnotVector::new(knots.clone(), p),
                Err(Error::InvalidKnots(_))
            ),
            "{knots:?} with p = {p} was accepted"
        );
    }
    let tiny = KnotVector::new(vec![0.0, 0.0, 0.0, 1e-300, 1.0, 1.0, 1.0], 2).unwrap();
    let v = tiny.dense_values(1e-301).unwrap();
    assert!(v.iter().all(|x| x.is_finite()) && (v.iter().sum::<f64>() - 1.0).abs() < 1e-15);
    assert!(matches!(
        KnotVector::open_uniform(1.0, 1.0, 3, 2),
        Err(Error::InvalidKnots(_))
    ));
    assert!(matches!(
        KnotVector::open_uniform(0.0, 1.0, 0, 2),
        Err(Error::InvalidArgument(_))
    ));
    let kv = KnotVector::open_uniform(0.0, 1.0, 4, 2).unwrap();
    assert!(matches!(
        kv.local_basis(1.5, 0),
        Err(Error::OutsideDomain { .. })
    ));
    assert!(matches!(
        kv.local_basis(f64::NAN, 0),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        cox_de_boor(&kv, 99, 2, 0.5),
        Err(Error::InvalidArgument(_))
    ));
    assert!(matches!(
        cox_de_boor(&kv, 0, 3, 0.5),
        Err(Error::InvalidDegree(_))
    ));
}

/// Book Eq. (4.23) applied k times, literally: the k-th derivative of
/// φ_{i,p} from the (k−1)-th derivatives of φ_{i,p−1} and φ_{i+1,p−1}, with
/// the 0/0 := 0 convention of the recursion.
fn literal_derivative(kv: &KnotVector, i: usize, p: usize, k: usize, x: f64) -> f64 {
    if k == 0 {
        return cox_de_boor(kv, i, p, x).unwrap();
    }
    let t = kv.knots();
    let pf = p as f64;
    let mut d = 0.0;
    if t[i + p] > t[i] {
        d += pf / (t[i + p] - t[i]) * literal_derivative(kv, i, p - 1, k - 1, x);
    }
    if t[i + p + 1] > t[i + 1] {
        d -= pf / (t[i + p + 1] - t[i + 1]) * literal_derivative(kv, i + 1, p - 1, k - 1, x);
    }
    d
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Every derivative up to order p of the span evaluator (NURBS Book
    /// A2.3) equals Eq. (4.23) applied repeatedly, on non-uniform knots with
    /// repeated interior knots.
    #[test]
    fn all_derivatives_match_the_repeated_literal_formula(kv in open_knots(6, 0.05), f in fractions()) {
        let p = kv.degree();
        for x in sample_points(&kv, &f) {
            let loc = kv.local_basis(x, p).unwrap();
            for k in 0..=p {
                let fast = loc.dense(k, kv.num_basis());
                let literal: Vec<f64> = (0..kv.num_basis())
                    .map(|i| literal_derivative(&kv, i, p, k, x))
                    .collect();
                let scale = literal.iter().map(|v| v.abs()).fold(1.0, f64::max);
                for i in 0..kv.num_basis() {
                    prop_assert!((fast[i] - literal[i]).abs() <= 1e-9 * scale,
                        "d^{k} φ_{i} at {x} (p = {p}): {} vs {}", fast[i], literal[i]);
                }
            }
        }
    }
}

/// The literal recursion refuses an index past the last function, and the
/// closed-span evaluator refuses spans that are empty or outside the
/// domain and points outside the span, but accepts the span's right end.
#[test]
fn out_of_range_indices_spans_and_points_are_refused() {
    let kv = KnotVector::new(vec![0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 3.0, 3.0, 3.0], 2).unwrap();
    let n = kv.num_basis();
    assert!(cox_de_boor(&kv, n - 1, 2, 2.5).is_ok());
    assert!(cox_de_boor(&kv, n, 2, 2.5).is_err());
    assert!(cox_de_boor(&kv, n - 1, 3, 2.5).is_err());
    // Spans: 2 = [0, 1), 3 = [1, 1) empty, 4 = [1, 2), 5 = [2, 3].
    assert!(kv.local_basis_on_span(1, 0.5, 1).is_err()); // below the degree
    assert!(kv.local_basis_on_span(3, 1.0, 1).is_err()); // empty span
    assert!(kv.local_basis_on_span(n, 2.5, 1).is_err()); // past the last
    assert!(kv.local_basis_on_span(2, 1.5, 1).is_err()); // x right of the span
    assert!(kv.local_basis_on_span(4, 0.5, 1).is_err()); // x left of the span
    assert!(kv.local_basis_on_span(4, f64::NAN, 1).is_err());
    // Both ends of a span are accepted; at the right end it is the left limit.
    let left = kv.local_basis_on_span(2, 1.0, 0).unwrap();
    assert_eq!(left.first, 0);
    let dense = left.dense(0, n);
    assert_relative_eq!(dense.iter().sum::<f64>(), 1.0, epsilon = 1e-14);
    // φ_2 on [0, 1) is x²: its left limit at 1 is 1 (it is 0 from the right,
    // the knot 1 having multiplicity 2 = p).
    assert_relative_eq!(dense[2], 1.0, epsilon = 1e-14);
    assert!(kv.local_basis_on_span(2, 0.0, 0).is_ok());
    assert!(kv.local_basis_on_span(5, 3.0, 0).is_ok());
    // Unclamped knots: spans 0 and 1 are non-empty but left of the domain
    // [ξ_2, ξ_3], span 3 right of it; only span 2 is inside.
    let uniform = KnotVector::new(vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0], 2).unwrap();
    assert_eq!(uniform.domain(), (2.0, 3.0));
    assert!(uniform.local_basis_on_span(1, 1.5, 0).is_err());
    assert!(uniform.local_basis_on_span(3, 3.5, 0).is_err());
    assert!(uniform.local_basis_on_span(2, 2.5, 0).is_ok());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The `Basis1d` interface of a knot vector is the knot vector (what the
    /// mass matrices and the MPM engine see), and the reusable-scratch
    /// evaluator gives every derivative of `local_basis`, bit for bit, also
    /// when one scratch serves several degrees and orders in turn.
    #[test]
    fn the_basis_interface_and_the_scratch_evaluator_are_the_knot_vector(
        kv in open_knots(6, 0.05), other in open_knots(6, 0.05), f in fractions()
    ) {
        let b: &dyn Basis1d = &kv;
        prop_assert_eq!(b.num_basis(), kv.num_basis());
        prop_assert_eq!(b.degree(), kv.degree());
        prop_assert_eq!(b.domain(), (kv.knots()[0], *kv.knots().last().unwrap()));
        prop_assert_eq!(b.cells(), kv.spans());
        // Gradient breaks: the interior knots where the functions are at
        // most C⁰, multiplicity ≥ max(p, 1) (thesis §6.1).
        let (a, e) = kv.domain();
        let p = kv.degree();
        let expected: Vec<f64> = kv.breakpoints().into_iter()
            .filter(|&(t, m)| t > a && t < e && m >= p.max(1)).map(|(t, _)| t).collect();
        prop_assert_eq!(b.gradient_breaks(), expected.clone());
        for t in &expected {
            prop_assert!(kv.knots().iter().filter(|&&k| k == *t).count() >= p.max(1));
        }
        let mut scratch = hompm::spline::bspline::SpanScratch::default();
        for x in sample_points(&kv, &f) {
            // Use the scratch on another degree first.
            let (oa, ob) = other.domain();
            other.local_basis_into(oa + 0.37 * (ob - oa), other.degree(), &mut scratch).unwrap();
            for order in [p, 1, 0] {
                let first = kv.local_basis_into(x, order, &mut scratch).unwrap();
                let reference = kv.local_basis(x, order).unwrap();
                prop_assert_eq!(first, reference.first);
                for k in 0..=order.min(p) {
                    prop_assert_eq!(scratch.derivative(k), reference.derivatives[k].as_slice());
                }
            }
        }
    }
}

/// The refusals of `KnotVector::new` name what is wrong: too few knots for
/// the degree is an invalid degree (p + 2 knots at least, thesis §6.1), and
/// a decreasing pair is named by both indices.
#[test]
fn knot_vector_refusals_name_the_offending_knots() {
    use hompm::error::Error;
    for (knots, p) in [
        (vec![0.0, 1.0], 1),
        (vec![0.0, 0.5, 1.0], 2),
        (vec![0.0, 1.0], 5),
    ] {
        let e = KnotVector::new(knots.clone(), p).unwrap_err();
        assert!(
            matches!(e, Error::InvalidDegree(_)),
            "{knots:?}, p = {p}: {e}"
        );
    }
    assert!(KnotVector::new(vec![0.0, 0.0, 1.0, 1.0], 1).is_ok());
    assert_eq!(
        KnotVector::new(vec![0.0, 0.5, 0.25, 1.0], 1),
        Err(Error::DecreasingKnot {
            index: 2,
            knot: 0.25,
            previous: 0.5
        })
    );
}

/// The queries of a knot vector on one worked by hand: p = 2 and
/// Ξ = {0, 0, 0, 0.25, 0.25, 0.6, 1, 1, 1} (0-based ξ_0 … ξ_8) have
/// n = 9 − 2 − 1 = 6 functions on the domain [ξ_2, ξ_6] = [0, 1], the
/// non-empty spans [0, 0.25], [0.25, 0.6] and [0.6, 1] (ξ_3 = ξ_4 leaves one
/// empty), and the breakpoints 0, 0.25, 0.6, 1 with multiplicities 3, 2, 1, 3.
/// The span of x is the largest i in [p, n) with ξ_i ≤ x, and the right end
/// belongs to the last non-empty span (i = 5).
#[test]
fn knot_vector_queries_on_a_hand_worked_vector() {
    let kv = KnotVector::new(vec![0.0, 0.0, 0.0, 0.25, 0.25, 0.6, 1.0, 1.0, 1.0], 2).unwrap();
    assert_eq!(kv.num_basis(), 6);
    assert_eq!(kv.degree(), 2);
    assert_eq!(kv.domain(), (0.0, 1.0));
    assert_eq!(kv.knots().len(), 9);
    assert_eq!(kv.spans(), vec![(0.0, 0.25), (0.25, 0.6), (0.6, 1.0)]);
    assert_eq!(
        kv.breakpoints(),
        vec![(0.0, 3), (0.25, 2), (0.6, 1), (1.0, 3)]
    );
    for (x, span) in [
        (0.0, 2),
        (0.1, 2),
        (0.25, 4),
        (0.3, 4),
        (0.6, 5),
        (0.99, 5),
        (1.0, 5),
    ] {
        assert_eq!(kv.find_span(x).unwrap(), span, "x = {x}");
    }
    assert_eq!(kv.check_point(0.5).unwrap(), 0.5);
    for x in [-1e-12, 1.0 + 1e-12, f64::NAN] {
        assert!(
            kv.check_point(x).is_err() && kv.find_span(x).is_err(),
            "x = {x}"
        );
    }
    // Uniform spans take the O(1) guess; the answer is the same rule.
    let uniform = KnotVector::open_uniform(-1.0, 1.0, 4, 2).unwrap();
    assert_eq!(
        uniform.spans(),
        vec![(-1.0, -0.5), (-0.5, 0.0), (0.0, 0.5), (0.5, 1.0)]
    );
    for (x, span) in [
        (-1.0, 2),
        (-0.5, 3),
        (-1e-300, 3),
        (0.0, 4),
        (0.7, 5),
        (1.0, 5),
    ] {
        assert_eq!(uniform.find_span(x).unwrap(), span, "x = {x}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// On any valid knot vector: the spans are the windows of consecutive
    /// breakpoints, the breakpoints' multiplicities add up to the knots in
    /// the domain, and find_span(x) is the largest i in [p, n) with ξ_i ≤ x
    /// (the last non-empty span at the right end), whose span holds x.
    #[test]
    fn spans_breakpoints_and_find_span_agree_with_the_knots(kv in general_knots(), f in fractions()) {
        let (a, b) = kv.domain();
        let (p, n) = (kv.degree(), kv.num_basis());
        let knots = kv.knots();
        let breaks = kv.breakpoints();
        let windows: Vec<(f64, f64)> = breaks.windows(2).map(|w| (w[0].0, w[1].0)).collect();
        prop_assert_eq!(kv.spans(), windows);
        let inside = knots.iter().filter(|&&k| a <= k && k <= b).count();
        prop_assert_eq!(breaks.iter().map(|&(_, m)| m).sum::<usize>(), inside);
        for t in f {
            let x = a + t * (b - a);
            let i = kv.find_span(x).unwrap();
            prop_assert!((p..n).contains(&i));
            prop_assert!(knots[i] < knots[i + 1], "span {} is empty", i);
            prop_assert!(knots[i] <= x && x <= knots[i + 1]);
            if x < b {
                let largest = (p..n).rev().find(|&j| knots[j] <= x).unwrap();
                prop_assert_eq!(i, largest);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// MLS paper Eqs. (4)–(5): the 2D function is the product of the 1D ones,
    /// its gradient is (N'_i N_j, N_i N'_j), and the 2D basis is a partition of unity.
    ///
    /// Map rows: mls-4, mls-5 — the tensor basis and its gradient are one product.
    #[test]
    fn tensor_basis_is_product_with_product_gradient(kx in open_knots(4, 0.05), ky in open_knots(4, 0.05),
                                                     s in 0.0f64..=1.0, t in 0.0f64..=1.0) {
        let (ax, bx) = kx.domain();
        let (ay, by) = ky.domain();
        let (x, y) = (ax + s * (bx - ax), ay + t * (by - ay));
        let basis = TensorBasis2d::new(kx.clone(), ky.clone());
        let loc = basis.local_basis(x, y).unwrap();
        prop_assert!((loc.values.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        let gx: f64 = loc.gradients.iter().map(|g| g[0]).sum();
        let gy: f64 = loc.gradients.iter().map(|g| g[1]).sum();
        prop_assert!(gx.abs() < 1e-9 && gy.abs() < 1e-9);
        let vx = kx.dense_values(x).unwrap();
        let vy = ky.dense_values(y).unwrap();
        let dx = kx.dense_derivatives(x).unwrap();
        let dy = ky.dense_derivatives(y).unwrap();
        let nx = kx.num_basis();
        prop_assert_eq!(basis.num_basis(), nx * ky.num_basis());
        for (k, &idx) in loc.indices.iter().enumerate() {
            let (i, j) = (idx % nx, idx / nx);
            prop_assert!((loc.values[k] - vx[i] * vy[j]).abs() < 1e-14);
            prop_assert!((loc.gradients[k][0] - dx[i] * vy[j]).abs() < 1e-10 * (1.0 + dx[i].abs()));
            prop_assert!((loc.gradients[k][1] - vx[i] * dy[j]).abs() < 1e-10 * (1.0 + dy[j].abs()));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The O(1) span guess on uniform knots rounds: (ξ_k − a)·spans/(b − a)
    /// often comes out just below k at a knot ξ_k itself. find_span still
    /// answers the rule, the largest i with ξ_i ≤ x, at every knot and just
    /// either side of it.
    #[test]
    fn find_span_on_uniform_knots_is_exact_at_and_beside_every_knot(
        a in -10.0f64..10.0, length in 0.01f64..20.0, spans in 1usize..50, p in 0usize..4,
    ) {
        let kv = KnotVector::open_uniform(a, a + length, spans, p).unwrap();
        let knots = kv.knots();
        let (lo, hi) = kv.domain();
        let rule = |x: f64| (p..kv.num_basis()).rev().find(|&i| knots[i] <= x).unwrap();
        for &knot in &knots[p..kv.num_basis()] {
            for x in [knot, knot.next_up(), knot.next_down()] {
                if lo <= x && x < hi {
                    prop_assert_eq!(kv.find_span(x).unwrap(), rule(x), "x = {}", x);
                }
            }
        }
    }
}

/// One scratch serving degree 3 and then degree 7 (16 and 64 entries in its
/// triangle, 16 = 2 · 8) resizes and gives degree 7's values and derivatives
/// bit for bit; a point outside the span it is asked about is refused with
/// that span's ends.
#[test]
fn a_scratch_grows_from_degree_three_to_seven_and_spans_refuse_with_their_ends() {
    use hompm::spline::bspline::SpanScratch;
    let low = KnotVector::open_uniform(0.0, 1.0, 4, 3).unwrap();
    let high = KnotVector::open_uniform(0.0, 1.0, 4, 7).unwrap();
    let mut scratch = SpanScratch::default();
    low.local_basis_into(0.3, 3, &mut scratch).unwrap();
    let first = high.local_basis_into(0.3, 7, &mut scratch).unwrap();
    let reference = high.local_basis(0.3, 7).unwrap();
    assert_eq!(first, reference.first);
    for k in 0..=7 {
        assert_eq!(scratch.derivative(k), reference.derivatives[k].as_slice());
    }
    // The MPM evaluator's scratch (values and gradients only) grows alike.
    let mut mpm_scratch = SpanScratch::default();
    let (mut v3, mut g3) = ([0.0; 4], [0.0; 4]);
    low.values_and_gradients_into(0.3, &mut mpm_scratch, &mut v3, &mut g3)
        .unwrap();
    let (mut v7, mut g7) = ([0.0; 8], [0.0; 8]);
    let first7 = high
        .values_and_gradients_into(0.3, &mut mpm_scratch, &mut v7, &mut g7)
        .unwrap();
    assert_eq!(first7, reference.first);
    assert_eq!(v7.as_slice(), reference.derivatives[0].as_slice());
    let order_one = high.local_basis(0.3, 1).unwrap();
    assert_eq!(g7.as_slice(), order_one.derivatives[1].as_slice());
    // The span of x = 0.3 on `low` is [0.25, 0.5] (0-based index 4).
    assert_eq!(low.find_span(0.3).unwrap(), 4);
    match low.local_basis_on_span(4, 0.7, 0) {
        Err(hompm::Error::OutsideDomain { x, a, b }) => assert_eq!((x, a, b), (0.7, 0.25, 0.5)),
        other => panic!("{other:?}"),
    }
}

/// The knots double precision can divide by and measure: a span of exactly
/// the smallest normal double is accepted (1/span is finite), a subnormal
/// span is refused even between two normal knots (1e-300 and 1e-300 +
/// 1e-310), and a domain whose length overflows is refused even when every
/// span is finite ([−1e308, 0, 1e308]).
#[test]
fn knots_are_refused_exactly_where_double_precision_cannot_divide_or_measure() {
    assert!(KnotVector::new(vec![0.0, f64::MIN_POSITIVE], 0).is_ok());
    let a = 1e-300;
    let b = a + 1e-310;
    assert!(b - a > 0.0 && b - a < f64::MIN_POSITIVE);
    assert!(matches!(
        KnotVector::new(vec![a, a, b, b], 1),
        Err(hompm::Error::InvalidKnots(_))
    ));
    assert!(matches!(
        KnotVector::new(vec![-1e308, 0.0, 1e308], 0),
        Err(hompm::Error::InvalidKnots(_))
    ));
}

/// `values_and_gradients_fixed::<W>` at x: the first index, values and gradients.
fn fixed_width<const W: usize>(basis: &KnotVector, x: f64) -> (usize, Vec<f64>, Vec<f64>) {
    let (mut v, mut g) = ([f64::NAN; W], [f64::NAN; W]);
    let first = basis
        .values_and_gradients_fixed::<W>(x, &mut v, &mut g)
        .unwrap();
    (first, v.to_vec(), g.to_vec())
}
