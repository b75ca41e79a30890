//! Issue #39, the 2D step: what was made faster computes the same bits.
//! The mapping-error record sums the particles in one pass
//! (`record_conservation`), and `Simulation2d::without_diagnostics` skips
//! it without changing the particles; the neo-Hookean σ is formed entry by
//! entry with the bits of its matrix expression; a step nobody observes
//! fuses phase 3 with the end-of-step scatter and gets the bits of the
//! two passes (and, with a reconstruction, gathers [ρ_p, v_p] as the
//! particles move, with the bits of a pass of its own); the basis of both
//! axes is evaluated in paired lanes with the bits of one axis at a time.

use hompm::mpm::conventions::{Conventions, Positions, Scheme, Transfer};
use hompm::mpm::diagnostics::compensated_sum;
use hompm::mpm2d::material::NeoHookean;
use hompm::mpm2d::step::{
    evaluate_basis, fuses_end_of_step, fuses_end_values, Conservation2d, Mapping2d, Simulation2d,
    StepObserver2d, StepPoint2d,
};
use hompm::scenes::aligned_vibration::{parameters, AlignedMethod};
use hompm::Result;
use nalgebra::Matrix2;

/// The aligned vibration of the MLS paper on `cells` cells per side, 9
/// particles per cell.
fn simulation(method: AlignedMethod, cells: usize) -> Simulation2d {
    let scene = parameters("mls-paper-e1e7").unwrap();
    scene.simulation(method, cells, 3, 1.0).unwrap()
}

/// After phase 1, the record the step just updated against the record
/// formed from one compensated sum per quantity, each its own pass (the
/// record as it was before issue #39).
struct OnePassPerSum {
    before: Conservation2d,
    checked: usize,
}

impl StepObserver2d for OnePassPerSum {
    fn observe(&mut self, point: StepPoint2d, sim: &mut Simulation2d) -> Result<()> {
        if point != StepPoint2d::GridMapping {
            return Ok(());
        }
        let (p, ws) = (&sim.particles, &sim.workspace);
        let particle_mass = compensated_sum(p.mass.iter().copied());
        let grid_mass = compensated_sum(ws.mass.iter().copied());
        let speeds = p.mass.iter().zip(&p.velocity);
        let scale = compensated_sum(speeds.map(|(m, v)| m * (v[0] * v[0] + v[1] * v[1]).sqrt()));
        let component = |d: usize| {
            let particles = compensated_sum(p.mass.iter().zip(&p.velocity).map(|(m, v)| m * v[d]));
            compensated_sum(ws.momentum.iter().map(|m| m[d])) - particles
        };
        let mut expected = self.before;
        expected.mass = expected
            .mass
            .max((grid_mass - particle_mass).abs() / particle_mass);
        if scale > 0.0 {
            expected.momentum = expected
                .momentum
                .max(component(0).hypot(component(1)) / scale);
        }
        assert_eq!(
            format!("{:?}", sim.conservation),
            format!("{expected:?}"),
            "step {}",
            sim.steps
        );
        self.before = sim.conservation;
        self.checked += 1;
        Ok(())
    }
}

/// The mapping errors of 200 steps of BSMPM and bilinear MPM are, bit for
/// bit, those of one compensated sum per pass, and are not all zero.
#[test]
fn the_2d_mapping_errors_in_one_pass_are_those_of_one_pass_per_sum() {
    for method in [AlignedMethod::bsmpm(2), AlignedMethod::Mpm] {
        let mut sim = simulation(method, 8);
        let dt = parameters("mls-paper-e1e7").unwrap().dt;
        let mut check = OnePassPerSum {
            before: sim.conservation,
            checked: 0,
        };
        for _ in 0..200 {
            sim.step_observed(dt, &mut check).unwrap();
        }
        assert_eq!(check.checked, 200);
        assert!(sim.conservation.mass > 0.0 || sim.conservation.momentum > 0.0);
    }
}

/// `without_diagnostics` leaves the record at its start and every particle
/// as the step with it on leaves it, bit for bit.
#[test]
fn the_2d_step_without_diagnostics_moves_the_particles_as_with_them() {
    for method in [AlignedMethod::bsmpm(2), AlignedMethod::Mpm] {
        let dt = parameters("mls-paper-e1e7").unwrap().dt;
        let mut on = simulation(method, 8);
        let mut off = simulation(method, 8).without_diagnostics();
        assert!(on.records_diagnostics() && !off.records_diagnostics());
        on.run(dt, 100).unwrap();
        off.run(dt, 100).unwrap();
        assert_eq!(
            format!("{:?}", on.particles),
            format!("{:?}", off.particles)
        );
        assert_eq!(off.conservation, Conservation2d::default());
        assert_ne!(on.conservation, Conservation2d::default());
    }
}

/// σ of Eq. (41) entry by entry (`NeoHookean::cauchy_stress_given_jacobian`)
/// is, bit for bit, the matrix expression (λ ln J / J) I + (F Fᵀ − I)(μ / J)
/// nalgebra evaluates, for deformations near and far from I, with signed
/// zeros off the diagonal.
#[test]
fn the_stress_entry_by_entry_is_the_matrix_expression_bit_for_bit() {
    let material = NeoHookean::from_young_poisson(1e7, 0.3).unwrap();
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut checked = 0;
    for k in 0..20_000 {
        let scale = [1e-12, 1e-6, 1e-2, 0.5][k % 4];
        let mut f = Matrix2::new(
            1.0 + scale * next(),
            scale * next(),
            scale * next(),
            1.0 + scale * next(),
        );
        if k % 5 == 0 {
            f[(0, 1)] = -0.0;
            f[(1, 0)] = if k % 10 == 0 { 0.0 } else { -0.0 };
        }
        let Ok(j) = NeoHookean::jacobian(&f) else {
            continue;
        };
        let b = f * f.transpose();
        let expected = Matrix2::identity() * (material.lambda * j.ln() / j)
            + (b - Matrix2::identity()) * (material.mu / j);
        let got = material.cauchy_stress_given_jacobian(&f, j);
        for (g, e) in got.iter().zip(expected.iter()) {
            assert_eq!(g.to_bits(), e.to_bits(), "F = {f:?}");
        }
        checked += 1;
    }
    assert!(checked > 19_000);
}

/// An observer that looks at every point and changes nothing: the step
/// takes one pass per phase.
struct Looks;

impl StepObserver2d for Looks {
    fn observe(&mut self, _: StepPoint2d, _: &mut Simulation2d) -> Result<()> {
        Ok(())
    }
}

/// Steps `fused` and `passes` (the same simulation) 300 times, the first
/// unobserved, the second observed at every point, and compares their
/// particles, end-of-step arrays and records bit for bit.
fn assert_fused_and_passes_agree(mut fused: Simulation2d, mut passes: Simulation2d) {
    let dt = parameters("mls-paper-e1e7").unwrap().dt;
    for _ in 0..300 {
        fused.step(dt).unwrap();
        passes.step_observed(dt, &mut Looks).unwrap();
    }
    assert_eq!(
        format!("{:?}", fused.particles),
        format!("{:?}", passes.particles)
    );
    let (a, b) = (&fused.workspace, &passes.workspace);
    for (x, y) in [
        (&a.momentum_end, &b.momentum_end),
        (&a.velocity_end, &b.velocity_end),
        (&a.velocity_next, &b.velocity_next),
    ] {
        assert_eq!(format!("{x:?}"), format!("{y:?}"));
    }
    assert_eq!(format!("{:?}", a.end_values), format!("{:?}", b.end_values));
    assert_eq!(
        format!("{:?}", fused.conservation),
        format!("{:?}", passes.conservation)
    );
    assert_eq!(fused.time, passes.time);
    let moved = fused.particles.displacement.iter().map(|u| u[0].abs());
    assert!(moved.fold(0.0, f64::max) > 1e-4);
}

/// A step nobody observes runs phase 3 and the end-of-step scatter in one
/// particle loop (`update_particles_and_end_momentum`); the observed step
/// runs `update_particles` and `end_of_step_velocity`. After 300 steps of
/// BSMPM p = 2, p = 3 and bilinear MPM, the particles and every nodal
/// array agree bit for bit.
#[test]
fn the_fused_end_of_step_computes_the_bits_of_the_two_passes() {
    for method in [
        AlignedMethod::bsmpm(2),
        AlignedMethod::bsmpm(3),
        AlignedMethod::Mpm,
    ] {
        let fused = simulation(method, 8);
        let (conventions, mapping) = (fused.settings.conventions, fused.settings.mapping);
        assert!(fuses_end_of_step(conventions, mapping));
        assert_fused_and_passes_agree(fused, simulation(method, 8));
    }
}

/// With a reconstruction (MLS, TLS, PU-TLS), a step nobody observes
/// gathers each particle's [ρ_p, v_p] in phase 3's loop
/// (`update_particles_and_end_values`); the observed step packs them in
/// `end_of_step_velocity`. After 300 steps the particles, the end-of-step
/// arrays, the gathered values and the record agree bit for bit.
#[test]
fn the_reconstructed_end_of_step_gathering_as_particles_move_computes_the_bits_of_the_two_passes() {
    for mapping in [Mapping2d::Mls, Mapping2d::Tls, Mapping2d::PuTls] {
        let method = AlignedMethod::bsmpm_with(2, mapping);
        let fused = simulation(method, 6);
        let conventions = fused.settings.conventions;
        assert!(fuses_end_values(conventions, mapping));
        assert!(!fuses_end_of_step(conventions, mapping));
        assert_fused_and_passes_agree(fused, simulation(method, 6));
    }
}

/// Another code's conventions (PIC, a FLIP/PIC blend, the projected
/// positions, USL) take neither fused end of step: with MLS, the step
/// nobody observes computes the observed step's bits for each.
#[test]
fn other_codes_conventions_with_a_reconstruction_take_the_passes() {
    let scene = parameters("mls-paper-e1e7").unwrap();
    let method = AlignedMethod::bsmpm_with(2, Mapping2d::Mls);
    let paper = Conventions::MLS_PAPER;
    for conventions in [
        Conventions {
            transfer: Transfer::Pic,
            ..paper
        },
        Conventions {
            transfer: Transfer::Blend(0.5),
            ..paper
        },
        Conventions {
            positions: Positions::Projected,
            ..paper
        },
        Conventions {
            scheme: Scheme::Usl,
            ..paper
        },
    ] {
        assert!(!fuses_end_values(conventions, Mapping2d::Mls));
        let run = || {
            scene
                .simulation_with(method, 6, 3, 1.0, conventions)
                .unwrap()
        };
        assert_fused_and_passes_agree(run(), run());
    }
}

/// `evaluate_basis` fills both axes' stencils in one pass, B-splines in
/// paired lanes (`KnotVector::values_and_gradients_pair`): after 100 steps
/// of BSMPM p = 2, p = 3 and bilinear MPM (particles off their starting
/// lattice), the
/// stencils are bit for bit those of `Grid::stencils_at` along each axis,
/// and a particle outside the square is still `ParticleLeftGrid`, naming it.
#[test]
fn the_basis_of_both_axes_in_one_pass_is_that_of_each_axis_bit_for_bit() {
    let dt = parameters("mls-paper-e1e7").unwrap().dt;
    for method in [
        AlignedMethod::bsmpm(2),
        AlignedMethod::bsmpm(3),
        AlignedMethod::Mpm,
    ] {
        let mut sim = simulation(method, 8);
        sim.run(dt, 100).unwrap();
        evaluate_basis(&sim.grid, &sim.particles, &mut sim.workspace, 0).unwrap();
        for (c, paired) in [
            (0, &sim.workspace.stencils_x),
            (1, &sim.workspace.stencils_y),
        ] {
            let xs: Vec<f64> = sim.particles.x.iter().map(|x| x[c]).collect();
            let one_axis = sim.grid.axis().stencils_at(&xs).unwrap();
            assert_eq!(
                format!("{:?}", paired.first),
                format!("{:?}", one_axis.first)
            );
            assert_eq!(
                format!("{:?}", paired.values),
                format!("{:?}", one_axis.values)
            );
            assert_eq!(
                format!("{:?}", paired.gradients),
                format!("{:?}", one_axis.gradients)
            );
        }
        sim.particles.x[5] = [0.5, 1.5];
        let e = evaluate_basis(&sim.grid, &sim.particles, &mut sim.workspace, 7).unwrap_err();
        assert!(
            matches!(
                e,
                hompm::Error::ParticleLeftGrid {
                    particle: 5,
                    step: 7,
                    ..
                }
            ),
            "{e:?}"
        );
    }
}
