//! # DDMPM's node integrals
//!
//! The dual domain of DDMPM (TLS paper §3.3, after Dhakal and Zhang): the
//! node volumes V_j = ∫_Ω φ_j dΩ and the integrals ∫_Ω φ_j ∇φ_i dΩ of the
//! linear Lagrange basis, exactly (two Gauss points per element) or by a
//! quadrature over the particles: one point per particle, or n subpoints
//! spread over its volume (TLS paper §6.2 and Table 8). A subpoint rule
//! with n = 128 visits 128 points per particle in every step, so its loop
//! keeps the sums of the current element in registers while the subpoints
//! stay in it (the same additions in the same order, so the same bits).
//!
//! Items: `DualDomain`, `SubpointRule`, `dual_domain`,
//! `accumulate_node_integrals`.

use super::NodeIntegrals;
use crate::basis::Basis1d;
use crate::error::{Error, Result};
use crate::lagrange::LagrangeBasis;
use crate::quadrature::GaussLegendre;

/// DDMPM's node integrals of a grid (TLS paper §3.3).
#[derive(Debug, Clone)]
pub(super) struct DualDomain {
    /// The rule that filled the integrals.
    pub(super) rule: NodeIntegrals,
    /// V_j = ∫ φ_j.
    pub(super) node_volume: Vec<f64>,
    /// g[j] = [∫ φ_j ∇φ_{j−1}, ∫ φ_j ∇φ_j, ∫ φ_j ∇φ_{j+1}].
    pub(super) g: Vec<[f64; 3]>,
    /// t_s − ½ for each of the rule's n subpoints (none for the exact
    /// rule), computed once with the rule ([`DualDomain::set_rule`]).
    subpoint_offsets: Vec<f64>,
}

impl DualDomain {
    /// Adds one quadrature point x with weight w to V_j and ∫φ_j∇φ_i
    /// (P1: the two functions of the element of x).
    fn add_point(&mut self, basis: &LagrangeBasis, x: f64, w: f64) -> Result<()> {
        let mut phi = [0.0; 2];
        let mut grad = [0.0; 2];
        let k = basis.evaluate_into(x, &mut phi, &mut grad)?;
        for (a_, &phi_j) in phi.iter().enumerate() {
            let j = k + a_;
            self.node_volume[j] += w * phi_j;
            for (b_, &grad_i) in grad.iter().enumerate() {
                // slot = i − j + 1 with i = k + b_.
                self.g[j][b_ + 1 - a_] += w * phi_j * grad_i;
            }
        }
        Ok(())
    }
}

/// The node integrals of DDMPM, TLS paper §3.3: V_j = ∫_Ω φ_j dΩ and
/// ∫_Ω φ_j ∇φ_i dΩ, exactly by two Gauss points per element.
pub(super) fn dual_domain(basis: &LagrangeBasis) -> Result<DualDomain> {
    let n = basis.num_basis();
    let mut dual = DualDomain {
        rule: NodeIntegrals::Exact,
        node_volume: vec![0.0; n],
        g: vec![[0.0; 3]; n],
        subpoint_offsets: Vec::new(),
    };
    let rule = GaussLegendre::new(2)?;
    for (c0, c1) in basis.cells() {
        for q in rule.on_interval(c0, c1) {
            dual.add_point(basis, q.x, q.weight)?;
        }
    }
    Ok(dual)
}

/// Where subpoint s of n sits in a particle's volume: at
/// x_p + V_p (t_s − ½) with t_s in [0, 1] (TLS paper §6.2).
#[derive(Debug, Clone, Copy)]
pub(super) enum SubpointRule {
    /// t = ½: the particle itself (particle quadrature).
    Middle,
    /// t_s = (s + ½)/n: the midpoints of n equal parts.
    Midpoints,
    /// t_s = s/(n − 1): n points from end to end.
    Ends,
}

impl SubpointRule {
    /// t_s for subpoint s of n.
    #[inline(always)]
    fn position(self, s: usize, n: usize) -> f64 {
        match self {
            Self::Middle => 0.5,
            Self::Midpoints => (s as f64 + 0.5) / n as f64,
            Self::Ends => s as f64 / (n - 1) as f64,
        }
    }
}

impl DualDomain {
    /// Takes `rule` for the node integrals and computes its subpoints'
    /// offsets t_s − ½ (TLS paper §6.2): each quotient t_s once here, not
    /// once per particle and step.
    pub(super) fn set_rule(&mut self, rule: NodeIntegrals) {
        let (n, position) = match rule {
            NodeIntegrals::Exact => (0, SubpointRule::Middle),
            NodeIntegrals::Particles => (1, SubpointRule::Middle),
            NodeIntegrals::Subpoints(n) => (n, SubpointRule::Midpoints),
            NodeIntegrals::EndSubpoints(n) => (n, SubpointRule::Ends),
        };
        self.rule = rule;
        self.subpoint_offsets = (0..n).map(|s| position.position(s, n) - 0.5).collect();
    }
}

/// V_j and ∫φ_j∇φ_i by the rule's n subpoints per particle, each of weight
/// V_p/n, at x_p + V_p (t_s − ½) clamped to the grid (TLS paper §3.3,
/// §6.2). Not for the exact rule, which has no subpoints.
pub(super) fn accumulate_node_integrals(
    dd: &mut DualDomain,
    basis: &LagrangeBasis,
    positions: &[f64],
    volumes: &[f64],
) -> Result<()> {
    // Taken out for the loop, which writes the sums into `dd`.
    let offsets = std::mem::take(&mut dd.subpoint_offsets);
    let summed = accumulate(dd, basis, positions, volumes, &offsets);
    dd.subpoint_offsets = offsets;
    summed
}

/// [`accumulate_node_integrals`] with t_s − ½ = `offsets[s]`.
#[inline(always)]
fn accumulate(
    dd: &mut DualDomain,
    basis: &LagrangeBasis,
    positions: &[f64],
    volumes: &[f64],
    offsets: &[f64],
) -> Result<()> {
    let n = offsets.len();
    let (a, b) = basis.domain();
    dd.node_volume.fill(0.0);
    dd.g.fill([0.0; 3]);
    let linear = basis.degree() == 1;
    let mut sums = ElementSums::NONE;
    for (&x, &v) in positions.iter().zip(volumes) {
        crate::error::finite("particle volume", v)?;
        if !(a..=b).contains(&x) {
            crate::error::finite("position", x)?;
            return Err(Error::OutsideDomain { x, a, b });
        }
        let w = v / n as f64;
        for &t in offsets {
            let offset = v * t;
            let at = (x + offset).clamp(a, b);
            if !linear {
                // Only P1 has a dual domain; any other basis takes the
                // point-by-point path (and its error).
                dd.add_point(basis, at, w)?;
                continue;
            }
            let (mut phi, mut grad) = ([0.0; 2], [0.0; 2]);
            let k = basis.evaluate_of_width::<2>(at, &mut phi, &mut grad)?;
            sums.move_to(k, dd);
            // j = k: ∫φ_k ∇φ_k, ∫φ_k ∇φ_{k+1}; j = k + 1: ∫φ_{k+1} ∇φ_k,
            // ∫φ_{k+1} ∇φ_{k+1} (the slots of `DualDomain::add_point`).
            for (b_, &grad_i) in grad.iter().enumerate() {
                sums.left_node[b_] += w * phi[0] * grad_i;
                sums.right_node[b_] += w * phi[1] * grad_i;
            }
            sums.volume[0] += w * phi[0];
            sums.volume[1] += w * phi[1];
        }
    }
    sums.store(dd);
    Ok(())
}

/// The sums of one element k held in registers: V_k, V_{k+1},
/// g[k][1..3] and g[k + 1][0..2].
#[derive(Clone, Copy)]
struct ElementSums {
    element: usize,
    volume: [f64; 2],
    left_node: [f64; 2],
    right_node: [f64; 2],
}

impl ElementSums {
    /// No element yet.
    const NONE: Self = Self {
        element: usize::MAX,
        volume: [0.0; 2],
        left_node: [0.0; 2],
        right_node: [0.0; 2],
    };

    /// Makes element k current: stores the previous one's sums, loads k's.
    #[inline(always)]
    fn move_to(&mut self, k: usize, dd: &mut DualDomain) {
        if k == self.element {
            return;
        }
        self.store(dd);
        let (g, v) = (&dd.g, &dd.node_volume);
        *self = Self {
            element: k,
            volume: [v[k], v[k + 1]],
            left_node: [g[k][1], g[k][2]],
            right_node: [g[k + 1][0], g[k + 1][1]],
        };
    }

    /// Stores the current element's sums.
    fn store(&self, dd: &mut DualDomain) {
        let k = self.element;
        if k == usize::MAX {
            return;
        }
        dd.node_volume[k] = self.volume[0];
        dd.node_volume[k + 1] = self.volume[1];
        dd.g[k][1..3].copy_from_slice(&self.left_node);
        dd.g[k + 1][0..2].copy_from_slice(&self.right_node);
    }
}
