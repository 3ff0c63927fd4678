//! GPU conformance: the renderer's WGSL shading functions, run by the compute harness
//! (`dermis_measure::conformance::harness`) on the real driver (lavapipe in CI), against the f64
//! references beside each model, over the renderer's materials and a grid of angles, light
//! distances and thicknesses. No skip: without an adapter the tests fail.

use dermis_engine::render::Gpu;
use dermis_engine::shading::material::{Material, SKIN1, WHITE_COAT};
use dermis_engine::shading::pixel::Pixel;
use dermis_engine::shading::ShadingModel;
use dermis_measure::bake;
use dermis_measure::conformance::harness::{Harness, Item};
use dermis_measure::conformance::{self, NdFunction, Precision, F32_ND, F32_SHADE};
use glam::DVec3;

fn gpu() -> Gpu {
    Gpu::headless().unwrap_or_else(|e| panic!("{e}"))
}

fn dir(theta_deg: f64, phi_deg: f64) -> DVec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

/// A tilted, non-axis-aligned shading frame (so nothing is exact by symmetry).
fn frame() -> (DVec3, DVec3, DVec3) {
    let n = DVec3::new(0.2, -0.3, 0.93).normalize();
    let t = (DVec3::new(1.0, 0.1, 0.0) - n * n.dot(DVec3::new(1.0, 0.1, 0.0))).normalize();
    (n, t, n.cross(t))
}

fn to_world(local: DVec3) -> DVec3 {
    let (n, t, b) = frame();
    t * local.x + b * local.y + n * local.z
}

fn materials() -> Vec<Material> {
    vec![
        SKIN1,
        WHITE_COAT,
        Material { eta: 1.4, ..SKIN1 },
        Material {
            g: 0.8,
            eta: 1.0936,
            ..SKIN1
        },
        Material {
            eta: 1.0,
            ..WHITE_COAT
        },
    ]
}

fn pixels() -> Vec<(Pixel, f64)> {
    let (n, t, b) = frame();
    let mut out = Vec::new();
    let thetas_l = [0.0, 25.0, 60.0, 85.0];
    let thetas_v = [0.0, 40.0, 80.0];
    let dists = [0.0005, 0.05, 0.8, 3.0, 12.0];
    let thick = [0.0, 0.02, 0.09, 0.25, 2.0];
    let probes = [0.0, 0.01, 0.5, 1.4, 3.0, 10.0];
    let mut k = 0;
    for (i, &tl) in thetas_l.iter().enumerate() {
        for (j, &tv) in thetas_v.iter().enumerate() {
            for &d in &dists {
                for &h in &thick {
                    let mut px = Pixel::new(
                        to_world(dir(tl, 30.0 * i as f64)),
                        to_world(dir(tv, 200.0 - 70.0 * j as f64)),
                    );
                    px.n = n;
                    px.t = t;
                    px.b = b;
                    px.light_dist_m = d;
                    px.thickness_m = h;
                    px.light = DVec3::new(12.0, 10.0, 9.0);
                    out.push((px.to_f32(), probes[k % probes.len()]));
                    k += 1;
                }
            }
        }
    }
    out
}

#[test]
fn every_model_matches_its_f64_reference_in_f32() {
    let gpu = gpu();
    println!("adapter: {}", gpu.adapter_name());
    let mut h = Harness::new(&gpu);
    let ambient = DVec3::new(0.05, 0.04, 0.03);
    let mats = materials();
    let px = pixels();
    // LUT models are checked by rendering (tests/render/subsurface_render.rs; see harness_checks).
    for model in ShadingModel::ALL
        .into_iter()
        .filter(|&m| conformance::harness_checks(m))
    {
        let params: Vec<_> = mats
            .iter()
            .map(|m| model.params_with(m, &bake::quick(m)))
            .collect();
        let items: Vec<Item> = (0..mats.len())
            .flat_map(|p| {
                px.iter().map(move |(pixel, x)| Item {
                    params: p,
                    pixel: *pixel,
                    probe: *x as f32 as f64,
                })
            })
            .map(|mut it| {
                it.pixel.ambient = ambient.as_vec3().as_dvec3();
                it
            })
            .collect();
        let out = h.shade(model, &params, &items, ambient);
        let (mut worst, mut worst_probe, mut bad) = (0.0f64, 0.0f64, Vec::new());
        for (it, o) in items.iter().zip(&out) {
            let want = conformance::reference_shade(model, &params[it.params], &it.pixel);
            let want_p =
                conformance::reference_probe(model, &params[it.params], &it.pixel, it.probe);
            for c in 0..3 {
                let (g, w) = (o.shade[c] as f64, want[c]);
                worst = worst.max(conformance::rel_error(g, w, 1e-30));
                if !F32_SHADE.accepts(g, w) {
                    bad.push(format!(
                        "shade c{c} {g:e} vs {w:e} at {:?} x={}",
                        it.pixel, it.probe
                    ));
                }
                let (g, w) = (o.probe[c] as f64, want_p[c]);
                worst_probe = worst_probe.max(conformance::rel_error(g, w, 1e-30));
                if !F32_SHADE.accepts(g, w) {
                    bad.push(format!("probe c{c} {g:e} vs {w:e} x={}", it.probe));
                }
            }
        }
        println!(
            "{:>15}: {} items, max rel err shade {worst:.2e}, probe {worst_probe:.2e}",
            model.name(),
            items.len()
        );
        assert!(
            bad.is_empty(),
            "{model}: {} outside {F32_SHADE:?}, e.g.\n{}",
            bad.len(),
            bad[..bad.len().min(5)].join("\n")
        );
    }
}

#[test]
fn nondimensional_functions_match_in_f32() {
    let gpu = gpu();
    let mut h = Harness::new(&gpu);
    for f in NdFunction::ALL {
        let inputs = common_nd_grid(f);
        let out = h.nd(f, Precision::F32, &inputs);
        let mut worst = 0.0f64;
        for (x, g) in inputs.iter().zip(&out) {
            let xd = x.map(f64::from);
            let w = f.reference(&xd);
            worst = worst.max(conformance::rel_error(*g as f64, w, 1e-30));
            assert!(
                F32_ND.accepts(*g as f64, w),
                "{}: {g:e} vs {w:e} at {x:?}",
                f.name()
            );
        }
        println!(
            "{:>22}: {} points, max rel err {worst:.2e}",
            f.name(),
            inputs.len()
        );
    }
}

/// Moderate grids (the stability suite covers the extremes).
fn common_nd_grid(f: NdFunction) -> Vec<[f32; 8]> {
    let mut v = Vec::new();
    match f {
        NdFunction::WardLobe => {
            for tl in [0.0, 20.0, 50.0, 80.0] {
                for tv in [0.0, 35.0, 70.0] {
                    for phi in [0.0, 45.0, 130.0, 250.0] {
                        let (l, vv) = (dir(tl, 10.0), dir(tv, phi));
                        let hh = l + vv;
                        for (ax, ay) in [(0.3, 0.36), (0.1, 0.1), (0.5, 0.2)] {
                            v.push([l.z, vv.z, hh.x, hh.y, hh.z, 0.06, ax, ay].map(|x| x as f32));
                        }
                    }
                }
            }
        }
        NdFunction::Fresnel => {
            for eta in [1.0, 1.0936, 1.3, 1.4, 2.0] {
                for i in 0..=20 {
                    v.push([eta as f32, i as f32 / 20.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
                }
            }
        }
        NdFunction::DipoleRd => {
            for rho in [0.0, 0.1, 1.0, 3.0, 10.0] {
                for s in [0.05, 0.3, 1.0] {
                    for zv in [1.0, 2.5, 4.0] {
                        v.push([rho, s, zv, 0.9, 0.0, 0.0, 0.0, 0.0]);
                    }
                }
            }
        }
        NdFunction::OssFdStable => {
            for a in [0.0, 0.01, 0.2, 1.0, 5.0] {
                for sp in [0.0, 0.05, 0.4, 2.0, 10.0] {
                    v.push([a, sp, 0.44, 0.0, 0.0, 0.0, 0.0, 0.0]);
                }
            }
        }
    }
    v
}

/// Ward's standard form (the default): reciprocity f(l, v) = f(v, l) and isotropy (rotation
/// about n leaves it unchanged) when α_x = α_y, on the GPU in f32.
#[test]
fn ward_default_is_reciprocal_and_isotropic_on_the_gpu() {
    let gpu = gpu();
    let mut h = Harness::new(&gpu);
    let mut inputs = Vec::new();
    for tl in [5.0, 30.0, 60.0, 85.0] {
        for tv in [10.0, 45.0, 75.0] {
            for phi in [0.0, 60.0, 170.0] {
                let (l, v) = (dir(tl, 20.0), dir(tv, 20.0 + phi));
                for (a, b) in [(l, v), (v, l)] {
                    let hh = a + b;
                    inputs.push([a.z, b.z, hh.x, hh.y, hh.z, 0.06, 0.30, 0.36].map(|x| x as f32));
                }
                // Isotropic lobe, and the same pair rotated by 77° about n.
                let rot = glam::DQuat::from_rotation_z(77f64.to_radians());
                for (a, b) in [(l, v), (rot * l, rot * v)] {
                    let hh = a + b;
                    inputs.push([a.z, b.z, hh.x, hh.y, hh.z, 0.06, 0.3, 0.3].map(|x| x as f32));
                }
            }
        }
    }
    let out = h.nd(NdFunction::WardLobe, Precision::F32, &inputs);
    let (mut worst_recip, mut worst_iso) = (0.0f64, 0.0f64);
    for q in out.chunks_exact(4) {
        let (f, r, i0, i1) = (q[0] as f64, q[1] as f64, q[2] as f64, q[3] as f64);
        worst_recip = worst_recip.max(conformance::rel_error(f, r, 1e-30));
        worst_iso = worst_iso.max(conformance::rel_error(i0, i1, 1e-30));
    }
    println!("ward (standard form) f32 on GPU: reciprocity max rel {worst_recip:.2e}, isotropy max rel {worst_iso:.2e}");
    assert!(worst_recip < 1e-5, "{worst_recip}");
    // The rotated pair is rounded to f32 independently, and the exponent reaches |e| ≈ 40
    // here, so the two sides differ by up to |e|·2⁻²⁴ per rounded component (≈ 1e-5).
    assert!(worst_iso < 1e-4, "{worst_iso}");
}
