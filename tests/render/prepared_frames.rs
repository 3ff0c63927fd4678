//! A prepared frame is everything its encode reads: prepare A, prepare B, encode A draws A
//! (checked by pixels against A drawn alone), because every buffer `prepare` writes — the
//! frame uniform, the subject's joint palettes, the shadow caster's and the penumbra's
//! constants, the props' and blobs' instances, the UI's vertices — has one copy per frame
//! that may wait (`FRAMES_PREPARED`); and a frame whose copy a later one was prepared into
//! is refused with one line, not drawn with another frame's data.

use crate::common;

use common::Rig;
use dermis_engine::render::{RgbaImage, FRAMES_PREPARED};
use dermis_engine::scene::FramePacket;
use glam::{Mat4, Vec3};

const W: u32 = 320;
const H: u32 = 200;

/// Pixels whose colour differs by more than `by` in some channel.
fn differing(a: &RgbaImage, b: &RgbaImage, by: u8) -> usize {
    a.pixels
        .chunks(4)
        .zip(b.pixels.chunks(4))
        .filter(|(p, q)| (0..3).any(|k| p[k].abs_diff(q[k]) > by))
        .count()
}

/// Frame B: the runner a metre to the side and turned, seen from elsewhere, no props, no UI.
fn other(p: &mut FramePacket) {
    if let Some(s) = &mut p.subject {
        s.world =
            Mat4::from_translation(Vec3::new(0.8, 0.0, 0.3)) * Mat4::from_rotation_y(1.2) * s.world;
    }
    p.view.view_proj *= Mat4::from_rotation_y(0.25);
    p.props = &[];
    p.ui = &[];
}

#[test]
fn encoding_a_frame_draws_what_was_prepared_for_it() {
    const { assert!(FRAMES_PREPARED >= 2) };
    let mut rig = Rig::new(W, H);
    let scope = rig
        .gpu
        .device
        .push_error_scope(wgpu::ErrorFilter::Validation);
    // Half a second of the menu: the runner idling in the showroom, the menu's UI over it.
    for _ in 0..30 {
        rig.update(1.0 / 60.0);
    }
    // A alone, then B alone.
    rig.prepare(|_| {});
    let a_alone = rig.draw();
    rig.prepare(other);
    let b_alone = rig.draw();
    // A, then B, prepared; A encoded, then B.
    rig.prepare(|_| {});
    let a = rig.frame.expect("prepared");
    rig.prepare(other);
    let b = rig.frame.expect("prepared");
    let renderer = &rig.gg.renderer;
    renderer
        .draw_offscreen(&rig.gpu, &rig.target, &a)
        .unwrap_or_else(|e| panic!("{e}"));
    let a_after_b = rig.target.read(&rig.gpu);
    renderer
        .draw_offscreen(&rig.gpu, &rig.target, &b)
        .unwrap_or_else(|e| panic!("{e}"));
    let b_after = rig.target.read(&rig.gpu);
    let error = pollster::block_on(scope.pop());
    assert!(error.is_none(), "{error:?}");

    let n = (W * H) as usize;
    let apart = differing(&a_alone, &b_alone, 8);
    let a_moved = differing(&a_alone, &a_after_b, 1);
    let b_moved = differing(&b_alone, &b_after, 1);
    println!(
        "A and B differ in {apart} of {n} px; A encoded after B was prepared differs from A \
         alone in {a_moved} px, B in {b_moved} px"
    );
    // The two frames are far apart (else the check below could not fail) …
    assert!(apart > n / 10, "frames A and B look alike: {apart} px");
    // … and each draws what was prepared for it.
    assert_eq!(a_moved, 0, "frame A drew some of B");
    assert_eq!(b_moved, 0, "frame B changed");

    // Once as many frames were prepared after A as there are copies, A's buffers hold a later
    // frame's: its encode refuses it with one line.
    for _ in 0..FRAMES_PREPARED - 1 {
        rig.prepare(|_| {});
    }
    let stale = rig
        .gg
        .renderer
        .draw_offscreen(&rig.gpu, &rig.target, &a)
        .expect_err("a stale frame was encoded");
    assert!(stale.contains("stale") && !stale.contains('\n'), "{stale}");
    rig.gg
        .renderer
        .draw_offscreen(&rig.gpu, &rig.target, &rig.frame.expect("prepared"))
        .unwrap_or_else(|e| panic!("the latest frame: {e}"));
}
