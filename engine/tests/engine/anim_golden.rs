//! Compares dermis's CPU skinning (`skin_positions`) with golden positions computed by an
//! independent implementation (three.js, tools/skin-golden) for every third-party model.

use crate::external;

use dermis_engine::anim::{first_skinned_mesh, skin_positions, Pose};
use dermis_engine::asset::load_gltf;
use serde_json::Value;

const TOLERANCE_M: f32 = 1e-4;

#[test]
fn skinning_matches_three_js_golden() {
    let mut checked = 0;
    for name in external::EXTERNAL_MODELS {
        let stem = name.rsplit('/').next().unwrap().trim_end_matches(".glb");
        let golden_path = external::data_dir().join(format!("golden/{stem}.json"));
        let golden: Value =
            serde_json::from_str(&std::fs::read_to_string(&golden_path).unwrap()).unwrap();
        let Some(path) = external::external_model(name) else {
            continue;
        };
        let model = load_gltf(&path).unwrap();
        let (node, mesh, _) = first_skinned_mesh(&model).unwrap();
        assert_eq!(golden["node"].as_u64().unwrap() as usize, node, "{name}");
        assert_eq!(golden["mesh"].as_u64().unwrap() as usize, mesh, "{name}");
        let clip = &model.animations[golden["clip"].as_u64().unwrap() as usize];
        let golden_duration = golden["clip_duration"].as_f64().unwrap() as f32;
        assert!(
            (clip.duration - golden_duration).abs() < 1e-5,
            "{name}: duration"
        );
        let mut pose = Pose::new(&model);
        let samples = golden["samples"].as_array().unwrap();
        assert!(samples.len() >= 4);
        for sample in samples {
            let t = sample["time"].as_f64().unwrap() as f32;
            pose.reset(&model);
            pose.apply_clip(clip, t);
            pose.update_world(&model);
            let positions = skin_positions(&model, mesh, &pose);
            assert_eq!(
                positions.len() as u64,
                golden["vertex_count"].as_u64().unwrap()
            );
            let verts = sample["vertices"].as_array().unwrap();
            assert!(verts.len() >= 50);
            let mut worst = 0.0f32;
            for v in verts {
                let i = v["index"].as_u64().unwrap() as usize;
                let p: Vec<f32> = v["position"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|x| x.as_f64().unwrap() as f32)
                    .collect();
                let d = (positions[i] - glam::Vec3::new(p[0], p[1], p[2])).length();
                worst = worst.max(d);
                assert!(
                    d <= TOLERANCE_M,
                    "{name} t={t} vertex {i}: dermis {:?} vs golden {p:?} (|d| = {d})",
                    positions[i]
                );
            }
            eprintln!(
                "{name} t={t}: worst difference {worst:e} m over {} vertices",
                verts.len()
            );
            checked += verts.len();
        }
    }
    eprintln!("{checked} vertex positions checked");
}
