//! A steady-state MUSL step allocates nothing (direct mapping, lumped mass),
//! and the reconstructions allocate the same bounded amount every step.
//!
//! This test binary installs a counting global allocator. The count is kept
//! per thread, so tests running in parallel do not see each other's
//! allocations.

use hompm::mpm::grid::Method;
use hompm::mpm::mapping::{ConsistentSolver, Mapping, MassMatrix};
use hompm::mpm::musl::Simulation;
use hompm::mpm2d::Mapping2d;
use hompm::scenes::{vibrating_bar, Discretisation};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct CountingAllocator;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn count_one() {
    // try_with: the thread-local may already be gone while a thread exits.
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
}

// SAFETY: every call is forwarded unchanged to the system allocator; the
// counter only reads and writes a thread-local integer.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count_one();
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count_one();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count_one();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

fn allocations() -> usize {
    ALLOCATIONS.with(|c| c.get())
}

/// The vibrating bar of thesis Table 4.1 with the given discretisation.
fn bar(d: Discretisation) -> Simulation {
    vibrating_bar::parameters("thesis-table-4.1")
        .unwrap()
        .simulation(&d)
        .unwrap()
}

/// Allocations of each of `steps` steps of 1e-5 s.
fn allocations_per_step(sim: &mut Simulation, steps: usize) -> Vec<usize> {
    (0..steps)
        .map(|_| {
            let before = allocations();
            sim.step(1e-5).unwrap();
            allocations() - before
        })
        .collect()
}

#[test]
fn direct_mapping_with_lumped_mass_allocates_nothing_after_the_first_step() {
    for method in [
        Method::Mpm,
        Method::MpmP2,
        Method::DDMPM,
        Method::DDMPM_PARTICLES,
        Method::ddmpm_subpoints(8),
        Method::Bsmpm { degree: 2 },
        Method::Bsmpm { degree: 3 },
    ] {
        let mut sim = bar(Discretisation::direct(method, 32, 4));
        sim.step(1e-5).unwrap();
        let counts = allocations_per_step(&mut sim, 20);
        assert!(
            counts.iter().all(|&c| c == 0),
            "{method:?}: allocations per step {counts:?}"
        );
    }
}

#[test]
fn reconstruction_allocations_do_not_grow_with_the_number_of_steps() {
    let cholesky = MassMatrix::Consistent(ConsistentSolver::Cholesky);
    let richardson = MassMatrix::Consistent(ConsistentSolver::richardson(1e-9));
    for (mapping, mass) in [
        (Mapping::Tls, MassMatrix::Lumped),
        (Mapping::Tls, cholesky),
        (Mapping::CubicSpline, cholesky),
        (Mapping::CubicSpline, richardson),
        (Mapping::Direct, cholesky),
    ] {
        let d = Discretisation::new(Method::Bsmpm { degree: 2 }, mapping, mass, 32, 4);
        let mut sim = bar(d);
        sim.step(1e-5).unwrap();
        let early = allocations_per_step(&mut sim, 5);
        allocations_per_step(&mut sim, 100);
        let late = allocations_per_step(&mut sim, 5);
        let bound = early.iter().max().copied().unwrap_or(0);
        assert!(
            late.iter().all(|&c| c <= bound),
            "{mapping:?} {mass:?}: {early:?} early, {late:?} after 100 more steps"
        );
    }
}

/// The 2D step of the MLS paper allocates nothing once warm: direct
/// mappings (MPM, BSMPM, the total-Lagrangian reference), the MLS
/// mapping, whose lists only grow when a Gauss point gathers more particles
/// than ever before (MLS paper Eqs. 18–37), and PU-TLS, whose buffers are
/// sized in `PuTlsShapes::new` for the most a step can need.
#[test]
fn a_steady_2d_step_allocates_nothing() {
    use hompm::scenes::aligned_vibration::{parameters, AlignedMethod};
    let scene = parameters("mls-paper-e1e7").unwrap();
    for method in [
        AlignedMethod::Mpm,
        AlignedMethod::bsmpm(2),
        AlignedMethod::bsmpm_with(2, Mapping2d::Mls),
        AlignedMethod::bsmpm_with(2, Mapping2d::PuTls),
        AlignedMethod::bsmpm_with(2, Mapping2d::PuTlsQuadratic),
        AlignedMethod::TotalLagrangian { degree: 2 },
    ] {
        let mut sim = scene.simulation(method, 4, 3, 1.0).unwrap();
        sim.run(scene.dt, 3).unwrap();
        let before = allocations();
        sim.run(scene.dt, 10).unwrap();
        assert_eq!(allocations() - before, 0, "{method:?}");
    }
}

/// Book Eqs. (4.26)–(4.29) with one to four unknowns are solved in stack
/// matrices: a fit allocates only its coefficient vector. (The dynamic
/// path gives the same numbers but allocates D, BF and the eigen workspace.)
#[test]
fn least_squares_fits_of_up_to_four_unknowns_allocate_only_their_coefficients() {
    use hompm::reconstruct::least_squares::fit_rows;
    for nb in 1..=4 {
        let xs: [f64; 6] = [0.1, 0.3, 0.45, 0.7, 0.9, 1.2];
        let row = |p: usize, psi: &mut [f64]| {
            for (k, v) in psi.iter_mut().enumerate() {
                *v = xs[p].powi(k as i32);
            }
        };
        let before = allocations();
        let fit = fit_rows(xs.len(), nb, row, |p| 1.0 + xs[p], None).unwrap();
        assert_eq!(allocations() - before, 1, "nb = {nb}");
        assert_eq!(fit.coefficients.len(), nb);
    }
}
