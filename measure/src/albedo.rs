//! The bake of the A ↔ α' table (`dermis_engine::shading::albedo`, `assets/sss/albedo.table`)
//! and its check: a flat medium made from a multi-scatter albedo A reflects A, measured by
//! the plane-parallel walker ([`mc::total_reflectance_diffuse`]: implicit absorption, an
//! estimator independent of the table's white walk), against the same check for the
//! `KHR_materials_volume_scatter` draft's analytic relation.

use dermis_engine::shading::albedo::{self, node_albedo, row_eta, Table, ETA_NODES, S_NODES};

use crate::mc::{self, Estimate, Medium};

/// Photons per η row of the shipped table, and its seed.
pub const PHOTONS: u64 = 4_000_000;
pub const SEED: u64 = 0x5EED_A1BE;

/// Measures the table: one white walk per η row ([`mc::albedo::multi_scatter_curve`]), all
/// interior nodes at once; the end nodes are exact (A(1) = 1, A(0) = 0). `progress(row)`
/// after each row. Deterministic for any `threads`.
pub fn bake_table(
    photons: u64,
    seed: u64,
    threads: usize,
    mut progress: impl FnMut(usize),
) -> Table {
    let interior: Vec<f64> = (1..S_NODES - 1).map(node_albedo).collect();
    let mut t = Table {
        multi: [[0.0; S_NODES]; ETA_NODES],
        std_err: [[0.0; S_NODES]; ETA_NODES],
        photons,
        seed,
    };
    for r in 0..ETA_NODES {
        let curve = mc::albedo::multi_scatter_curve(
            row_eta(r),
            &interior,
            photons,
            seed + r as u64,
            threads,
        );
        t.multi[r][0] = 1.0;
        for (k, e) in curve.multi.iter().enumerate() {
            t.multi[r][k + 1] = e.mean as f32;
            t.std_err[r][k + 1] = e.std_err as f32;
        }
        progress(r);
    }
    t
}

/// The `KHR_materials_volume_scatter` draft's single-scatter albedo for a multi-scatter
/// albedo ρ_ms (its "Multi-Scatter Albedo" section, Kulla & Conty 2017):
/// ρ_ss = 1 − (4.09712 + 4.20863 ρ_ms − √(9.59217 + 41.6808 ρ_ms + 17.7126 ρ_ms²))².
/// (For g = 0 it is α'.) Measurement only: the engine inverts the measured table.
pub fn draft_single_scatter_albedo(multi: f64) -> f64 {
    let a = multi.clamp(0.0, 1.0);
    let k = 4.09712 + 4.20863 * a - (9.59217 + 41.6808 * a + 17.7126 * a * a).sqrt();
    (1.0 - k * k).clamp(0.0, 1.0)
}

/// The multi-scatter albedo (per incident power) of the flat semi-infinite medium of reduced
/// albedo `single` (σ'_t = 1 mm⁻¹), relative index `eta`, anisotropy `g` (σ_s = σ'_s/(1 − g)),
/// measured by the plane walker under diffuse light.
pub fn measured_multi(
    single: f64,
    eta: f64,
    g: f64,
    photons: u64,
    seed: u64,
    threads: usize,
) -> Estimate {
    let m = Medium::new(1.0 - single, single, g, eta);
    mc::total_reflectance_diffuse(&m, photons, seed, threads)
}

/// One row of the sweep: the medium made from `multi` at `eta`, `g` by the table's inversion
/// and by the draft's relation, and what each reflects.
#[derive(Clone, Debug)]
pub struct SweepRow {
    pub multi: f64,
    pub eta: f64,
    pub g: f64,
    pub single: f64,
    pub measured: Estimate,
    pub draft_single: f64,
    pub draft_measured: Estimate,
}

impl SweepRow {
    /// (measured − A)/A for the table's medium and the draft's.
    pub fn errors(&self) -> (f64, f64) {
        (
            self.measured.mean / self.multi - 1.0,
            self.draft_measured.mean / self.multi - 1.0,
        )
    }
}

/// Photons for a check at multi-scatter albedo A: the relative standard error of the diffuse
/// reflectance grows as A falls (≈ 0.3 % at every A with this many).
pub fn sweep_photons(multi: f64, scale: u64) -> u64 {
    ((scale as f64 / multi.max(0.01)) as u64).max(1000)
}

/// The check for one (A, η, g): each medium's A measured with [`sweep_photons`]`(A, scale)`.
pub fn sweep_row(multi: f64, eta: f64, g: f64, scale: u64, seed: u64, threads: usize) -> SweepRow {
    let photons = sweep_photons(multi, scale);
    let single = albedo::single_scatter_albedo(multi, eta, g);
    let draft_single = draft_single_scatter_albedo(multi);
    SweepRow {
        multi,
        eta,
        g,
        single,
        measured: measured_multi(single, eta, g, photons, seed, threads),
        draft_single,
        draft_measured: measured_multi(draft_single, eta, g, photons, seed + 1, threads),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_medium_made_from_a_reflects_a_within_two_percent() {
        // A small Monte Carlo (the full sweep: `dermis albedo`): the medium the table's
        // inversion makes from A, walked by the absorbing plane walker under diffuse light.
        let mut worst: f64 = 0.0;
        for (multi, eta) in [
            (0.05, 1.4),
            (0.3, 1.05),
            (0.6, 1.33),
            (0.8, 1.55),
            (0.86, 1.4),
            (0.95, 1.0),
        ] {
            let single = albedo::single_scatter_albedo(multi, eta, 0.0);
            let measured = measured_multi(single, eta, 0.0, sweep_photons(multi, 20_000), 11, 2);
            let err = measured.mean / multi - 1.0;
            eprintln!(
                "A {multi} η {eta}: α' {single:.6} → {:.4} ± {:.4} ({:+.2} %)",
                measured.mean,
                measured.std_err,
                100.0 * err,
            );
            assert!(measured.std_err < 0.005 * multi, "too few photons");
            assert!(err.abs() < 0.02, "A {multi} η {eta}: {:+.2} %", 100.0 * err);
            worst = worst.max(err.abs());
        }
        eprintln!("worst {:.2} %", 100.0 * worst);
    }

    #[test]
    fn a_rebaked_row_agrees_with_the_shipped_one_within_its_noise() {
        // η = 1.4, another seed, few photons: every interior node within 4 combined SE.
        let t = &albedo::TABLE;
        let r = 4;
        let nodes: Vec<usize> = (4..S_NODES - 1).step_by(12).collect();
        let albedos: Vec<f64> = nodes.iter().map(|&k| node_albedo(k)).collect();
        let c = mc::albedo::multi_scatter_curve(row_eta(r), &albedos, 20_000, 77, 2);
        for (&k, e) in nodes.iter().zip(&c.multi) {
            let (v, se) = (f64::from(t.multi[r][k]), f64::from(t.std_err[r][k]));
            let z = (e.mean - v).abs() / (e.std_err.powi(2) + se * se).sqrt();
            assert!(z < 4.0, "node {k}: {} vs shipped {v} ({z:.1} SE)", e.mean);
        }
    }

    #[test]
    fn the_draft_relation_is_what_the_extension_prints() {
        assert!(draft_single_scatter_albedo(1.0) > 0.999_999);
        assert!(draft_single_scatter_albedo(0.0) < 1e-4);
        let mut last = 0.0;
        for i in 1..=100 {
            let s = draft_single_scatter_albedo(i as f64 / 100.0);
            assert!(s >= last);
            last = s;
        }
    }
}
