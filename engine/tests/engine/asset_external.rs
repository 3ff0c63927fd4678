//! Loads each third-party model and checks that counts are sensible and nothing is NaN.

use crate::external;

use dermis_engine::asset::{load_gltf, MAX_JOINTS};

#[test]
fn external_models_load_sensibly() {
    for name in external::EXTERNAL_MODELS {
        let Some(path) = external::external_model(name) else {
            continue;
        };
        let model = std::panic::catch_unwind(|| load_gltf(&path))
            .unwrap_or_else(|_| panic!("{name}: loader panicked"))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let verts: usize = model
            .meshes
            .iter()
            .flat_map(|m| &m.primitives)
            .map(|p| p.vertices.len())
            .sum();
        let joints: usize = model.skins.iter().map(|s| s.joints.len()).sum();
        eprintln!(
            "{name}: {} nodes, {} meshes, {verts} vertices, {} skins / {joints} joints, {} clips, \
             {} textures",
            model.nodes.len(),
            model.meshes.len(),
            model.skins.len(),
            model.animations.len(),
            model.textures.len()
        );
        assert!(model.source.contains(name.rsplit('/').next().unwrap()));
        assert!(verts >= 100, "{name}: {verts} vertices");
        assert!(!model.skins.is_empty(), "{name}: no skin");
        for s in &model.skins {
            assert!(s.joints.len() >= 2 && s.joints.len() <= MAX_JOINTS);
            assert_eq!(s.joints.len(), s.inverse_bind.len());
            assert!(s.inverse_bind.iter().all(|m| m.is_finite()));
        }
        assert!(!model.animations.is_empty(), "{name}: no clip");
        for c in &model.animations {
            assert!(
                c.duration > 0.0 && c.duration < 60.0,
                "{name}: duration {}",
                c.duration
            );
            assert!(!c.channels.is_empty());
        }
        assert!(!model.roots.is_empty());
        for p in model.meshes.iter().flat_map(|m| &m.primitives) {
            assert_eq!(p.indices.len() % 3, 0);
            assert!(p.indices.iter().all(|&i| (i as usize) < p.vertices.len()));
            for v in &p.vertices {
                let floats = v
                    .position
                    .iter()
                    .chain(&v.normal)
                    .chain(&v.tangent)
                    .chain(&v.uv);
                assert!(
                    floats.chain(&v.weights).all(|x| x.is_finite()),
                    "{name}: NaN"
                );
                let sum: f32 = v.weights.iter().sum();
                assert!((sum - 1.0).abs() < 1e-4, "{name}: weight sum {sum}");
                assert!((v.tangent[3].abs() - 1.0).abs() < 1e-6);
                assert!(v.thickness > 0.0);
            }
        }
        let (_, mesh, skin) = dermis_engine::anim::first_skinned_mesh(&model).unwrap();
        let max_joint = model.meshes[mesh]
            .primitives
            .iter()
            .flat_map(|p| &p.vertices)
            .flat_map(|v| v.joints)
            .max()
            .unwrap();
        assert!((max_joint as usize) < model.skins[skin].joints.len());
        for t in &model.textures {
            assert_eq!(t.rgba8().unwrap().len(), (t.width * t.height * 4) as usize);
        }
    }
}
