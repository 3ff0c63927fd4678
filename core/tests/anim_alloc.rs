//! The per-frame animation path (apply/blend clip, world update, joint palette) must not
//! allocate once the pose exists.

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use dermis_core::anim::{first_skinned_mesh, joint_palette, Pose};
use dermis_core::asset::{load_gltf, MAX_JOINTS};
use glam::Mat4;

struct Counting;

thread_local! {
    static ALLOCS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCS.try_with(|a| a.set(a.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = ALLOCS.try_with(|a| a.set(a.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn animation_frame_does_not_allocate() {
    let mut models =
        vec![dermis_core::asset::load_gltf(&common::data_dir().join("skinned.glb")).unwrap()];
    for name in common::EXTERNAL_MODELS {
        if let Some(p) = common::external_model(name) {
            models.push(load_gltf(&p).unwrap());
        }
    }
    for model in &models {
        let (_, _, skin) = first_skinned_mesh(model).unwrap();
        let mut pose = Pose::new(model);
        let mut palette = vec![Mat4::IDENTITY; MAX_JOINTS];
        let before = ALLOCS.with(|a| a.get());
        for frame in 0..100 {
            let t = frame as f32 / 30.0;
            let clip = &model.animations[frame % model.animations.len()];
            pose.reset(model);
            pose.apply_clip(clip, t % clip.duration.max(1e-3));
            pose.blend_clip(&model.animations[0], t, 0.3);
            pose.update_world(model);
            joint_palette(model, skin, &pose, &mut palette);
        }
        let after = ALLOCS.with(|a| a.get());
        assert_eq!(
            after - before,
            0,
            "{}: {} allocations in 100 frames",
            model.source,
            after - before
        );
    }
}
