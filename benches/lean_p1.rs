//! hompm's 1D P1 MUSL step against the lean step of benches/lean/p1.rs
//! (issue #39): the same bar (thesis Table 4.1), the same numbers bit for
//! bit (tests/spec/speed/lean_p1.rs), 4 particles per cell on 1024 and
//! 16384 cells. divan's throughput ("item/s") is particle-steps per
//! second; ns per particle-step = 1e9 / throughput, and hompm/lean is the
//! issue's ratio (target ≤ 1.4).
//!
//! Three hompm variants show what the monitors cost: the step as every
//! scene runs it (its `RunDiagnostics` on), the same step watched by the
//! stability monitor after every step (what `hompm run` does), and the step
//! with its diagnostics off (`Simulation::without_diagnostics`, the same
//! numbers).
//!
//! Run with `cargo bench --bench lean_p1`. One thread.

#[path = "lean/p1.rs"]
mod p1;

use divan::counter::ItemsCount;
use hompm::mpm::grid::Method;
use hompm::mpm::monitor::StabilityMonitor;
use hompm::scenes::{vibrating_bar, Discretisation};
use p1::LeanP1;

/// Large arrays start at staggered offsets within the page
/// (`hompm::placement`): placement only, the same bits.
#[global_allocator]
static ALLOCATOR: hompm::placement::StaggeredAllocator =
    hompm::placement::StaggeredAllocator::new();

fn main() {
    divan::main();
}

const CELLS: &[usize] = &[1024, 16384];
const PPC: usize = 4;
const DT: f64 = 1e-5;

fn simulation(cells: usize) -> hompm::mpm::musl::Simulation {
    let p = vibrating_bar::parameters("thesis-table-4.1").expect("known set");
    let mut sim = p
        .simulation(&Discretisation::direct(Method::Mpm, cells, PPC))
        .expect("valid scene");
    sim.step(DT).expect("stable");
    sim
}

fn steps(cells: usize) -> usize {
    (262_144 / (cells * PPC)).max(2)
}

#[divan::bench(args = CELLS, sample_count = 10, sample_size = 1)]
fn hompm_step(bencher: divan::Bencher, cells: usize) {
    let n = steps(cells);
    bencher
        .counter(ItemsCount::new(cells * PPC * n))
        .with_inputs(|| simulation(cells))
        .bench_local_values(|mut sim| {
            for _ in 0..n {
                sim.step(DT).expect("stable");
            }
            sim
        });
}

#[divan::bench(args = CELLS, sample_count = 10, sample_size = 1)]
fn hompm_step_watched(bencher: divan::Bencher, cells: usize) {
    let n = steps(cells);
    bencher
        .counter(ItemsCount::new(cells * PPC * n))
        .with_inputs(|| {
            let sim = simulation(cells);
            let monitor = StabilityMonitor::new(&sim, DT).expect("monitor");
            (sim, monitor)
        })
        .bench_local_values(|(mut sim, mut monitor)| {
            for _ in 0..n {
                let summary = sim.step_summarised(DT).expect("stable");
                monitor.check_step(&sim, &summary).expect("within budget");
            }
            sim
        });
}

#[divan::bench(args = CELLS, sample_count = 10, sample_size = 1)]
fn hompm_step_without_diagnostics(bencher: divan::Bencher, cells: usize) {
    let n = steps(cells);
    bencher
        .counter(ItemsCount::new(cells * PPC * n))
        .with_inputs(|| simulation(cells).without_diagnostics())
        .bench_local_values(|mut sim| {
            for _ in 0..n {
                sim.step(DT).expect("stable");
            }
            sim
        });
}

#[divan::bench(args = CELLS, sample_count = 10, sample_size = 1)]
fn lean_step(bencher: divan::Bencher, cells: usize) {
    let n = steps(cells);
    bencher
        .counter(ItemsCount::new(cells * PPC * n))
        .with_inputs(|| LeanP1::from_simulation(&simulation(cells)))
        .bench_local_values(|mut lean| {
            for _ in 0..n {
                lean.step(DT);
            }
            lean
        });
}
