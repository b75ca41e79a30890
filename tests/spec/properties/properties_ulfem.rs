//! The updated-Lagrangian FEM reference (fem::ulfem): second-order accurate on
//! the small-deformation bar, typed errors on bad input.

use hompm::fem::ulfem::{Ulfem, UlfemMaterial};
use hompm::mpm::musl::Constitutive;
use hompm::scenes::vibrating_bar;

fn bar_error(elements: usize) -> f64 {
    let p = vibrating_bar::parameters("thesis-table-4.1").unwrap();
    let m = UlfemMaterial {
        density: p.density,
        young: p.young,
        constitutive: Constitutive::SmallStrain,
        gravity: 0.0,
        gravity_ramp: None,
    };
    let mut ul = Ulfem::new(
        p.length,
        elements,
        m,
        |x| p.velocity(x, 0.0),
        vec![0, elements],
    )
    .unwrap();
    for _ in 0..2000 {
        ul.step(1e-4).unwrap();
    }
    let xs: Vec<f64> = (0..=100).map(|k| p.length * k as f64 / 100.0).collect();
    let e: f64 = xs
        .iter()
        .map(|&x| (ul.displacement_at(x) - p.displacement(x, ul.time)).powi(2))
        .sum::<f64>()
        / xs.len() as f64;
    e.sqrt()
}

/// Against thesis Eq. (4.1): RMS displacement error at t = 0.2 s falls about
/// four-fold per halving of h (P1 elements are second order).
#[test]
fn ulfem_is_second_order_on_the_small_deformation_bar() {
    let (e16, e32) = (bar_error(16), bar_error(32));
    let order = (e16 / e32).log2();
    assert!(
        order > 1.8 && order < 2.2,
        "order {order} ({e16:e}, {e32:e})"
    );
    assert!(e32 < 1e-4);
}

#[test]
fn ulfem_rejects_bad_input() {
    let m = UlfemMaterial {
        density: 1.0,
        young: 1.0,
        constitutive: Constitutive::SmallStrain,
        gravity: 0.0,
        gravity_ramp: None,
    };
    let refused = |r: hompm::Result<Ulfem>, needle: &str| match r {
        Err(hompm::Error::InvalidArgument(msg)) => assert!(msg.contains(needle), "{msg}"),
        other => panic!(
            "expected InvalidArgument with '{needle}', got {:?}",
            other.map(|_| ())
        ),
    };
    refused(
        Ulfem::new(1.0, 0, m, |_| 0.0, vec![]),
        "positive length, elements",
    );
    refused(
        Ulfem::new(1.0, 4, m, |_| 0.0, vec![9]),
        "fixed node 9 outside 0..=4",
    );
    refused(
        Ulfem::new(-1.0, 4, m, |_| 0.0, vec![]),
        "positive length, elements",
    );
    let mut ul = Ulfem::new(1.0, 4, m, |_| 0.0, vec![0]).unwrap();
    match ul.step(0.0) {
        Err(hompm::Error::NotPositive { what, value }) => {
            assert_eq!((what.as_str(), value), ("the time step", 0.0))
        }
        other => panic!("{other:?}"),
    }
    assert!(ul.step(1e-3).is_ok());
}
