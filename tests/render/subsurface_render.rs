//! The spatial subsurface models through the real renderer (lavapipe) against the stored
//! Monte Carlo references (`tools/reference/`), with tolerances set from the references'
//! own noise, and the rule that the screen-space pass exists only where a model calls for it.

use dermis_engine::render::passes::PassId;
use dermis_engine::render::{Gpu, LiveObjects, PipelineSet, Renderer};
use dermis_engine::shading::{Material, ShadingModel};
use dermis_measure::ground_truth::{self, metric, ReferenceSet, Scene};
use dermis_measure::scenes::SceneRenderer;

fn gpu() -> Gpu {
    Gpu::headless().unwrap_or_else(|e| panic!("{e}"))
}

fn set(m: &Material) -> ReferenceSet {
    ReferenceSet::load(&ground_truth::file_for(
        &ground_truth::default_dir(),
        &m.name,
    ))
    .unwrap_or_else(|e| panic!("{e}"))
}

fn skin1() -> Material {
    let [skin1, _] = ground_truth::acceptance_materials();
    skin1
}

/// The error a model may have on top of the reference's own noise.
fn tolerance(entry: &ground_truth::Entry, model_error: f64) -> f64 {
    let noise = metric::score(&entry.values, entry).ref_rel_se_all;
    model_error + 3.0 * noise
}

/// `model`'s image of the reference scene `entry` in material `m`.
fn render(
    (gpu, probe): (&Gpu, &mut SceneRenderer),
    model: ShadingModel,
    m: &Material,
    entry: &ground_truth::Entry,
) -> Vec<[f64; 3]> {
    probe
        .render(gpu, model, m, &entry.scene, &entry.edges)
        .unwrap_or_else(|e| panic!("{}: {e}", model.name()))
}

#[test]
fn the_measured_profile_matches_path_traced_point_lights() {
    let gpu = gpu();
    let mut probe = SceneRenderer::new(&gpu);
    let m = skin1();
    let set = set(&m);
    for h in [2.0, 5.0, 20.0] {
        let entry = set
            .entry(&Scene::PointLight { h_mm: h })
            .expect("reference has the point light");
        let tab = render((&gpu, &mut probe), ShadingModel::Tabulated, &m, entry);
        let ward = render((&gpu, &mut probe), ShadingModel::Ward, &m, entry);
        let (t, w) = (metric::score(&tab, entry), metric::score(&ward, entry));
        println!(
            "h = {h} mm: tabulated {:.3}, ward {:.3} (MC rel SE {:.3})",
            t.mean_log_all, w.mean_log_all, t.ref_rel_se_all
        );
        // The acceptance bound of the spatial-transport issue is 0.10 on skin1.
        assert!(t.mean_log_all <= tolerance(entry, 0.10), "h {h}: {t:?}");
        // A local BRDF cannot spread light: it is measurably worse, everywhere.
        assert!(
            w.mean_log_all > 2.0 * t.mean_log_all,
            "h {h}: {w:?} vs {t:?}"
        );
        // A black or doubled image scores badly (the metric cannot be gamed).
        let black = vec![[0.0; 3]; tab.len()];
        assert!(metric::score(&black, entry).mean_log_all > 5.0);
        let doubled: Vec<[f64; 3]> = tab.iter().map(|v| v.map(|x| 2.0 * x)).collect();
        assert!(metric::score(&doubled, entry).mean_log_all > 0.5);
    }
}

#[test]
fn translucency_matches_path_traced_backlit_slabs() {
    let gpu = gpu();
    let mut probe = SceneRenderer::new(&gpu);
    let m = skin1();
    let set = set(&m);
    for d in [0.5, 1.0, 2.0] {
        let entry = set
            .entry(&Scene::SlabBacklit { thickness_mm: d })
            .expect("reference has the slab");
        for model in [ShadingModel::Tabulated, ShadingModel::Preintegrated] {
            let got = probe
                .render(&gpu, model, &m, &entry.scene, &entry.edges)
                .unwrap();
            let s = metric::score(&got, entry);
            assert!(
                s.mean_log_all <= tolerance(entry, 0.10),
                "{model} d {d}: {s:?}"
            );
        }
        // Burley's profile has no translucency: nothing comes through.
        let burley = probe
            .render(&gpu, ShadingModel::Burley, &m, &entry.scene, &entry.edges)
            .unwrap();
        assert!(burley.iter().all(|v| v.iter().all(|&x| x.abs() < 1e-9)));
    }
}

/// `preintegrated` on `m`'s reference spheres: each scored (printed) and held to
/// `each_bound` over the reference's noise, `check`ed with its bands; the scores' and the
/// noise's sums and the count.
fn preintegrated_spheres(
    (gpu, probe): (&Gpu, &mut SceneRenderer),
    m: &Material,
    each_bound: f64,
    mut check: impl FnMut(&ground_truth::Entry, &[[f64; 3]]),
) -> (f64, f64, f64) {
    let (mut sum, mut noise, mut n) = (0.0, 0.0, 0.0);
    let set = set(m);
    for entry in set
        .entries
        .iter()
        .filter(|e| matches!(e.scene, Scene::Sphere { .. }))
    {
        let got = render((gpu, &mut *probe), ShadingModel::Preintegrated, m, entry);
        let s = metric::score(&got, entry);
        println!("{} {}: {:.3}", m.name, entry.scene.label(), s.mean_log_all);
        check(entry, &got);
        assert!(
            s.mean_log_all <= tolerance(entry, each_bound),
            "{} {}: {s:?}",
            m.name,
            entry.scene.label()
        );
        sum += s.mean_log_all;
        noise += s.ref_rel_se_all;
        n += 1.0;
    }
    (sum, noise, n)
}

#[test]
fn the_preintegrated_lut_matches_path_traced_spheres_and_flat_ground() {
    // The LUT's rows are the Monte Carlo sphere walker's (baked offline, shipped); rendered
    // through the real renderer (three views, linear filtering in log2 M, curvature from
    // the mesh's derivatives) the spheres must score within the acceptance bound of the
    // spatial-transport issue (best model ≤ 0.10 on spheres), each sphere within 0.15.
    let gpu = gpu();
    let mut probe = SceneRenderer::new(&gpu);
    let (mut sum, mut noise, mut n) = (0.0, 0.0, 0.0);
    for m in ground_truth::acceptance_materials() {
        let (s, e, k) = preintegrated_spheres((&gpu, &mut probe), &m, 0.15, |_, _| {});
        (sum, noise, n) = (sum + s, noise + e, n + k);
        let set = set(&m);
        // Flat ground (the LUT's flattest row) far on the lit side of a shadow edge: the
        // diffuse reflectance at incidence θ, the edge reference's plateau.
        for theta in [0.0f64, 45.0] {
            let entry = set
                .entry(&Scene::ShadowEdge { theta_deg: theta })
                .expect("reference has the edge");
            let k = entry.values.len() - 1;
            let edges = &entry.edges[k..];
            let got = probe
                .render(&gpu, ShadingModel::Preintegrated, &m, &entry.scene, edges)
                .unwrap();
            for (c, (&g, (&w, &se))) in got[0]
                .iter()
                .zip(entry.values[k].iter().zip(&entry.std_err[k]))
                .enumerate()
            {
                let se = se / w;
                assert!(
                    (g / w - 1.0).abs() < 0.04 + 3.0 * se,
                    "{} θ {theta} c {c}: {g} vs {w}",
                    m.name
                );
            }
        }
    }
    assert_eq!(n, 6.0, "three spheres per material");
    assert!(sum / n <= 0.10 + 3.0 * noise / n, "mean {:.3}", sum / n);
}

#[test]
fn a_grid_served_lut_matches_path_traced_spheres_into_the_dark_side() {
    // Materials no preset covers take their sphere rows from the shipped grid
    // (`shading::sphere_grid`). Past the terminator the light decays as e^(−σ_tr d), and a
    // grid interpolated the wrong way there rendered the back of skin-dark's 20 mm sphere 2⁴
    // too dark in red: below f16, a black band against the truth's light (sphere family
    // 0.175 against 0.073 from a direct bake).
    let gpu = gpu();
    let mut probe = SceneRenderer::new(&gpu);
    let (mut sum, mut noise, mut n) = (0.0, 0.0, 0.0);
    for m in ground_truth::test_materials() {
        assert!(m.matching_preset().is_none(), "{} is a preset's", m.name);
        // Every band the truth resolves is lit: nothing black where light arrives.
        let lit = |entry: &ground_truth::Entry, got: &[[f64; 3]]| {
            for (k, (g, w)) in got.iter().zip(&entry.values).enumerate() {
                for c in 0..3 {
                    let resolved = w[c] > 0.0 && entry.std_err[k][c] < 0.2 * w[c];
                    assert!(
                        !resolved || g[c] > 0.0,
                        "{} {} band {k} channel {c}: black, the truth {}",
                        m.name,
                        entry.scene.label(),
                        w[c]
                    );
                }
            }
        };
        let (s, e, k) = preintegrated_spheres((&gpu, &mut probe), &m, 0.20, lit);
        (sum, noise, n) = (sum + s, noise + e, n + k);
    }
    assert_eq!(n, 9.0, "three spheres per material");
    assert!(sum / n <= 0.10 + 3.0 * noise / n, "mean {:.3}", sum / n);
}

#[test]
fn the_screen_space_pass_exists_only_where_a_model_calls_for_it() {
    let gpu = gpu();
    let format = wgpu::TextureFormat::Rgba8UnormSrgb;
    let assets = dermis_engine::scene::SceneAssets::load(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"),
        None,
    )
    .unwrap();
    let pipelines = || LiveObjects::read(&gpu.device).render_pipelines;
    // (pipelines built with nothing loaded, whether the subsurface pass is one of them,
    // pipelines the props add once loaded).
    let count = |set: &PipelineSet| {
        let before = pipelines();
        let mut r = Renderer::with_pipelines(&gpu, format, set);
        let built = pipelines() - before;
        let (kind, model) = &assets.props[0];
        r.load_prop(&gpu, *kind, model);
        (
            built,
            r.is_on(PassId::subsurface),
            pipelines() - before - built,
        )
    };
    let local = PipelineSet {
        models: vec![ShadingModel::Ward, ShadingModel::Preintegrated],
        unlit: false,
    };
    let spatial = PipelineSet {
        models: vec![ShadingModel::Ward, ShadingModel::Tabulated],
        unlit: false,
    };
    // The character pipelines; the spatial set adds the subsurface pass. Props add theirs
    // when they are loaded: one, and in the spatial set their two-target variant too.
    assert_eq!(count(&local), (2, false, 1));
    assert_eq!(count(&spatial), (2 + 1, true, 2));
}

/// Issue 34 item 3: a point light close to a flat skin (1–20 mm) through `preintegrated`'s
/// per-channel lifted light, on both acceptance materials.
#[test]
fn preintegrated_follows_close_point_lights() {
    let gpu = gpu();
    let mut probe = SceneRenderer::new(&gpu);
    for m in ground_truth::acceptance_materials() {
        let set = set(&m);
        for h in [2.0, 5.0, 20.0] {
            let entry = set
                .entry(&Scene::PointLight { h_mm: h })
                .expect("reference has the point light");
            let pre = render((&gpu, &mut probe), ShadingModel::Preintegrated, &m, entry);
            let p = metric::score(&pre, entry);
            println!(
                "{} h = {h} mm: preintegrated {:.3} {:?} (MC rel SE {:.3})",
                m.name, p.mean_log_all, p.mean_log, p.ref_rel_se_all
            );
            // Below the spatial-transport acceptance bound (0.10 over the reference's noise):
            // the channels' shared lifted cosine broke it at 2 mm on skin1 (red far too dark),
            // the median/√3 lift without the oblique shift or the fade scored 0.102 there
            // (white coat 0.087: the Poisson tail far too bright far out).
            assert!(
                p.mean_log_all <= tolerance(entry, 0.06),
                "{} h {h}: {p:?}",
                m.name
            );
        }
    }
}
