//! The bakes of the nondimensional grids the runtime interpolates every material's tables
//! from (`dermis_core::shading::grid`: `assets/sss/optics.tables`; `sphere_grid`:
//! `assets/sss/optics.lut`), written by `dermis lut`. Each node is one channel's medium with
//! σ'_t = 1 mm⁻¹ (lengths in mean free paths): σ_a = s², σ'_s = 1 − s², g = 0, measured by
//! the same code as a material's direct bake ([`crate::bake::measure_channel`],
//! [`crate::lut::sphere_run`]) at the shipped budget. Seeds fixed per node; deterministic for
//! any thread count.

use dermis_core::shading::bake::Budget;
use dermis_core::shading::grid::{
    rho_node, s_node, tau_node, Node, TablesGrid, ETA_COUNT, RHO_COUNT, S_COUNT, TAU_COUNT,
};
use dermis_core::shading::preintegrated::LUT_U;
use dermis_core::shading::sphere_grid::{self, r_node, SphereGrid, ETA_ROWS, R_COUNT};
use dermis_core::shading::albedo::row_eta;

use crate::bake::{measure_channel, Layout};
use crate::mc::Medium;

const TABLES_SEED: u64 = 0x5EED_6A1D;
const SPHERES_SEED: u64 = 0x5EED_5F6A;

/// The medium of grid node s at η (σ'_t = 1).
pub fn node_medium(s: f64, eta: f64) -> Medium {
    Medium::new(s * s, 1.0 - s * s, 0.0, eta)
}

/// One node of the tables grid.
pub fn measure_node(i: usize, r: usize, budget: &Budget, threads: usize) -> Node {
    let s = s_node(i);
    let med = node_medium(s, row_eta(r));
    let sigma_tr = 3f64.sqrt() * s;
    let mut edges = vec![0.0];
    edges.extend((0..RHO_COUNT).map(rho_node));
    // Strips out to ten diffusion lengths (at least ten mean free paths).
    let x_max = (10.0 / sigma_tr).clamp(10.0, 1e4);
    let thicknesses: Vec<f64> = (0..TAU_COUNT).map(tau_node).collect();
    let seed = TABLES_SEED + 1000 * TablesGrid::index(i, r) as u64;
    let at = Layout {
        edges: &edges,
        x_max,
        thicknesses: &thicknesses,
    };
    let ch = measure_channel(&med, sigma_tr, &at, budget, seed, threads);
    let mut cdf = Vec::with_capacity(RHO_COUNT);
    let mut sum = 0.0;
    for m in &ch.mass {
        sum += m;
        cdf.push(sum);
    }
    Node {
        cdf,
        oblique: ch.oblique,
        shift: ch.shift,
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

/// One row of the sphere grid: log2 M per band for η row `e`, s node `i` (of
/// [`sphere_grid::s_indices`]), radius `k`.
pub fn sphere_node(e: usize, i: usize, k: usize, budget: &Budget, threads: usize) -> Vec<u16> {
    let s = s_node(sphere_grid::s_indices()[i]);
    let med = node_medium(s, row_eta(ETA_ROWS[e]));
    let seed = SPHERES_SEED + 7919 * (SphereGrid::offset(e, i, k) / LUT_U) as u64;
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
    let n_s = sphere_grid::s_indices().len();
    let total = ETA_ROWS.len() * n_s * R_COUNT;
    let mut codes = Vec::with_capacity(sphere_grid::len());
    let mut done = 0;
    for e in 0..ETA_ROWS.len() {
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

#[cfg(test)]
mod tests {
    use super::*;
    use dermis_core::shading::bake::DEFAULT_BUDGET;
    use dermis_core::shading::{grid, sphere_grid};

    #[test]
    fn the_shipped_grids_are_what_the_bakes_measure() {
        // The cheapest nodes (short walks: α' = 0.22; a small ball) re-measured at the shipped
        // budget are what the shipped files hold, to their f32 / u16 rounding (the bakes are
        // deterministic for any thread count).
        let tables = grid::shipped().expect("assets/sss/optics.tables matches this build");
        let i = S_COUNT - 2;
        let again = TablesGrid {
            nodes: vec![measure_node(i, 4, &DEFAULT_BUDGET, 2); S_COUNT * ETA_COUNT],
            budget: DEFAULT_BUDGET,
        };
        let again = TablesGrid::from_bytes(&again.to_bytes(), &DEFAULT_BUDGET).unwrap();
        assert_eq!(again.nodes[0], tables.nodes[TablesGrid::index(i, 4)]);
        let spheres = sphere_grid::shipped().expect("assets/sss/optics.lut matches this build");
        let (e, i, k) = (2, sphere_grid::s_indices().len() - 1, 0);
        let at = SphereGrid::offset(e, i, k);
        assert_eq!(
            sphere_node(e, i, k, &DEFAULT_BUDGET, 2),
            spheres.codes[at..at + LUT_U].to_vec()
        );
    }

    #[test]
    fn the_grids_nodes_are_physical() {
        let tables = grid::shipped().expect("shipped tables grid");
        for (k, n) in tables.nodes.iter().enumerate() {
            assert!(n.cdf.windows(2).all(|w| w[0] <= w[1]), "node {k}: Φ̂ falls");
            // α' = 0 (the last s node) scatters nothing back.
            let last = k % S_COUNT == S_COUNT - 1;
            assert!(last || n.total() > 0.0, "node {k}: total {}", n.total());
            assert!(n.total() < 1.0, "node {k}: total {}", n.total());
            assert!(n.slab.iter().all(|t| (0.0..=1.0).contains(t)), "node {k}");
            assert!(n.oblique.iter().all(|q| (0.0..=4.0).contains(q)));
        }
        // A whiter medium reflects more and spreads wider (η = 1.4; near α' = 1 the median
        // is set by the first returns, within the noise of neighbouring nodes).
        let at = |i| &tables.nodes[TablesGrid::index(i, 4)];
        for i in 1..S_COUNT {
            assert!(at(i).total() < at(i - 1).total(), "s node {i}");
        }
        // (The last node, α' = 0, returns nothing: it has no median.)
        for i in 1..S_COUNT - 1 {
            assert!(at(i).median() < 1.05 * at(i - 1).median(), "s node {i}");
        }
        assert!(at(S_COUNT - 2).median() < 0.5 * at(0).median());
    }
}
