//! Golden snapshots of B-spline values and derivatives at 11 points:
//! - Ξ = {0,0,0,1/3,2/3,1,1,1}, p = 2 (book Fig. 4.1, TLS paper Fig. 2, MLS paper Fig. 1);
//! - Ξ = {0,0,0,1,2,3,4,4,5,5,5}, p = 2 (thesis Fig. 6.2).
//!
//! Values are printed at fixed precision (12 decimals) so that the snapshot
//! does not depend on float formatting.

use hompm::spline::KnotVector;
use rstest::rstest;

fn table(kv: &KnotVector) -> String {
    let (a, b) = kv.domain();
    let mut s = format!("knots = {:?}, degree = {}\n", kv.knots(), kv.degree());
    for k in 0..=10 {
        let x = a + (b - a) * k as f64 / 10.0;
        let v = kv.dense_values(x).unwrap();
        let d = kv.dense_derivatives(x).unwrap();
        let fmt = |u: &[f64]| {
            u.iter()
                .map(|z| format!("{:+.12}", if *z == 0.0 { 0.0 } else { *z }))
                .collect::<Vec<_>>()
                .join(" ")
        };
        s.push_str(&format!(
            "x = {x:.4}\n  phi  {}\n  dphi {}\n",
            fmt(&v),
            fmt(&d)
        ));
    }
    s
}

#[rstest]
#[case::book_fig_4_1("book_fig_4_1", vec![0.0, 0.0, 0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0, 1.0, 1.0])]
#[case::thesis_fig_6_2("thesis_fig_6_2", vec![0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 4.0, 4.0, 5.0, 5.0, 5.0])]
fn quadratic_bspline_tables_of_book_fig_4_1_and_thesis_fig_6_2_are_unchanged(
    #[case] name: &str,
    #[case] knots: Vec<f64>,
) {
    let kv = KnotVector::new(knots, 2).unwrap();
    insta::with_settings!({snapshot_path => "../../../golden/snapshots", prepend_module_to_snapshot => false}, {
        insta::assert_snapshot!(format!("basis_{name}"), table(&kv));
    });
}

/// Hand values for the book's Fig. 4.1 basis at x = 1/2 (middle of the
/// middle span): φ = (0, 1/8, 3/4, 1/8, 0), φ' = (0, −3/2, 0, 3/2, 0).
#[test]
fn book_fig_4_1_basis_at_the_middle_equals_the_hand_values() {
    let kv = KnotVector::new(vec![0.0, 0.0, 0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0, 1.0, 1.0], 2).unwrap();
    let v = kv.dense_values(0.5).unwrap();
    let d = kv.dense_derivatives(0.5).unwrap();
    let ev = [0.0, 0.125, 0.75, 0.125, 0.0];
    let ed = [0.0, -1.5, 0.0, 1.5, 0.0];
    for i in 0..5 {
        assert!((v[i] - ev[i]).abs() < 1e-15);
        assert!((d[i] - ed[i]).abs() < 1e-13);
    }
}
