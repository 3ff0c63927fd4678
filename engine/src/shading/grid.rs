//! The spatial models' tables for **any** material, interpolated from one nondimensional grid
//! measured offline by the project's Monte Carlo (`assets/sss/optics.tables`, baked by
//! `dermis lut --out assets/sss --grid tables`, `dermis_measure::grid`): no Monte Carlo at run
//! time, on the desktop or the phone.
//!
//! **Why one grid serves every material.** For g = 0 the transport in a channel is fixed by
//! its reduced albedo α' and η once lengths are measured in units of 1/σ'_t: the pencil
//! beam's exitance is R(r) = σ'_t² R̂(σ'_t r; α', η) (a kernel ring [a, b) mm holds the mass
//! Φ̂(σ'_t b) − Φ̂(σ'_t a) of the nondimensional cumulative Φ̂), q(μ) = R(μ)/R(1) is
//! dimensionless, the forward shift is δ = δ̂/σ'_t, a slab d mm thick transmits T̂(σ'_t d),
//! a sphere of radius ρ mm is the nondimensional sphere σ'_t ρ ([`super::sphere_grid`]). Each
//! channel has its own σ'_t and α', so channels scale independently. For g ≠ 0 the grid serves
//! the similar medium (σ'_s = σ_s(1 − g), isotropic), as every model of the project does; its
//! error against the real phase function is measured in `docs/optics.md` §3.
//!
//! **Axes.** s = √(1 − α'): [`S_COUNT`] nodes from [`S_FIRST`] to [`S_LAST`] (α' from
//! 1 − 9·10⁻⁶ to 0.05) equally spaced in w = ln(s/α'): geometric in s toward α' → 1, where
//! the length scale 1/σ_tr = 1/(σ'_t √3 s) changes fastest, about even in α' toward α' → 0,
//! where the albedo and the slabs' decay do; clamped below (a whiter channel takes the
//! s = S_FIRST shapes), and past S_LAST the total falls linearly to 0 at α' = 0. η: t = √(η − 1) on
//! [`ETA_COUNT`] equally spaced nodes over η 1.0–1.6 ([`eta_node`]; just above η = 1 total
//! internal reflection sets in and the tables change like √(η − 1)); clamped outside.
//! Per node: Φ̂ over ρ̂ = 10⁻³·2^{k/5} (k < [`RHO_COUNT`]: to 1.7·10⁴ mean free paths), q and
//! δ̂ at the oblique nodes, T̂ over τ = 2^{j/2 − 4} (j < [`TAU_COUNT`]: 0.0625–256).
//!
//! **Interpolation** (per channel): scalars (the kernel's total, ln of its median radius,
//! q, δ̂, and ln T̂ at the channel's τ relative to the asymptotic decay, ln T̂ + κ(s)τ) by cubic
//! Lagrange over the four nearest nodes in ln s and in t; the kernel's shape by displacement: each of the four bracketing nodes' normalised
//! cumulative Φ̂/Φ̂(∞), monotone cubic in ln ρ̂, is read at ρ̂ scaled by the ratio of its median
//! radius to the interpolated one, and the four are blended bilinearly (a kernel whose scale
//! changes between nodes keeps its shape instead of turning into two bumps). The same f64
//! code runs on every platform, so the APK's tables equal the desktop's for the same optics.

use std::sync::OnceLock;

use super::bake::{
    budget_values, ring_edges, Bake, Budget, DEFAULT_BUDGET, OBLIQUE_NODES, SLAB_FIRST_MM,
    SLAB_NODES,
};
use super::interp::{lagrange4, linear2, monotone};
use super::transport::asymptotic_decay;
use super::Material;

/// s nodes: equally spaced in w = ln(s/α') (α' = 1 − s²) from S_FIRST to S_LAST: geometric
/// in s toward α' → 1, where a material's length scale 1/(σ'_t √3 s) changes fastest, and
/// about even in α' toward α' → 0, where the albedo and the slabs' decay change fastest.
pub const S_FIRST: f64 = 0.003;
pub const S_LAST: f64 = 0.9747;
pub const S_COUNT: usize = 20;
/// η nodes: t = √(η − 1) equally spaced over [0, √(ETA_MAX − 1)].
pub const ETA_MAX: f64 = 1.6;
pub const ETA_COUNT: usize = 6;
/// Kernel radii ρ̂_k = RHO_FIRST·2^{k/RHO_PER_OCTAVE} (mean free paths 1/σ'_t).
pub const RHO_FIRST: f64 = 1e-3;
pub const RHO_PER_OCTAVE: usize = 5;
pub const RHO_COUNT: usize = 121;
/// Slab thicknesses τ_j = 2^{j/2 − 4} (mean free paths).
pub const TAU_COUNT: usize = 25;

/// w = ln(s/α') of s (the s axis' coordinate).
pub fn s_coordinate(s: f64) -> f64 {
    (s / (1.0 - s * s)).ln()
}

/// The s of coordinate w: the root in (0, 1) of e^w s² + s − e^w = 0.
fn s_of(w: f64) -> f64 {
    let e = w.exp();
    2.0 * e / (1.0 + (1.0 + 4.0 * e * e).sqrt())
}

/// s of node i.
pub fn s_node(i: usize) -> f64 {
    let (a, b) = (s_coordinate(S_FIRST), s_coordinate(S_LAST));
    s_of(a + (b - a) * i as f64 / (S_COUNT - 1) as f64)
}

/// η of node r of an axis of `count` nodes equally spaced in t = √(η − 1).
pub fn eta_node_of(r: usize, count: usize) -> f64 {
    let t = (ETA_MAX - 1.0).sqrt() * r as f64 / (count - 1) as f64;
    1.0 + t * t
}

/// η of the tables grid's node r.
pub fn eta_node(r: usize) -> f64 {
    eta_node_of(r, ETA_COUNT)
}

/// ρ̂ of kernel node k.
pub fn rho_node(k: usize) -> f64 {
    RHO_FIRST * 2f64.powf(k as f64 / RHO_PER_OCTAVE as f64)
}

/// τ of slab node j.
pub fn tau_node(j: usize) -> f64 {
    2f64.powf(j as f64 / 2.0 - 4.0)
}

/// One node's measured tables (σ'_t = 1).
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// Φ̂(ρ̂_k): power leaving within ρ̂_k of a normally incident pencil beam, per unit
    /// incident power (specular excluded).
    pub cdf: Vec<f64>,
    /// q(μ_k) at the oblique nodes (q(0) = 0, q(1) = 1).
    pub oblique: [f64; OBLIQUE_NODES],
    /// δ̂(μ_k) (mean free paths).
    pub shift: [f64; OBLIQUE_NODES],
    /// T̂(τ_j): diffuse transmittance of the backlit slab.
    pub slab: Vec<f64>,
}

/// The grid: nodes η-major ([`TablesGrid::index`]), and the budget they were measured with.
#[derive(Clone, Debug, PartialEq)]
pub struct TablesGrid {
    pub nodes: Vec<Node>,
    pub budget: Budget,
}

const MAGIC: &[u8; 8] = b"DERMGRD2";
const NODE_VALUES: usize = RHO_COUNT + 2 * OBLIQUE_NODES + TAU_COUNT;

/// The budget the shipped grids are measured with: the direct bake's ([`DEFAULT_BUDGET`]).
pub const GRID_BUDGET: Budget = DEFAULT_BUDGET;

/// The axes and budget a file records (a file of other axes or budget is refused).
fn header(budget: &Budget) -> Vec<f64> {
    let mut h = vec![
        S_FIRST,
        S_LAST,
        S_COUNT as f64,
        ETA_MAX,
        ETA_COUNT as f64,
        RHO_FIRST,
        RHO_PER_OCTAVE as f64,
        RHO_COUNT as f64,
        TAU_COUNT as f64,
        OBLIQUE_NODES as f64,
    ];
    h.extend(budget_values(budget));
    h
}

/// The f32 little-endian values of `bytes`, as f64.
fn f32s(bytes: &[u8]) -> impl Iterator<Item = f64> + '_ {
    bytes
        .chunks_exact(4)
        .map(|b| f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])))
}

/// Whether `bytes` start with `magic` and the f64 `header`; the rest.
pub(crate) fn strip_header<'a>(
    bytes: &'a [u8],
    magic: &[u8; 8],
    header: &[f64],
) -> Option<&'a [u8]> {
    let body = bytes.strip_prefix(magic.as_slice())?;
    let (head, rest) = body.split_at_checked(8 * header.len())?;
    head.chunks_exact(8)
        .zip(header)
        .all(|(b, v)| b == v.to_le_bytes())
        .then_some(rest)
}

/// Magic then the f64 header, little-endian.
pub(crate) fn write_header(magic: &[u8; 8], header: &[f64]) -> Vec<u8> {
    let mut out = magic.to_vec();
    for v in header {
        out.extend(v.to_le_bytes());
    }
    out
}

impl TablesGrid {
    /// Index of node (s node i, η node r).
    pub fn index(i: usize, r: usize) -> usize {
        r * S_COUNT + i
    }

    /// Magic, the header (f64), the nodes (f32).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = write_header(MAGIC, &header(&self.budget));
        for n in &self.nodes {
            let values = n
                .cdf
                .iter()
                .chain(&n.oblique)
                .chain(&n.shift)
                .chain(&n.slab);
            for v in values {
                out.extend((*v as f32).to_le_bytes());
            }
        }
        out
    }

    /// The grid in `bytes` if it has these axes and was measured at `budget`.
    pub fn from_bytes(bytes: &[u8], budget: &Budget) -> Option<TablesGrid> {
        let rest = strip_header(bytes, MAGIC, &header(budget))?;
        if rest.len() != 4 * NODE_VALUES * S_COUNT * ETA_COUNT {
            return None;
        }
        let nodes = rest
            .chunks_exact(4 * NODE_VALUES)
            .map(|b| {
                let v: Vec<f64> = f32s(b).collect();
                let (cdf, rest) = v.split_at(RHO_COUNT);
                let (oblique, rest) = rest.split_at(OBLIQUE_NODES);
                let (shift, slab) = rest.split_at(OBLIQUE_NODES);
                Node {
                    cdf: cdf.to_vec(),
                    oblique: std::array::from_fn(|k| oblique[k]),
                    shift: std::array::from_fn(|k| shift[k]),
                    slab: slab.to_vec(),
                }
            })
            .collect();
        Some(TablesGrid {
            nodes,
            budget: *budget,
        })
    }
}

/// The shipped grid's bytes.
pub const SHIPPED: &[u8] = include_bytes!("../../../assets/sss/optics.tables");

/// The shipped grid (`None` only if the file does not match this build's axes and budget,
/// which a test rules out; logged once).
pub fn shipped() -> Option<&'static TablesGrid> {
    static GRID: OnceLock<Option<TablesGrid>> = OnceLock::new();
    GRID.get_or_init(|| {
        let grid = TablesGrid::from_bytes(SHIPPED, &GRID_BUDGET);
        if grid.is_none() {
            log::error!("assets/sss/optics.tables does not match this build (`dermis lut --grid`)");
        }
        grid
    })
    .as_ref()
}

/// The position of `s` on the tables grid's s axis (node units, in w; clamped).
pub(crate) fn s_index(s: f64) -> f64 {
    let s = if s.is_finite() { s } else { S_FIRST };
    let s = s.clamp(S_FIRST, S_LAST);
    let (a, b) = (s_coordinate(S_FIRST), s_coordinate(S_LAST));
    ((s_coordinate(s) - a) / (b - a) * (S_COUNT - 1) as f64).clamp(0.0, (S_COUNT - 1) as f64)
}

/// The position of `s` on an axis of `nodes` (node units, in ln s; clamped).
pub(crate) fn s_position(s: f64, nodes: &[f64]) -> f64 {
    let s = if s.is_finite() { s } else { nodes[0] };
    let s = s.clamp(nodes[0], nodes[nodes.len() - 1]);
    let k = nodes.partition_point(|&v| v <= s).clamp(1, nodes.len() - 1) - 1;
    let f = (s.ln() - nodes[k].ln()) / (nodes[k + 1].ln() - nodes[k].ln());
    k as f64 + f.clamp(0.0, 1.0)
}

/// The position of `eta` on an η axis of `count` nodes (node units, in t = √(η − 1);
/// clamped to 1.0–[`ETA_MAX`]).
pub(crate) fn eta_position(eta: f64, count: usize) -> f64 {
    let t = (eta - 1.0).max(0.0).sqrt() / (ETA_MAX - 1.0).sqrt();
    if t.is_finite() {
        (t * (count - 1) as f64).clamp(0.0, (count - 1) as f64)
    } else {
        0.0
    }
}

/// s = √(1 − α') per channel, and σ'_t (floored).
pub fn channel(m: &Material, c: usize) -> (f64, f64) {
    let st = m.sigma_t_prime()[c].max(1e-9);
    let s = m.one_minus_albedo()[c].clamp(0.0, 1.0).sqrt();
    (s, st)
}

impl Node {
    /// Total diffuse reflectance at normal incidence per incident power.
    pub fn total(&self) -> f64 {
        self.cdf[RHO_COUNT - 1]
    }

    /// Φ̂(ρ̂)/Φ̂(∞): monotone cubic in ln ρ̂, linear in ρ̂ below the first node.
    pub fn shape(&self, rho: f64) -> f64 {
        let total = self.total().max(f64::MIN_POSITIVE);
        if rho <= RHO_FIRST {
            return (self.cdf[0] * rho.max(0.0) / RHO_FIRST) / total;
        }
        let x = (rho / RHO_FIRST).log2() * RHO_PER_OCTAVE as f64;
        (monotone(&self.cdf, x) / total).clamp(0.0, 1.0)
    }

    /// The radius holding half the kernel's power (bisection in ln ρ̂).
    pub fn median(&self) -> f64 {
        let (mut lo, mut hi) = (RHO_FIRST.ln() - 10.0, rho_node(RHO_COUNT - 1).ln());
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if self.shape(mid.exp()) < 0.5 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        (0.5 * (lo + hi)).exp()
    }

    /// ln T̂(τ) of the node of s: linear in τ between nodes; below the first node T̂ ∝ τ
    /// (single scattering); beyond the last, the medium's asymptotic decay (as the direct
    /// bake extrapolates thick slabs).
    pub fn ln_slab(&self, tau: f64, s: f64) -> f64 {
        const FLOOR: f64 = 1e-30;
        let ln = |j: usize| self.slab[j].max(FLOOR).ln();
        let first = tau_node(0);
        if tau <= first {
            return ln(0) + (tau.max(1e-9) / first).ln();
        }
        let last = TAU_COUNT - 1;
        if tau >= tau_node(last) {
            let decay = asymptotic_decay(s * s, 1.0 - s * s);
            return ln(last) - decay * (tau - tau_node(last));
        }
        let j = ((2.0 * (tau.log2() + 4.0)).floor() as usize).min(last - 1);
        let (a, b) = (tau_node(j), tau_node(j + 1));
        let f = ((tau - a) / (b - a)).clamp(0.0, 1.0);
        ln(j) * (1.0 - f) + ln(j + 1) * f
    }
}

impl TablesGrid {
    /// Σ w·value over the 4 × 4 Lagrange window of (ln s, t) around a channel's `s`, `eta`.
    fn scalar(&self, s: f64, eta: f64, value: impl Fn(&Node, f64) -> f64) -> f64 {
        let (i0, ws) = lagrange4(s_index(s), S_COUNT);
        let (r0, we) = lagrange4(eta_position(eta, ETA_COUNT), ETA_COUNT);
        let mut sum = 0.0;
        for (a, wa) in ws.iter().enumerate() {
            for (b, wb) in we.iter().enumerate() {
                if wa * wb != 0.0 {
                    let i = i0 + a;
                    sum += wa * wb * value(&self.nodes[Self::index(i, r0 + b)], s_node(i));
                }
            }
        }
        sum
    }

    /// The total diffuse reflectance at normal incidence (per incident power) of a channel of
    /// s = √(1 − α') at `eta`, interpolated as [`TablesGrid::bake`] does.
    pub fn total(&self, s: f64, eta: f64) -> f64 {
        let darker = if s > S_LAST {
            ((1.0 - s) / (1.0 - S_LAST)).clamp(0.0, 1.0)
        } else {
            1.0
        };
        (self.scalar(s, eta, |n, _| n.total()) * darker).clamp(0.0, 1.0)
    }

    /// The tables of `m`, every channel interpolated from the grid (see the module docs), on
    /// the same rings, nodes and layout as a direct bake.
    pub fn bake(&self, m: &Material) -> Bake {
        let edges = ring_edges(m);
        let x_max = *edges.last().unwrap_or(&10.0);
        let mut mass = vec![[0.0; 3]; edges.len() - 1];
        let mut oblique = [[0.0; 3]; OBLIQUE_NODES];
        let mut shift = [[0.0; 3]; OBLIQUE_NODES];
        let mut slab = [[0.0; 3]; SLAB_NODES];
        let decays: Vec<f64> = s_nodes()
            .iter()
            .map(|&s| asymptotic_decay(s * s, 1.0 - s * s))
            .collect();
        let decay_at = |sn: f64| decays[s_index(sn).round() as usize];
        for c in 0..3 {
            let (s, st) = channel(m, c);
            let eta = m.eta;
            let total = self.total(s, eta);
            let median = self.scalar(s, eta, |n, _| n.median().ln()).exp();
            // The shape by displacement between the bracketing nodes.
            let (i, fi) = linear2(s_index(s), S_COUNT);
            let (r, fr) = linear2(eta_position(eta, ETA_COUNT), ETA_COUNT);
            let corners = [
                (i, r, (1.0 - fi) * (1.0 - fr)),
                (i + 1, r, fi * (1.0 - fr)),
                (i, r + 1, (1.0 - fi) * fr),
                (i + 1, r + 1, fi * fr),
            ];
            let near: Vec<(&Node, f64, f64)> = corners
                .iter()
                .filter(|(_, _, w)| *w > 0.0)
                .map(|&(i, r, w)| {
                    let n = &self.nodes[Self::index(i, r)];
                    (n, n.median() / median, w)
                })
                .collect();
            let shape =
                |rho: f64| -> f64 { near.iter().map(|(n, k, w)| w * n.shape(rho * k)).sum() };
            let mut below = 0.0;
            for (k, w) in edges.windows(2).enumerate() {
                let at = shape(st * w[1]);
                mass[k][c] = (total * (at - below)).max(0.0);
                below = at;
            }
            for k in 0..OBLIQUE_NODES {
                oblique[k][c] = self.scalar(s, eta, |n, _| n.oblique[k]).clamp(0.0, 4.0);
                shift[k][c] = (self.scalar(s, eta, |n, _| n.shift[k]) / st).clamp(0.0, x_max);
            }
            oblique[0][c] = 0.0;
            oblique[OBLIQUE_NODES - 1][c] = 1.0;
            shift[OBLIQUE_NODES - 1][c] = 0.0;
            let s_in = s.min(S_LAST);
            // ln T̂ falls about as −κ(s)τ (κ: the asymptotic decay in mean free paths, which
            // steepens fast as α' → 0): the nodes' ln T̂ + κτ is what is interpolated, then
            // the channel's own −κτ is added back.
            let own = asymptotic_decay(s_in * s_in, 1.0 - s_in * s_in);
            for (k, t) in slab.iter_mut().enumerate() {
                let tau = st * SLAB_FIRST_MM * (1u32 << k) as f64;
                let ln = self.scalar(s_in, eta, |n, sn| n.ln_slab(tau, sn) + decay_at(sn) * tau)
                    - own * tau;
                // Past S_LAST the transmittance falls with the total's factor.
                let darker = self.total(s, eta) / self.total(s_in, eta).max(f64::MIN_POSITIVE);
                t[c] = (ln.min(0.0).exp() * darker.min(1.0)).max(0.0);
            }
        }
        Bake {
            edges,
            mass,
            oblique,
            shift,
            slab,
        }
    }
}

/// The s nodes.
pub fn s_nodes() -> Vec<f64> {
    (0..S_COUNT).map(s_node).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::borrow::Cow;

    /// A grid whose nodes are an analytic family: the 2D exponential kernel of length
    /// L(s) = 1/(√3 s), total A(s) = e^{−6s}; q, δ̂, T̂ smooth in s.
    fn analytic() -> TablesGrid {
        let total = |s: f64| (-6.0 * s).exp();
        let cdf = |s: f64, rho: f64| {
            let x = rho * 3f64.sqrt() * s;
            total(s) * (1.0 - (1.0 + x) * (-x).exp())
        };
        let nodes = (0..ETA_COUNT)
            .flat_map(|_| (0..S_COUNT).map(s_node))
            .map(|s| Node {
                cdf: (0..RHO_COUNT).map(|k| cdf(s, rho_node(k))).collect(),
                oblique: std::array::from_fn(|k| (k as f64 / 6.0) * (1.0 + s)),
                shift: std::array::from_fn(|k| (6 - k) as f64 / s.max(0.01)),
                slab: (0..TAU_COUNT)
                    .map(|j| (-3f64.sqrt() * s * tau_node(j)).exp() * 0.5)
                    .collect(),
            })
            .collect();
        TablesGrid {
            nodes,
            budget: GRID_BUDGET,
        }
    }

    #[test]
    fn interpolation_between_nodes_keeps_the_kernels_shape_and_scale() {
        let g = analytic();
        // s halfway (in ln s) between nodes 6 and 7, σ'_t = 2 mm⁻¹.
        let s = (s_node(6) * s_node(7)).sqrt();
        let st = 2.0;
        let m = Material {
            name: Cow::Borrowed("t"),
            origin: super::super::material::Origin::Builtin,
            sigma_a: [s * s * st; 3],
            sigma_s_prime: [(1.0 - s * s) * st; 3],
            eta: 1.35,
            g: 0.0,
            textured: true,
        };
        let b = g.bake(&m);
        let x = |r: f64| r * st * 3f64.sqrt() * s;
        let want = |r: f64| (-6.0 * s).exp() * (1.0 - (1.0 + x(r)) * (-x(r)).exp());
        let total = (-6.0 * s).exp();
        for (k, w) in b.edges.windows(2).enumerate() {
            let exact = want(w[1]) - want(w[0]);
            if exact > 0.01 * total {
                let got = b.mass[k][0];
                assert!(
                    (got / exact - 1.0).abs() < 0.02,
                    "ring {k}: {got} vs {exact}"
                );
            }
        }
        // Slabs: T̂(τ) with τ = σ'_t d, interpolated in s (within the τ nodes).
        for (k, t) in b.slab.iter().enumerate() {
            let tau = st * SLAB_FIRST_MM * (1u32 << k) as f64;
            let exact = (-3f64.sqrt() * s * tau).exp() * 0.5;
            assert!(
                (t[0] / exact - 1.0).abs() < 0.02,
                "slab {k}: {} vs {exact}",
                t[0]
            );
        }
        // δ = δ̂/σ'_t.
        let d = b.shift[3][0] * st;
        assert!((d / (3.0 / s) - 1.0).abs() < 0.02, "{d}");
    }

    #[test]
    fn the_eta_axis_is_dense_near_one_and_positions_invert_the_nodes() {
        assert_eq!(eta_node(0), 1.0);
        assert!((eta_node(ETA_COUNT - 1) - ETA_MAX).abs() < 1e-12);
        // The first step is the smallest: t = √(η − 1) spaces the nodes quadratically.
        assert!(
            eta_node(1) - eta_node(0) < 0.2 * (eta_node(ETA_COUNT - 1) - eta_node(ETA_COUNT - 2))
        );
        for r in 0..ETA_COUNT {
            assert!((eta_position(eta_node(r), ETA_COUNT) - r as f64).abs() < 1e-9);
        }
        assert_eq!(eta_position(0.9, ETA_COUNT), 0.0);
        assert_eq!(eta_position(f64::NAN, ETA_COUNT), 0.0);
        assert_eq!(eta_position(2.0, ETA_COUNT), (ETA_COUNT - 1) as f64);
        for (i, s) in s_nodes().iter().enumerate() {
            assert!((s_index(*s) - i as f64).abs() < 1e-9, "{i}");
        }
        assert!(
            (s_node(0) - S_FIRST).abs() < 1e-15 && (s_node(S_COUNT - 1) - S_LAST).abs() < 1e-12
        );
        // Geometric toward white, even in α' toward dark.
        let alpha = |i: usize| 1.0 - s_node(i) * s_node(i);
        assert!((s_node(2) / s_node(1) - s_node(1) / s_node(0)).abs() < 0.01);
        let last = S_COUNT - 1;
        assert!(
            ((alpha(last - 1) - alpha(last)) / (alpha(last - 2) - alpha(last - 1)) - 1.0).abs()
                < 0.5
        );
    }

    #[test]
    fn the_file_round_trips_and_refuses_other_layouts() {
        let g = analytic();
        let bytes = g.to_bytes();
        let back = TablesGrid::from_bytes(&bytes, &GRID_BUDGET).unwrap();
        assert_eq!(back.nodes.len(), g.nodes.len());
        assert!((back.nodes[3].cdf[50] - g.nodes[3].cdf[50]).abs() < 1e-6);
        assert!(TablesGrid::from_bytes(&bytes[..bytes.len() - 4], &GRID_BUDGET).is_none());
        let other = Budget {
            kernel: 1,
            ..GRID_BUDGET
        };
        assert!(TablesGrid::from_bytes(&bytes, &other).is_none());
    }
}
