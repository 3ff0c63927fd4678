//! The per-frame animation path (apply/blend clip, world update, joint palette) must not
//! allocate once the pose exists.

use crate::external;

use dermis_engine::anim::{first_skinned_mesh, joint_palette, Pose};
use dermis_engine::asset::{load_gltf, MAX_JOINTS};
use glam::Mat4;

#[test]
fn animation_frame_does_not_allocate() {
    let _shared = crate::shared();
    let mut models =
        vec![dermis_engine::asset::load_gltf(&external::data_dir().join("skinned.glb")).unwrap()];
    for name in external::EXTERNAL_MODELS {
        if let Some(p) = external::external_model(name) {
            models.push(load_gltf(&p).unwrap());
        }
    }
    for model in &models {
        let (_, _, skin) = first_skinned_mesh(model).unwrap();
        let mut pose = Pose::new(model);
        let mut palette = vec![Mat4::IDENTITY; MAX_JOINTS];
        let before = crate::thread_allocations();
        for frame in 0..100 {
            let t = frame as f32 / 30.0;
            let clip = &model.animations[frame % model.animations.len()];
            pose.reset(model);
            pose.apply_clip(clip, t % clip.duration.max(1e-3));
            pose.blend_clip(&model.animations[0], t, 0.3);
            pose.update_world(model);
            joint_palette(model, skin, &pose, &mut palette);
        }
        let after = crate::thread_allocations();
        assert_eq!(
            after - before,
            0,
            "{}: {} allocations in 100 frames",
            model.source,
            after - before
        );
    }
}
