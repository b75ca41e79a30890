//! Cost of the 2D step of the MLS paper (bilinear MPM, quadratic BSMPM,
//! quadratic BSMPM with MLS or with 2D TLS) on the aligned vibration with 9 particles per
//! cell at 16 and 64 cells per direction (2 304 and 36 864 particles), body
//! force included.
//!
//! Run with `cargo bench --bench mpm2d`. Each sample runs enough steps for
//! about 100 000 particle-steps; divan's throughput column ("item/s") is
//! particle-steps per second, so ns per particle-step = 1e9 / throughput.
//! One thread (the step is sequential).
//!
//! `phase` times each phase function of the step on its own, once over all
//! particles of a simulation that has taken one step, in the same unit
//! (ns per particle): where a step's time goes, so that a change to one
//! phase is measured where it is made. `basis` is Eqs. (4)–(5) on both
//! axes, `body-force` the manufactured b_p(t), `map` phase 1 (Eqs. 18–25,
//! direct or reconstructed), `nodal` Eqs. (26)–(28), `particles` (29)–(30),
//! `end-of-step` (31)–(33), `deformation` (34)–(37) and (41).

use divan::counter::ItemsCount;
use hompm::mpm2d::step::{
    end_of_step_velocity, evaluate_basis, map_direct, map_reconstructed, nodal_update,
    update_deformation, update_particles, Simulation2d,
};
use hompm::mpm2d::Mapping2d;
use hompm::scenes::aligned_vibration::{parameters, AlignedMethod};

/// Large arrays start at staggered offsets within the page
/// (`hompm::placement`): placement only, the same bits.
#[global_allocator]
static ALLOCATOR: hompm::placement::StaggeredAllocator =
    hompm::placement::StaggeredAllocator::new();

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

/// "method/cells" → the method and the cells per side.
fn case_of(case: &str) -> (AlignedMethod, usize) {
    let (method, cells) = case.split_once('/').expect("method/cells");
    let method = match method {
        "mpm" => AlignedMethod::Mpm,
        "bsmpm2" => AlignedMethod::bsmpm(2),
        "bsmpm2-mls" => AlignedMethod::bsmpm_with(2, Mapping2d::Mls),
        _ => AlignedMethod::bsmpm_with(2, Mapping2d::Tls),
    };
    (method, cells.parse().expect("cells"))
}

#[divan::bench(args = CASES, sample_count = 8, sample_size = 1)]
fn particle_steps(bencher: divan::Bencher, case: &str) {
    let (method, cells) = case_of(case);
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

const PHASES: &[&str] = &[
    "basis",
    "body-force",
    "map",
    "nodal",
    "particles",
    "end-of-step",
    "deformation",
];

/// "phase:method/cells" for every phase and method at 64 cells.
fn phase_cases() -> Vec<String> {
    let methods = ["mpm", "bsmpm2", "bsmpm2-mls", "bsmpm2-tls"];
    PHASES
        .iter()
        .flat_map(|phase| methods.map(|m| format!("{phase}:{m}/64")))
        .collect()
}

// divan hands each argument as &T, and the cases are built Strings.
#[allow(clippy::ptr_arg)]
#[divan::bench(args = phase_cases(), sample_count = 8, sample_size = 1)]
fn phase(bencher: divan::Bencher, case: &String) {
    let (phase, case) = case.split_once(':').expect("phase:case");
    let (method, cells) = case_of(case);
    let scene = parameters("mls-paper-e1e7").expect("known set");
    let particles = cells * cells * 9;
    let dt = scene.dt;
    bencher
        .counter(ItemsCount::new(particles))
        .with_inputs(|| {
            let mut sim = scene
                .simulation(method, cells, 3, 1.0)
                .expect("valid scene");
            sim.step(dt).expect("stable");
            sim
        })
        .bench_local_values(|mut sim: Simulation2d| {
            let (mapping, conventions) = (sim.settings.mapping, sim.settings.conventions);
            let (grid, p, ws) = (&sim.grid, &mut sim.particles, &mut sim.workspace);
            match phase {
                "basis" => evaluate_basis(grid, p, ws, 1).expect("inside"),
                "body-force" => {
                    if let Some(b) = &sim.body_force {
                        b.fill(dt, &p.x0, &mut ws.body_force);
                    }
                }
                "map" if mapping == Mapping2d::Direct => map_direct(grid, p, ws),
                "map" => map_reconstructed(grid, p, ws).expect("reconstructs"),
                "nodal" => nodal_update(grid, ws, dt),
                "particles" => update_particles(grid, p, ws, conventions, dt),
                "end-of-step" => end_of_step_velocity(grid, p, ws, mapping),
                _ => update_deformation(grid, p, ws, &sim.settings.material, dt).expect("stable"),
            }
            sim
        });
}
