//! The Monte Carlo bakes of the spatial models' tables (`dermis_engine::shading::bake`: kernel,
//! q(μ), δ(μ), slab transmittances) and, in [`crate::lut`], of the pre-integration LUT. Run
//! offline by `dermis lut`: per preset (the shipped `assets/sss/<preset>-eta<η>.tables` and
//! `.lut`) and per node of the nondimensional grids every other material's tables are
//! interpolated from ([`crate::grid`], [`measure_channel`] being the one measurement of both);
//! through [`install`], a direct bake where a command or a test asks for one (`dermis bench
//! tables` measures the grid against it).
//!
//! Seeds are fixed and differ from every reference set's, photons in fixed batches, so a bake
//! is deterministic and independent of the thread count.

use dermis_engine::shading::bake::{
    self, oblique_node, ring_edges, Bake, Budget, OBLIQUE_NODES, SLAB_FIRST_MM, SLAB_NODES,
};
use dermis_engine::shading::{fresnel, preintegrated, Material};

use crate::mc::{self, Medium};

/// Makes this process bake the tables and LUT of every material no shipped file covers
/// directly by the Monte Carlo at the shipped budget (seconds for the tables, minutes for the
/// LUT) instead of interpolating them from the grid: only where a command or a test asks for
/// a direct bake (the APK never links it).
pub fn install() {
    bake::install_baker(|m| measure(m, bake::DEFAULT_BUDGET, threads()));
    preintegrated::install_baker(|m, b| {
        crate::lut::bake_lut(b, m, &bake::DEFAULT_BUDGET, threads())
    });
}

/// The machine's threads.
pub fn threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The tables of `m` measured with [`QUICK_BUDGET`] (for tests that run the per-pixel code
/// over many materials).
pub fn quick(m: &Material) -> Bake {
    measure(m, QUICK_BUDGET, threads())
}

/// Strips on each side of the edge for the forward shift.
const STRIPS: usize = 48;

/// A quick bake for tests that run the per-pixel code over many materials (the tables are
/// noisier, the code paths the same).
pub const QUICK_BUDGET: Budget = Budget {
    kernel: 1_000,
    oblique: 100,
    slab: 100,
    kernel_events: 100_000,
    events: 10_000,
    max_events: 2_000,
    min_photons: 20,
    sphere: 200,
    sphere_events: 20_000,
};

pub fn medium(m: &Material, c: usize) -> Medium {
    Medium::new(m.sigma_a[c], m.sigma_s_prime[c], m.g, m.eta)
}

/// Photons for a run of `geom`/`source` within `events`: a pilot of a few photons measures
/// the events per photon.
fn photons_for(
    med: &Medium,
    (geom, source): (mc::Geometry, mc::Source),
    wanted: u64,
    events: u64,
    budget: &Budget,
    seed: u64,
) -> u64 {
    let pilot = 20.max(budget.min_photons.min(200));
    let r = mc::simulate(
        med,
        geom,
        source,
        &detectors(&[], budget),
        pilot,
        seed ^ 0xA5A5,
        1,
    );
    let per_photon = (r.events as f64 / pilot as f64).max(1.0);
    ((events as f64 / per_photon) as u64).clamp(budget.min_photons, wanted.max(budget.min_photons))
}

fn detectors(edges: &[f64], budget: &Budget) -> mc::Detectors {
    mc::Detectors {
        edges: edges.to_vec(),
        max_events: budget.max_events,
        ..Default::default()
    }
}

/// The measured tables of one channel's medium (lengths in the medium's units).
pub struct Channel {
    /// Power leaving through each bin of the layout's edges per unit incident power.
    pub mass: Vec<f64>,
    /// q(μ_k) at the oblique nodes (q(0) = 0, q(1) = 1).
    pub oblique: [f64; OBLIQUE_NODES],
    /// δ(μ_k) (0 at μ = 1).
    pub shift: [f64; OBLIQUE_NODES],
    /// Diffuse transmittance at each of the layout's thicknesses.
    pub slab: Vec<f64>,
}

/// Where one channel's tables are measured (lengths in the medium's units).
pub struct Layout<'a> {
    /// The kernel's annuli.
    pub edges: &'a [f64],
    /// The oblique beams' strips reach ±x_max.
    pub x_max: f64,
    /// The backlit slabs, ascending.
    pub thicknesses: &'a [f64],
}

/// Measures one channel's medium `med`: the pencil beam's exitance through the annuli, q(μ)
/// and δ(μ) at the oblique nodes from symmetric strips, and the backlit slabs' diffuse
/// transmittance ([`slab_column`]), where `at` says; seeds derived from `seed`. The one
/// measurement of a direct bake ([`measure`]) and of a grid node (`crate::grid`).
pub fn measure_channel(
    med: &Medium,
    at: &Layout,
    budget: &Budget,
    seed: u64,
    threads: usize,
) -> Channel {
    let (edges, x_max) = (at.edges, at.x_max);
    let semi = mc::Geometry::SemiInfinite;
    let normal = (semi, mc::Source::Normal);
    let n = photons_for(
        med,
        normal,
        budget.kernel,
        budget.kernel_events,
        budget,
        seed,
    );
    let r = mc::simulate(
        med,
        semi,
        mc::Source::Normal,
        &detectors(edges, budget),
        n,
        seed,
        threads,
    );
    let mass = edges
        .windows(2)
        .zip(&r.reflectance_profile.values)
        .map(|(w, v)| v * std::f64::consts::PI * (w[1] * w[1] - w[0] * w[0]))
        .collect();
    // Oblique beams: reflectance and forward shift from the shadow-edge estimator over
    // symmetric strips (the cumulative exitance across the edge).
    let strips: Vec<f64> = (0..=2 * STRIPS)
        .map(|i| x_max * (i as f64 / STRIPS as f64 - 1.0))
        .collect();
    let oblique_run = |mu: f64, seed: u64| {
        let source = mc::Source::Collimated { mu };
        let n = photons_for(
            med,
            (semi, source),
            budget.oblique,
            budget.events,
            budget,
            seed,
        );
        let cap = budget.max_events;
        let e = mc::edge::shadow_edge_with(med, mu, &strips, cap, n, seed, threads);
        let r = e.reflectance.mean;
        // E[Δx]·R = ∫₀^∞ (R − M) dx − ∫_{−∞}^0 M dx; the beam travels toward −x.
        let moment: f64 = strips
            .windows(2)
            .zip(&e.strips.values)
            .map(|(w, m)| {
                let width = w[1] - w[0];
                if w[0] >= 0.0 {
                    (r - m) * width
                } else {
                    -m * width
                }
            })
            .sum();
        (r, -moment / r.max(f64::MIN_POSITIVE))
    };
    let mut oblique = [0.0; OBLIQUE_NODES];
    let mut shift = [0.0; OBLIQUE_NODES];
    let (normal, _) = oblique_run(1.0, seed + 1);
    for k in 1..OBLIQUE_NODES - 1 {
        let mu = oblique_node(k);
        let (r, delta) = oblique_run(mu, seed + 10 + k as u64);
        // Where the medium reflects (next to) nothing the ratio is noise: Fresnel's
        // transmission ratio stands in; q stays within [0, 4] whatever the noise.
        oblique[k] = if normal > 1e-9 {
            (r / normal).clamp(0.0, 4.0)
        } else {
            fresnel::transmittance_shader(med.eta, mu)
                / fresnel::transmittance_shader(med.eta, 1.0).max(1e-12)
        };
        shift[k] = if delta.is_finite() {
            delta.clamp(0.0, x_max)
        } else {
            0.0
        };
    }
    oblique[OBLIQUE_NODES - 1] = 1.0;
    shift[0] = shift[1];
    let slab = slab_column(med, at.thicknesses, budget, seed + 100, threads);
    Channel {
        mass,
        oblique,
        shift,
        slab,
    }
}

/// Measures the tables for `m` within `budget` on `threads` threads: the direct bake of one
/// material (the presets' shipped files; every other material's tables are interpolated from
/// the grid, [`crate::grid`], whose yardstick this is).
pub fn measure(m: &Material, budget: Budget, threads: usize) -> Bake {
    measure_seeded(m, budget, threads, 0x5EED_BA4E)
}

/// [`measure`] with other seeds (derived from `seed`): the same bake's noise.
pub fn measure_seeded(m: &Material, budget: Budget, threads: usize, seed: u64) -> Bake {
    let edges = ring_edges(m);
    let x_max = *edges.last().unwrap_or(&10.0);
    let thicknesses = direct_thicknesses();
    let at = Layout {
        edges: &edges,
        x_max,
        thicknesses: &thicknesses,
    };
    let mut mass = vec![[0.0; 3]; edges.len() - 1];
    let mut oblique = [[0.0; 3]; OBLIQUE_NODES];
    let mut slab = [[0.0; 3]; SLAB_NODES];
    let mut shift = [[0.0; 3]; OBLIQUE_NODES];
    for c in 0..3 {
        let seed = seed + 1000 * c as u64;
        let ch = measure_channel(&medium(m, c), &at, &budget, seed, threads);
        for (k, v) in ch.mass.iter().enumerate() {
            mass[k][c] = *v;
        }
        for k in 0..OBLIQUE_NODES {
            oblique[k][c] = ch.oblique[k];
            shift[k][c] = ch.shift[k];
        }
        for (k, v) in ch.slab.iter().enumerate() {
            slab[k][c] = *v;
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

/// The slab thicknesses of a material's tables (mm): SLAB_FIRST_MM · 2^k.
pub fn direct_thicknesses() -> Vec<f64> {
    (0..SLAB_NODES)
        .map(|k| SLAB_FIRST_MM * (1u32 << k) as f64)
        .collect()
}

/// The diffuse transmittance (the unscattered beam excluded: it is the light seen through the
/// slab, not translucency) of slabs of the ascending `thicknesses` lit at normal incidence, for
/// one channel's medium. Each slab runs up to `budget.slab` photons within the event cap (a
/// dark medium's photons die in a few events, so its thick slabs get many). Thick slabs transmit
/// too few photons to measure: past the first node beyond a diffusion length whose relative
/// error exceeds 25 %, the transmittance carries on from the last measured node with the
/// medium's asymptotic decay ([`asymptotic_decay`]).
fn slab_column(
    med: &Medium,
    thicknesses: &[f64],
    budget: &Budget,
    seed: u64,
    threads: usize,
) -> Vec<f64> {
    let mut slab: Vec<f64> = Vec::with_capacity(thicknesses.len());
    let decay = asymptotic_decay(med.sigma_a, med.sigma_s_prime);
    let mut extrapolating = false;
    for (k, &d) in thicknesses.iter().enumerate() {
        let carried = |slab: &[f64]| slab[k - 1] * (-decay * (d - thicknesses[k - 1])).exp();
        if k > 0 && extrapolating {
            slab.push(carried(&slab));
            continue;
        }
        let geom = mc::Geometry::Slab { d };
        let seed = seed + k as u64;
        let source = mc::Source::Normal;
        let n = photons_for(
            med,
            (geom, source),
            budget.slab,
            budget.events,
            budget,
            seed,
        );
        let r = mc::simulate(med, geom, source, &detectors(&[], budget), n, seed, threads);
        let diffuse = (r.transmittance.mean - r.unscattered.mean).max(0.0);
        let se = r.transmittance.std_err + r.unscattered.std_err;
        let thick = d * decay >= 1.0;
        let poor = diffuse <= 0.0 || se > 0.25 * diffuse;
        if k > 0 && thick && poor {
            extrapolating = true;
            slab.push(carried(&slab));
        } else {
            slab.push(diffuse);
        }
    }
    slab
}

pub use dermis_engine::shading::transport::asymptotic_decay;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ground_truth::acceptance_material;
    use dermis_engine::shading::material::{PRESETS, SKIN1};
    use dermis_engine::shading::subsurface;
    use glam::DVec3;

    #[test]
    fn light_deep_in_a_medium_decays_as_transport_theory_says() {
        // ω' → 1: diffusion's σ_tr = √(3σ_a σ'_t); ω' = 1/2: κ = 0.9575 (Case's ν₀ = 1/κ =
        // 1.044); ω' → 0: the extinction σ'_t; and the limits themselves.
        let (a, s) = (1e-5_f64, 1.0);
        let diffusion = (3.0 * a * (a + s)).sqrt();
        assert!((asymptotic_decay(a, s) / diffusion - 1.0).abs() < 1e-3);
        assert!((asymptotic_decay(1.0, 1.0) / 2.0 - 0.9575).abs() < 1e-3);
        assert!((asymptotic_decay(1.0, 1e-6) - 1.0).abs() < 1e-4);
        assert_eq!(asymptotic_decay(0.3, 0.0), 0.3);
        assert_eq!(asymptotic_decay(0.0, 2.0), 0.0);
        assert_eq!(asymptotic_decay(0.0, 0.0), 0.0);
        assert_eq!(asymptotic_decay(f64::NAN, 1.0), 0.0);
        // Slower than diffusion for every absorbing medium, and faster as absorption grows.
        let mut last = 0.0;
        for k in 1..40 {
            let a = 0.05 * k as f64;
            let d = asymptotic_decay(a, 1.0);
            assert!(d > last && d < (3.0 * a * (a + 1.0)).sqrt(), "σ_a {a}: {d}");
            last = d;
        }
    }

    #[test]
    fn a_dark_mediums_thick_slabs_transmit_as_its_reference_says() {
        // skin-dark (single-scattering albedo 0.46 in blue: far from diffusion) against its
        // path-traced references (2·10⁶ photons, tools/reference/skin-dark.json) through the
        // table's log-linear interpolation, as the shaders read it. Diffusion's decay for the
        // nodes it could not measure made blue at 5 mm 15× too dark (|ln| 2.7); now the worst
        // is blue at 5 mm, 0.15, between its last measured node (4 mm) and the asymptotic
        // decay's 8 mm (the decay there is not yet asymptotic: 1.29 against 1.45 mm⁻¹).
        let [dark, ..] = crate::ground_truth::test_materials();
        let path = crate::ground_truth::file_for(&crate::ground_truth::source_dir(), &dark.name);
        let refs = crate::ground_truth::ReferenceSet::load(&path).expect("skin-dark references");
        let slabs: Vec<_> = (0..3)
            .map(|c| {
                slab_column(
                    &medium(&dark, c),
                    &direct_thicknesses(),
                    &bake::DEFAULT_BUDGET,
                    7,
                    2,
                )
            })
            .collect();
        let ln_t: [DVec3; SLAB_NODES] =
            std::array::from_fn(|k| DVec3::from_array([0, 1, 2].map(|c| slabs[c][k].ln())));
        let mut scored = 0;
        for e in &refs.entries {
            let crate::ground_truth::Scene::SlabBacklit { thickness_mm } = e.scene else {
                continue;
            };
            let model = subsurface::slab_transmittance(&ln_t, thickness_mm);
            for c in 0..3 {
                let (model, truth) = (model[c], e.values[0][c]);
                let err = (model / truth).ln().abs();
                assert!(err < 0.2, "{thickness_mm} mm ch{c}: {model} vs {truth}");
                scored += 1;
            }
        }
        assert!(scored >= 12, "{scored} slab values scored");
    }

    #[test]
    fn every_preset_has_shipped_tables_at_the_current_budget() {
        // Tables baked with another budget, material or layout would be ignored (and the
        // runtime would fall back to another material's): `dermis lut --out assets/sss`.
        for m in PRESETS
            .iter()
            .flat_map(|m| [m.clone(), acceptance_material(m)])
        {
            let b = bake::shipped(&m)
                .unwrap_or_else(|| panic!("no shipped tables for {}", bake::file_name(&m)));
            assert!(b.mass.iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
            assert!(b.reflectance().iter().all(|r| *r > 0.01 && *r < 1.0));
        }
    }

    #[test]
    fn the_shipped_tables_are_what_the_bake_measures() {
        // skin1's tables re-baked at the shipped budget equal the shipped ones within the
        // Monte Carlo's noise (the bake is deterministic, so on the machine that baked them
        // they are identical), and a quick bake's reflectance agrees within its own noise.
        let shipped = bake::shipped(&SKIN1).expect("shipped skin1 tables");
        let again = measure(&SKIN1, bake::DEFAULT_BUDGET, 2);
        assert_eq!(again.edges, shipped.edges);
        for (k, (a, b)) in again.mass.iter().zip(&shipped.mass).enumerate() {
            for c in 0..3 {
                assert!((a[c] - b[c]).abs() <= 1e-3 * b[c] + 1e-9, "ring {k} ch{c}");
            }
        }
        let close = |a: &[[f64; 3]], b: &[[f64; 3]], tol: f64| {
            a.iter()
                .flatten()
                .zip(b.iter().flatten())
                .all(|(x, y)| (x - y).abs() <= tol)
        };
        assert!(close(&again.oblique, &shipped.oblique, 1e-3));
        assert!(close(&again.shift, &shipped.shift, 1e-3));
        assert!(close(&again.slab, &shipped.slab, 1e-4));
        let quick = quick(&SKIN1).reflectance();
        let full = shipped.reflectance();
        for c in 0..3 {
            assert!(
                (quick[c] - full[c]).abs() < 0.05 * full[c],
                "ch{c}: {quick:?} vs {full:?}"
            );
        }
        // The bytes round-trip, and tables for another material are refused.
        let bytes = shipped.to_bytes(&SKIN1, &bake::DEFAULT_BUDGET);
        assert_eq!(
            Bake::from_bytes(&bytes, &SKIN1, &bake::DEFAULT_BUDGET),
            Some(shipped)
        );
        let other = acceptance_material(&SKIN1);
        assert_eq!(
            Bake::from_bytes(&bytes, &other, &bake::DEFAULT_BUDGET),
            None
        );
    }
}
