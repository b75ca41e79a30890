//! Issue #39, the reconstructed 2D step (MLS, TLS, PU-TLS): what was made
//! faster computes the same bits. The Gauss points' sums (MLS paper
//! Eqs. 18–21 and 31) are formed two points at a time, each in its own
//! list's order. (The end of step that gathers [ρ_p, v_p] as the particles
//! move is compared with the observed step's in step_2d.rs.)

use hompm::mpm2d::reconstruction::storage_order;
use hompm::mpm2d::step::{Mapping2d, Simulation2d, StepObserver2d, StepPoint2d};
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
/// list order from +0 (`term(φ_gp, p)` is the entry's term): the sum of
/// one point at a time.
fn one_point_sum<const N: usize>(
    sim: &Simulation2d,
    g: usize,
    term: impl Fn(f64, usize) -> [f64; N],
) -> [f64; N] {
    let lists = sim.workspace.reconstruction.as_ref().unwrap().lists();
    let entries = lists.start[g]..lists.end[g];
    let pairs = lists.particle[entries.clone()]
        .iter()
        .zip(&lists.phi[entries]);
    pairs.fold([0.0; N], |q, (&k, &phi)| {
        let t = term(phi, k as usize);
        std::array::from_fn(|i| q[i] + t[i])
    })
}

/// `steps` steps of BSMPM p = 2 with `mapping` on 6 cells, each observed.
fn observed_run<O: StepObserver2d>(
    mapping: Mapping2d,
    steps: usize,
    observer: &mut O,
) -> Simulation2d {
    let dt = parameters("mls-paper-e1e7").unwrap().dt;
    let mut sim = simulation(mapping, 6);
    for _ in 0..steps {
        sim.step_observed(dt, observer).unwrap();
    }
    sim
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
            let d = |k: usize| ws.particle_values[k];
            let expected = one_point_sum(sim, g, |phi, k| d(k).map(|f| phi * f));
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
    for mapping in RECONSTRUCTED {
        let mut check = OnePointAtATime::default();
        observed_run(mapping, 60, &mut check);
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
            let q = one_point_sum(sim, gx + ng * gy, |phi, k| {
                let (rho, v) = (p.density[k], p.velocity[k]);
                [phi * rho * v[0], phi * rho * v[1]]
            });
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
    for mapping in RECONSTRUCTED {
        let mut check = EndMomentumOnePointAtATime::default();
        let sim = observed_run(mapping, 40, &mut check);
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
