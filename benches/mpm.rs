//! Particle-steps per second of one MUSL step for each method, on the vibrating
//! bar of thesis Table 4.1 with 64 cells × 8 PPC (512 particles). Run with
//! `cargo bench --bench mpm`; divan prints the time of 10 steps, so
//! particle-steps/s = 5120 / time.

use hompm::mpm::grid::Method;
use hompm::mpm::mapping::{ConsistentSolver, Mapping, MassMatrix};
use hompm::scenes::{vibrating_bar, Discretisation};

fn main() {
    divan::main();
}

const CASES: &[&str] = &[
    "mpm/direct/lumped",
    "ddmpm/direct/lumped",
    "bsmpm2/direct/lumped",
    "bsmpm3/direct/lumped",
    "bsmpm2/direct/consistent",
    "bsmpm2/tls/lumped",
    "bsmpm2/tls/consistent",
    "bsmpm2/cubic-spline/richardson",
];

fn discretisation(case: &str) -> Discretisation {
    let parts: Vec<&str> = case.split('/').collect();
    let method = match parts[0] {
        "mpm" => Method::Mpm,
        "ddmpm" => Method::Ddmpm,
        "bsmpm3" => Method::Bsmpm { degree: 3 },
        _ => Method::Bsmpm { degree: 2 },
    };
    let mapping = Mapping::parse(parts[1]).expect("known mapping");
    let mass = match parts[2] {
        "lumped" => MassMatrix::Lumped,
        "consistent" => MassMatrix::Consistent(ConsistentSolver::Cholesky),
        _ => MassMatrix::Consistent(ConsistentSolver::Richardson { tolerance: 1e-9 }),
    };
    Discretisation {
        method,
        force_mapping: mapping,
        velocity_mapping: mapping,
        mass,
        cells: 64,
        ppc: 8,
    }
}

#[divan::bench(args = CASES, sample_count = 20)]
fn ten_steps(bencher: divan::Bencher, case: &str) {
    let p = vibrating_bar::parameters("thesis-table-4.1").expect("known set");
    let d = discretisation(case);
    bencher
        .with_inputs(|| p.simulation(&d).expect("valid scene"))
        .bench_local_values(|mut sim| {
            sim.run(1e-5, 10).expect("stable");
            sim
        });
}
