//! Cost of the MUSL step for every method, mapping and mass, on the vibrating
//! bar of thesis Table 4.1 with 8 particles per cell at 64, 1024 and 16384
//! cells (512, 8192 and 131072 particles).
//!
//! Run with `cargo bench --bench mpm`; filter with a substring, e.g.
//! `cargo bench --bench mpm -- "mpm/direct"`. Each sample runs enough steps
//! for about 65 536 particle-steps; divan's throughput column ("item/s") is
//! particle-steps per second, so ns per particle-step = 1e9 / throughput.
//! One thread (the step is sequential).

use divan::counter::ItemsCount;
use hompm::mpm::grid::Method;
use hompm::mpm::mapping::{ConsistentSolver, Mapping, MassMatrix};
use hompm::scenes::{vibrating_bar, Discretisation};

/// Large arrays start at staggered offsets within the page
/// (`hompm::placement`): placement only, the same bits.
#[global_allocator]
static ALLOCATOR: hompm::placement::StaggeredAllocator =
    hompm::placement::StaggeredAllocator::new();

fn main() {
    divan::main();
}

const METHODS: &[&str] = &[
    "mpm",
    "ddmpm",
    "ddmpm-particles",
    "ddmpm-sub8",
    "bsmpm2",
    "bsmpm3",
];
const MAPPINGS: &[&str] = &["direct", "tls", "cubic-spline"];
const MASSES: &[&str] = &["lumped", "consistent", "richardson"];
const CELLS: &[usize] = &[64, 1024, 16384];

/// Every case as `method/mapping/mass/cells`. Richardson is run with the
/// cubic-spline mapping only, as in thesis §7.2.
fn cases() -> Vec<String> {
    let mut out = Vec::new();
    for m in METHODS {
        for map in MAPPINGS {
            // The per-step DDMPM rules are measured with the direct mapping,
            // where TLS paper Table 8 uses them.
            if m.starts_with("ddmpm-") && *map != "direct" {
                continue;
            }
            for mass in MASSES {
                if *mass == "richardson" && *map != "cubic-spline" {
                    continue;
                }
                for cells in CELLS {
                    out.push(format!("{m}/{map}/{mass}/{cells}"));
                }
            }
        }
    }
    out
}

fn discretisation(case: &str) -> Discretisation {
    let parts: Vec<&str> = case.split('/').collect();
    let method = match parts[0] {
        "mpm" => Method::Mpm,
        "ddmpm" => Method::DDMPM,
        // DDMPM with node integrals re-evaluated every step (issue #11).
        "ddmpm-particles" => Method::DDMPM_PARTICLES,
        "ddmpm-sub8" => Method::ddmpm_subpoints(8),
        "bsmpm3" => Method::Bsmpm { degree: 3 },
        _ => Method::Bsmpm { degree: 2 },
    };
    let mapping = match parts[1] {
        "direct" => Mapping::Direct,
        "tls" => Mapping::Tls,
        _ => Mapping::CubicSpline,
    };
    let mass = match parts[2] {
        "lumped" => MassMatrix::Lumped,
        "consistent" => MassMatrix::Consistent(ConsistentSolver::Cholesky),
        _ => MassMatrix::Consistent(ConsistentSolver::richardson(1e-9)),
    };
    let cells = parts[3].parse().expect("cell count");
    Discretisation::new(method, mapping, mass, cells, 8)
}

#[divan::bench(args = cases(), sample_count = 8, sample_size = 1)]
fn particle_steps(bencher: divan::Bencher, case: &str) {
    let p = vibrating_bar::parameters("thesis-table-4.1").expect("known set");
    let d = discretisation(case);
    let particles = d.cells * d.ppc;
    let steps = (65_536 / particles).max(2);
    bencher
        .counter(ItemsCount::new(particles * steps))
        .with_inputs(|| {
            let mut sim = p.simulation(&d).expect("valid scene");
            sim.step(1e-5).expect("stable");
            sim
        })
        .bench_local_values(|mut sim| {
            sim.run(1e-5, steps).expect("stable");
            sim
        });
}
