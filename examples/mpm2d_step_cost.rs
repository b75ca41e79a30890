//! Runs the 2D step of benches/lean_mpm2d.rs for a given number of steps,
//! one variant at a time, so that `valgrind --tool=callgrind` can count
//! its instructions: the difference between two step counts divided by
//! the extra particle-steps is the cost per particle-step, free of the
//! set-up and independent of the machine's load (issue #39).
//!
//! `cargo run --release --example mpm2d_step_cost -- VARIANT CELLS STEPS`
//! with VARIANT one of `hompm-bsmpm`, `lean-bsmpm` (quadratic B-splines,
//! benches/lean/mpm2d.rs), `hompm-bilinear` and `lean-bilinear`, and
//! `hompm-bsmpm-bare` and `hompm-bilinear-bare`, hompm's step with its
//! monitors off (`Simulation2d::without_diagnostics`), as the lean step
//! has none. The
//! aligned vibration of the MLS paper (`mls-paper-e1e7`), 9 particles per
//! cell, Δt = 1e-5 s, the manufactured body force included; one step is
//! taken before the counted ones, as in the bench. With the environment
//! variable `PORTABLE` set, every kernel takes its baseline copy
//! (`hompm::dispatch::force_portable`), to see what AVX2 buys on a host.

#[path = "../benches/lean/mpm2d.rs"]
mod mpm2d;

use hompm::mpm2d::Mapping2d;
use hompm::scenes::aligned_vibration::{parameters, AlignedMethod};
use mpm2d::{LeanBilinear2d, LeanBsmpm2d};

/// Large arrays start at staggered offsets within the page
/// (`hompm::placement`): placement only, the same bits.
#[global_allocator]
static ALLOCATOR: hompm::placement::StaggeredAllocator =
    hompm::placement::StaggeredAllocator::new();

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let usage =
        "usage: mpm2d_step_cost hompm-bsmpm[-bare]|lean-bsmpm|hompm-bilinear[-bare]|lean-bilinear|hompm-mls|hompm-tls|hompm-pu-tls CELLS STEPS";
    let (variant, cells, steps) = match args.as_slice() {
        [_, v, c, s] => (v.as_str(), c.parse::<usize>()?, s.parse::<usize>()?),
        _ => return Err(usage.into()),
    };
    let method = match variant {
        "hompm-bsmpm" | "hompm-bsmpm-bare" | "lean-bsmpm" => AlignedMethod::bsmpm(2),
        "hompm-bilinear" | "hompm-bilinear-bare" | "lean-bilinear" => AlignedMethod::Mpm,
        "hompm-mls" => AlignedMethod::bsmpm_with(2, Mapping2d::Mls),
        "hompm-tls" => AlignedMethod::bsmpm_with(2, Mapping2d::Tls),
        "hompm-pu-tls" => AlignedMethod::bsmpm_with(2, Mapping2d::PuTls),
        _ => return Err(usage.into()),
    };
    if std::env::var_os("PORTABLE").is_some() {
        hompm::dispatch::force_portable(true);
    }
    let scene = parameters("mls-paper-e1e7")?;
    let dt = scene.dt;
    let mut sim = scene.simulation(method, cells, 3, 1.0)?;
    sim.step(dt)?;
    if variant.ends_with("-bare") {
        sim = sim.without_diagnostics();
    }
    let x = match variant {
        "lean-bsmpm" => {
            let mut lean = LeanBsmpm2d::<3>::from_simulation(&sim, &scene);
            (0..steps).for_each(|_| lean.step(dt));
            lean.x[0]
        }
        "lean-bilinear" => {
            let mut lean = LeanBilinear2d::from_simulation(&sim, &scene);
            (0..steps).for_each(|_| lean.step(dt));
            lean.x[0]
        }
        _ => {
            sim.run(dt, steps)?;
            sim.particles.x[0]
        }
    };
    println!("{x:?}");
    Ok(())
}
