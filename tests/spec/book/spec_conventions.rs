//! The conventions of other codes (`hompm::mpm::conventions`), each a step
//! computed by hand.
//!
//! 1D: the two particles of spec_musl_step.rs on two P1 cells of [0, 2]
//! (x = 0.5, 1.25; m_p = 2, 2; v_p = 1, −2; σ_p = 3, −1; V_p = 1, 0.5;
//! traction 0.5 on particle 1; E = 10, g = −1, Δt = 0.1). There
//! m_i = (1, 2.5, 0.5) and a_i = (2, −2.25, 0.25) (book Eqs. 4.5, 4.8), and
//! the grid velocity of another code's step is
//!
//! - p_i = Σ_p m_p v_p φ_i = (2·½, 2·½ − 4·¾, −4·¼) = (1, −2, −1),
//! - v_i^n = p_i/m_i = (1, −0.8, −2),
//! - ṽ_i = v_i^n + Δt a_i = (1.2, −1.025, −1.975).
//!
//! 2D: one particle on a bilinear grid, where the body force at the nodes
//! and the FLIP/PIC blend are worked the same way.

use approx::assert_relative_eq;
use hompm::mpm::conventions::{
    registered, BodyForceAt, Conventions, Positions, Scheme, Transfer, REGISTRY,
};
use hompm::mpm::grid::{Grid, Method};
use hompm::mpm::mapping::{Mapping, MassMatrix};
use hompm::mpm::musl::{Constitutive, Settings, Simulation};
use hompm::mpm::particles::Particles;
use hompm::mpm2d::step::{Formulation, Mapping2d, Settings2d, Simulation2d};
use hompm::mpm2d::{Basis2d, Grid2d, NeoHookean, Particles2d};
use hompm::scenes::aligned_vibration::{parameters, SolutionForm};

const DT: f64 = 0.1;

/// The two particles after one step with `conventions`.
fn one_step(conventions: Conventions) -> Simulation {
    let grid = Grid::new(Method::Mpm, 0.0, 2.0, 2).unwrap();
    let mut p = Particles::new(
        vec![0.5, 1.25],
        vec![1.0, 0.5],
        vec![2.0, 4.0],
        vec![1.0, -2.0],
        vec![3.0, -1.0],
    )
    .unwrap();
    p.traction = vec![0.0, 0.5];
    let settings = Settings {
        force_mapping: Mapping::Direct,
        velocity_mapping: Mapping::Direct,
        mass: MassMatrix::Lumped,
        constitutive: Constitutive::SmallStrain,
        young: 10.0,
        poisson: 0.0,
        body_force: None,
        gravity: -1.0,
        gravity_ramp: None,
        dirichlet: vec![],
        consistent_acceleration: false,
        tls_density_average: hompm::reconstruct::taylor::CellAverage::Exact,
        conventions,
    };
    let mut sim = Simulation::new(grid, p, settings).unwrap();
    sim.step(DT).unwrap();
    sim
}

fn with(scheme: Scheme, transfer: Transfer, positions: Positions) -> Conventions {
    Conventions {
        scheme,
        transfer,
        positions,
        ..Conventions::BOOK
    }
}

fn assert_all(computed: &[f64], expected: &[f64]) {
    assert_eq!(computed.len(), expected.len());
    for (c, e) in computed.iter().zip(expected) {
        assert_relative_eq!(*c, *e, epsilon = 1e-12, max_relative = 1e-12);
    }
}

#[test]
fn another_codes_step_forms_the_grid_velocity_and_its_update_from_the_particle_momentum() {
    let sim = one_step(with(Scheme::Musl, Transfer::Flip, Positions::Grid));
    let ws = sim.workspace();
    assert_all(&ws.nodal_momentum, &[1.0, -2.0, -1.0]);
    assert_all(&ws.nodal_velocity, &[1.0, -0.8, -2.0]);
    assert_all(&ws.updated_velocity, &[1.2, -1.025, -1.975]);
}

#[test]
fn positions_grid_moves_the_particles_with_the_updated_grid_velocity_and_strains_them_with_the_projected_one(
) {
    // Δu_p = Δt Σ φ ṽ: (0.1·(½·1.2 − ½·1.025), 0.1·(−¾·1.025 − ¼·1.975)).
    let sim = one_step(with(Scheme::Musl, Transfer::Flip, Positions::Grid));
    assert_all(&sim.particles.displacement, &[0.00875, -0.12625]);
    assert_all(&sim.particles.x, &[0.50875, 1.12375]);
    // MUSL's strain is the book's, from the projected v_i = (0.9875,
    // −0.9025, −2.1625): Δε = 0.1·(−0.9875 − 0.9025), 0.1·(0.9025 − 2.1625).
    assert_all(&sim.workspace().strain_increment, &[-0.189, -0.126]);
    // The velocity is FLIP's, as in the book's step.
    assert_all(&sim.particles.velocity, &[0.9875, -2.1625]);
    // The book's step moves them with the projected velocity instead.
    let book = one_step(Conventions::BOOK);
    assert_all(
        &book.particles.displacement,
        &[
            0.1 * -0.9025 / 2.0 + 0.1 * 0.9875 / 2.0,
            0.1 * (0.75 * -0.9025 + 0.25 * -2.1625),
        ],
    );
}

#[test]
fn pic_sets_the_particle_velocity_to_the_interpolated_updated_grid_velocity() {
    // v_p = Σ φ ṽ = (½·1.2 − ½·1.025, −¾·1.025 − ¼·1.975).
    let sim = one_step(with(Scheme::Musl, Transfer::Pic, Positions::Projected));
    assert_all(&sim.particles.velocity, &[0.0875, -1.2625]);
}

#[test]
fn the_flip_blend_weights_flip_by_alpha_and_pic_by_one_minus_alpha() {
    // ½·(0.9875, −2.1625) + ½·(0.0875, −1.2625); and α = 0.9.
    let sim = one_step(with(
        Scheme::Musl,
        Transfer::Blend(0.5),
        Positions::Projected,
    ));
    assert_all(&sim.particles.velocity, &[0.5375, -1.7125]);
    let sim = one_step(with(
        Scheme::Musl,
        Transfer::Blend(0.9),
        Positions::Projected,
    ));
    assert_all(
        &sim.particles.velocity,
        &[0.9 * 0.9875 + 0.1 * 0.0875, 0.9 * -2.1625 + 0.1 * -1.2625],
    );
}

#[test]
fn usl_strains_and_moves_the_particles_with_the_updated_grid_velocity_without_a_second_projection()
{
    let sim = one_step(with(Scheme::Usl, Transfer::Flip, Positions::Grid));
    // Δε = 0.1·(−1.2 − 1.025), 0.1·(1.025 − 1.975); σ = 3 + 10Δε, −1 + 10Δε.
    assert_all(&sim.workspace().strain_increment, &[-0.2225, -0.095]);
    assert_all(&sim.particles.stress, &[0.775, -1.95]);
    assert_all(&sim.particles.volume, &[0.7775, 0.5 * 0.905]);
    assert_all(&sim.particles.x, &[0.50875, 1.12375]);
    assert_all(&sim.particles.velocity, &[0.9875, -2.1625]);
}

#[test]
fn usf_updates_the_stress_from_the_start_of_step_grid_velocity_before_the_internal_force() {
    let sim = one_step(with(Scheme::Usf, Transfer::Flip, Positions::Grid));
    // Δε = 0.1·(−1 − 0.8), 0.1·(0.8 − 2); σ = 3 − 1.8, −1 − 1.2;
    // V = 1·0.82, 0.5·0.88.
    assert_all(&sim.workspace().strain_increment, &[-0.18, -0.12]);
    assert_all(&sim.particles.stress, &[1.2, -2.2]);
    assert_all(&sim.particles.volume, &[0.82, 0.44]);
    // f_int from σV = (0.984, −0.968): (−0.984, 1.952, −0.968);
    // a = ((−1 + 0.984)/1, (0.375 − 2.5 − 1.952)/2.5, (0.125 − 0.5 + 0.968)/0.5).
    assert_all(&sim.workspace().internal_force, &[-0.984, 1.952, -0.968]);
    assert_all(&sim.workspace().acceleration, &[-0.016, -1.6308, 1.186]);
    // v_p += 0.1 Σ φ a; x_p += 0.1 Σ φ ṽ with ṽ = (0.9984, −0.96308, −1.8814).
    assert_all(&sim.particles.velocity, &[0.91766, -2.09266]);
    assert_all(&sim.particles.x, &[0.501766, 1.130734]);
}

#[test]
fn usl_and_usf_without_a_projection_refuse_projected_positions() {
    for scheme in [Scheme::Usl, Scheme::Usf] {
        let c = with(scheme, Transfer::Flip, Positions::Projected);
        assert!(c.validate().is_err());
    }
    assert!(with(Scheme::Musl, Transfer::Pic, Positions::Projected)
        .validate()
        .is_ok());
}

#[test]
fn another_codes_conventions_are_refused_with_a_reconstruction_or_a_consistent_mass() {
    let grid = Grid::new(Method::Bsmpm { degree: 2 }, 0.0, 2.0, 2).unwrap();
    let p = Particles::new(
        vec![0.5, 1.25],
        vec![1.0; 2],
        vec![1.0; 2],
        vec![0.0; 2],
        vec![0.0; 2],
    )
    .unwrap();
    let settings = Settings {
        force_mapping: Mapping::Tls,
        velocity_mapping: Mapping::Tls,
        mass: MassMatrix::Lumped,
        constitutive: Constitutive::SmallStrain,
        young: 10.0,
        poisson: 0.0,
        body_force: None,
        gravity: 0.0,
        gravity_ramp: None,
        dirichlet: vec![],
        consistent_acceleration: false,
        tls_density_average: hompm::reconstruct::taylor::CellAverage::Exact,
        conventions: with(Scheme::Usl, Transfer::Flip, Positions::Grid),
    };
    let e = Simulation::new(grid, p, settings)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("direct mapping with a lumped mass"), "{e}");
}

#[test]
fn every_flag_value_is_registered_once_with_help_citation_and_codes_and_parses_back() {
    for c in REGISTRY {
        assert!(!c.help.is_empty() && !c.citation.is_empty() && !c.codes.is_empty());
        assert_eq!(
            REGISTRY
                .iter()
                .filter(|d| d.flag == c.flag && d.value == c.value)
                .count(),
            1
        );
    }
    for v in registered("scheme") {
        assert_eq!(Scheme::from_name(v.value).unwrap().name(), v.value);
    }
    for v in registered("positions") {
        assert_eq!(Positions::from_name(v.value).unwrap().name(), v.value);
    }
    for v in registered("body-force") {
        assert_eq!(BodyForceAt::from_name(v.value).unwrap().name(), v.value);
    }
    assert_eq!(Transfer::from_name("flip").unwrap(), Transfer::Flip);
    assert_eq!(Transfer::from_name("pic").unwrap(), Transfer::Pic);
    assert_eq!(
        Transfer::from_name("flip:0.99").unwrap(),
        Transfer::Blend(0.99)
    );
    assert_eq!(Transfer::from_name("flip:1").unwrap(), Transfer::Flip);
    assert_eq!(Transfer::from_name("flip:0").unwrap(), Transfer::Pic);
    assert_eq!(Transfer::from_name("apic").unwrap(), Transfer::Apic);
    for bad in ["flip:1.5", "flip:-0.1", "flip:x", "mpm", "flip:"] {
        assert!(Transfer::from_name(bad).is_err(), "{bad}");
    }
    assert!(Scheme::from_name("mls").is_err());
    assert_eq!(Transfer::Blend(0.99).flip_weight(), 0.99);
}

/// b = (X, 2Y) per unit mass: the particle and the node forms differ.
struct LinearForce;
impl hompm::mpm2d::BodyForce2d for LinearForce {
    fn fill(&self, _t: f64, x0: &[[f64; 2]], out: &mut [[f64; 2]]) {
        for (o, x) in out.iter_mut().zip(x0) {
            *o = [x[0], 2.0 * x[1]];
        }
    }
}

/// One particle at (0.25, 0.25) with V = 0.5, ρ = 4 (m = 2) and
/// v = (1, −2), zero stress, on 2 × 2 bilinear cells of [0, 1]² (h = ½):
/// N = ¼ on the four nodes (0, 0), (½, 0), (0, ½), (½, ½).
fn one_particle_2d(conventions: Conventions) -> Simulation2d {
    let grid = Grid2d::new(Basis2d::Bilinear, 1.0, 2).unwrap();
    let p = Particles2d::new(vec![[0.25, 0.25]], vec![0.5], 4.0, vec![[1.0, -2.0]]).unwrap();
    let settings = Settings2d {
        formulation: Formulation::UpdatedLagrangian,
        mapping: Mapping2d::Direct,
        material: NeoHookean::from_young_poisson(1.0, 0.3).unwrap(),
        mls_support: 1.0,
        conventions,
    };
    let force: Box<dyn hompm::mpm2d::BodyForce2d> = Box::new(LinearForce);
    let mut sim = Simulation2d::new(grid, p, settings, Some(force)).unwrap();
    sim.step(DT).unwrap();
    sim
}

#[test]
fn the_body_force_at_the_nodes_is_the_nodal_mass_times_b_at_the_node() {
    // m_i = ½ on the four nodes; b(X_i) = (0, ½, 0, ½) along x for nodes
    // 0, 1, 3, 4 (i = ix + 3 iy): f_x = (0, ¼, 0, ¼).
    let nodes = one_particle_2d(Conventions {
        body_force: BodyForceAt::Nodes,
        ..Conventions::MLS_PAPER
    });
    let f: Vec<f64> = nodes.workspace.force.iter().map(|f| f[0]).collect();
    assert_all(&f, &[0.0, 0.25, 0.0, 0.0, 0.25, 0.0, 0.0, 0.0, 0.0]);
    // From the particles, Σ_p N_i m_p b(X_p) = ¼ · 2 · ¼ on each.
    let particles = one_particle_2d(Conventions::MLS_PAPER);
    let f: Vec<f64> = particles.workspace.force.iter().map(|f| f[0]).collect();
    assert_all(&f, &[0.125, 0.125, 0.0, 0.125, 0.125, 0.0, 0.0, 0.0, 0.0]);
}

#[test]
fn the_2d_blend_and_projected_positions_follow_the_1d_formulas() {
    // Particles form: a_i = f_i/m_i = (¼, 0) on the four nodes (walls zero
    // the normal components on nodes 0, 1, 3: a_x = 0 at x = 0, so nodes 0
    // and 3); v^{t+1}_i = v_i + Δt a_i.
    let flip = one_particle_2d(Conventions::MLS_PAPER);
    let pic = one_particle_2d(Conventions {
        transfer: Transfer::Pic,
        ..Conventions::MLS_PAPER
    });
    let half = one_particle_2d(Conventions {
        transfer: Transfer::Blend(0.5),
        ..Conventions::MLS_PAPER
    });
    for d in 0..2 {
        let expected = 0.5 * flip.particles.velocity[0][d] + 0.5 * pic.particles.velocity[0][d];
        assert_relative_eq!(
            half.particles.velocity[0][d],
            expected,
            max_relative = 1e-12
        );
    }
    // PIC: v_p = Σ N_i v_i^{t+1}, the velocity Eq. (30) moves the particle with.
    let moved = [
        (pic.particles.x[0][0] - 0.25) / DT,
        (pic.particles.x[0][1] - 0.25) / DT,
    ];
    for (v, m) in pic.particles.velocity[0].iter().zip(moved) {
        assert_relative_eq!(*v, m, max_relative = 1e-12);
    }
    // Projected positions move the particle with v^L = Σ N_i v_i^L.
    let projected = one_particle_2d(Conventions {
        positions: Positions::Projected,
        ..Conventions::MLS_PAPER
    });
    let ws = &projected.workspace;
    for (d, x) in projected.particles.x[0].into_iter().enumerate() {
        let v_end: f64 = [0usize, 1, 3, 4]
            .iter()
            .map(|&i| 0.25 * ws.velocity_end[i][d])
            .sum();
        assert!(v_end.abs() > 1e-3, "the particle moves in {d}");
        assert_relative_eq!(x, 0.25 + DT * v_end, max_relative = 1e-12);
    }
    // Both rules keep u_p = x_p − X_p.
    for p in [&projected.particles, &pic.particles, &half.particles] {
        assert_eq!(p.displacement[0], [p.x[0][0] - 0.25, p.x[0][1] - 0.25]);
    }
    assert!((projected.particles.x[0][0] - flip.particles.x[0][0]).abs() > 1e-6);
}

#[test]
fn usl_in_2d_deforms_with_the_updated_grid_velocity() {
    let usl = one_particle_2d(Conventions {
        scheme: Scheme::Usl,
        ..Conventions::MLS_PAPER
    });
    assert_eq!(usl.workspace.velocity_end, usl.workspace.velocity_next);
    let usf = Conventions {
        scheme: Scheme::Usf,
        ..Conventions::MLS_PAPER
    };
    let grid = Grid2d::new(Basis2d::Bilinear, 1.0, 2).unwrap();
    let p = Particles2d::new(vec![[0.25, 0.25]], vec![0.5], 4.0, vec![[1.0, -2.0]]).unwrap();
    let settings = Settings2d {
        formulation: Formulation::UpdatedLagrangian,
        mapping: Mapping2d::Direct,
        material: NeoHookean::from_young_poisson(1.0, 0.3).unwrap(),
        mls_support: 1.0,
        conventions: usf,
    };
    assert!(Simulation2d::new(grid, p, settings, None).is_err());
}

#[test]
fn the_axis_aligned_solution_has_one_half_wave_and_its_own_body_force() {
    let mut s = parameters("mls-paper-e1e7").unwrap();
    s.solution = SolutionForm::AxisAligned;
    let t = 0.0031;
    let phase = (s.young / s.density).sqrt() * std::f64::consts::PI * t / s.length;
    // u_x = A sin(πX/L) sin(cπt/L): at X = ½ the sine is 1.
    assert_relative_eq!(
        s.displacement([0.5, 0.3], t)[0],
        s.amplitude * phase.sin(),
        max_relative = 1e-14
    );
    // b = ü − ∇·P/ρ₀ by central differences of this form.
    let m = s.material().unwrap();
    let (hx, ht) = (1e-5, 1e-7);
    for x0 in [[0.13, 0.71], [0.4, 0.22], [0.9, 0.55]] {
        let p_at = |x: [f64; 2]| m.first_piola(&s.deformation_gradient(x, t)).unwrap();
        let b = s.body_force(x0, t).unwrap();
        for d in 0..2 {
            let mut plus = x0;
            let mut minus = x0;
            plus[d] += hx;
            minus[d] -= hx;
            let div = (p_at(plus)[(d, d)] - p_at(minus)[(d, d)]) / (2.0 * hx);
            let u = |t: f64| s.displacement(x0, t)[d];
            let acc = (u(t + ht) - 2.0 * u(t) + u(t - ht)) / (ht * ht);
            assert_relative_eq!(b[d], acc - div / s.density, max_relative = 1e-4);
        }
    }
    // The two forms differ.
    let paper = parameters("mls-paper-e1e7").unwrap();
    assert!((paper.displacement([0.5, 0.3], t)[0]).abs() < 1e-15);
    assert_eq!(
        SolutionForm::from_name("axis-aligned").unwrap(),
        SolutionForm::AxisAligned
    );
    assert!(SolutionForm::from_name("uintah").is_err());
}

/// One particle at (x, y) on Taichi's grid (`--knots padded`, quadratic
/// B-splines, 4 cells on [0, 1]) with APIC and the affine gradient.
fn taichi_particle(x: f64, y: f64, stress: nalgebra::Matrix2<f64>) -> Simulation2d {
    let grid = Grid2d::with_knots(
        Basis2d::BSpline { degree: 2 },
        1.0,
        4,
        hompm::mpm::conventions::Knots::Padded,
    )
    .unwrap();
    let mut p = Particles2d::new(vec![[x, y]], vec![0.01], 4.0, vec![[0.0; 2]]).unwrap();
    p.stress[0] = stress;
    let settings = Settings2d {
        formulation: Formulation::UpdatedLagrangian,
        mapping: Mapping2d::Direct,
        material: NeoHookean::from_young_poisson(1.0, 0.3).unwrap(),
        mls_support: 1.0,
        conventions: taichi(),
    };
    Simulation2d::new(grid, p, settings, None).unwrap()
}

fn taichi() -> Conventions {
    Conventions {
        scheme: Scheme::Usl,
        transfer: Transfer::Apic,
        knots: hompm::mpm::conventions::Knots::Padded,
        gradient: hompm::mpm::conventions::Gradient::Affine,
        ..Conventions::MLS_PAPER
    }
}

#[test]
fn padded_knots_are_node_centred_quadratic_b_splines_with_one_node_beyond_each_wall() {
    let h = 0.25;
    let sim = taichi_particle(0.3 * h, 0.6, nalgebra::Matrix2::zeros());
    let grid = &sim.grid;
    assert_eq!(grid.nodes_per_side(), 4 + 3);
    assert_eq!(grid.wall_rows(), 2);
    let along = grid.node_positions_along();
    assert_all(&along, &[-0.25, 0.0, 0.25, 0.5, 0.75, 1.0, 1.25]);
    // Taichi's weights: base = floor(x/h − ½) = −1, fx = x/h − base = 1.3:
    // (½(3/2 − fx)², ¾ − (fx − 1)², ½(fx − ½)²) on nodes −1, 0, 1.
    let fx: f64 = 1.3;
    let s = &sim.workspace.stencils_x;
    assert_eq!(s.first[0], 0, "node −1 is the first");
    assert_all(
        s.values_of(0),
        &[
            0.5 * (1.5 - fx).powi(2),
            0.75 - (fx - 1.0).powi(2),
            0.5 * (fx - 0.5).powi(2),
        ],
    );
    // Only quadratic B-splines are padded.
    assert!(Grid2d::with_knots(
        Basis2d::BSpline { degree: 3 },
        1.0,
        4,
        hompm::mpm::conventions::Knots::Padded
    )
    .is_err());
    assert!(Grid2d::with_knots(
        Basis2d::Bilinear,
        1.0,
        4,
        hompm::mpm::conventions::Knots::Padded
    )
    .is_err());
}

#[test]
fn apic_recovers_an_affine_grid_velocity_and_its_gradient_exactly() {
    // v_i = a + G x_i on every node: v_p = a + G x_p and C_p = G
    // (Jiang et al. 2015, quadratic B-splines).
    let (a, g) = ([0.3, -0.2], nalgebra::Matrix2::new(1.5, -0.7, 0.4, 2.0));
    let mut sim = taichi_particle(0.37, 0.61, nalgebra::Matrix2::zeros());
    let along = sim.grid.node_positions_along();
    let n = along.len();
    for i in 0..n * n {
        let x = [along[i % n], along[i / n]];
        sim.workspace.velocity_next[i] = [
            a[0] + g[(0, 0)] * x[0] + g[(0, 1)] * x[1],
            a[1] + g[(1, 0)] * x[0] + g[(1, 1)] * x[1],
        ];
    }
    let (grid, p, ws) = (&sim.grid, &mut sim.particles, &sim.workspace);
    hompm::mpm2d::step::update_particles_apic(grid, p, ws, 0.0);
    let v = [
        a[0] + g[(0, 0)] * 0.37 + g[(0, 1)] * 0.61,
        a[1] + g[(1, 0)] * 0.37 + g[(1, 1)] * 0.61,
    ];
    assert_all(&p.velocity[0], &v);
    assert_relative_eq!(p.affine[0], g, max_relative = 1e-12);
}

#[test]
fn the_affine_internal_force_balances_and_its_first_moment_is_minus_v_sigma() {
    // f_i = −V σ D⁻¹ (x_i − x_p) N_i with D = Σ N (x_i − x_p)²: Σ_i f_i = 0
    // and Σ_i f_i ⊗ (x_i − x_p) = −V σ (MLS-MPM, Hu et al. 2018).
    let sigma = nalgebra::Matrix2::new(3.0, 0.5, 0.5, -2.0);
    let (x, y) = (0.41, 0.77);
    let mut sim = taichi_particle(x, y, sigma);
    let (grid, p, ws) = (&sim.grid, &sim.particles, &mut sim.workspace);
    hompm::mpm2d::step::map_direct_apic(grid, p, ws, hompm::mpm::conventions::Gradient::Affine);
    let along = grid.node_positions_along();
    let n = along.len();
    let (mut total, mut moment) = ([0.0; 2], nalgebra::Matrix2::zeros());
    for (i, f) in ws.force.iter().enumerate() {
        let d = [along[i % n] - x, along[i / n] - y];
        total[0] += f[0];
        total[1] += f[1];
        for r in 0..2 {
            for c in 0..2 {
                moment[(r, c)] += f[r] * d[c];
            }
        }
    }
    assert!(
        total[0].abs() < 1e-14 && total[1].abs() < 1e-14,
        "{total:?}"
    );
    assert_relative_eq!(moment, -sigma * p.volume[0], max_relative = 1e-12);
    // With the basis gradient the same moment holds (Σ ∇N_i ⊗ x_i = I),
    // but the nodal forces differ.
    let basis = ws.force.clone();
    let (grid, p, ws) = (&sim.grid, &sim.particles, &mut sim.workspace);
    hompm::mpm2d::step::map_direct_apic(grid, p, ws, hompm::mpm::conventions::Gradient::Basis);
    assert!(basis
        .iter()
        .zip(&ws.force)
        .any(|(a, b)| (a[0] - b[0]).abs() > 1e-3));
}

#[test]
fn taichis_conventions_are_refused_where_they_mean_nothing() {
    let c = taichi();
    assert!(c.validate().is_ok());
    assert!(Conventions {
        scheme: Scheme::Musl,
        ..c
    }
    .validate()
    .is_err());
    assert!(Conventions {
        transfer: Transfer::Flip,
        ..c
    }
    .validate()
    .is_err());
    assert!(c.is_two_d_only());
    // The 1D step has none of them.
    let grid = Grid::new(Method::Mpm, 0.0, 2.0, 2).unwrap();
    let p = Particles::new(vec![0.5], vec![1.0], vec![1.0], vec![0.0], vec![0.0]).unwrap();
    let settings = Settings {
        force_mapping: Mapping::Direct,
        velocity_mapping: Mapping::Direct,
        mass: MassMatrix::Lumped,
        constitutive: Constitutive::SmallStrain,
        young: 1.0,
        poisson: 0.0,
        body_force: None,
        gravity: 0.0,
        gravity_ramp: None,
        dirichlet: vec![],
        consistent_acceleration: false,
        tls_density_average: hompm::reconstruct::taylor::CellAverage::Exact,
        conventions: c,
    };
    let e = Simulation::new(grid, p, settings)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("2D only"), "{e}");
    // APIC needs D_p > 0, which bilinear functions lose at the nodes.
    let grid = Grid2d::new(Basis2d::Bilinear, 1.0, 2).unwrap();
    let p = Particles2d::new(vec![[0.25, 0.25]], vec![0.5], 4.0, vec![[0.0; 2]]).unwrap();
    let settings = Settings2d {
        formulation: Formulation::UpdatedLagrangian,
        mapping: Mapping2d::Direct,
        material: NeoHookean::from_young_poisson(1.0, 0.3).unwrap(),
        mls_support: 1.0,
        conventions: Conventions {
            knots: hompm::mpm::conventions::Knots::Open,
            ..c
        },
    };
    assert!(Simulation2d::new(grid, p, settings, None).is_err());
}

#[test]
fn the_flags_of_a_set_of_conventions_name_exactly_what_differs_from_the_dimensions_default() {
    assert!(Conventions::BOOK.flags(1).is_empty());
    assert!(Conventions::MLS_PAPER.flags(2).is_empty());
    assert_eq!(Conventions::default_for(1), Conventions::BOOK);
    assert_eq!(Conventions::default_for(2), Conventions::MLS_PAPER);
    assert!(Conventions::MLS_PAPER.is_mls_paper() && !Conventions::BOOK.is_mls_paper());
    assert!(Conventions::BOOK.is_book() && !Conventions::MLS_PAPER.is_book());
    // The MLS paper's step in 1D differs from the book's in its positions
    // only, and the book's in 2D likewise.
    assert_eq!(Conventions::MLS_PAPER.flags(1), vec!["--positions grid"]);
    assert_eq!(Conventions::BOOK.flags(2), vec!["--positions projected"]);
    let every = Conventions {
        scheme: Scheme::Usl,
        transfer: Transfer::Apic,
        positions: Positions::Grid,
        body_force: BodyForceAt::Nodes,
        knots: hompm::mpm::conventions::Knots::Padded,
        gradient: hompm::mpm::conventions::Gradient::Affine,
    };
    assert_eq!(
        every.flags(1),
        vec![
            "--scheme usl",
            "--transfer apic",
            "--positions grid",
            "--body-force nodes",
            "--knots padded",
            "--gradient affine"
        ]
    );
    // Each 2D-only convention alone makes the set 2D-only.
    for one in [
        Conventions {
            transfer: Transfer::Apic,
            ..Conventions::BOOK
        },
        Conventions {
            knots: hompm::mpm::conventions::Knots::Padded,
            ..Conventions::BOOK
        },
        Conventions {
            gradient: hompm::mpm::conventions::Gradient::Affine,
            ..Conventions::BOOK
        },
    ] {
        assert!(one.is_two_d_only(), "{one:?}");
    }
    assert!(!Conventions::BOOK.is_two_d_only() && !Conventions::MLS_PAPER.is_two_d_only());
}

#[test]
fn apic_maps_the_affine_momentum_whose_first_moment_is_m_c_d() {
    // Σ_i (mv)_i = m_p v_p and Σ_i (mv)_i ⊗ (x_i − x_p) = m_p C_p D_p with
    // D_p = h²/4 I for quadratic B-splines (Jiang et al. 2015).
    let (x, y) = (0.41, 0.77);
    let mut sim = taichi_particle(x, y, nalgebra::Matrix2::zeros());
    let c = nalgebra::Matrix2::new(1.5, -0.7, 0.4, 2.0);
    sim.particles.velocity[0] = [0.3, -0.2];
    sim.particles.affine[0] = c;
    let (grid, p, ws) = (&sim.grid, &sim.particles, &mut sim.workspace);
    hompm::mpm2d::step::map_direct_apic(grid, p, ws, hompm::mpm::conventions::Gradient::Affine);
    let along = grid.node_positions_along();
    let n = along.len();
    let m = p.mass[0];
    let (mut total, mut moment) = ([0.0; 2], nalgebra::Matrix2::zeros());
    for (i, mv) in ws.momentum.iter().enumerate() {
        let d = [along[i % n] - x, along[i / n] - y];
        total[0] += mv[0];
        total[1] += mv[1];
        for r in 0..2 {
            for k in 0..2 {
                moment[(r, k)] += mv[r] * d[k];
            }
        }
    }
    assert_all(&total, &[m * 0.3, m * -0.2]);
    assert_relative_eq!(ws.mass.iter().sum::<f64>(), m, max_relative = 1e-12);
    let h = 0.25;
    assert_relative_eq!(moment, c * (m * h * h / 4.0), max_relative = 1e-12);
}

#[test]
fn another_codes_step_is_refused_when_either_mapping_is_not_direct() {
    for (force, velocity) in [
        (Mapping::Tls, Mapping::Direct),
        (Mapping::Direct, Mapping::Tls),
    ] {
        let grid = Grid::new(Method::Bsmpm { degree: 2 }, 0.0, 2.0, 2).unwrap();
        let p = Particles::new(
            vec![0.5, 1.25],
            vec![1.0; 2],
            vec![1.0; 2],
            vec![0.0; 2],
            vec![0.0; 2],
        )
        .unwrap();
        let settings = Settings {
            force_mapping: force,
            velocity_mapping: velocity,
            mass: MassMatrix::Lumped,
            constitutive: Constitutive::SmallStrain,
            young: 10.0,
            poisson: 0.0,
            body_force: None,
            gravity: 0.0,
            gravity_ramp: None,
            dirichlet: vec![],
            consistent_acceleration: false,
            tls_density_average: hompm::reconstruct::taylor::CellAverage::Exact,
            conventions: with(Scheme::Usl, Transfer::Flip, Positions::Grid),
        };
        assert!(
            Simulation::new(grid, p, settings).is_err(),
            "{force:?} {velocity:?}"
        );
    }
}
