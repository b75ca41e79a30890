//! hompm's 2D step against the lean step of benches/lean/mpm2d.rs (issue
//! #39): the aligned vibration of the MLS paper (`mls-paper-e1e7`, the
//! manufactured body force included), bilinear MPM and quadratic BSMPM with
//! the direct mapping, 9 particles per cell on 16 and 64 cells per side
//! (2 304 and 36 864 particles), the same numbers bit for bit
//! (tests/spec/speed/lean_2d.rs). divan's throughput ("item/s") is
//! particle-steps per second; ns per particle-step = 1e9 / throughput, and
//! hompm/lean is the ratio; the `_bare` benches time hompm's step
//! with its monitors off (`Simulation2d::without_diagnostics`).
//!
//! Run with `cargo bench --bench lean_mpm2d`. One thread. On a loaded
//! machine count instructions instead (examples/mpm2d_step_cost.rs).

#[path = "lean/mpm2d.rs"]
mod mpm2d;

use divan::counter::ItemsCount;
use hompm::mpm2d::step::Simulation2d;
use hompm::scenes::aligned_vibration::{parameters, AlignedMethod, AlignedVibration};
use mpm2d::{LeanBilinear2d, LeanBsmpm2d};

/// Large arrays start at staggered offsets within the page
/// (`hompm::placement`): placement only, the same bits.
#[global_allocator]
static ALLOCATOR: hompm::placement::StaggeredAllocator =
    hompm::placement::StaggeredAllocator::new();

fn main() {
    divan::main();
}

const CELLS: &[usize] = &[16, 64];
const PER_SIDE: usize = 3;

fn scene() -> AlignedVibration {
    parameters("mls-paper-e1e7").expect("known set")
}

/// The simulation after one step.
fn simulation(method: AlignedMethod, cells: usize) -> Simulation2d {
    let scene = scene();
    let mut sim = scene
        .simulation(method, cells, PER_SIDE, 1.0)
        .expect("valid scene");
    sim.step(scene.dt).expect("stable");
    sim
}

fn particles(cells: usize) -> usize {
    cells * cells * PER_SIDE * PER_SIDE
}

/// About 100 000 particle-steps per sample.
fn steps(cells: usize) -> usize {
    (100_000 / particles(cells)).max(3)
}

fn hompm_step(bencher: divan::Bencher, method: AlignedMethod, cells: usize) {
    hompm_step_of(bencher, cells, move || simulation(method, cells));
}

/// hompm's step with its monitors off (`Simulation2d::without_diagnostics`),
/// as the lean step has none.
fn hompm_step_bare(bencher: divan::Bencher, method: AlignedMethod, cells: usize) {
    hompm_step_of(bencher, cells, move || {
        simulation(method, cells).without_diagnostics()
    });
}

fn hompm_step_of(bencher: divan::Bencher, cells: usize, make: impl Fn() -> Simulation2d) {
    let (n, dt) = (steps(cells), scene().dt);
    bencher
        .counter(ItemsCount::new(particles(cells) * n))
        .with_inputs(make)
        .bench_local_values(|mut sim| {
            sim.run(dt, n).expect("stable");
            sim
        });
}

#[divan::bench(args = CELLS, sample_count = 10, sample_size = 1)]
fn hompm_step_bsmpm(bencher: divan::Bencher, cells: usize) {
    hompm_step(bencher, AlignedMethod::bsmpm(2), cells);
}

#[divan::bench(args = CELLS, sample_count = 10, sample_size = 1)]
fn hompm_step_bilinear(bencher: divan::Bencher, cells: usize) {
    hompm_step(bencher, AlignedMethod::Mpm, cells);
}

#[divan::bench(args = CELLS, sample_count = 10, sample_size = 1)]
fn hompm_step_bsmpm_bare(bencher: divan::Bencher, cells: usize) {
    hompm_step_bare(bencher, AlignedMethod::bsmpm(2), cells);
}

#[divan::bench(args = CELLS, sample_count = 10, sample_size = 1)]
fn hompm_step_bilinear_bare(bencher: divan::Bencher, cells: usize) {
    hompm_step_bare(bencher, AlignedMethod::Mpm, cells);
}

#[divan::bench(args = CELLS, sample_count = 10, sample_size = 1)]
fn lean_step_bsmpm(bencher: divan::Bencher, cells: usize) {
    let (n, scene) = (steps(cells), scene());
    bencher
        .counter(ItemsCount::new(particles(cells) * n))
        .with_inputs(|| {
            LeanBsmpm2d::<3>::from_simulation(&simulation(AlignedMethod::bsmpm(2), cells), &scene)
        })
        .bench_local_values(|mut lean| {
            (0..n).for_each(|_| lean.step(scene.dt));
            lean
        });
}

#[divan::bench(args = CELLS, sample_count = 10, sample_size = 1)]
fn lean_step_bilinear(bencher: divan::Bencher, cells: usize) {
    let (n, scene) = (steps(cells), scene());
    bencher
        .counter(ItemsCount::new(particles(cells) * n))
        .with_inputs(|| {
            LeanBilinear2d::from_simulation(&simulation(AlignedMethod::Mpm, cells), &scene)
        })
        .bench_local_values(|mut lean| {
            (0..n).for_each(|_| lean.step(scene.dt));
            lean
        });
}
