//! Stability suite (issue 4 §2): every model and variant over a dense grid of extremes —
//! σ_a ∈ {0, 1e-6 … 1e6} mm⁻¹, σ'_s ∈ {1e-6 … 1e6} mm⁻¹ (α' from 0 to 1 − 1e-12), η ∈ {0.8, 1,
//! 1.3, 1.4}, g ∈ {0, 0.8}, grazing angles, light distances 0 … 100 m, depths 0 and 1e-9 … 100
//! mm, probe radii/depths r, d = 0, 1e-9 … 100 mm — in f32 on the GPU through the conformance
//! harness. The DEFAULT variants (ward, dipole, oss-stable, burley) must stay finite and
//! non-negative and within `F32_SHADE` of the f64 reference; the printed variants are only
//! tabulated here (tests/render/shading_printed_defects.rs asserts their defects).
//!
//! f16: the per-pixel maths on nondimensional inputs (`*_nd`, fresnel) in half precision,
//! inside f16's range (`NdFunction::f16_domain`), within `F16_ND`; it runs where the adapter
//! has SHADER_F16 (lavapipe does) and says so; with CI=true a missing f16 is a failure.

use dermis_engine::render::Gpu;
use dermis_engine::shading::material::{Material, Origin};
use dermis_engine::shading::pixel::Pixel;
use dermis_engine::shading::ShadingModel;
use dermis_measure::bake;
use dermis_measure::conformance::harness::{Harness, Item};
use dermis_measure::conformance::{
    self, round_f16, NdFunction, Precision, F16_ND, F32_ND, F32_SHADE,
};
use glam::DVec3;

fn gpu() -> Gpu {
    Gpu::headless().unwrap_or_else(|e| panic!("{e}"))
}

fn dir(theta_deg: f64, phi_deg: f64) -> DVec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

const SIGMA_A: [f64; 6] = [0.0, 1e-6, 1e-3, 1.0, 1e3, 1e6];
const SIGMA_S: [f64; 5] = [1e-6, 1e-3, 1.0, 1e3, 1e6];
const ETA: [f64; 4] = [0.8, 1.0, 1.3, 1.4];
const G: [f64; 2] = [0.0, 0.8];

fn materials() -> Vec<Material> {
    let mut out = Vec::new();
    for a in SIGMA_A {
        for s in SIGMA_S {
            for eta in ETA {
                for g in G {
                    out.push(Material {
                        name: "grid".into(),
                        origin: Origin::Builtin,
                        sigma_a: [a, a * 0.5, a * 2.0],
                        sigma_s_prime: [s, s * 2.0, s * 0.5],
                        eta,
                        g,
                        textured: true,
                    });
                }
            }
        }
    }
    out
}

/// Directions (grazing included), light distances [m], depths [mm], probe arguments [mm].
fn pixels() -> Vec<(Pixel, f64)> {
    let dirs_l = [(0.0, 0.0), (60.0, 30.0), (89.99, 120.0), (90.0, 200.0)];
    let dirs_v = [(0.0, 0.0), (45.0, 210.0), (89.99, 300.0)];
    let dists = [0.0, 1e-3, 0.1, 3.0, 100.0];
    let depths_mm = [0.0, 1e-9, 1e-3, 1.0, 100.0];
    let probes = [0.0, 1e-9, 1e-6, 1e-3, 1.0, 1.4, 3.0, 100.0];
    let mut out = Vec::new();
    let mut k = 0;
    for l in dirs_l {
        for v in dirs_v {
            for d in dists {
                for h in depths_mm {
                    let mut px = Pixel::new(dir(l.0, l.1), dir(v.0, v.1));
                    px.light_dist_m = d;
                    px.thickness_m = h / 12.0; // oss: d [mm] = thickness [m] × 12
                    out.push((px.to_f32(), probes[k % probes.len()] as f32 as f64));
                    k += 1;
                }
            }
        }
    }
    out
}

#[derive(Default)]
struct Stats {
    n: usize,
    non_finite: usize,
    negative: usize,
    outside: usize,
    max_rel: f64,
    example: Option<String>,
}

impl Stats {
    fn add(
        &mut self,
        got: f64,
        want: f64,
        tol: conformance::Tolerance,
        floor: f64,
        what: impl Fn() -> String,
    ) {
        self.n += 1;
        if !got.is_finite() {
            self.non_finite += 1;
        } else if got < 0.0 {
            self.negative += 1;
        }
        if got.is_finite() && want.is_finite() {
            self.max_rel = self.max_rel.max(conformance::rel_error(got, want, floor));
        }
        if !tol.accepts(got, want) {
            self.outside += 1;
            if self.example.is_none() {
                self.example = Some(format!("{got:e} vs f64 {want:e} at {}", what()));
            }
        }
    }
}

fn is_default(m: ShadingModel) -> bool {
    matches!(
        m,
        ShadingModel::Ward
            | ShadingModel::Dipole
            | ShadingModel::OssStable
            | ShadingModel::Burley
            | ShadingModel::Tabulated
            | ShadingModel::Preintegrated
    )
}

#[test]
fn every_model_in_f32_over_the_extremes() {
    let gpu = gpu();
    println!("adapter: {}", gpu.adapter_name());
    let mut h = Harness::new(&gpu);
    let mats = materials();
    let px = pixels();
    let ambient = DVec3::new(0.05, 0.04, 0.03);
    println!("| model | items | max rel err (shade / sub-function) vs f64 | outside tol | non-finite | negative |");
    println!("|---|---|---|---|---|---|");
    let mut failures = Vec::new();
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
                    pixel: Pixel {
                        ambient: DVec3::new(0.05, 0.04, 0.03).as_vec3().as_dvec3(),
                        ..*pixel
                    },
                    probe: *x,
                })
            })
            .collect();
        let out = h.shade(model, &params, &items, ambient);
        let mut st = Stats::default();
        for (it, o) in items.iter().zip(&out) {
            let p = &params[it.params];
            let want = conformance::reference_shade(model, p, &it.pixel);
            let want_p = conformance::reference_probe(model, p, &it.pixel, it.probe);
            for c in 0..3 {
                let m = &mats[it.params];
                let what = || {
                    format!(
                        "{model} σ_a={} σ'_s={} η={} g={} pixel {:?} x={}",
                        m.sigma_a[c], m.sigma_s_prime[c], m.eta, m.g, it.pixel, it.probe
                    )
                };
                st.add(o.shade[c] as f64, want[c], F32_SHADE, 1e-30, what);
                st.add(o.probe[c] as f64, want_p[c], F32_SHADE, 1e-30, what);
            }
        }
        let tag = if is_default(model) { "" } else { " (printed)" };
        println!(
            "| {}{tag} | {} | {:.2e} | {} | {} | {} |",
            model.name(),
            st.n,
            st.max_rel,
            st.outside,
            st.non_finite,
            st.negative
        );
        if let Some(e) = &st.example {
            println!("  first outside tolerance: {e}");
        }
        if is_default(model) && (st.non_finite + st.negative + st.outside) > 0 {
            failures.push(format!(
                "{model}: {} non-finite, {} negative, {} outside {F32_SHADE:?}",
                st.non_finite, st.negative, st.outside
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Extreme grids of the nondimensional functions.
fn nd_grid(f: NdFunction) -> Vec<[f64; 8]> {
    let mut v = Vec::new();
    match f {
        NdFunction::WardLobe => {
            let thetas = [0.0, 1e-4, 30.0, 70.0, 89.9, 89.999, 90.0];
            for tl in thetas {
                for tv in thetas {
                    // 180°: h ∥ n for equal angles, θ_h → 90° for grazing pairs.
                    for dphi in [0.0, 90.0, 179.9, 180.0] {
                        let (l, vv) = (dir(tl, 15.0), dir(tv, 15.0 + dphi));
                        let hh = l + vv;
                        for (ax, ay) in [
                            (1e-9, 1e-9),
                            (1e-4, 2e-4),
                            (1e-3, 1e-3),
                            (0.05, 0.08),
                            (0.1, 0.1),
                            (0.3, 0.36),
                            (1.0, 0.5),
                        ] {
                            v.push([l.z, vv.z, hh.x, hh.y, hh.z, 0.06, ax, ay]);
                        }
                    }
                }
            }
        }
        NdFunction::Fresnel => {
            for eta in [0.5, 0.8, 0.999, 1.0, 1.000001, 1.3, 1.4, 2.0, 3.0] {
                for c in [0.0, 1e-7, 1e-3, 0.1, 0.5, 0.6, 0.9, 1.0] {
                    v.push([eta, c, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
                }
            }
        }
        NdFunction::DipoleRd => {
            for rho in [0.0, 1e-15, 1e-9, 1e-3, 0.5, 1.0, 10.0, 30.0, 1e3, 1e8] {
                for s in [0.0, 1e-6, 1e-3, 0.1, 1.0, 3f64.sqrt()] {
                    for zv in [1.0 + 4.0 * 1.0032 / 3.0, 3.4, 8.0] {
                        for albedo in [0.0, 0.5, 1.0] {
                            v.push([rho, s, zv, albedo, 0.0, 0.0, 0.0, 0.0]);
                        }
                    }
                }
            }
        }
        NdFunction::OssFdStable => {
            let depths = [
                0.0, 1e-15, 1e-9, 1e-4, 0.1, 0.2499, 0.25, 0.2501, 1.0, 30.0, 1e3, 1e8,
            ];
            for a in depths {
                for sp in depths {
                    for fdr in [0.0, 0.0016, 0.44, 0.999] {
                        v.push([a, sp, fdr, 0.0, 0.0, 0.0, 0.0, 0.0]);
                    }
                }
            }
        }
    }
    v
}

#[test]
fn nondimensional_maths_in_f32_and_f16() {
    let gpu = gpu();
    let mut h = Harness::new(&gpu);
    let ci = std::env::var("CI").is_ok_and(|v| v == "true");
    let f16 = h.has_f16();
    if f16 {
        println!("f16: RAN (adapter {} has SHADER_F16)", gpu.adapter_name());
    } else if ci {
        panic!(
            "f16: adapter {} has no SHADER_F16 (CI=true: lavapipe must offer it)",
            gpu.adapter_name()
        );
    } else {
        println!(
            "f16: DID NOT RUN (adapter {} has no SHADER_F16)",
            gpu.adapter_name()
        );
    }
    println!("| function | f32 points | f32 max rel err (floor 1e-30) | f32 non-finite/negative | f16 points (in range) | f16 max rel err (floor 6.1e-5) | f16 non-finite |");
    println!("|---|---|---|---|---|---|---|");
    let mut failures = Vec::new();
    for f in NdFunction::ALL {
        let grid = nd_grid(f);
        // f32 over the whole grid.
        let inputs: Vec<[f32; 8]> = grid.iter().map(|x| x.map(|v| v as f32)).collect();
        let out = h.nd(f, Precision::F32, &inputs);
        let mut s32 = Stats::default();
        for (x, g) in inputs.iter().zip(&out) {
            let xd = x.map(f64::from);
            let tol = if f == NdFunction::Fresnel && conformance::near_critical_angle(xd[0], xd[1])
            {
                conformance::F32_CRITICAL_ANGLE
            } else {
                F32_ND
            };
            s32.add(*g as f64, f.reference(&xd), tol, 1e-30, || {
                format!("{xd:?}")
            });
        }
        if s32.non_finite + s32.negative + s32.outside > 0 {
            failures.push(format!(
                "{} f32: {} non-finite, {} negative, {} outside; {:?}",
                f.name(),
                s32.non_finite,
                s32.negative,
                s32.outside,
                s32.example
            ));
        }
        // f16 inside its range, on inputs rounded to f16.
        let mut s16 = Stats::default();
        if f16 {
            let inputs: Vec<[f32; 8]> = grid
                .iter()
                .filter(|x| f.f16_domain(x))
                .map(|x| x.map(|v| round_f16(v) as f32))
                .collect();
            let out = h.nd(f, Precision::F16, &inputs);
            for (x, g) in inputs.iter().zip(&out) {
                let xd = x.map(f64::from);
                s16.add(*g as f64, f.reference(&xd), F16_ND, 6.1e-5, || {
                    format!("{xd:?}")
                });
            }
            if s16.non_finite + s16.negative + s16.outside > 0 {
                failures.push(format!(
                    "{} f16: {} non-finite, {} negative, {} outside; {:?}",
                    f.name(),
                    s16.non_finite,
                    s16.negative,
                    s16.outside,
                    s16.example
                ));
            }
        }
        let f16_cols = if f16 {
            format!("{} | {:.2e} | {}", s16.n, s16.max_rel, s16.non_finite)
        } else {
            "— | not run | —".into()
        };
        println!(
            "| {} | {} | {:.2e} | {}/{} | {f16_cols} |",
            f.name(),
            s32.n,
            s32.max_rel,
            s32.non_finite,
            s32.negative
        );
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
