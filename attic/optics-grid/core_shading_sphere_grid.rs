//! `preintegrated`'s sphere rows for **any** material, interpolated from one nondimensional
//! grid measured offline by the project's Monte Carlo sphere walker (`assets/sss/optics.lut`,
//! baked by `dermis lut --out assets/sss --only spheres`, `dermis_measure::lut`).
//!
//! A LUT row is the exitance per unit beam irradiance of a sphere of radius ρ (mm) in bands of
//! n·l; for g = 0 it is that of the nondimensional sphere R̂ = σ'_t ρ of the channel's α' and
//! η ([`super::grid`]). The grid holds log2 of it over the LUT's [`LUT_U`] bands at
//! R̂ = 0.04·2^{k/2} (k < 38: to 1.5·10⁴ mean free paths, past which a ball is flat), every
//! other s node of the tables grid and its last (11, s = 0.004–1), and η = 1.0, 1.2, 1.4, 1.6;
//! each node's row is post-processed as a material's is (noisy lit bands smoothed, holes
//! filled, the dark tail bounded by diffusion; `dermis_measure::lut::log_row`). A material's
//! row j, channel c: cubic Lagrange in ln s and in η, linear in ln R̂, on log2 M. Values are
//! stored as u16 steps of 1/1024 in log2 M from −48 (0.07 % per step).

use std::sync::OnceLock;

use super::bake::{Budget, DEFAULT_BUDGET};
use super::grid::{self, s_position, strip_header};
use super::interp::{lagrange4, linear2};
use super::preintegrated::{row_radius_mm, LUT_U, LUT_V};
use super::Material;

/// Sphere radii R̂_k = R_FIRST·2^{k/R_PER_OCTAVE} (mean free paths).
pub const R_FIRST: f64 = 0.04;
pub const R_PER_OCTAVE: usize = 2;
pub const R_COUNT: usize = 38;
/// The η rows of the albedo table the sphere grid has.
pub const ETA_ROWS: [usize; 4] = [0, 2, 4, 6];
/// log2 M = LOG2_MIN + code / STEPS.
const LOG2_MIN: f64 = -48.0;
const STEPS: f64 = 1024.0;

/// The tables grid's s nodes this grid has: every other, and the last.
pub fn s_indices() -> Vec<usize> {
    let mut v: Vec<usize> = (0..grid::S_COUNT - 1).step_by(2).collect();
    v.push(grid::S_COUNT - 1);
    v
}

/// R̂ of node k.
pub fn r_node(k: usize) -> f64 {
    R_FIRST * 2f64.powf(k as f64 / R_PER_OCTAVE as f64)
}

/// The grid: per (η row, s node, radius) [`LUT_U`] codes of log2 M, η-major then s then R̂.
#[derive(Clone, Debug, PartialEq)]
pub struct SphereGrid {
    pub codes: Vec<u16>,
    pub budget: Budget,
}

const MAGIC: &[u8; 8] = b"DERMSPH1";

fn header(budget: &Budget) -> Vec<f64> {
    let mut h: Vec<f64> = s_indices().iter().map(|&i| grid::s_node(i)).collect();
    h.extend(ETA_ROWS.map(super::albedo::row_eta));
    h.extend([R_FIRST, R_PER_OCTAVE as f64, R_COUNT as f64, LUT_U as f64, LOG2_MIN, STEPS]);
    h.extend(super::bake::budget_values(budget));
    h
}

/// Values per grid: (η rows) × (s nodes) × (radii) × bands.
pub fn len() -> usize {
    ETA_ROWS.len() * s_indices().len() * R_COUNT * LUT_U
}

/// The code of log2 M (clamped to the code's range).
pub fn encode(log2: f64) -> u16 {
    ((log2 - LOG2_MIN) * STEPS).round().clamp(0.0, u16::MAX as f64) as u16
}

fn decode(code: u16) -> f64 {
    LOG2_MIN + f64::from(code) / STEPS
}

impl SphereGrid {
    /// Offset of the row (η row e, s node i, radius k) in `codes`.
    pub fn offset(e: usize, i: usize, k: usize) -> usize {
        ((e * s_indices().len() + i) * R_COUNT + k) * LUT_U
    }

    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = MAGIC.to_vec();
        for v in header(&self.budget) {
            out.extend(v.to_le_bytes());
        }
        for c in &self.codes {
            out.extend(c.to_le_bytes());
        }
        out
    }

    pub fn from_bytes(bytes: &[u8], budget: &Budget) -> Option<SphereGrid> {
        let rest = strip_header(bytes, MAGIC, &header(budget))?;
        if rest.len() != 2 * len() {
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

    /// log2 M of band `u` of the row (η row e, s node i, radius k).
    pub fn at(&self, e: usize, i: usize, k: usize, u: usize) -> f64 {
        decode(self.codes[Self::offset(e, i, k) + u])
    }

    /// The sphere rows of `m`'s LUT: log2 M per texel and channel, row-major over v then u
    /// (the layout of `preintegrated::Lut`'s first [`LUT_V`] rows).
    ///
    /// The rows are interpolated relative to the albedo: each node's log2 M less log2 of its
    /// kernel total (the tables grid's node at the same s and η), plus log2 of the total the
    /// tables grid interpolates for the channel (its s nodes are twice as dense; the albedo
    /// is what changes fastest with s, the rows' shape much less).
    pub fn rows(&self, m: &Material, tables: &grid::TablesGrid) -> Vec<[f64; 3]> {
        // The α' = 0 node (nothing comes back: log2 M at the floor) is not interpolated
        // with; a darker channel takes the last other node's rows.
        let s_all: Vec<f64> = s_indices().iter().map(|&i| grid::s_node(i)).collect();
        let s_nodes = &s_all[..s_all.len() - 1];
        let mut out = vec![[0.0; 3]; LUT_V * LUT_U];
        let eta_x = (m.eta - super::albedo::ETA_FIRST) / (2.0 * super::albedo::ETA_STEP);
        let log2_total = |s: f64, eta: f64| tables.total(s, eta).max(1e-12).log2();
        let node_totals: Vec<Vec<f64>> = ETA_ROWS
            .iter()
            .map(|&r| {
                let eta = super::albedo::row_eta(r);
                s_nodes.iter().map(|&s| log2_total(s, eta)).collect()
            })
            .collect();
        let (e0, we) = lagrange4(eta_x, ETA_ROWS.len());
        for c in 0..3 {
            let st = m.sigma_t_prime()[c].max(1e-9);
            let s = m.one_minus_albedo()[c].clamp(0.0, 1.0).sqrt();
            let (i0, ws) = lagrange4(s_position(s, s_nodes), s_nodes.len());
            let log2_total = log2_total(s, m.eta);
            for j in 0..LUT_V {
                let r = st * row_radius_mm(j);
                let x = (r / R_FIRST).max(1e-12).log2() * R_PER_OCTAVE as f64;
                let (k, f) = linear2(x, R_COUNT);
                for u in 0..LUT_U {
                    let mut v = log2_total;
                    for (a, wa) in ws.iter().enumerate().filter(|(_, w)| **w != 0.0) {
                        for (b, wb) in we.iter().enumerate().filter(|(_, w)| **w != 0.0) {
                            let (e, i) = (e0 + b, i0 + a);
                            let at = |k| self.at(e, i, k, u);
                            let row = at(k) * (1.0 - f) + at(k + 1) * f;
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

/// The shipped grid (`None` only if the file does not match this build, which a test rules
/// out).
pub fn shipped() -> Option<&'static SphereGrid> {
    static GRID: OnceLock<Option<SphereGrid>> = OnceLock::new();
    GRID.get_or_init(|| {
        let grid = SphereGrid::from_bytes(
            include_bytes!("../../../assets/sss/optics.lut"),
            &DEFAULT_BUDGET,
        );
        if grid.is_none() {
            log::error!("assets/sss/optics.lut does not match this build (`dermis lut`)");
        }
        grid
    })
    .as_ref()
}
