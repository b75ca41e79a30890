//! Cost of the 2D step of the MLS paper (bilinear MPM, quadratic BSMPM,
//! quadratic BSMPM with MLS or with 2D TLS) on the aligned vibration with 9 particles per
//! cell at 16 and 64 cells per direction (2 304 and 36 864 particles), body
//! force included.
//!
//! Run with `cargo bench --bench mpm2d`. Each sample runs enough steps for
//! about 100 000 particle-steps; divan's throughput column ("item/s") is
//! particle-steps per second, so ns per particle-step = 1e9 / throughput.
//! One thread (the step is sequential).

use divan::counter::ItemsCount;
use hompm::scenes::aligned_vibration::{parameters, AlignedMethod};

fn main() {
    divan::main();
}

const CASES: &[&str] = &[
    "mpm/16",
    "mpm/64",
    "bsmpm2/16",
    "bsmpm2/64",
    "bsmpm2-mls/16",
    "bsmpm2-mls/64",
    "bsmpm2-tls/16",
    "bsmpm2-tls/64",
];

#[divan::bench(args = CASES, sample_count = 8, sample_size = 1)]
fn particle_steps(bencher: divan::Bencher, case: &str) {
    let (method, cells) = case.split_once('/').expect("method/cells");
    let method = match method {
        "mpm" => AlignedMethod::Mpm,
        "bsmpm2" => AlignedMethod::Bsmpm { degree: 2 },
        "bsmpm2-mls" => AlignedMethod::BsmpmMls { degree: 2 },
        _ => AlignedMethod::BsmpmTls { degree: 2 },
    };
    let cells: usize = cells.parse().expect("cells");
    let scene = parameters("mls-paper-e1e7").expect("known set");
    let particles = cells * cells * 9;
    let steps = (100_000 / particles).max(3);
    bencher
        .counter(ItemsCount::new(particles * steps))
        .with_inputs(|| {
            let mut sim = scene
                .simulation(method, cells, 3, 1.0)
                .expect("valid scene");
            sim.step(scene.dt).expect("stable");
            sim
        })
        .bench_local_values(|mut sim| {
            sim.run(scene.dt, steps).expect("stable");
            sim
        });
}
