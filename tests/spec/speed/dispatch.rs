//! Issue #39: the kernels that `hompm::dispatch` compiles twice (for the
//! x86-64 baseline and with AVX2) give the same bits, so the processor a
//! run lands on changes its time and nothing else. Each method that runs
//! one of them (MLS: the moment sums, the shape functions, the Gauss-point
//! sums; PU-TLS: the blend of its patches, the Gauss-point sums; TLS: the
//! normal solve of each cell; every 2D method: the mapping-error record) takes 40 steps of the aligned vibration once on each copy, and
//! every bit of every particle and of the record must agree.
//!
//! `dispatch::force_portable` is process-wide: a test that runs beside
//! this one may take the baseline copy for a while, which by the claim
//! tested here changes none of its bits.

use hompm::dispatch::{avx2_in_use, force_portable};
use hompm::mpm2d::Mapping2d;
use hompm::scenes::aligned_vibration::{parameters, AlignedMethod};

/// The bits of every particle quantity and of the mapping-error record
/// after `steps` steps on `cells`² cells, 9 particles per cell.
fn state_bits(method: AlignedMethod, cells: usize, steps: usize) -> Vec<u64> {
    let scene = parameters("mls-paper-e1e7").unwrap();
    let mut sim = scene.simulation(method, cells, 3, 1.0).unwrap();
    for _ in 0..steps {
        sim.step(scene.dt).unwrap();
    }
    let p = &sim.particles;
    let mut bits = Vec::new();
    for k in 0..p.len() {
        bits.extend(p.x[k].iter().chain(&p.velocity[k]).map(|v| v.to_bits()));
        bits.extend(
            p.deformation[k]
                .iter()
                .chain(p.stress[k].iter())
                .map(|v| v.to_bits()),
        );
        bits.extend([p.volume[k], p.density[k]].map(f64::to_bits));
    }
    let c = sim.conservation;
    bits.extend([c.mass, c.momentum].map(f64::to_bits));
    bits
}

#[test]
fn avx2_and_baseline_kernels_give_the_same_bits() {
    let methods = [
        AlignedMethod::bsmpm_with(2, Mapping2d::Mls),
        AlignedMethod::bsmpm_with(2, Mapping2d::PuTls),
        AlignedMethod::bsmpm_with(2, Mapping2d::Tls),
        AlignedMethod::bsmpm(2),
        AlignedMethod::Mpm,
    ];
    #[cfg(target_arch = "x86_64")]
    let has_avx2 = std::arch::is_x86_feature_detected!("avx2");
    #[cfg(not(target_arch = "x86_64"))]
    let has_avx2 = false;
    if !has_avx2 {
        eprintln!(
            "this processor has no AVX2: both runs take the baseline copy, nothing is compared"
        );
    }
    for method in methods {
        force_portable(true);
        assert!(!avx2_in_use(), "force_portable(true) leaves AVX2 on");
        let baseline = state_bits(method, 6, 40);
        force_portable(false);
        assert_eq!(avx2_in_use(), has_avx2, "the AVX2 kernels are not taken");
        let dispatched = state_bits(method, 6, 40);
        let differing = baseline
            .iter()
            .zip(&dispatched)
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(
            (differing, baseline.len()),
            (0, dispatched.len()),
            "{method:?}: {differing} of {} values differ between the baseline and the AVX2 kernels",
            baseline.len()
        );
    }
}
