//! Runs the 1D P1 step of benches/lean_p1.rs for a given number of steps,
//! one variant at a time, so that `valgrind --tool=callgrind` can count
//! its instructions: the difference between two step counts divided by
//! the extra particle-steps is the cost per particle-step, free of the
//! set-up and independent of the machine's load (issue #39).
//!
//! `cargo run --release --example p1_step_cost -- VARIANT CELLS STEPS`
//! with VARIANT one of `step` (diagnostics on), `watched` (and the
//! stability monitor after every step), `bare` (diagnostics off) and
//! `lean` (benches/lean/p1.rs). 4 particles per cell, Δt = 1e-5 s, the bar
//! of thesis Table 4.1.

#[path = "../benches/lean/p1.rs"]
mod p1;

use hompm::mpm::grid::Method;
use hompm::mpm::monitor::StabilityMonitor;
use hompm::scenes::{vibrating_bar, Discretisation};

/// Large arrays start at staggered offsets within the page
/// (`hompm::placement`): placement only, the same bits.
#[global_allocator]
static ALLOCATOR: hompm::placement::StaggeredAllocator =
    hompm::placement::StaggeredAllocator::new();

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: p1_step_cost step|watched|bare|lean CELLS STEPS";
    let (variant, cells, steps) = match args.as_slice() {
        [_, v, c, s] => (v.as_str(), c.parse::<usize>()?, s.parse::<usize>()?),
        _ => return Err(usage.into()),
    };
    let dt = 1e-5;
    let p = vibrating_bar::parameters("thesis-table-4.1")?;
    let mut sim = p.simulation(&Discretisation::direct(Method::Mpm, cells, 4))?;
    sim.step(dt)?;
    match variant {
        "step" => (0..steps).try_for_each(|_| sim.step(dt))?,
        "watched" => {
            let mut monitor = StabilityMonitor::new(&sim, dt)?;
            for _ in 0..steps {
                let summary = sim.step_summarised(dt)?;
                monitor.check_step(&sim, &summary)?;
            }
        }
        "bare" => {
            sim = sim.without_diagnostics();
            (0..steps).try_for_each(|_| sim.step(dt))?;
        }
        "lean" => {
            let mut lean = p1::LeanP1::from_simulation(&sim);
            for _ in 0..steps {
                lean.step(dt);
            }
            println!("{}", lean.x[0]);
        }
        _ => return Err(usage.into()),
    }
    println!("{}", sim.particles.x[0]);
    Ok(())
}
