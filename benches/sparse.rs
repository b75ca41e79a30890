//! Does hompm's own CSR (`sparse.rs`) earn its place next to faer's sparse
//! matrices (issue #14)? The two operations the MUSL step repeats every step
//! with a consistent mass, measured both ways on the same entries:
//!
//! - **assembly** of the projection's mass matrix from particle stencils:
//!   `BandAssembly` (add into the band, then CSR) against faer's
//!   `SparseColMat::try_new_from_triplets` (sort and sum the triplets);
//! - **product** M·x, the work of every Richardson and CG iteration: CSR
//!   `mul_vec` against faer's sparse × dense product.
//!
//! Quadratic B-splines (stencil width 3), 8 particles per cell, 64 to 16384
//! cells. Run with `cargo bench --bench sparse`; the figures are quoted in
//! the module doc of `src/sparse.rs`.

use divan::Bencher;
use hompm::sparse::{BandAssembly, SparseMatrix};

/// Large arrays start at staggered offsets within the page
/// (`hompm::placement`): placement only, the same bits.
#[global_allocator]
static ALLOCATOR: hompm::placement::StaggeredAllocator =
    hompm::placement::StaggeredAllocator::new();

fn main() {
    divan::main();
}

const CELLS: &[usize] = &[64, 1024, 16384];
const WIDTH: usize = 3;
const PPC: usize = 8;

/// The (i, j, m_p φ_i φ_j) entries of particles spread over `cells` cells,
/// in the order the step adds them.
fn entries(cells: usize) -> (usize, Vec<(usize, usize, f64)>) {
    let dofs = cells + WIDTH - 1;
    let mut t = Vec::with_capacity(cells * PPC * WIDTH * WIDTH);
    for e in 0..cells {
        for p in 0..PPC {
            let xi = (p as f64 + 0.5) / PPC as f64;
            let phi = [
                0.5 * (1.0 - xi).powi(2),
                0.5 + xi * (1.0 - xi),
                0.5 * xi * xi,
            ];
            for a in 0..WIDTH {
                for b in 0..WIDTH {
                    t.push((e + a, e + b, 0.1 * phi[a] * phi[b]));
                }
            }
        }
    }
    (dofs, t)
}

#[divan::bench(args = CELLS)]
fn assemble_band_to_csr(bencher: Bencher, cells: usize) {
    let (n, t) = entries(cells);
    let mut band = BandAssembly::default();
    bencher.bench_local(|| {
        band.reset(n, WIDTH - 1);
        for &(i, j, v) in &t {
            band.add(i, j, v);
        }
        band.to_sparse().unwrap()
    });
}

#[divan::bench(args = CELLS)]
fn assemble_faer_triplets(bencher: Bencher, cells: usize) {
    let (n, t) = entries(cells);
    bencher.bench_local(|| {
        let triplets: Vec<faer::sparse::Triplet<usize, usize, f64>> = t
            .iter()
            .map(|&(i, j, v)| faer::sparse::Triplet::new(i, j, v))
            .collect();
        faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &triplets).unwrap()
    });
}

#[divan::bench(args = CELLS)]
fn product_csr(bencher: Bencher, cells: usize) {
    let (n, t) = entries(cells);
    let m = SparseMatrix::from_triplets(n, n, &t).unwrap();
    let x: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
    let mut y = vec![0.0; n];
    bencher.bench_local(|| m.mul_vec(divan::black_box(&x), &mut y));
}

#[divan::bench(args = CELLS)]
fn product_faer(bencher: Bencher, cells: usize) {
    let (n, t) = entries(cells);
    let m = SparseMatrix::from_triplets(n, n, &t)
        .unwrap()
        .to_faer()
        .unwrap();
    let x = faer::Mat::<f64>::from_fn(n, 1, |i, _| (i as f64).sin());
    bencher.bench_local(|| &m * divan::black_box(&x));
}
