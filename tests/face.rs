//! The scanned head and its path-traced references (`tools/mitsuba/face/`): the exported
//! scene is the engine's (mesh in metres, the material's coefficients), the cached references
//! were rendered from exactly those files, `render --hdr` is linear radiance, and the face
//! score of a black or doubled image is what it must be.

use std::path::{Path, PathBuf};
use std::process::Command;

use dermis_core::face::head::{self, FaceLight, HeadRenderer};
use dermis_core::face::pfm::FloatImage;
use dermis_core::render::Gpu;
use dermis_core::shading::{material::SKIN1, ShadingModel};
use dermis_measure::face::cache::Cache;
use dermis_measure::face::export::{SceneJson, WeldedMesh};
use dermis_measure::face::score::CAP;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn cache_dir() -> PathBuf {
    root().join("tools/mitsuba/face")
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
    // The committed scene the references were rendered from is this export, byte for byte.
    for name in ["head.ply", "scene.json"] {
        assert!(
            std::fs::read(dir.join(name)).unwrap()
                == std::fs::read(cache_dir().join(name)).unwrap(),
            "tools/mitsuba/face/{name} is not what the engine exports now: re-export and re-render"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cached_references_match_their_scene_files() {
    let cache = Cache::load(&cache_dir()).unwrap();
    assert_eq!(cache.references.len(), 3);
    assert!(cache.record.mitsuba.starts_with("3.9"));
    for (light, r) in &cache.references {
        let scored = r.mask.iter().flatten().filter(|k| **k).count();
        assert!(scored >= 50, "{}: {scored} block channels", light.name());
        assert!(r.relative_noise() < 0.2, "{}", light.name());
    }
    // A scene file that is not the rendered one is refused.
    let dir = tmp("stale");
    for e in std::fs::read_dir(cache_dir()).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, dir.join(p.file_name().unwrap())).unwrap();
    }
    let scene = std::fs::read_to_string(dir.join("scene.json")).unwrap();
    std::fs::write(dir.join("scene.json"), scene.replace("1.3", "1.4")).unwrap();
    let e = Cache::load(&dir).err().unwrap();
    assert!(e.contains("scene.json") && e.contains("re-render"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn face_score_of_black_doubled_and_the_reference_itself() {
    let cache = Cache::load(&cache_dir()).unwrap();
    for (_, r) in &cache.references {
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
fn hdr_radiance_is_linear_in_the_light() {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let model = head::load(&assets(), false).unwrap();
    let mut r = HeadRenderer::new(&gpu, &model, &SKIN1, 96, 96, true).unwrap();
    let cam = head::camera();
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
    let cam = head::camera();
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
