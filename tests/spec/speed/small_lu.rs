//! Issue #39: the 2D TLS fit inverts its normal matrix D (TLS paper
//! Eqs. 13–14) with `hompm::mpm2d::lu::try_inverse_lu`, a fixed-size LU
//! with partial pivoting meant to give nalgebra's `try_inverse` bits for
//! M ≥ 5. Checked here bit for bit (every entry's `to_bits`, and `None`
//! where nalgebra finds D singular) on random matrices, on normal matrices
//! of particles (random, nearly collinear and too few for the basis), and on
//! small-integer matrices whose columns tie for the pivot or vanish.

use hompm::mpm2d::lu::try_inverse_lu;
use hompm::mpm2d::tls::TaylorBasis2d;
use nalgebra::SMatrix;
use proptest::prelude::*;

/// nalgebra's inverse of `d` as an array, or None.
fn nalgebra_inverse<const M: usize>(d: &[[f64; M]; M]) -> Option<[[f64; M]; M]> {
    let inverse = SMatrix::<f64, M, M>::from_fn(|i, j| d[i][j]).try_inverse()?;
    Some(std::array::from_fn(|i| {
        std::array::from_fn(|j| inverse[(i, j)])
    }))
}

/// The bits of an optional inverse (NaN payloads included).
fn bits<const M: usize>(m: Option<[[f64; M]; M]>) -> Option<Vec<u64>> {
    m.map(|m| m.iter().flatten().map(|x| x.to_bits()).collect())
}

fn assert_same<const M: usize>(d: &[[f64; M]; M]) -> Result<(), TestCaseError> {
    prop_assert_eq!(
        bits(try_inverse_lu(d)),
        bits(nalgebra_inverse(d)),
        "D = {:?}",
        d
    );
    Ok(())
}

/// D = Σ_p ψ̂(x_p)ψ̂(x_p)ᵀ over the M functions from `skip` on.
fn normal_matrix<const M: usize>(points: &[(f64, f64)], skip: usize) -> [[f64; M]; M] {
    // The cell [−1, 1]²: ψ̂ at a point is ψ̂ at its (ξ, η), the basis TLS fits.
    let cell = TaylorBasis2d::new([-1.0, -1.0], [1.0, 1.0]).unwrap();
    let mut d = [[0.0; M]; M];
    for &(xi, eta) in points {
        let r = cell.evaluate([xi, eta]);
        for i in 0..M {
            for j in 0..M {
                d[i][j] += r[skip + i] * r[skip + j];
            }
        }
    }
    d
}

/// Points of the cell [−1, 1]², `spread` off the line η = slope·ξ + c.
fn points(n: usize) -> impl Strategy<Value = Vec<(f64, f64)>> {
    (
        prop::collection::vec((-1.0..1.0f64, -1.0..1.0f64), n),
        -2.0..2.0f64,
        -0.5..0.5f64,
        prop_oneof![Just(0.0), Just(1e-12), Just(1e-6), Just(1e-3), Just(1.0)],
    )
        .prop_map(|(raw, slope, c, spread)| {
            raw.into_iter()
                .map(|(xi, e)| (xi, (slope * xi + c + spread * e).clamp(-1.0, 1.0)))
                .collect()
        })
}

fn square<const M: usize>(entries: Vec<f64>) -> [[f64; M]; M] {
    std::array::from_fn(|i| std::array::from_fn(|j| entries[M * i + j]))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// Any matrix of moderate entries.
    #[test]
    fn random_matrices_invert_to_nalgebras_bits(
        e5 in prop::collection::vec(-1e3..1e3f64, 25),
        e6 in prop::collection::vec(-1e3..1e3f64, 36),
    ) {
        assert_same::<5>(&square(e5))?;
        assert_same::<6>(&square(e6))?;
    }

    /// Small integers: ties for the largest pivot, zero columns, exact
    /// singularity (nalgebra's None).
    #[test]
    fn integer_matrices_tie_and_vanish_as_nalgebras(
        e5 in prop::collection::vec(-2i8..=2, 25),
        e6 in prop::collection::vec(-2i8..=2, 36),
    ) {
        assert_same::<5>(&square(e5.into_iter().map(f64::from).collect()))?;
        assert_same::<6>(&square(e6.into_iter().map(f64::from).collect()))?;
    }

    /// TLS normal matrices of 1 to 12 particles, conservative (M = 5) and
    /// unconstrained (M = 6), from well spread to collinear.
    #[test]
    fn normal_matrices_invert_to_nalgebras_bits(
        p in (1usize..=12).prop_flat_map(points),
    ) {
        assert_same::<5>(&normal_matrix::<5>(&p, 1))?;
        assert_same::<6>(&normal_matrix::<6>(&p, 0))?;
    }
}
