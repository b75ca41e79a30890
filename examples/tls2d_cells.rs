//! # hompm's 2D TLS on given particles, for scripts/tls2d_code_check.sh
//!
//! Reads particles from standard input, one per line: `x y V f s` (position,
//! volume, a value fitted under the constraint, a value fitted without it),
//! on the grid of `cells`² cells of side L (the two arguments), and prints,
//! for every Gauss point of every cell that holds particles, hompm's
//! reconstructed values (TLS paper Eqs. 13–14 in 2D, src/mpm2d/tls.rs):
//! f̃_g = Σ_p φ_gp f_p with the conservative TLS and s̃_g = Σ_p φ_gp s_p
//! with the unconstrained one, each under the engine's basis rule
//! ([`BasisRule::Conditioning`]) and the particle-count rule of MPM2D_basic
//! ([`BasisRule::ParticleCount`]). The Gauss points are the engine's
//! (`Grid2d::gauss_abscissae`, 2×2 Gauss–Legendre per cell).
//!
//! Output, one line per Gauss point, 17 significant digits:
//! `cx cy q x_g y_g n f_cond f_count s_cond s_count`.
//!
//! Items: `main`.

use hompm::mpm2d::reconstruction::{GaussGrid, GaussReconstruction};
use hompm::mpm2d::tls::{BasisRule, TaylorOrder2d, TlsShapes, TlsVariant};
use hompm::mpm2d::{Basis2d, Grid2d, Particles2d};
use hompm::reconstruct::taylor::DegenerateCells;
use hompm::{Error, Result};
use std::io::Read;

/// Σ_p φ_gp v_p at every Gauss point of the shapes' lists.
fn values_at_gauss_points(shapes: &TlsShapes, values: &[f64]) -> Vec<f64> {
    let lists = shapes.lists();
    (0..lists.start.len())
        .map(|g| {
            (lists.start[g]..lists.end[g])
                .map(|k| lists.phi[k] * values[lists.particle[k] as usize])
                .sum()
        })
        .collect()
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = || Error::InvalidArgument("usage: tls2d_cells CELLS LENGTH < particles".into());
    let cells: usize = args
        .first()
        .and_then(|a| a.parse().ok())
        .ok_or_else(usage)?;
    let length: f64 = args.get(1).and_then(|a| a.parse().ok()).ok_or_else(usage)?;
    let mut text = String::new();
    std::io::stdin()
        .read_to_string(&mut text)
        .map_err(|e| Error::Io(e.to_string()))?;
    let mut rows = Vec::new();
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        let row: Vec<f64> = line
            .split_whitespace()
            .map(|w| w.parse::<f64>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|e| Error::InvalidArgument(format!("{line:?}: {e}")))?;
        if row.len() != 5 {
            return Err(Error::InvalidArgument(format!("{line:?}: want x y V f s")));
        }
        rows.push(row);
    }
    let grid = Grid2d::new(Basis2d::BSpline { degree: 2 }, length, cells)?;
    let h = grid.cell_size();
    let positions: Vec<[f64; 2]> = rows.iter().map(|r| [r[0], r[1]]).collect();
    let volumes = rows.iter().map(|r| r[2]).collect();
    let particles = Particles2d::new(positions, volumes, 1.0, vec![[0.0; 2]; rows.len()])?;
    let cell_of = |x: f64| ((x / h).floor().max(0.0) as usize).min(cells - 1);
    let cell_x: Vec<usize> = particles.x.iter().map(|p| cell_of(p[0])).collect();
    let cell_y: Vec<usize> = particles.x.iter().map(|p| cell_of(p[1])).collect();
    let gauss = GaussGrid {
        abscissae: grid.gauss_abscissae(),
        cells,
        cell_size: h,
    };
    let f: Vec<f64> = rows.iter().map(|r| r[3]).collect();
    let s: Vec<f64> = rows.iter().map(|r| r[4]).collect();
    let mut columns = Vec::new();
    for (variant, values) in [
        (TlsVariant::Conservative, &f),
        (TlsVariant::Unconstrained, &s),
    ] {
        for rule in [BasisRule::Conditioning, BasisRule::ParticleCount] {
            let mut shapes = TlsShapes::new(
                TaylorOrder2d::Quadratic,
                variant,
                DegenerateCells::ReduceBasis,
                cells,
                particles.len(),
            )?
            .with_basis_rule(rule);
            shapes.evaluate(&gauss, &particles, &cell_x, &cell_y)?;
            columns.push(values_at_gauss_points(&shapes, values));
        }
    }
    let ng = 2 * cells;
    for cy in 0..cells {
        for cx in 0..cells {
            let n = (0..particles.len())
                .filter(|&k| cell_x[k] == cx && cell_y[k] == cy)
                .count();
            if n == 0 {
                continue;
            }
            for (q, (i, j)) in [(0, 0), (1, 0), (0, 1), (1, 1)].into_iter().enumerate() {
                let g = (2 * cx + i) + ng * (2 * cy + j);
                let (xg, yg) = (gauss.abscissae[2 * cx + i], gauss.abscissae[2 * cy + j]);
                let values: Vec<String> =
                    columns.iter().map(|c| format!("{:.16e}", c[g])).collect();
                println!("{cx} {cy} {q} {xg:.16e} {yg:.16e} {n} {}", values.join(" "));
            }
        }
    }
    Ok(())
}
