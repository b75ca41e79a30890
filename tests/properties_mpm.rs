//! Properties of the MPM mappings and bases: book Eq. (4.24), TLS paper §3.3
//! and §5.5.

use hompm::mpm::diagnostics::relative_l2_error;
use hompm::mpm::grid::{Grid, Method};
use hompm::mpm::mapping::{
    project_velocity, ConsistentSolver, Mapping, MappingWorkspace, MassMatrix,
};
use hompm::mpm::particles::Particles;
use proptest::prelude::*;

mod common;

fn method_strategy() -> impl Strategy<Value = Method> {
    prop_oneof![
        Just(Method::Mpm),
        Just(Method::DDMPM),
        (1usize..=4).prop_map(|degree| Method::Bsmpm { degree })
    ]
}

/// Random particles: `ppc` per cell, jittered inside their sub-interval.
fn particles(cells: usize, ppc: usize, jitter: &[f64], vel: &[f64]) -> Particles {
    let n = cells * ppc;
    let dx = 1.0 / n as f64;
    let x0: Vec<f64> = (0..n)
        .map(|k| (k as f64 + 0.5 + 0.8 * (jitter[k % jitter.len()] - 0.5)) * dx)
        .collect();
    let v: Vec<f64> = (0..n).map(|k| vel[k % vel.len()]).collect();
    let rho: Vec<f64> = (0..n)
        .map(|k| 1.0 + 0.5 * jitter[(3 * k) % jitter.len()])
        .collect();
    Particles::new(x0, vec![dx; n], rho, v, vec![0.0; n]).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Book Eq. (4.24): the direct mapping preserves total mass and momentum
    /// for any partition-of-unity basis; TLS does too (TLS paper §5.5), with
    /// lumped or consistent mass.
    #[test]
    fn mappings_conserve_mass_and_momentum(method in method_strategy(), cells in 2usize..10, ppc in 3usize..6,
                                           jitter in proptest::collection::vec(0.0f64..1.0, 7),
                                           vel in proptest::collection::vec(0.1f64..1.0, 5),
                                           tls in any::<bool>(), consistent in any::<bool>()) {
        let grid = Grid::new(method, 0.0, 1.0, cells).unwrap();
        let p = particles(cells, ppc, &jitter, &vel);
        let stencils = grid.stencils_at(&p.x).unwrap();
        let mapping = if tls { Mapping::Tls } else { Mapping::Direct };
        let mass = if consistent { MassMatrix::Consistent(ConsistentSolver::Cholesky) } else { MassMatrix::Lumped };
        // With two Gauss points per element the TLS consistent mass has rank
        // ≤ 2·cells; below the DOF count it is singular, a typed error.
        let rank_deficient = tls && consistent && 2 * cells < grid.num_dofs();
        let mut ws = MappingWorkspace::new(&grid, p.len()).unwrap();
        ws.begin_step(&grid, &p, &[mapping]).unwrap();
        let proj = match project_velocity(&grid, &p, &stencils, mapping, mass, &mut ws) {
            Err(hompm::Error::Singular(_)) if rank_deficient => return Ok(()),
            other => other.unwrap(),
        };
        let m = p.total_mass();
        let q = p.total_momentum();
        prop_assert!((proj.grid_mass - m).abs() <= 1e-12 * m);
        prop_assert!((proj.grid_momentum - q).abs() <= 1e-10 * q.abs().max(m));
    }

    /// TLS paper §3.3: the DDMPM gradients sum to zero (a rigid translation
    /// produces no strain), like the P1 gradients they blend.
    #[test]
    fn ddmpm_gradients_sum_to_zero(cells in 2usize..20, t in 0.0f64..=1.0) {
        let grid = Grid::new(Method::DDMPM, 0.0, 2.0, cells).unwrap();
        let s = grid.shape(2.0 * t).unwrap();
        let sum: f64 = s.gradients.iter().sum();
        let scale = s.gradients.iter().map(|g| g.abs()).fold(1.0, f64::max);
        prop_assert!(sum.abs() < 1e-12 * scale);
        prop_assert!((s.values.iter().sum::<f64>() - 1.0).abs() < 1e-14);
    }
}

/// A uniform velocity field is a rigid translation: one MUSL step moves every
/// particle by v Δt and creates no stress, for every method and mapping. The
/// body sits inside a larger grid, except for DDMPM, whose grid-domain
/// smoothing sees the empty DOFs beyond a free surface (docs/conventions.md).
#[test]
fn rigid_translation_creates_no_stress() {
    use hompm::mpm::musl::Simulation;
    for method in [
        Method::Mpm,
        Method::DDMPM,
        Method::Bsmpm { degree: 2 },
        Method::Bsmpm { degree: 3 },
    ] {
        for mapping in [Mapping::Direct, Mapping::Tls, Mapping::CubicSpline] {
            let grid = if method == Method::DDMPM {
                Grid::new(method, 0.0, 1.0, 4).unwrap()
            } else {
                Grid::new(method, -1.0, 2.0, 12).unwrap()
            };
            let mut p = Particles::uniform(0.0, 1.0, 16, 1.0).unwrap();
            p.v = vec![0.3; 16];
            let settings = common::free_settings(
                mapping,
                MassMatrix::Consistent(ConsistentSolver::Cholesky),
                10.0,
            );
            let mut sim = Simulation::new(grid, p, settings).unwrap();
            sim.step(1e-3).unwrap();
            for k in 0..16 {
                assert!(
                    sim.particles.stress[k].abs() < 1e-9,
                    "{method:?} {mapping:?}: σ = {}",
                    sim.particles.stress[k]
                );
                assert!(
                    (sim.particles.u[k] - 3e-4).abs() < 1e-12,
                    "{method:?} {mapping:?}: u = {}",
                    sim.particles.u[k]
                );
            }
        }
    }
}

#[test]
fn relative_l2_error_definition() {
    let e = relative_l2_error(&[1.0, 2.0], &[1.0, 1.0]).unwrap();
    assert!((e - (0.5f64).sqrt()).abs() < 1e-15);
    assert!(relative_l2_error(&[1.0], &[0.0]).is_err());
    assert!(relative_l2_error(&[], &[]).is_err());
    // Both measures refuse what they cannot compare: unequal lengths,
    // nothing at all, or a non-finite value on either side (issue #13).
    use hompm::mpm::diagnostics::rms_error;
    for (c, r) in [
        (&[1.0][..], &[1.0, 2.0][..]),
        (&[][..], &[][..]),
        (&[f64::NAN][..], &[1.0][..]),
        (&[1.0][..], &[f64::INFINITY][..]),
    ] {
        assert!(rms_error(c, r).is_err(), "{c:?} against {r:?}");
        assert!(relative_l2_error(c, r).is_err(), "{c:?} against {r:?}");
    }
    assert_eq!(rms_error(&[1.0, 3.0], &[1.0, 1.0]).unwrap(), 2.0f64.sqrt());
}

/// Book Eqs. (4.39)–(4.44), TLS paper §5.4: the TLS mapping fits ρv (not
/// ρ or v alone) per cell and integrates it against φ_i. With ρ = 1 + x and
/// v = 1 − x, ρv = 1 − x² is quadratic, so quadratic TLS reproduces it up
/// to the constant that conserves the particles' cell momentum (a
/// midpoint-rule error of O(h²)), and p_i = ∫ρv φ_i follows.
#[test]
fn tls_projection_integrates_the_product_of_density_and_velocity() {
    use hompm::mpm::mapping::assemble_projection;
    use hompm::quadrature::gauss_on_cells;
    let grid = Grid::new(Method::Bsmpm { degree: 2 }, 0.0, 1.0, 8).unwrap();
    let n = 8 * 16;
    let x0: Vec<f64> = (0..n).map(|k| (k as f64 + 0.5) / n as f64).collect();
    let volume = vec![1.0 / n as f64; n];
    let density: Vec<f64> = x0.iter().map(|x| 1.0 + x).collect();
    let velocity: Vec<f64> = x0.iter().map(|x| 1.0 - x).collect();
    let particles = Particles::new(x0, volume, density, velocity, vec![0.0; n]).unwrap();
    let stencils = grid.stencils_at(&particles.x).unwrap();
    let mut ws = MappingWorkspace::new(&grid, n).unwrap();
    ws.begin_step(&grid, &particles, &[Mapping::Tls]).unwrap();
    assemble_projection(&grid, &particles, &stencils, Mapping::Tls, false, &mut ws).unwrap();
    let mut exact = vec![0.0; grid.num_dofs()];
    for q in gauss_on_cells(&grid.cells(), 6).unwrap() {
        let s = grid.shape(q.x).unwrap();
        for (j, phi) in s.values.iter().enumerate() {
            exact[s.first + j] += q.weight * (1.0 - q.x * q.x) * phi;
        }
    }
    for (i, (p, e)) in ws.momentum.iter().zip(&exact).enumerate() {
        assert!((p - e).abs() < 2e-4, "p_{i} = {p}, ∫ρvφ_{i} = {e}");
    }
}
