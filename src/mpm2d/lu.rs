//! # The inverse of a small normal matrix, by LU with partial pivoting
//!
//! The 2D TLS fit (TLS paper Eqs. 13–14 in 2D, [`super::tls`]) inverts its
//! per-cell normal matrix D = Σ_p ψ̂(x_p) ψ̂(x_p)ᵀ, of size M ≤ 6. nalgebra's
//! `try_inverse` does this for M ≥ 5 by an LU decomposition with partial
//! pivoting written for any size: its loops and matrix views cost more than
//! the arithmetic at M = 5 (issue #39, docs/conventions.md "The fused step").
//! [`try_inverse_lu`] is the same algorithm on a fixed-size array, written
//! so that every floating-point operation is the one nalgebra 0.35 performs
//! (`linalg::lu::try_invert_to`, `gauss_step(_swap)`,
//! `solve_lower_triangular_with_diag_mut`, `solve_upper_triangular_mut`),
//! on the same operands in the same order for each entry: the result has
//! nalgebra's bits, `None` included (tests/spec/speed/small_lu.rs proves it
//! against `try_inverse`). Only the order in which *independent* entries are
//! computed differs (row by row, which the compiler vectorises), and that
//! moves no bit. No operation is fused (Rust does not contract a·b + c).
//!
//! nalgebra's `axpy` forms y ← (−c)·x·1 + 1·y; multiplying by 1 and
//! negating a product are exact, so that is y − c·x here, bit for bit.
//!
//! Items: [`try_inverse_lu`].

/// D⁻¹ of the M × M matrix `d` (`d[i][j]` = D_ij) by Gaussian elimination
/// with partial pivoting, PD = LU, then L Y = P and U X = Y column by column
/// (the normal matrix of TLS paper Eqs. (13)–(14)); `None` where a pivot
/// (the first largest |D_ij| of its column, at or below the diagonal) is
/// zero. Bit for bit nalgebra 0.35's `try_inverse` for M = 5 and 6 (module
/// doc; nalgebra inverts M ≤ 4 by closed forms instead); M ≤ 6.
/// Always inlined, so that TLS's dispatched `normal_solve` compiles it with
/// AVX2 too.
#[inline(always)]
pub fn try_inverse_lu<const M: usize>(d: &[[f64; M]; M]) -> Option<[[f64; M]; M]> {
    // The steps below are written out for I = 0 … 5: M ≤ 6, checked when
    // the function is compiled for an M.
    const { assert!(M <= 6, "try_inverse_lu is written for M ≤ 6") };
    let mut lu = *d;
    // The rows of the identity in the order the pivoting leaves them: P.
    let mut order: [usize; M] = std::array::from_fn(|i| i);
    let factored = eliminate::<M, 0>(&mut lu, &mut order)
        && eliminate::<M, 1>(&mut lu, &mut order)
        && eliminate::<M, 2>(&mut lu, &mut order)
        && eliminate::<M, 3>(&mut lu, &mut order)
        && eliminate::<M, 4>(&mut lu, &mut order)
        && eliminate::<M, 5>(&mut lu, &mut order);
    if !factored {
        return None;
    }
    let mut x: [[f64; M]; M] =
        std::array::from_fn(|r| std::array::from_fn(|c| if c == order[r] { 1.0 } else { 0.0 }));
    forward_substitute::<M, 0>(&lu, &mut x);
    forward_substitute::<M, 1>(&lu, &mut x);
    forward_substitute::<M, 2>(&lu, &mut x);
    forward_substitute::<M, 3>(&lu, &mut x);
    forward_substitute::<M, 4>(&lu, &mut x);
    let solved = back_substitute::<M, 5>(&lu, &mut x)
        && back_substitute::<M, 4>(&lu, &mut x)
        && back_substitute::<M, 3>(&lu, &mut x)
        && back_substitute::<M, 2>(&lu, &mut x)
        && back_substitute::<M, 1>(&lu, &mut x)
        && back_substitute::<M, 0>(&lu, &mut x);
    solved.then_some(x)
}

/// Step I of the elimination (nalgebra's `gauss_step(_swap)`; nothing if
/// I ≥ M): the pivot row p ≥ I of the first largest |D_pI| (nalgebra's
/// `icamax`: a later row wins only if strictly larger), false if D_pI = 0;
/// rows I and p swapped (nalgebra moves the parts left of, at and right of
/// column I in three moves: the whole rows, here); then the multipliers
/// l_rI = D_rI · (1/D_II) below the pivot and D_rk ← D_rk − l_rI D_Ik.
/// I is a constant so that each step's loops unroll.
#[inline(always)]
fn eliminate<const M: usize, const I: usize>(
    lu: &mut [[f64; M]; M],
    order: &mut [usize; M],
) -> bool {
    if I >= M {
        return true;
    }
    let mut pivot = I;
    let mut largest = lu[I][I].abs();
    for (r, row) in lu[I + 1..].iter().enumerate() {
        let value = row[I].abs();
        if value > largest {
            largest = value;
            pivot = I + 1 + r;
        }
    }
    let diag = lu[pivot][I];
    if diag == 0.0 {
        return false;
    }
    lu.swap(I, pivot);
    order.swap(I, pivot);
    let inverse_diag = 1.0 / diag;
    let pivot_row = lu[I];
    for row in &mut lu[I + 1..] {
        let l = row[I] * inverse_diag;
        row[I] = l;
        for (entry, u) in row[I + 1..].iter_mut().zip(&pivot_row[I + 1..]) {
            *entry -= l * u;
        }
    }
    true
}

/// Step I of L Y = P with L's unit diagonal (nalgebra's
/// `solve_lower_triangular_with_diag_mut` with diag = 1, whose y_I/1 is
/// y_I; nothing if I ≥ M − 1): y_r ← y_r − l_rI y_I for r > I, every column
/// at once.
#[inline(always)]
fn forward_substitute<const M: usize, const I: usize>(lu: &[[f64; M]; M], y: &mut [[f64; M]; M]) {
    if I + 1 >= M {
        return;
    }
    let solved = y[I];
    for (row, lu_row) in y[I + 1..].iter_mut().zip(&lu[I + 1..]) {
        let l = lu_row[I];
        for (y_rc, y_ic) in row.iter_mut().zip(solved) {
            *y_rc -= y_ic * l;
        }
    }
}

/// Step I of U X = Y (nalgebra's `solve_upper_triangular_mut`, I
/// descending; nothing if I ≥ M): x_I = y_I / u_II, then y_r ← y_r − u_rI x_I
/// for r < I, every column at once; false if u_II is zero.
#[inline(always)]
fn back_substitute<const M: usize, const I: usize>(
    lu: &[[f64; M]; M],
    x: &mut [[f64; M]; M],
) -> bool {
    if I >= M {
        return true;
    }
    let diag = lu[I][I];
    if diag == 0.0 {
        return false;
    }
    for x_ic in x[I].iter_mut() {
        *x_ic /= diag;
    }
    let solved = x[I];
    for (row, lu_row) in x[..I].iter_mut().zip(&lu[..I]) {
        let u = lu_row[I];
        for (x_rc, x_ic) in row.iter_mut().zip(solved) {
            *x_rc -= x_ic * u;
        }
    }
    true
}
