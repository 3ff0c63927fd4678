//! `preintegrated`'s sphere rows for **any** material, interpolated from one nondimensional
//! grid measured offline by the project's Monte Carlo sphere walker (`assets/sss/optics.lut`,
//! baked by `dermis lut --out assets/sss --grid spheres`, `dermis_measure::grid`).
//!
//! A LUT row is the exitance per unit beam irradiance of a sphere of radius ρ (mm) in bands of
//! n·l; for g = 0 it is that of the nondimensional sphere R̂ = σ'_t ρ of the channel's α' and
//! η ([`super::grid`]). The grid holds log2 of it over the LUT's [`LUT_U`] bands at
//! R̂ = R_FIRST·2^{k/R_PER_OCTAVE} (k < [`R_COUNT`]), at [`S_NODES`] s nodes ([`s_node`]: α'
//! 1 − 9·10⁻⁶ to 0.10), and at [`ETA_COUNT`] η nodes equally spaced in √(η − 1);
//! each node's row is post-processed as a material's is (noisy lit bands smoothed, holes
//! filled, the dark tail bounded; `dermis_measure::lut::log_row`). A material's row j,
//! channel c: cubic Lagrange in ln s and in √(η − 1), cubic Lagrange in ln R̂, on log2 M
//! relative to the kernel's total (below). Stored as u16 steps of 1/1024 in log2 M from −48
//! (0.07 % per step).

use std::sync::OnceLock;

use super::bake::{budget_values, Budget};
use super::grid::{self, eta_node_of, eta_position, s_position, strip_header, write_header};
use super::interp::lagrange4;
use super::preintegrated::{row_radius_mm, LUT_U, LUT_V};
use super::Material;

/// Sphere radii R̂_k = R_FIRST·2^{k/R_PER_OCTAVE} (mean free paths).
pub const R_FIRST: f64 = 0.04;
pub const R_PER_OCTAVE: usize = 2;
pub const R_COUNT: usize = 34;
/// η nodes, equally spaced in √(η − 1) over 1.0–[`grid::ETA_MAX`].
pub const ETA_COUNT: usize = 4;
/// log2 M = LOG2_MIN + code / STEPS.
const LOG2_MIN: f64 = -48.0;
const STEPS: f64 = 1024.0;

/// s nodes: S_FIRST·(S_LAST/S_FIRST)^{2i/15} for i < S_NODES − 1, then S_LAST (≈; geometric in
/// s: the rows are interpolated relative to the kernel's total, which carries the albedo's
/// fast change toward α' → 0).
pub const S_NODES: usize = 9;
const S_FIRST: f64 = 0.003;
const S_LAST: f64 = 0.95;

/// s of node i.
pub fn s_node(i: usize) -> f64 {
    let k = if i + 1 >= S_NODES { 15 } else { 2 * i };
    S_FIRST * (S_LAST / S_FIRST).powf(k as f64 / 15.0)
}

/// η of node e.
pub fn eta_node(e: usize) -> f64 {
    eta_node_of(e, ETA_COUNT)
}

/// R̂ of node k.
pub fn r_node(k: usize) -> f64 {
    R_FIRST * 2f64.powf(k as f64 / R_PER_OCTAVE as f64)
}

/// The grid: per (η node, s node, radius) [`LUT_U`] codes of log2 M, η-major then s then R̂.
#[derive(Clone, Debug, PartialEq)]
pub struct SphereGrid {
    pub codes: Vec<u16>,
    pub budget: Budget,
}

const MAGIC: &[u8; 8] = b"DERMSPH2";

fn header(budget: &Budget) -> Vec<f64> {
    let mut h: Vec<f64> = (0..S_NODES).map(s_node).collect();
    h.extend((0..ETA_COUNT).map(eta_node));
    h.extend([
        R_FIRST,
        R_PER_OCTAVE as f64,
        R_COUNT as f64,
        LUT_U as f64,
        LOG2_MIN,
        STEPS,
    ]);
    h.extend(budget_values(budget));
    h
}

/// Rows per grid: (η nodes) × (s nodes) × (radii).
pub fn rows() -> usize {
    ETA_COUNT * S_NODES * R_COUNT
}

/// The code of log2 M (clamped to the code's range).
pub fn encode(log2: f64) -> u16 {
    ((log2 - LOG2_MIN) * STEPS)
        .round()
        .clamp(0.0, u16::MAX as f64) as u16
}

fn decode(code: u16) -> f64 {
    LOG2_MIN + f64::from(code) / STEPS
}

impl SphereGrid {
    /// Row number of (η node e, s node i, radius k); its codes start at LUT_U times it.
    pub fn row(e: usize, i: usize, k: usize) -> usize {
        (e * S_NODES + i) * R_COUNT + k
    }

    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = write_header(MAGIC, &header(&self.budget));
        for c in &self.codes {
            out.extend(c.to_le_bytes());
        }
        out
    }

    pub fn from_bytes(bytes: &[u8], budget: &Budget) -> Option<SphereGrid> {
        let rest = strip_header(bytes, MAGIC, &header(budget))?;
        if rest.len() != 2 * LUT_U * rows() {
            return None;
        }
        let codes = rest
            .chunks_exact(2)
            .map(|b| u16::from_le_bytes([b[0], b[1]]))
            .collect();
        Some(SphereGrid {
            codes,
            budget: *budget,
        })
    }

    /// log2 M of band `u` of the row (η node e, s node i, radius k).
    pub fn at(&self, e: usize, i: usize, k: usize, u: usize) -> f64 {
        decode(self.codes[Self::row(e, i, k) * LUT_U + u])
    }

    /// The sphere rows of `m`'s LUT: log2 M per texel and channel, row-major over v then u
    /// (the layout of `preintegrated::Lut`'s first [`LUT_V`] rows).
    ///
    /// The rows are interpolated relative to the albedo: each node's log2 M less log2 of its
    /// kernel total (the tables grid's at the same s and η), plus log2 of the total the tables
    /// grid interpolates for the channel (its s nodes are twice as dense; the albedo is what
    /// changes fastest with s, the rows' shape much less).
    // `c` indexes the texels' channels and names the material's channel alike.
    #[allow(clippy::needless_range_loop)]
    pub fn rows(&self, m: &Material, tables: &grid::TablesGrid) -> Vec<[f64; 3]> {
        // Past the last s node (α' = 0.10) the rows keep their shape and follow the total.
        let s_all: Vec<f64> = (0..S_NODES).map(s_node).collect();
        let mut out = vec![[0.0; 3]; LUT_V * LUT_U];
        let log2_total = |s: f64, eta: f64| tables.total(s, eta).max(1e-12).log2();
        let node_totals: Vec<Vec<f64>> = (0..ETA_COUNT)
            .map(|e| s_all.iter().map(|&s| log2_total(s, eta_node(e))).collect())
            .collect();
        let (e0, we) = lagrange4(eta_position(m.eta, ETA_COUNT), ETA_COUNT);
        for c in 0..3 {
            let (s, st) = grid::channel(m, c);
            let (i0, ws) = lagrange4(s_position(s, &s_all), s_all.len());
            // Past the terminator (u < ½) light reaches a point through the ball and decays
            // as e^(−σ_tr d): ln M is linear in σ_tr/σ'_t = √3·s at a given R̂, so the dark
            // side is interpolated linearly in s between the two nodes around it (a cubic in
            // ln s, as the lit side is, swings by up to 2⁴ between nodes whose tails differ
            // by 2¹⁶).
            let dark = {
                let s = if s.is_finite() { s } else { s_all[0] };
                let k = s_all.partition_point(|&v| v <= s).clamp(1, s_all.len() - 1) - 1;
                let f = ((s - s_all[k]) / (s_all[k + 1] - s_all[k])).clamp(0.0, 1.0);
                let mut w = [0.0; 4];
                w[k - i0] = 1.0 - f;
                w[k + 1 - i0] = f;
                w
            };
            let own_total = log2_total(s, m.eta);
            for j in 0..LUT_V {
                let r = st * row_radius_mm(j);
                let x = (r / R_FIRST).max(1e-12).log2() * R_PER_OCTAVE as f64;
                let (k0, wk) = lagrange4(x, R_COUNT);
                for u in 0..LUT_U {
                    let mut v = own_total;
                    let ws = if 2 * u + 1 < LUT_U { &dark } else { &ws };
                    for (a, wa) in ws.iter().enumerate().filter(|(_, w)| **w != 0.0) {
                        for (b, wb) in we.iter().enumerate().filter(|(_, w)| **w != 0.0) {
                            let (e, i) = (e0 + b, i0 + a);
                            let row: f64 = wk
                                .iter()
                                .enumerate()
                                .map(|(d, w)| w * self.at(e, i, k0 + d, u))
                                .sum();
                            v += wa * wb * (row - node_totals[e][i]);
                        }
                    }
                    out[j * LUT_U + u][c] = v;
                }
            }
        }
        out
    }
}

/// The shipped grid's bytes.
pub const SHIPPED: &[u8] = include_bytes!("../../../assets/sss/optics.lut");

/// The shipped grid (`None` only if the file does not match this build, which a test rules
/// out; logged once).
pub fn shipped() -> Option<&'static SphereGrid> {
    static GRID: OnceLock<Option<SphereGrid>> = OnceLock::new();
    GRID.get_or_init(|| {
        let grid = SphereGrid::from_bytes(SHIPPED, &grid::GRID_BUDGET);
        if grid.is_none() {
            log::error!("assets/sss/optics.lut does not match this build (`dermis lut --grid`)");
        }
        grid
    })
    .as_ref()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_round_trip_to_a_step_and_the_file_refuses_other_layouts() {
        for v in [-40.0, -3.21, 0.0, 2.5] {
            assert!((decode(encode(v)) - v).abs() <= 0.5 / STEPS);
        }
        assert_eq!(encode(-100.0), 0);
        let g = SphereGrid {
            codes: (0..LUT_U * rows()).map(|k| (k % 60000) as u16).collect(),
            budget: grid::GRID_BUDGET,
        };
        let bytes = g.to_bytes();
        assert_eq!(SphereGrid::from_bytes(&bytes, &grid::GRID_BUDGET), Some(g));
        assert!(SphereGrid::from_bytes(&bytes[..bytes.len() - 2], &grid::GRID_BUDGET).is_none());
    }
}
