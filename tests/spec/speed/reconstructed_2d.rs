//! Issue #39, the reconstructed 2D step (MLS, TLS, PU-TLS): what was made
//! faster computes the same bits. The Gauss points' sums (MLS paper
//! Eqs. 18–21 and 31) are formed two points at a time, each in its own
//! list's order, and a step nobody observes gathers each moved particle's
//! [ρ_p, v_p] for Eq. (31) in phase 3's loop instead of a pass of its own.

use hompm::mpm2d::reconstruction::storage_order;
use hompm::mpm2d::step::{
    fuses_end_of_step, fuses_end_values, Mapping2d, Simulation2d, StepObserver2d, StepPoint2d,
};
use hompm::scenes::aligned_vibration::{parameters, AlignedMethod};
use hompm::Result;

const RECONSTRUCTED: [Mapping2d; 3] = [Mapping2d::Mls, Mapping2d::Tls, Mapping2d::PuTls];

/// The aligned vibration of the MLS paper, BSMPM p = 2 with `mapping`, on
/// `cells` cells per side, 9 particles per cell.
fn simulation(mapping: Mapping2d, cells: usize) -> Simulation2d {
    let scene = parameters("mls-paper-e1e7").unwrap();
    let method = AlignedMethod::bsmpm_with(2, mapping);
    scene.simulation(method, cells, 3, 1.0).unwrap()
}

/// Σ_p φ_gp f_p over Gauss point g's list, one entry after the other in
/// list order from +0: the sum of one point at a time.
fn one_point_sum<const N: usize>(
    sim: &Simulation2d,
    g: usize,
    term: impl Fn(usize) -> [f64; N],
) -> [f64; N] {
    let lists = sim.workspace.reconstruction.as_ref().unwrap().lists();
    let entries = lists.start[g]..lists.end[g];
    let pairs = lists.particle[entries.clone()]
        .iter()
        .zip(&lists.phi[entries]);
    pairs.fold([0.0; N], |q, (&k, &phi)| {
        let f = term(k as usize);
        std::array::from_fn(|i| q[i] + phi * f[i])
    })
}

/// After phase 1, every Gauss point's eight values against the sum of one
/// point at a time; counts the pairs of points whose lists differ in
/// length (so that the longer list's tail is summed alone).
#[derive(Default)]
struct OnePointAtATime {
    checked: usize,
    unequal_pairs: usize,
}

impl StepObserver2d for OnePointAtATime {
    fn observe(&mut self, point: StepPoint2d, sim: &mut Simulation2d) -> Result<()> {
        if point != StepPoint2d::GridMapping {
            return Ok(());
        }
        let ws = &sim.workspace;
        let ng = 2 * sim.grid.cells_per_side();
        for (gx, gy) in storage_order(sim.grid.cells_per_side()) {
            let g = gx + ng * gy;
            let expected = one_point_sum(sim, g, |k| ws.particle_values[k]);
            assert_eq!(
                format!("{:?}", ws.gauss_values[g]),
                format!("{expected:?}"),
                "step {}, Gauss point ({gx}, {gy})",
                sim.steps
            );
            self.checked += 1;
        }
        let lists = ws.reconstruction.as_ref().unwrap().lists();
        let length = |g: usize| lists.end[g] - lists.start[g];
        let points: Vec<usize> = storage_order(sim.grid.cells_per_side())
            .map(|(gx, gy)| gx + ng * gy)
            .collect();
        let pairs = points.chunks_exact(2);
        self.unequal_pairs += pairs.filter(|p| length(p[0]) != length(p[1])).count();
        Ok(())
    }
}

/// The values of Eqs. (18)–(21) at every Gauss point, over 60 steps of
/// MLS, TLS and PU-TLS, are bit for bit the sums of one point at a time;
/// with MLS, paired lists of different lengths occur.
#[test]
fn two_gauss_points_summed_at_once_give_the_bits_of_one_point_at_a_time() {
    let dt = parameters("mls-paper-e1e7").unwrap().dt;
    for mapping in RECONSTRUCTED {
        let mut sim = simulation(mapping, 6);
        let mut check = OnePointAtATime::default();
        for _ in 0..60 {
            sim.step_observed(dt, &mut check).unwrap();
        }
        assert_eq!(check.checked, 60 * 4 * 36, "{mapping:?}");
        if mapping == Mapping2d::Mls {
            assert!(check.unequal_pairs > 0);
        }
    }
}

/// After the end of step (Eqs. 31–33), (mv)^L against the one-point sums
/// (ρv)_g^L = Σ_p φ_gp ρ_p v_p, each scattered as N_i(x_g) (ρv)_g^L ω
/// (Eq. 31), point by point in storage order.
#[derive(Default)]
struct EndMomentumOnePointAtATime {
    checked: usize,
}

impl StepObserver2d for EndMomentumOnePointAtATime {
    fn observe(&mut self, point: StepPoint2d, sim: &mut Simulation2d) -> Result<()> {
        if point != StepPoint2d::EndOfStepVelocity {
            return Ok(());
        }
        let (grid, p) = (&sim.grid, &sim.particles);
        let (n, ng) = (grid.nodes_per_side(), 2 * grid.cells_per_side());
        let (s, omega) = (grid.gauss_stencils(), grid.gauss_weight());
        let w = s.width();
        let mut expected = vec![[0.0; 2]; sim.workspace.momentum_end.len()];
        for (gx, gy) in storage_order(grid.cells_per_side()) {
            // φ ρ v is formed as (φ ρ) v, not φ (ρ v).
            let q = {
                let lists = sim.workspace.reconstruction.as_ref().unwrap().lists();
                let g = gx + ng * gy;
                let entries = lists.start[g]..lists.end[g];
                let pairs = lists.particle[entries.clone()]
                    .iter()
                    .zip(&lists.phi[entries]);
                pairs.fold([0.0; 2], |q, (&k, &phi)| {
                    let (rho, v) = (p.density[k as usize], p.velocity[k as usize]);
                    [q[0] + phi * rho * v[0], q[1] + phi * rho * v[1]]
                })
            };
            let q = [q[0] * omega, q[1] * omega];
            let (vx, vy) = (&s.values[gx * w..][..w], &s.values[gy * w..][..w]);
            for (b, &nb) in vy.iter().enumerate() {
                for (a, &na) in vx.iter().enumerate() {
                    let i = (s.first[gy] + b) * n + s.first[gx] + a;
                    let nn = na * nb;
                    expected[i][0] += nn * q[0];
                    expected[i][1] += nn * q[1];
                }
            }
        }
        assert_eq!(
            format!("{:?}", sim.workspace.momentum_end),
            format!("{expected:?}"),
            "step {}",
            sim.steps
        );
        self.checked += 1;
        Ok(())
    }
}

/// (mv)^L of Eq. (31), over 40 steps of MLS, TLS and PU-TLS, is bit for
/// bit the scatter of the one-point sums, and not zero.
#[test]
fn the_end_of_step_momentum_summed_two_points_at_a_time_is_that_of_one_point_at_a_time() {
    let dt = parameters("mls-paper-e1e7").unwrap().dt;
    for mapping in RECONSTRUCTED {
        let mut sim = simulation(mapping, 6);
        let mut check = EndMomentumOnePointAtATime::default();
        for _ in 0..40 {
            sim.step_observed(dt, &mut check).unwrap();
        }
        assert_eq!(check.checked, 40, "{mapping:?}");
        let largest = sim
            .workspace
            .momentum_end
            .iter()
            .map(|m| m[0].abs())
            .fold(0.0, f64::max);
        assert!(largest > 0.0, "{mapping:?}");
    }
}

/// An observer that looks at every point and changes nothing: the step
/// takes one pass per phase.
struct Looks;

impl StepObserver2d for Looks {
    fn observe(&mut self, _: StepPoint2d, _: &mut Simulation2d) -> Result<()> {
        Ok(())
    }
}

/// A step nobody observes gathers [ρ_p, v_p] in phase 3's loop
/// (`update_particles_and_end_values`); the observed step packs them in
/// `end_of_step_velocity`. After 150 steps of MLS, TLS and PU-TLS, the
/// particles, the end-of-step nodal arrays and the record agree bit for bit.
#[test]
fn the_reconstructed_end_of_step_gathering_as_particles_move_computes_the_bits_of_the_two_passes() {
    let dt = parameters("mls-paper-e1e7").unwrap().dt;
    for mapping in RECONSTRUCTED {
        let (mut fused, mut passes) = (simulation(mapping, 6), simulation(mapping, 6));
        let conventions = fused.settings.conventions;
        assert!(fuses_end_values(conventions, mapping));
        assert!(!fuses_end_of_step(conventions, mapping));
        for _ in 0..150 {
            fused.step(dt).unwrap();
            passes.step_observed(dt, &mut Looks).unwrap();
        }
        assert_eq!(
            format!("{:?}", fused.particles),
            format!("{:?}", passes.particles)
        );
        let (a, b) = (&fused.workspace, &passes.workspace);
        assert_eq!(format!("{:?}", a.end_values), format!("{:?}", b.end_values));
        assert_eq!(
            format!("{:?}", a.momentum_end),
            format!("{:?}", b.momentum_end)
        );
        assert_eq!(
            format!("{:?}", a.velocity_end),
            format!("{:?}", b.velocity_end)
        );
        assert_eq!(
            format!("{:?}", fused.conservation),
            format!("{:?}", passes.conservation)
        );
        let moved = fused.particles.displacement.iter().map(|u| u[0].abs());
        assert!(moved.fold(0.0, f64::max) > 1e-4, "{mapping:?}");
    }
}
