//! The scanned head and its ground truth (`tools/reference/face/`, the project's Monte Carlo on
//! the head mesh): the exported scene is the engine's (mesh in metres, the material's
//! coefficients), the cached truth was computed for exactly this scene (a changed scene, light
//! or a corrupt file is refused with one line), a tiny truth computed now agrees with the cache
//! within its noise and does not depend on the thread count, `render --hdr` is linear
//! radiance, and the face score of a black or doubled image is what it must be.

use std::path::{Path, PathBuf};
use std::process::Command;

use dermis_engine::asset::head;
use dermis_engine::render::pfm::FloatImage;
use dermis_engine::render::Gpu;
use dermis_engine::scene::face::{self, FaceLight};
use dermis_engine::shading::{material::SKIN1, ShadingModel};
use dermis_measure::face::export::{SceneJson, WeldedMesh};
use dermis_measure::face::render::HeadRenderer;
use dermis_measure::face::score::{CAP, MAX_REL_SE, WIDE_REL_SE};
use dermis_measure::face::truth::{self, FaceScene, TruthRun};
use dermis_measure::face::truth_cache;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn cache_dir() -> PathBuf {
    root().join("tools/reference/face")
}

fn assets() -> PathBuf {
    root().join("assets")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("dermis-face-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn exported_scene_is_the_engines_head_in_metres_with_the_materials_coefficients() {
    let model = head::load(&assets(), false).unwrap();
    let dir = tmp("export");
    dermis_measure::face::export::write(&dir, &model, &SKIN1).unwrap();
    // The mesh: closed, outward, and a real head's size in metres.
    let mesh = WeldedMesh::from_ply(&std::fs::read(dir.join("head.ply")).unwrap()).unwrap();
    assert_eq!(mesh, WeldedMesh::from_model(&model).unwrap());
    assert_eq!(mesh.open_and_nonmanifold_edges(), (0, 0));
    assert!(mesh.volume() > 0.0);
    let ears = mesh
        .positions
        .iter()
        .filter(|p| (0.03..0.06).contains(&p.y))
        .map(|p| p.x.abs())
        .fold(0f32, f32::max);
    assert!((0.07..0.085).contains(&ears), "ear half-width {ears} m");
    // The material: skin1's σ_a, σ_s = σ'_s/(1 − g), g, η.
    let scene: SceneJson =
        serde_json::from_slice(&std::fs::read(dir.join("scene.json")).unwrap()).unwrap();
    assert_eq!(scene.medium.sigma_a_per_mm, SKIN1.sigma_a);
    assert_eq!(scene.medium.sigma_s_per_mm, SKIN1.sigma_s_prime);
    assert_eq!((scene.medium.g, scene.medium.eta), (SKIN1.g, SKIN1.eta));
    assert_eq!(scene.lights.len(), 3);
    assert_eq!(
        scene.lights[1].position,
        FaceLight::Side.position().to_array()
    );
    // The truth's mesh is this one.
    let face = FaceScene::head(&assets()).unwrap();
    assert_eq!(face.mesh, mesh);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_cached_truth_is_this_scenes_and_precise_and_a_changed_scene_is_refused() {
    let scene = FaceScene::head(&assets()).unwrap();
    let truths = truth_cache::load_named(&cache_dir(), &scene).unwrap();
    assert_eq!(truths.len(), 3);
    for (light, t) in &truths {
        let r = &t.reference;
        let rel = r.relative_errors();
        println!(
            "{}: {} scored block channels, relative SE median {:.4}",
            light.name(),
            rel.len(),
            rel[rel.len() / 2]
        );
        // Front and side light most of what the camera sees; the back light only a grazing
        // strip beside the ear, whose blocks reach the bar only with many more photons.
        let want = if *light == FaceLight::Back { 1 } else { 300 };
        assert!(
            rel.len() >= want,
            "{}: {} block channels",
            light.name(),
            rel.len()
        );
        assert!(rel.iter().all(|&e| e <= MAX_REL_SE as f64));
        // Every photon is accounted for: next to nothing lost through the mesh's cracks (a few
        // photons in 10⁷), the books balance.
        for e in &t.record.energy {
            assert!(e.lost[0] < 1e-5 * e.incident[0], "{e:?}");
            let books = e.specular[0] + e.escaped[0] + e.absorbed[0] + e.capped[0];
            let se = e.escaped[1] + e.absorbed[1] + e.specular[1];
            assert!((books - e.incident[0]).abs() < 5.0 * se + 1e-9, "{e:?}");
        }
    }
    // Another material, another light position: refused, with how to regenerate.
    let mut other = scene.clone();
    other.material.eta = 1.4;
    let e = truth_cache::load_named(&cache_dir(), &other).err().unwrap();
    assert!(
        e.contains("another scene") && e.contains("dermis reference"),
        "{e}"
    );
    let moved = FaceLight::Front.position() + glam::Vec3::X * 0.01;
    let e = truth_cache::load(&cache_dir(), &scene, "front", moved, 1.0)
        .err()
        .unwrap();
    assert!(e.contains("another scene") && !e.contains('\n'), "{e}");
    // A corrupt image or index: one line, no panic.
    let dir = tmp("corrupt");
    for e in std::fs::read_dir(cache_dir()).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, dir.join(p.file_name().unwrap())).unwrap();
    }
    let bytes = std::fs::read(dir.join("side.pfm")).unwrap();
    std::fs::write(dir.join("side.pfm"), &bytes[..bytes.len() / 2]).unwrap();
    let e = truth_cache::load_named(&dir, &scene).err().unwrap();
    assert!(e.contains("side") && !e.contains('\n'), "{e}");
    std::fs::write(dir.join("truth.json"), "{ not json").unwrap();
    let e = truth_cache::load_named(&dir, &scene).err().unwrap();
    assert!(e.contains("truth.json") && !e.contains('\n'), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_small_truth_agrees_with_the_cache_and_does_not_depend_on_threads() {
    let scene = FaceScene::head(&assets()).unwrap();
    let mesh = scene.closed_mesh().unwrap();
    let light = FaceLight::Side.position();
    let small = |threads| {
        let run = TruthRun {
            photons: 8192,
            seed: 11,
            threads,
        };
        truth::compute(&scene, &mesh, "side", light, 1.0, &run, &mut |_, _| {}).unwrap()
    };
    let (one, two) = (small(1), small(2));
    assert_eq!(one.radiance, two.radiance);
    assert_eq!(one.std_err, two.std_err);
    assert_eq!(one.record.scene_fnv1a64, scene.hash(light, 1.0));
    let cached = truth_cache::load(&cache_dir(), &scene, "side", light, 1.0).unwrap();
    // The radiance summed over the head: the small run against the cache, within its noise.
    for c in 0..3 {
        let (mut s, mut v, mut want) = (0f64, 0f64, 0f64);
        for ((p, e), q) in one
            .radiance
            .pixels
            .iter()
            .zip(&one.std_err.pixels)
            .zip(&cached.radiance.pixels)
        {
            assert!(p[c].is_finite() && p[c] >= 0.0);
            s += p[c] as f64;
            v += (e[c] as f64).powi(2);
            want += q[c] as f64;
        }
        let z = (s - want).abs() / v.sqrt();
        println!(
            "channel {c}: small {s:.2} ± {:.2}, cached {want:.2}, z {z:.2}",
            v.sqrt()
        );
        assert!(
            s > 0.0 && z < 5.0,
            "channel {c}: {s} vs the cache's {want} (z {z:.1})"
        );
    }
}

#[test]
fn face_score_of_black_doubled_and_the_truth_itself() {
    let scene = FaceScene::head(&assets()).unwrap();
    for (_, t) in truth_cache::load_named(&cache_dir(), &scene).unwrap() {
        let r = &t.reference;
        let f = &r.full;
        let scaled = |k: f32| FloatImage {
            pixels: f.pixels.iter().map(|p| p.map(|c| c * k)).collect(),
            ..f.clone()
        };
        let own = r.score(f).unwrap();
        assert!(own.mean_abs_ln < 1e-6, "{own:?}");
        let d = r.score(&scaled(2.0)).unwrap();
        assert!((d.mean_abs_ln - 2f64.ln()).abs() < 1e-5, "{d:?}");
        assert_eq!(r.score(&scaled(0.0)).unwrap().mean_abs_ln, CAP);
    }
}

#[test]
fn the_truths_coverage_is_where_the_renderer_draws_the_head() {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let model = head::load(&assets(), false).unwrap();
    let alpha = truth_cache::load_alpha(&cache_dir()).unwrap();
    let n = (alpha.len() as f64).sqrt() as u32;
    let mut r = HeadRenderer::new(&gpu, &model, &SKIN1, n, n, true).unwrap();
    let lit = r
        .radiance(
            &gpu,
            ShadingModel::Ward,
            &face::camera(),
            FaceLight::Front.position(),
            1.0,
        )
        .unwrap();
    // Every pixel the renderer lights the truth's camera sees wholly or in part; the head's
    // inside pixels are lit in the main (the front light reaches most of what the camera sees).
    let (mut inside, mut lit_inside, mut stray) = (0, 0, 0);
    for (p, a) in lit.iter().zip(&alpha) {
        let on = p.iter().any(|c| *c > 0.0);
        if *a >= 0.999 {
            inside += 1;
            lit_inside += usize::from(on);
        } else if *a == 0.0 && on {
            stray += 1;
        }
    }
    println!("{inside} covered pixels, {lit_inside} lit, {stray} lit outside the head");
    assert_eq!(stray, 0);
    assert!(inside > 4000 && lit_inside * 10 > inside * 7);
}

#[test]
fn reference_refuses_a_light_inside_the_head_before_any_work() {
    let dir = tmp("inside");
    let out = Command::new(env!("CARGO_BIN_EXE_dermis"))
        .args([
            "reference",
            "--scene",
            "head",
            "--light",
            "0,0.05,0.01",
            "--out",
        ])
        .arg(dir.join("out"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("inside the head"), "{err}");
    assert!(out.stdout.is_empty());
    assert!(std::fs::read_dir(dir.join("out")).map_or(true, |mut d| d.next().is_none()));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn hdr_radiance_is_linear_in_the_light() {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let model = head::load(&assets(), false).unwrap();
    let mut r = HeadRenderer::new(&gpu, &model, &SKIN1, 96, 96, true).unwrap();
    let cam = face::camera();
    for shading in [ShadingModel::Ward, ShadingModel::Tabulated] {
        let pos = FaceLight::Front.position();
        let one = r.radiance(&gpu, shading, &cam, pos, 1.0).unwrap();
        let two = r.radiance(&gpu, shading, &cam, pos, 2.0).unwrap();
        let (mut lit, mut worst) = (0, 0f32);
        for (a, b) in one.iter().zip(&two) {
            for c in 0..3 {
                if a[c] > 1e-3 {
                    lit += 1;
                    worst = worst.max((b[c] / a[c] - 2.0).abs());
                } else {
                    assert!(b[c] < 4e-3);
                }
            }
        }
        assert!(lit > 3000, "{shading}: {lit} lit pixel channels");
        // f16 targets: 2⁻¹⁰ relative rounding on each.
        assert!(worst < 4e-3, "{shading}: doubled light gives ×2 ± {worst}");
    }
}

#[test]
fn the_heads_uvs_are_v_down_like_its_maps() {
    // The albedo has the face upright: the crown along the top rows, the nose tip ~40 % down.
    let maps = head::Maps {
        albedo: false,
        normal: false,
    };
    let model = head::load_with(&assets(), maps).unwrap();
    let vs = &model.meshes[0].primitives[0].vertices;
    let top = |axis: usize| {
        vs.iter()
            .max_by(|a, b| a.position[axis].total_cmp(&b.position[axis]))
            .unwrap()
    };
    let (crown, nose) = (top(1), top(2));
    assert!(crown.uv[1] < 0.05, "crown at v {}", crown.uv[1]);
    assert!(
        (0.3..0.45).contains(&nose.uv[1]),
        "nose tip at v {}",
        nose.uv[1]
    );
    // Tangents generated for these UVs: unit, perpendicular to the normal, ±1 handedness.
    for v in vs.iter().step_by(97) {
        let t = glam::Vec3::from_slice(&v.tangent[..3]);
        let n = glam::Vec3::from_array(v.normal).normalize();
        assert!((t.length() - 1.0).abs() < 1e-3 && t.dot(n).abs() < 1e-3);
        assert!(v.tangent[3].abs() == 1.0);
    }
}

#[test]
fn the_normal_map_changes_the_heads_skin_and_both_stay_finite() {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let maps = |normal| head::Maps {
        albedo: false,
        normal,
    };
    let with = head::load_with(&assets(), maps(true)).unwrap();
    let without = head::load_with(&assets(), maps(false)).unwrap();
    assert!(with.materials[0].normal_texture.is_some());
    assert!(without.materials[0].normal_texture.is_none());
    let (w, h) = (160, 160);
    let mut rw = HeadRenderer::new(&gpu, &with, &SKIN1, w, h, true).unwrap();
    let mut ro = HeadRenderer::new(&gpu, &without, &SKIN1, w, h, true).unwrap();
    let cam = face::camera();
    for shading in [ShadingModel::Preintegrated, ShadingModel::Ward] {
        for light in [FaceLight::Front, FaceLight::Side] {
            let pos = light.position();
            let a = rw.radiance(&gpu, shading, &cam, pos, 1.0).unwrap();
            let b = ro.radiance(&gpu, shading, &cam, pos, 1.0).unwrap();
            for img in [&a, &b] {
                let bad = img
                    .iter()
                    .filter(|p| p.iter().any(|c| !c.is_finite() || *c < 0.0))
                    .count();
                assert_eq!(
                    bad, 0,
                    "{shading} {light:?}: {bad} pixels not finite or negative"
                );
            }
            // Skin lit in both: the mapped normals move its radiance pixel by pixel, and
            // leave the head's total about where it was.
            let (mut n, mut sum_ln, mut moved) = (0usize, 0f64, 0usize);
            let (mut ta, mut tb) = (0f64, 0f64);
            for (p, q) in a.iter().zip(&b) {
                ta += p[0] as f64;
                tb += q[0] as f64;
                if p[0] > 1e-3 && q[0] > 1e-3 {
                    let d = (p[0] as f64 / q[0] as f64).ln().abs();
                    n += 1;
                    sum_ln += d;
                    moved += usize::from(d > 0.02);
                }
            }
            let mean = sum_ln / n.max(1) as f64;
            println!(
                "{shading} {light:?}: {n} lit px, mean |ln(with/without)| {mean:.4}, \
                 {moved} px moved > 2 %, totals {:.3}",
                ta / tb
            );
            assert!(n > 2000, "{shading} {light:?}: {n} lit pixels");
            assert!(
                mean > 0.01 && moved > n / 10,
                "{shading} {light:?}: the normal map changes little (mean {mean:.4}, {moved} px)"
            );
            assert!(
                (0.85..1.15).contains(&(ta / tb)),
                "{shading} {light:?}: the normal map moved the head's total by {:.3}",
                ta / tb
            );
        }
    }
}

#[test]
fn render_head_writes_hdr_and_png() {
    let dir = tmp("cli");
    let (png, pfm) = (dir.join("head.png"), dir.join("head.pfm"));
    let out = Command::new(env!("CARGO_BIN_EXE_dermis"))
        .args([
            "render",
            "--scene",
            "head",
            "--size",
            "64x64",
            "--shading",
            "ward",
        ])
        .args(["--face-light", "side", "--out"])
        .arg(&png)
        .arg("--hdr")
        .arg(&pfm)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("Lee Perry-Smith"));
    let img = FloatImage::load(&pfm).unwrap();
    assert_eq!((img.width, img.height), (64, 64));
    // Black background in the corners, radiance on the head.
    assert_eq!(img.pixels[0], [0.0; 3]);
    assert!(img.pixels.iter().filter(|p| p[0] > 0.01).count() > 500);
    assert!(png.is_file());
    let bad = Command::new(env!("CARGO_BIN_EXE_dermis"))
        .args(["render", "--scene", "head", "--hdr"])
        .arg(dir.join("x.exr"))
        .output()
        .unwrap();
    assert!(!bad.status.success());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_light_the_head_returns_to_itself_brings_its_shadows_toward_the_truth() {
    // Every local model leaves a cast shadow black where the truth holds light that left the
    // skin and came back to it (asset::bounce): with the head's own returned light,
    // `preintegrated` is nearer the truth on the wide bar (the shadows, the sockets, the
    // terminator) under every named light than with it zeroed.
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let with = head::load(&assets(), false).unwrap();
    let vs = &with.meshes[0].primitives[0].vertices;
    let seen = vs.iter().map(|v| v.bounce[3] as f64).sum::<f64>() / vs.len() as f64;
    assert!((0.05..0.5).contains(&seen), "mean self view factor {seen}");
    let mut without = with.clone();
    for p in &mut without.meshes[0].primitives {
        for v in &mut p.vertices {
            v.bounce = [0.0; 4];
        }
    }
    let scene = FaceScene::head(&assets()).unwrap();
    let (w, h) = (scene.width, scene.height);
    let mut rw = HeadRenderer::new(&gpu, &with, &SKIN1, w, h, true).unwrap();
    let mut ro = HeadRenderer::new(&gpu, &without, &SKIN1, w, h, true).unwrap();
    let cam = face::camera();
    for (light, t) in truth_cache::load_named(&cache_dir(), &scene).unwrap() {
        let position = light.position();
        let wide = t.reference.clone().with_max_rel_se(WIDE_REL_SE);
        let score = |r: &mut HeadRenderer| {
            let shading = ShadingModel::Preintegrated;
            let px = r
                .radiance(&gpu, shading, &cam, position, t.record.intensity)
                .unwrap();
            wide.score(&FloatImage::new(w, h, px).unwrap())
                .unwrap()
                .mean_abs_ln
        };
        let (a, b) = (score(&mut rw), score(&mut ro));
        println!(
            "{}: wide {a:.3} with the returned light, {b:.3} without",
            t.record.name
        );
        assert!(a < b, "{}: {a} with, {b} without", t.record.name);
    }
}
