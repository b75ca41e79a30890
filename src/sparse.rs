//! # Compressed sparse row matrices
//!
//! The storage of every mass matrix in hompm. 1D B-spline mass matrices are
//! banded (half-bandwidth p) and 2D ones have (2p+1)² entries per row, so
//! O(n) storage and O(n) products. Gauss–Seidel (book §4.7) needs ordered
//! access to the rows of the matrix while it overwrites the iterate, which is
//! why hompm keeps this small CSR type; factorisations and eigenvalues are
//! delegated to faer ([`SparseMatrix::to_faer`], [`SparseMatrix::to_dense`]).
//!
//! Measured against faer (`cargo bench --bench sparse`, 2 cores, quadratic
//! B-splines, 8 particles per cell; issue #14): assembling a projection's
//! mass matrix through [`BandAssembly`] takes 8.6 µs / 162 µs / 3.0 ms at
//! 64 / 1024 / 16384 cells, against 52 µs / 948 µs / 33 ms for faer's
//! `SparseColMat::try_new_from_triplets` on the same entries (6–11× — the
//! band needs no sort); the product M·x is the same within noise (3.08 µs
//! against 3.36 µs at 1024 cells). The band assembly is the measured reason
//! this module stays; its CSR output could become a faer matrix without
//! loss, which is left for later.
//!
//! Items: [`SparseMatrix`], [`BandAssembly`].

use crate::error::{Error, Result};

/// A real matrix in compressed sparse row form. Rows hold their column
/// indices in ascending order.
#[derive(Debug, Clone, PartialEq)]
pub struct SparseMatrix {
    rows: usize,
    cols: usize,
    row_ptr: Vec<usize>,
    col_idx: Vec<usize>,
    values: Vec<f64>,
}

impl SparseMatrix {
    /// Builds from (row, col, value) triplets; duplicates are summed, exact
    /// zeros kept (they are structural). Errors on an index out of range or a
    /// non-finite value.
    pub fn from_triplets(
        rows: usize,
        cols: usize,
        triplets: &[(usize, usize, f64)],
    ) -> Result<Self> {
        let mut t: Vec<(usize, usize, f64)> = Vec::with_capacity(triplets.len());
        for &(i, j, v) in triplets {
            if i >= rows || j >= cols {
                return Err(Error::InvalidArgument(format!(
                    "entry ({i}, {j}) outside a {rows}×{cols} matrix"
                )));
            }
            if !v.is_finite() {
                return Err(Error::NonFinite {
                    what: format!("matrix entry ({i}, {j})"),
                    value: v,
                });
            }
            t.push((i, j, v));
        }
        t.sort_by_key(|a| (a.0, a.1));
        let mut row_ptr = vec![0; rows + 1];
        let mut col_idx = Vec::with_capacity(t.len());
        let mut values: Vec<f64> = Vec::with_capacity(t.len());
        let mut last: Option<(usize, usize)> = None;
        for (i, j, v) in t {
            if last == Some((i, j)) {
                *values.last_mut().expect("a previous entry exists") += v;
            } else {
                col_idx.push(j);
                values.push(v);
                row_ptr[i + 1] += 1;
                last = Some((i, j));
            }
        }
        for i in 0..rows {
            row_ptr[i + 1] += row_ptr[i];
        }
        Ok(Self {
            rows,
            cols,
            row_ptr,
            col_idx,
            values,
        })
    }

    /// The n×n diagonal matrix with the given diagonal.
    pub fn diagonal_matrix(diag: &[f64]) -> Result<Self> {
        let t: Vec<_> = diag.iter().enumerate().map(|(i, &v)| (i, i, v)).collect();
        Self::from_triplets(diag.len(), diag.len(), &t)
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Number of columns.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.values.len()
    }

    /// Column indices and values of row i.
    pub fn row(&self, i: usize) -> (&[usize], &[f64]) {
        let r = self.row_ptr[i]..self.row_ptr[i + 1];
        (&self.col_idx[r.clone()], &self.values[r])
    }

    /// Entry (i, j), zero if not stored.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (c, v) = self.row(i);
        c.binary_search(&j).map(|k| v[k]).unwrap_or(0.0)
    }

    /// The diagonal.
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.rows.min(self.cols))
            .map(|i| self.get(i, i))
            .collect()
    }

    /// Row sums Σ_j A_ij.
    pub fn row_sums(&self) -> Vec<f64> {
        (0..self.rows).map(|i| self.row(i).1.iter().sum()).collect()
    }

    /// y = A x: y_i = Σ_j a_ij x_j, summed in column order from −0 as
    /// `Iterator::sum` does. Two rows at a time: each row's sum is one chain
    /// of additions, which the processor overlaps with the next row's only
    /// in part, so the two chains are interleaved by hand (the same
    /// additions in the same order per row: the same bits;
    /// tests/spec/properties/properties_mass.rs). Measured on this machine against
    /// one row at a time: 1.5–1.9× faster on 1D mass matrices (p = 2 and
    /// 8), 1.1–1.2× on 2D ones (p = 2, 4, 8).
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        let rows = self.rows.min(y.len());
        let mut pairs = y[..rows].chunks_exact_mut(2);
        for (q, out) in (&mut pairs).enumerate() {
            let r: [(&[usize], &[f64]); 2] = std::array::from_fn(|k| self.row(2 * q + k));
            let common = r.iter().map(|(c, _)| c.len()).min().unwrap_or(0);
            let mut sums = [-0.0; 2];
            for e in 0..common {
                for (s, (c, v)) in sums.iter_mut().zip(&r) {
                    *s += v[e] * x[c[e]];
                }
            }
            for ((s, (c, v)), o) in sums.iter_mut().zip(&r).zip(out) {
                *o = c[common..]
                    .iter()
                    .zip(&v[common..])
                    .fold(*s, |s, (&j, &a)| s + a * x[j]);
            }
        }
        let done = rows - pairs.into_remainder().len();
        for (i, yi) in y.iter_mut().enumerate().take(rows).skip(done) {
            let (c, v) = self.row(i);
            *yi = c.iter().zip(v).map(|(&j, &a)| a * x[j]).sum();
        }
    }

    /// y = Aᵀ x.
    pub fn mul_transpose_vec(&self, x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        for (i, &xi) in x.iter().enumerate().take(self.rows) {
            let (c, v) = self.row(i);
            for (&j, &a) in c.iter().zip(v) {
                y[j] += a * xi;
            }
        }
    }

    /// The transpose.
    pub fn transpose(&self) -> Self {
        let mut t = Vec::with_capacity(self.nnz());
        for i in 0..self.rows {
            let (c, v) = self.row(i);
            for (&j, &a) in c.iter().zip(v) {
                t.push((j, i, a));
            }
        }
        Self::from_triplets(self.cols, self.rows, &t).expect("transpose of a valid matrix")
    }

    /// Keeps rows `row_keep` and columns `col_keep` (in that order).
    pub fn submatrix(&self, row_keep: &[usize], col_keep: &[usize]) -> Self {
        let mut col_map = vec![usize::MAX; self.cols];
        for (new, &old) in col_keep.iter().enumerate() {
            col_map[old] = new;
        }
        let mut t = Vec::new();
        for (new_i, &i) in row_keep.iter().enumerate() {
            let (c, v) = self.row(i);
            for (&j, &a) in c.iter().zip(v) {
                if col_map[j] != usize::MAX {
                    t.push((new_i, col_map[j], a));
                }
            }
        }
        Self::from_triplets(row_keep.len(), col_keep.len(), &t)
            .expect("submatrix of a valid matrix")
    }

    /// Scales row i by s_i: diag(s) · A.
    pub fn scale_rows(&self, s: &[f64]) -> Self {
        let mut out = self.clone();
        for (i, si) in s.iter().enumerate().take(self.rows) {
            for v in &mut out.values[self.row_ptr[i]..self.row_ptr[i + 1]] {
                *v *= si;
            }
        }
        out
    }

    /// The Kronecker product B ⊗ A (A varies fastest): entry
    /// (i_a + m_a·i_b, j_a + n_a·j_b) = A(i_a, j_a)·B(i_b, j_b).
    pub fn kron(b: &SparseMatrix, a: &SparseMatrix) -> Self {
        let mut t = Vec::with_capacity(a.nnz() * b.nnz());
        for ib in 0..b.rows {
            let (cb, vb) = b.row(ib);
            for ia in 0..a.rows {
                let (ca, va) = a.row(ia);
                for (&jb, &bv) in cb.iter().zip(vb) {
                    for (&ja, &av) in ca.iter().zip(va) {
                        t.push((ia + a.rows * ib, ja + a.cols * jb, av * bv));
                    }
                }
            }
        }
        Self::from_triplets(a.rows * b.rows, a.cols * b.cols, &t)
            .expect("Kronecker of valid matrices")
    }

    /// Dense copy (for tests and small eigenvalue problems).
    pub fn to_dense(&self) -> faer::Mat<f64> {
        let mut d = faer::Mat::<f64>::zeros(self.rows, self.cols);
        for i in 0..self.rows {
            let (c, v) = self.row(i);
            for (&j, &a) in c.iter().zip(v) {
                d[(i, j)] = a;
            }
        }
        d
    }

    /// A faer sparse column matrix with the same entries (for Cholesky).
    pub fn to_faer(&self) -> Result<faer::sparse::SparseColMat<usize, f64>> {
        let mut t = Vec::with_capacity(self.nnz());
        for i in 0..self.rows {
            let (c, v) = self.row(i);
            for (&j, &a) in c.iter().zip(v) {
                t.push(faer::sparse::Triplet::new(i, j, a));
            }
        }
        faer::sparse::SparseColMat::try_new_from_triplets(self.rows, self.cols, &t)
            .map_err(|e| Error::InvalidArgument(format!("cannot build a faer matrix: {e:?}")))
    }
}

/// A square banded matrix assembled entry by entry, in O(n · bandwidth)
/// time and memory: the mass matrix of a velocity projection, whose entries
/// couple only functions that share a stencil (half-bandwidth = stencil
/// width − 1). It gives the same [`SparseMatrix`] as
/// [`SparseMatrix::from_triplets`] on the same entries in the same order:
/// duplicates are summed in insertion order (from −0.0, so the first value is
/// kept exactly) and only entries that were added are stored.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BandAssembly {
    n: usize,
    half: usize,
    values: Vec<f64>,
    touched: Vec<bool>,
}

impl BandAssembly {
    /// Clears the assembly for an n×n matrix of half-bandwidth `half`
    /// (allocates only when it grows).
    pub fn reset(&mut self, n: usize, half: usize) {
        self.n = n;
        self.half = half;
        let len = n * (2 * half + 1);
        self.values.clear();
        self.values.resize(len, -0.0);
        self.touched.clear();
        self.touched.resize(len, false);
    }

    /// A_ij += v. Panics if |i − j| exceeds the half-bandwidth (a caller bug).
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        assert!(
            i.abs_diff(j) <= self.half,
            "entry ({i}, {j}) outside the band"
        );
        let k = i * (2 * self.half + 1) + j + self.half - i;
        self.values[k] += v;
        self.touched[k] = true;
    }

    /// The assembled matrix in CSR form. Errors on a non-finite entry.
    pub fn to_sparse(&self) -> Result<SparseMatrix> {
        let w = 2 * self.half + 1;
        let mut row_ptr = Vec::with_capacity(self.n + 1);
        let mut col_idx = Vec::new();
        let mut values = Vec::new();
        row_ptr.push(0);
        for i in 0..self.n {
            for o in 0..w {
                let k = i * w + o;
                if !self.touched[k] {
                    continue;
                }
                let j = i + o - self.half;
                let v = self.values[k];
                if !v.is_finite() {
                    return Err(Error::NonFinite {
                        what: format!("matrix entry ({i}, {j})"),
                        value: v,
                    });
                }
                col_idx.push(j);
                values.push(v);
            }
            row_ptr.push(col_idx.len());
        }
        Ok(SparseMatrix {
            rows: self.n,
            cols: self.n,
            row_ptr,
            col_idx,
            values,
        })
    }
}
