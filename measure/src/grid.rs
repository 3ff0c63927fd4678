//! The bakes of the nondimensional grids the runtime interpolates every material's tables
//! from (`dermis_engine::shading::grid`: `assets/sss/optics.tables`; `sphere_grid`:
//! `assets/sss/optics.lut`), written by `dermis lut --grid`. Each node is one channel's medium
//! with σ'_t = 1 mm⁻¹ (lengths in mean free paths): σ_a = s², σ'_s = 1 − s², g = 0, measured
//! by the same code as a material's direct bake ([`crate::bake::measure_channel`],
//! [`crate::lut::sphere_run`]) at the shipped budget. Seeds fixed per node; the bytes are the
//! same for any thread count.

use dermis_engine::shading::bake::{Bake, Budget, OBLIQUE_NODES, SLAB_NODES};
use dermis_engine::shading::grid::{
    self, eta_node, rho_node, s_node, tau_node, Node, TablesGrid, ETA_COUNT, RHO_COUNT, S_COUNT,
    TAU_COUNT,
};
use dermis_engine::shading::preintegrated::{self, Lut, LUT_U, LUT_V};
use dermis_engine::shading::sphere_grid::{self, r_node, SphereGrid, R_COUNT};
use dermis_engine::shading::Material;

use crate::bake::{measure_channel, Layout};
use crate::mc::Medium;

const TABLES_SEED: u64 = 0x5EED_6A1D;
const SPHERES_SEED: u64 = 0x5EED_5F6A;

/// The medium of grid node s at η (σ'_t = 1, g = 0).
pub fn node_medium(s: f64, eta: f64) -> Medium {
    Medium::new(s * s, 1.0 - s * s, 0.0, eta)
}

/// One node (s node i, η node r) of the tables grid.
pub fn measure_node(i: usize, r: usize, budget: &Budget, threads: usize) -> Node {
    let s = s_node(i);
    let med = node_medium(s, eta_node(r));
    let sigma_tr = 3f64.sqrt() * s;
    let mut edges = vec![0.0];
    edges.extend((0..RHO_COUNT).map(rho_node));
    // Strips out to eight diffusion lengths (at least ten mean free paths), as a material's
    // rings reach eight of its longest channel's.
    let x_max = (8.0 / sigma_tr).clamp(10.0, 1e4);
    let thicknesses: Vec<f64> = (0..TAU_COUNT).map(tau_node).collect();
    let seed = TABLES_SEED + 1000 * TablesGrid::index(i, r) as u64;
    let at = Layout {
        edges: &edges,
        x_max,
        thicknesses: &thicknesses,
    };
    let ch = measure_channel(&med, &at, budget, seed, threads);
    let mut cdf = Vec::with_capacity(RHO_COUNT);
    let mut sum = 0.0;
    for m in &ch.mass {
        sum += m;
        cdf.push(sum);
    }
    let mut shift = ch.shift;
    shift[shift.len() - 1] = 0.0;
    let mut oblique = ch.oblique;
    oblique[0] = 0.0;
    Node {
        cdf,
        oblique,
        shift,
        slab: ch.slab,
    }
}

/// Every node of the tables grid; `progress(done, total)` after each.
pub fn bake_tables(
    budget: &Budget,
    threads: usize,
    mut progress: impl FnMut(usize, usize),
) -> TablesGrid {
    let total = S_COUNT * ETA_COUNT;
    let mut nodes = Vec::with_capacity(total);
    for r in 0..ETA_COUNT {
        for i in 0..S_COUNT {
            nodes.push(measure_node(i, r, budget, threads));
            progress(nodes.len(), total);
        }
    }
    TablesGrid {
        nodes,
        budget: *budget,
    }
}

/// One row of the sphere grid: the codes of log2 M per band for η node `e`, s node `i` (of
/// [`sphere_grid::s_node`]), radius `k`.
pub fn sphere_node(e: usize, i: usize, k: usize, budget: &Budget, threads: usize) -> Vec<u16> {
    let s = sphere_grid::s_node(i);
    let med = node_medium(s, sphere_grid::eta_node(e));
    let seed = SPHERES_SEED + 7919 * SphereGrid::row(e, i, k) as u64;
    crate::lut::sphere_run(&med, r_node(k), 3f64.sqrt() * s, budget, seed, threads)
        .iter()
        .map(|ln| sphere_grid::encode(ln / std::f64::consts::LN_2))
        .collect()
}

/// Every row of the sphere grid; `progress(done, total)` after each.
pub fn bake_spheres(
    budget: &Budget,
    threads: usize,
    mut progress: impl FnMut(usize, usize),
) -> SphereGrid {
    let n_s = sphere_grid::S_NODES;
    let total = sphere_grid::rows();
    let mut codes = Vec::with_capacity(total * LUT_U);
    let mut done = 0;
    for e in 0..sphere_grid::ETA_COUNT {
        for i in 0..n_s {
            for k in 0..R_COUNT {
                codes.extend(sphere_node(e, i, k, budget, threads));
                done += 1;
                progress(done, total);
            }
        }
    }
    SphereGrid {
        codes,
        budget: *budget,
    }
}

/// How far a material's tables and LUT interpolated from the grids are from its direct bake:
/// the largest relative difference per table, over what carries light (rings holding ≥ 1 %
/// of their channel's total, shifts above 0.01 mm, slab transmittances above 10⁻⁶, sphere-row
/// texels within 2⁻⁶ of their row's peak).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Difference {
    /// The total diffuse reflectance (Σ ring masses).
    pub total: f64,
    pub rings: f64,
    pub median_radius: f64,
    pub q_mu: f64,
    pub shift_mu: f64,
    pub slab: f64,
    /// The sphere rows: largest and mean relative difference of M.
    pub sphere_max: f64,
    pub sphere_mean: f64,
}

impl Difference {
    /// The named values, in table order.
    pub fn named(&self) -> [(&'static str, f64); 8] {
        [
            ("total_reflectance", self.total),
            ("kernel_rings", self.rings),
            ("median_radius", self.median_radius),
            ("q_mu", self.q_mu),
            ("shift_mu", self.shift_mu),
            ("slab", self.slab),
            ("sphere_rows_max", self.sphere_max),
            ("sphere_rows_mean", self.sphere_mean),
        ]
    }
}

/// The grid's stated bounds against a direct bake at the shipped budget (largest relative
/// difference, g = 0; measured by `dermis bench tables`, docs/optics.md §3).
/// g = 0, α' ≥ 0.45: the measured worst of 13 materials (the dark channels' thick slabs and
/// the whitest media's δ are dominated by the direct bake's own noise, which is as large).
pub const BOUND_TOTAL: f64 = 0.05;
pub const BOUND_RINGS: f64 = 0.40;
pub const BOUND_MEDIAN: f64 = 0.06;
pub const BOUND_Q: f64 = 0.12;
pub const BOUND_SHIFT: f64 = 0.80;
pub const BOUND_SLAB: f64 = 0.65;
/// The sphere rows' mean relative difference (their largest single texel is not bounded:
/// docs/optics.md §3).
pub const BOUND_SPHERE: f64 = 0.15;

/// Largest |a/b − 1| over the pairs whose reference `b` passes `keep`.
fn worst(pairs: impl Iterator<Item = (f64, f64)>, keep: impl Fn(f64) -> bool) -> f64 {
    pairs
        .filter(|(_, b)| keep(*b))
        .map(|(a, b)| (a / b - 1.0).abs())
        .fold(0.0, f64::max)
}

/// The grid's tables `g` and LUT `gl` against the direct bake's `d` and `dl` (the sphere rows'
/// differences NaN without LUTs).
pub fn difference(g: &Bake, d: &Bake, luts: Option<(&Lut, &Lut)>) -> Difference {
    let per_channel = |f: &dyn Fn(usize) -> f64| (0..3).map(f).fold(0.0, f64::max);
    let rings = per_channel(&|c| {
        let total: f64 = d.mass.iter().map(|m| m[c]).sum();
        worst(g.mass.iter().zip(&d.mass).map(|(a, b)| (a[c], b[c])), |b| {
            b > 0.01 * total
        })
    });
    let total = worst(g.reflectance().into_iter().zip(d.reflectance()), |_| true);
    let q_mu = per_channel(&|c| {
        worst(
            (1..OBLIQUE_NODES - 1).map(|k| (g.oblique[k][c], d.oblique[k][c])),
            |b| b > 0.0,
        )
    });
    let shift_mu = per_channel(&|c| {
        worst(
            (1..OBLIQUE_NODES - 1).map(|k| (g.shift[k][c], d.shift[k][c])),
            |b| b > 0.01,
        )
    });
    let slab = per_channel(&|c| {
        worst((0..SLAB_NODES).map(|k| (g.slab[k][c], d.slab[k][c])), |b| {
            b > 1e-6
        })
    });
    let median_radius = per_channel(&|c| (g.median_radius(c) / d.median_radius(c) - 1.0).abs());
    let (mut sphere_max, mut sum, mut n) = (0.0f64, 0.0f64, 0usize);
    let Some((gl, dl)) = luts else {
        return Difference {
            total,
            rings,
            median_radius,
            q_mu,
            shift_mu,
            slab,
            sphere_max: f64::NAN,
            sphere_mean: f64::NAN,
        };
    };
    for j in 0..LUT_V {
        for c in 0..3 {
            let peak = (0..LUT_U).map(|i| dl.at(i, j, c)).fold(f32::MIN, f32::max);
            for i in (0..LUT_U).filter(|&i| dl.at(i, j, c) > peak - 6.0) {
                let rel = 2f64.powf(f64::from(gl.at(i, j, c) - dl.at(i, j, c))) - 1.0;
                sphere_max = sphere_max.max(rel.abs());
                sum += rel.abs();
                n += 1;
            }
        }
    }
    Difference {
        total,
        rings,
        median_radius,
        q_mu,
        shift_mu,
        slab,
        sphere_max,
        sphere_mean: sum / n.max(1) as f64,
    }
}

/// `m`'s tables and LUT (sphere and factor rows) from the shipped grids alone, whatever
/// shipped file or direct baker there is (`None` if the tables grid is unreadable; no LUT if
/// the sphere grid is).
pub fn interpolated(m: &Material) -> Option<(Bake, Option<Lut>)> {
    let tables = grid::shipped()?;
    let b = tables.bake(m);
    let lut = sphere_grid::shipped().map(|spheres| {
        let rows = spheres.rows(m, tables);
        preintegrated::lut_from(&rows, &b, m)
    });
    Some((b, lut))
}

#[cfg(test)]
mod tests {
    use super::*;
    use dermis_engine::shading::grid::GRID_BUDGET;

    #[test]
    fn the_shipped_grids_are_what_the_bakes_measure() {
        // The cheapest nodes (short walks: the darkest s; a small ball) re-measured at the
        // shipped budget are what the shipped files hold, to their f32 / u16 rounding (the
        // bakes are deterministic for any thread count).
        let tables = grid::shipped().expect("assets/sss/optics.tables matches this build");
        let i = S_COUNT - 1;
        let again = TablesGrid {
            nodes: vec![measure_node(i, 4, &GRID_BUDGET, 2); S_COUNT * ETA_COUNT],
            budget: GRID_BUDGET,
        };
        let again = TablesGrid::from_bytes(&again.to_bytes(), &GRID_BUDGET).unwrap();
        assert_eq!(again.nodes[0], tables.nodes[TablesGrid::index(i, 4)]);
        let spheres = sphere_grid::shipped().expect("assets/sss/optics.lut matches this build");
        let (e, i, k) = (2, sphere_grid::S_NODES - 1, 0);
        let at = SphereGrid::row(e, i, k) * LUT_U;
        assert_eq!(
            sphere_node(e, i, k, &GRID_BUDGET, 2),
            spheres.codes[at..at + LUT_U].to_vec()
        );
    }

    #[test]
    fn a_non_preset_materials_tables_come_from_the_grid_within_the_stated_bound() {
        // A medium no preset file covers, between grid nodes in every axis: what the runtime
        // serves is the grid's interpolation (no Monte Carlo), and it is the direct bake at
        // the shipped budget within the bounds docs/optics.md §3 states (`dermis bench
        // tables`: the direct bake's own noise included). Its smallest sphere's row, re-measured
        // directly, checks the sphere grid.
        use dermis_engine::shading::bake::{self, Source};
        let st = [0.8, 1.5, 2.5];
        let alpha = [0.995, 0.93, 0.75];
        let m = Material {
            name: std::borrow::Cow::Borrowed("between"),
            origin: dermis_engine::shading::material::Origin::Builtin,
            sigma_a: std::array::from_fn(|c| (1.0 - alpha[c]) * st[c]),
            sigma_s_prime: std::array::from_fn(|c| alpha[c] * st[c]),
            eta: 1.33,
            g: 0.0,
            textured: true,
        };
        assert_eq!(bake::source(&m), Source::Grid);
        let (grid, grid_lut) =
            interpolated(&m).expect("the shipped tables grid matches this build");
        let grid_lut = grid_lut.expect("the shipped sphere grid matches this build");
        assert_eq!(*bake::for_material(&m), grid);
        let direct = crate::bake::measure(&m, GRID_BUDGET, 2);
        let j = LUT_V - 1;
        let mut direct_lut = grid_lut.clone();
        for c in 0..3 {
            let row = crate::lut::sphere_row(&m, j, c, &GRID_BUDGET, 2);
            for (i, ln) in row.iter().enumerate() {
                direct_lut.texels[j * LUT_U + i][c] = (ln / std::f64::consts::LN_2) as f32;
            }
        }
        let d = difference(&grid, &direct, Some((&grid_lut, &direct_lut)));
        let bounds = [
            ("total", d.total, BOUND_TOTAL),
            ("rings", d.rings, BOUND_RINGS),
            ("median", d.median_radius, BOUND_MEDIAN),
            ("q", d.q_mu, BOUND_Q),
            ("δ", d.shift_mu, BOUND_SHIFT),
            ("slab", d.slab, BOUND_SLAB),
            ("sphere rows (mean)", d.sphere_mean, BOUND_SPHERE),
        ];
        for (what, got, bound) in bounds {
            assert!(got <= bound, "{what}: {got} > {bound} ({d:?})");
        }
    }

    #[test]
    fn the_grids_nodes_are_physical() {
        let tables = grid::shipped().expect("shipped tables grid");
        for (k, n) in tables.nodes.iter().enumerate() {
            assert!(n.cdf.windows(2).all(|w| w[0] <= w[1]), "node {k}: Φ̂ falls");
            assert!(
                n.total() > 0.0 && n.total() < 1.0,
                "node {k}: {}",
                n.total()
            );
            assert!(n.slab.iter().all(|t| (0.0..=1.0).contains(t)), "node {k}");
            assert!(n.oblique.iter().all(|q| (0.0..=4.0).contains(q)));
        }
        // A whiter medium reflects more and spreads wider (η node 4).
        let at = |i| &tables.nodes[TablesGrid::index(i, 4)];
        for i in 1..S_COUNT {
            assert!(at(i).total() < at(i - 1).total(), "s node {i}");
        }
        // (The darkest nodes, α' ≤ 0.1, return light within a mean free path: their median is
        // the first returns' and within the noise of its neighbours.)
        for i in 1..S_COUNT - 2 {
            assert!(at(i).median() < 1.05 * at(i - 1).median(), "s node {i}");
        }
        assert!(at(S_COUNT - 1).median() < 0.5 * at(0).median());
        // A higher index traps more light inside: less comes back (s node 8).
        let row = |r| tables.nodes[TablesGrid::index(8, r)].total();
        for r in 1..ETA_COUNT {
            assert!(row(r) < row(r - 1), "η node {r}");
        }
    }
}
