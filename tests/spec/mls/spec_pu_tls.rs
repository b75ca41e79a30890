//! Partition-of-unity TLS in 2D (src/mpm2d/pu_tls.rs, hompm's construction
//! from TLS paper Eqs. 13–14 and MLS paper Eqs. 18–25): its patches are the
//! grid's quadratic B-splines, it maps mass and momentum to rounding, it
//! reproduces linear fields whose particle sums are their integrals, its
//! shape functions move continuously when a particle crosses a cell edge
//! (where 2D TLS jumps), a degenerate patch is refused by name or reduced
//! conservatively, and the aligned vibration's steps keep mass and momentum.

use approx::assert_relative_eq;
use hompm::error::Error;
use hompm::mpm2d::pu_tls::{open_quadratic_on_cell, PuTlsShapes};
use hompm::mpm2d::reconstruction::{GaussGrid, GaussReconstruction, Reconstruction};
use hompm::mpm2d::tls::{TaylorOrder2d, TlsShapes};
use hompm::mpm2d::{Basis2d, Grid2d, Mapping2d, Particles2d};
use hompm::reconstruct::taylor::DegenerateCells;
use hompm::rng::SplitMix64;
use hompm::scenes::aligned_vibration::{parameters, AlignedMethod};

/// `per_side`² particles per cell of `cells`² cells on [0, 1]², each moved
/// by up to ±jitter/2 of its spacing.
fn scattered(cells: usize, per_side: usize, jitter: f64, seed: u64) -> Particles2d {
    let mut rng = SplitMix64::new(seed);
    let mut p = Particles2d::cell_centred(1.0, cells, per_side, 1000.0, |_| [0.0; 2]).unwrap();
    let d = 1.0 / (cells * per_side) as f64;
    for x in p.x.iter_mut() {
        x[0] += jitter * d * (rng.uniform() - 0.5);
        x[1] += jitter * d * (rng.uniform() - 0.5);
    }
    p
}

/// The cells of the particles along x and y, by the grid's own rule.
fn cells_of(grid: &Grid2d, p: &Particles2d) -> [Vec<usize>; 2] {
    [0, 1].map(|c| {
        p.x.iter()
            .map(|x| grid.axis().cell_of(x[c]).unwrap())
            .collect()
    })
}

/// Evaluates `shapes` for `p` on `cells`² cells of [0, 1]².
fn evaluate(
    shapes: &mut dyn GaussReconstruction,
    p: &Particles2d,
    cells: usize,
) -> hompm::error::Result<Grid2d> {
    let grid = Grid2d::new(Basis2d::BSpline { degree: 2 }, 1.0, cells)?;
    let gauss = GaussGrid {
        abscissae: grid.gauss_abscissae(),
        cells,
        cell_size: grid.cell_size(),
    };
    let [cx, cy] = cells_of(&grid, p);
    shapes.evaluate(&gauss, p, &cx, &cy)?;
    Ok(grid)
}

/// φ_gp as a dense matrix, row g = gx + 2·cells·gy.
fn dense(shapes: &dyn GaussReconstruction, particles: usize) -> Vec<Vec<f64>> {
    let lists = shapes.lists();
    (0..lists.start.len())
        .map(|g| {
            let mut row = vec![0.0; particles];
            for e in lists.start[g]..lists.end[g] {
                row[lists.particle[e] as usize] += lists.phi[e];
            }
            row
        })
        .collect()
}

/// The patches are the grid's own open-uniform quadratic B-splines (book
/// Eqs. 4.19–4.20): the pieces of `open_quadratic_on_cell` equal the grid
/// axis's basis at random points of every cell, on grids of 1, 2, 3 and 6
/// cells (the first and last cells carry the repeated knots' pieces).
#[test]
fn pu_tls_patches_are_the_grids_open_quadratic_bsplines() {
    let mut rng = SplitMix64::new(5);
    for cells in [1, 2, 3, 6] {
        let grid = Grid2d::new(Basis2d::BSpline { degree: 2 }, 1.0, cells).unwrap();
        for _ in 0..40 {
            let x = rng.uniform();
            let shape = grid.axis().shape(x).unwrap();
            let c = grid.axis().cell_of(x).unwrap();
            assert_eq!(shape.first, c);
            let ours = open_quadratic_on_cell(cells, c, x * cells as f64 - c as f64);
            for (a, b) in ours.iter().zip(&shape.values) {
                assert!(
                    (a - b).abs() < 1e-14,
                    "{cells} cells at {x}: {ours:?} vs {b}"
                );
            }
        }
    }
}

/// The module doc's proof: Σ_g ω_g φ_gp = V_p for every particle, so the
/// mapped mass Σ_g ω_g Σ_p φ_gp ρ_p and momentum Σ_g ω_g Σ_p φ_gp ρ_p v_p
/// equal Σ_p V_p ρ_p and Σ_p V_p ρ_p v_p to ≤ 1e-13 relative, on a random
/// cloud of random densities and velocities (6 × 6 cells, 9 particles per
/// cell jittered by up to 90 % of their spacing, varied volumes), with
/// linear and with quadratic patches.
#[test]
fn pu_tls_maps_mass_and_momentum_of_a_random_cloud_to_rounding() {
    let cells = 6;
    let mut p = scattered(cells, 3, 0.9, 17);
    let mut rng = SplitMix64::new(19);
    let n = p.len();
    for k in 0..n {
        p.volume[k] *= rng.open_interval(0.5, 1.5);
        p.density[k] = rng.open_interval(500.0, 2000.0);
        p.velocity[k] = [rng.open_interval(-3.0, 3.0), rng.open_interval(-3.0, 3.0)];
    }
    for order in [TaylorOrder2d::Linear, TaylorOrder2d::Quadratic] {
        let mut shapes = PuTlsShapes::new(order, DegenerateCells::ReduceBasis, cells, n).unwrap();
        let grid = evaluate(&mut shapes, &p, cells).unwrap();
        assert_eq!(shapes.repaired(), 0, "{order:?}");
        let omega = grid.gauss_weight();
        let lists = shapes.lists();
        let mut carried = vec![0.0; n];
        let mut mapped = [0.0; 3];
        for g in 0..lists.start.len() {
            for e in lists.start[g]..lists.end[g] {
                let (k, phi) = (lists.particle[e] as usize, lists.phi[e]);
                carried[k] += omega * phi;
                let rho = p.density[k];
                let value = [rho, rho * p.velocity[k][0], rho * p.velocity[k][1]];
                for (m, v) in mapped.iter_mut().zip(value) {
                    *m += omega * phi * v;
                }
            }
        }
        for (k, c) in carried.iter().enumerate() {
            assert_relative_eq!(*c, p.volume[k], max_relative = 1e-13);
        }
        let mass: f64 = (0..n).map(|k| p.volume[k] * p.density[k]).sum();
        let scale: f64 = (0..n)
            .map(|k| p.volume[k] * p.density[k] * p.velocity[k][0].hypot(p.velocity[k][1]))
            .sum();
        assert!(
            (mapped[0] - mass).abs() <= 1e-13 * mass,
            "{mapped:?} {mass}"
        );
        for d in 0..2 {
            let momentum: f64 = (0..n)
                .map(|k| p.volume[k] * p.density[k] * p.velocity[k][d])
                .sum();
            assert!(
                (mapped[1 + d] - momentum).abs() <= 1e-13 * scale,
                "{order:?} {d}: {} vs {momentum}",
                mapped[1 + d]
            );
        }
    }
}

/// The largest error of Σ_p φ_gp f(x_p) against f(x_g) over the Gauss
/// points of the cells `inner` .. cells − `inner` on each axis.
fn worst_at_gauss_points(
    shapes: &dyn GaussReconstruction,
    grid: &Grid2d,
    p: &Particles2d,
    inner: usize,
    f: &dyn Fn(f64, f64) -> f64,
) -> f64 {
    let lists = shapes.lists();
    let (a, ng) = (grid.gauss_abscissae(), 2 * grid.cells_per_side());
    let mut worst: f64 = 0.0;
    for gy in 2 * inner..ng - 2 * inner {
        for gx in 2 * inner..ng - 2 * inner {
            let g = gx + ng * gy;
            let value: f64 = (lists.start[g]..lists.end[g])
                .map(|e| {
                    let k = lists.particle[e] as usize;
                    lists.phi[e] * f(p.x[k][0], p.x[k][1])
                })
                .sum();
            worst = worst.max((value - f(a[gx], a[gy])).abs());
        }
    }
    worst
}

/// Particles at the `points`×`points` Gauss points of each of `cells`²
/// cells, the Gauss weights as volumes.
fn at_gauss_points(cells: usize, points: usize) -> Particles2d {
    let rule = hompm::quadrature::GaussLegendre::new(points).unwrap();
    let (mut positions, mut volumes) = (Vec::new(), Vec::new());
    let h = 1.0 / cells as f64;
    for cy in 0..cells {
        for cx in 0..cells {
            for a in rule.on_interval(cx as f64 * h, (cx + 1) as f64 * h) {
                for b in rule.on_interval(cy as f64 * h, (cy + 1) as f64 * h) {
                    positions.push([a.x, b.x]);
                    volumes.push(a.weight * b.weight);
                }
            }
        }
    }
    let n = positions.len();
    Particles2d::new(positions, volumes, 1000.0, vec![[0.0; 2]; n]).unwrap()
}

/// With the particles at the 3×3 Gauss points of every cell and the Gauss
/// weights as volumes, Σ_p N_e(x_p) V_p f(x_p) is ∫ N_e f for a linear f
/// (a cubic per axis), so each patch's constraint and fit give f_e = f and
/// the blend Σ_e N_e f = f at every Gauss point (≤ 1e-12). A quadratic is
/// not reproduced by linear patches. With the particles at the grid's own
/// 2×2 Gauss points, the constraint's two sums are the same sum, and
/// quadratic patches reproduce a quadratic wherever every patch is
/// quadratic (away from the walls, where the patches of one-cell supports
/// see two abscissae per axis and are reduced to linear).
#[test]
fn pu_tls_reproduces_the_fields_of_its_patch_basis_whose_particle_sums_are_integrals() {
    let linear = |x: f64, y: f64| 0.7 - 1.3 * x + 2.1 * y;
    let quadratic = |x: f64, y: f64| linear(x, y) + 0.9 * x * x - 1.7 * x * y + 0.4 * y * y;
    let p = at_gauss_points(4, 3);
    let mut shapes = PuTlsShapes::for_engine(4, p.len()).unwrap();
    let grid = evaluate(&mut shapes, &p, 4).unwrap();
    let lin = worst_at_gauss_points(&shapes, &grid, &p, 0, &linear);
    let quad = worst_at_gauss_points(&shapes, &grid, &p, 0, &quadratic);
    assert!(lin <= 1e-12, "linear: {lin:e}");
    assert!(quad > 1e-4, "quadratic: {quad:e}");
    let p = at_gauss_points(5, 2);
    for (order, exact) in [
        (TaylorOrder2d::Quadratic, true),
        (TaylorOrder2d::Linear, false),
    ] {
        let mut shapes = PuTlsShapes::new(order, DegenerateCells::ReduceBasis, 5, p.len()).unwrap();
        let grid = evaluate(&mut shapes, &p, 5).unwrap();
        let worst = worst_at_gauss_points(&shapes, &grid, &p, 1, &quadratic);
        assert_eq!(worst <= 1e-12, exact, "{order:?}: {worst:e}");
    }
}

/// The largest change of any φ_gp when one particle moves from x = 0.5 − δ
/// to 0.5 + δ, across the edge between cells (1, ·) and (2, ·) of a 4×4
/// grid.
fn shape_jump_across_a_cell_edge(pu: bool, delta: f64) -> f64 {
    let cells = 4;
    let phi = |x: f64| {
        let mut p = scattered(cells, 3, 0.6, 23);
        let k = (0..p.len())
            .min_by(|&a, &b| (p.x[a][0] - 0.5).abs().total_cmp(&(p.x[b][0] - 0.5).abs()))
            .unwrap();
        p.x[k][0] = x;
        let mut shapes: Box<dyn GaussReconstruction> = if pu {
            Box::new(PuTlsShapes::for_engine(cells, p.len()).unwrap())
        } else {
            Box::new(TlsShapes::for_engine(cells, p.len()).unwrap())
        };
        evaluate(shapes.as_mut(), &p, cells).unwrap();
        dense(shapes.as_ref(), p.len())
    };
    let (left, right) = (phi(0.5 - delta), phi(0.5 + delta));
    left.iter()
        .flatten()
        .zip(right.iter().flatten())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
}

/// Continuity: the weights N_e(x_p) vanish with their slope at the edge of
/// every support, so a particle moving by 2δ = 2e-9 across a cell edge
/// changes every PU-TLS φ_gp by O(δ) (≤ 1e-6), where the per-cell fit of
/// 2D TLS changes some by O(1) (docs/reproduction-notes.md, "BSMPM with
/// Taylor least squares in 2D").
#[test]
fn a_particle_crossing_a_cell_edge_moves_pu_tls_shapes_continuously_where_tls_jumps() {
    let delta = 1e-9;
    let pu = shape_jump_across_a_cell_edge(true, delta);
    let tls = shape_jump_across_a_cell_edge(false, delta);
    assert!(pu <= 1e-6, "PU-TLS {pu:e}");
    assert!(tls >= 1e-2, "TLS {tls:e}");
}

/// TLS paper §5.3, as 2D TLS: the corner patch N_(0,0), supported on cell
/// (0, 0) alone, with one particle there has no linear fit. Under `Error`
/// it is `Error::SingularCell` naming the patch and its support; under
/// `ReduceBasis` it falls back to the constant, counts as repaired, and
/// still conserves (Σ_g ω_g φ_gp = V_p).
#[test]
fn a_patch_without_a_linear_fit_is_refused_by_name_or_reduced_conservatively() {
    let cells = 3;
    let mut p = scattered(cells, 3, 0.5, 29);
    let h = 1.0 / cells as f64;
    // Keep one particle of cell (0, 0).
    let keep: Vec<usize> = (0..p.len())
        .filter(|&k| !(p.x[k][0] < h && p.x[k][1] < h))
        .chain((0..p.len()).find(|&k| p.x[k][0] < h && p.x[k][1] < h))
        .collect();
    let n = keep.len();
    p = Particles2d::new(
        keep.iter().map(|&k| p.x[k]).collect(),
        keep.iter().map(|&k| p.volume[k]).collect(),
        1000.0,
        vec![[0.0; 2]; n],
    )
    .unwrap();
    let mut strict =
        PuTlsShapes::new(TaylorOrder2d::Linear, DegenerateCells::Error, cells, n).unwrap();
    match evaluate(&mut strict, &p, cells) {
        Err(Error::SingularCell {
            cell,
            lower,
            upper,
            detail,
        }) => {
            assert_eq!(cell, [0, 0]);
            assert_eq!(lower, [0.0, 0.0]);
            assert_relative_eq!(upper[0], h, max_relative = 1e-15);
            assert_relative_eq!(upper[1], h, max_relative = 1e-15);
            assert!(detail.contains("1 particles"), "{detail}");
        }
        other => panic!("expected a singular patch, got {other:?}"),
    }
    let mut shapes = PuTlsShapes::for_engine(cells, n).unwrap();
    let grid = evaluate(&mut shapes, &p, cells).unwrap();
    assert_eq!(shapes.repaired(), 1);
    super::spec_mpm2d::assert_every_particle_carries_its_volume(
        &shapes,
        grid.gauss_weight(),
        &p.volume,
    );
    assert!(PuTlsShapes::new(
        TaylorOrder2d::Linear,
        DegenerateCells::VirtualPoints,
        cells,
        n
    )
    .is_err());
}

/// The step with PU-TLS in both mappings keeps mass and momentum to
/// ≤ 1e-13 relative (compensated sums) at every phase-1 mapping: 300 steps
/// of the aligned vibration on 8 × 8 cells and 3 on 32 × 32 (9 particles
/// per cell), without reducing any patch and with κ₁ reported. (The step's
/// own record sums without compensation and reads 1.0e-13 on 32 cells for
/// every mapping, the direct one included.)
#[test]
fn the_pu_tls_mapping_keeps_mass_and_momentum_at_every_step_of_the_aligned_vibration() {
    let s = parameters("mls-paper-e1e7").unwrap();
    let method = AlignedMethod::bsmpm_with(2, Mapping2d::PuTls);
    for (cells, steps) in [(8, 300), (32, 3)] {
        let mut sim = s.simulation(method, cells, 3, 1.0).unwrap();
        let mut probe = super::spec_mpm2d::ConservationProbe {
            largest: [0.0; 2],
            mappings: 0,
        };
        for _ in 0..steps {
            sim.step_observed(s.dt, &mut probe).unwrap();
        }
        assert_eq!(probe.mappings, steps);
        assert_eq!(sim.reconstruction_record.most_repaired, 0);
        assert!(sim.reconstruction_record.largest_condition >= 1.0);
        let [mass, momentum] = probe.largest;
        assert!(
            mass <= 1e-13 && momentum <= 1e-13,
            "{cells} cells: {:?}",
            probe.largest
        );
    }
}
