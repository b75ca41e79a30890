//! Property tests of the quadrature rules: thesis Appendix A.3 and §7.2.

use approx::assert_relative_eq;
use hompm::quadrature::{gauss_on_cells, half_span_rule, GaussLegendre};
use proptest::prelude::*;

/// The n-point rule integrates x^k on [−1, 1] exactly for k ≤ 2n − 1, for
/// n = 1..=20, to 1e-14 (thesis A.3: "polynomials of degree 2n − 1 or less").
#[test]
fn gauss_rules_are_exact_for_monomials_up_to_degree_2n_minus_1() {
    for n in 1..=20 {
        let rule = GaussLegendre::new(n).unwrap();
        assert_relative_eq!(rule.weights().iter().sum::<f64>(), 2.0, epsilon = 1e-14);
        for k in 0..=(2 * n - 1) {
            let exact = if k % 2 == 0 {
                2.0 / (k as f64 + 1.0)
            } else {
                0.0
            };
            let q: f64 = rule
                .nodes()
                .iter()
                .zip(rule.weights())
                .map(|(x, w)| w * x.powi(k as i32))
                .sum();
            assert!(
                (q - exact).abs() < 1e-14,
                "n = {n}, k = {k}: {q} vs {exact}"
            );
        }
        // Degree 2n is not integrated exactly: the bound is sharp (checked
        // where the error constant is still far above rounding).
        if n <= 8 {
            let k = 2 * n;
            let q: f64 = rule
                .nodes()
                .iter()
                .zip(rule.weights())
                .map(|(x, w)| w * x.powi(k as i32))
                .sum();
            assert!((q - 2.0 / (k as f64 + 1.0)).abs() > 1e-10, "n = {n}");
        }
    }
}

/// Thesis Eq. (A.1): the 2-point rule is ±√(1/3) with weights 1; the 3-point
/// rule is 0, ±√(3/5) with weights 8/9, 5/9.
#[test]
fn two_and_three_point_rules_match_closed_forms() {
    let g2 = GaussLegendre::new(2).unwrap();
    assert_eq!((g2.len(), g2.is_empty()), (2, false));
    assert_relative_eq!(g2.nodes()[1], (1.0f64 / 3.0).sqrt(), epsilon = 1e-15);
    assert_relative_eq!(g2.nodes()[0], -(1.0f64 / 3.0).sqrt(), epsilon = 1e-15);
    assert_relative_eq!(g2.weights()[0], 1.0, epsilon = 1e-15);
    let g3 = GaussLegendre::new(3).unwrap();
    assert_relative_eq!(g3.nodes()[2], (0.6f64).sqrt(), epsilon = 1e-15);
    assert_eq!(g3.nodes()[1], 0.0);
    assert_relative_eq!(g3.weights()[1], 8.0 / 9.0, epsilon = 1e-15);
    assert_relative_eq!(g3.weights()[0], 5.0 / 9.0, epsilon = 1e-15);
}

/// Thesis §7.2: four points per span at (3ξ_j+ξ_{j+1})/4 ± (ξ_{j+1}−ξ_j)/4·√(1/3)
/// and (ξ_j+3ξ_{j+1})/4 ± …, each with weight (ξ_{j+1}−ξ_j)/4.
#[test]
fn half_span_rule_matches_thesis_formulas() {
    let (a, b) = (0.2, 1.0);
    let q = half_span_rule(&[(a, b)]).unwrap();
    let s = (1.0f64 / 3.0).sqrt();
    let expected = [
        -(b - a) / 4.0 * s + (3.0 * a + b) / 4.0,
        (b - a) / 4.0 * s + (3.0 * a + b) / 4.0,
        -(b - a) / 4.0 * s + (a + 3.0 * b) / 4.0,
        (b - a) / 4.0 * s + (a + 3.0 * b) / 4.0,
    ];
    for (p, e) in q.iter().zip(expected) {
        assert_relative_eq!(p.x, e, epsilon = 1e-15);
        assert_relative_eq!(p.weight, (b - a) / 4.0, epsilon = 1e-15);
    }
}

#[test]
fn bad_rules_are_errors() {
    assert!(GaussLegendre::new(0).is_err());
    assert!(gauss_on_cells(&[(1.0, 1.0)], 2).is_err());
    assert!(gauss_on_cells(&[(0.0, f64::NAN)], 2).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// A random polynomial of degree ≤ 2n − 1 on a random interval is
    /// integrated exactly (to rounding) by the mapped n-point rule, Eq. (A.2).
    #[test]
    fn mapped_rule_is_exact(n in 1usize..=20, a in -5.0f64..5.0, len in 0.1f64..4.0,
                            coeffs in proptest::collection::vec(-1.0f64..1.0, 40)) {
        let b = a + len;
        let deg = 2 * n - 1;
        let c = &coeffs[..=deg];
        // Polynomial in the centred variable s = (x − m)/len keeps values O(1).
        let m = 0.5 * (a + b);
        let f = |x: f64| c.iter().rev().fold(0.0, |acc, ck| acc * ((x - m) / len) + ck);
        let exact: f64 = c.iter().enumerate().map(|(k, ck)| {
            let kp = k as f64 + 1.0;
            ck * len * (0.5f64.powf(kp) - (-0.5f64).powf(kp)) / kp
        }).sum();
        let q = GaussLegendre::new(n).unwrap().integrate(a, b, f);
        prop_assert!((q - exact).abs() < 1e-13 * (1.0 + exact.abs()), "{q} vs {exact}");
    }

    /// The half-span rule integrates cubics exactly on every span.
    #[test]
    fn half_span_rule_is_exact_for_cubics(c in proptest::collection::vec(-1.0f64..1.0, 4),
                                         cuts in proptest::collection::vec(0.0f64..1.0, 1..6)) {
        let mut pts: Vec<f64> = cuts.iter().copied().filter(|&c| c > 1e-3 && c < 1.0 - 1e-3).collect();
        pts.push(0.0);
        pts.push(1.0);
        pts.sort_by(|a, b| a.partial_cmp(b).unwrap());
        pts.dedup_by(|a, b| (*a - *b).abs() < 1e-3);
        let spans: Vec<(f64, f64)> = pts.windows(2).map(|w| (w[0], w[1])).collect();
        let f = |x: f64| c[0] + c[1] * x + c[2] * x * x + c[3] * x * x * x;
        let exact = c[0] + c[1] / 2.0 + c[2] / 3.0 + c[3] / 4.0;
        let q: f64 = half_span_rule(&spans).unwrap().iter().map(|p| p.weight * f(p.x)).sum();
        prop_assert!((q - exact).abs() < 1e-13);
    }
}
