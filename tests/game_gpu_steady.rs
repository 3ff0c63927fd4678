//! §4.3, measured on the real renderer: during play — the bot playing, the player switching
//! the shading model — no GPU object (buffer, texture, view, bind group, pipeline, shader,
//! sampler) is created, and wgpu's own allocations per frame do not grow over 1000 frames —
//! the menu's showroom showing the scanned head for a while in between (uploaded at load).
//! One test in its own binary, so the counting allocator sees only this thread's work.

use std::path::Path;

use dermis_core::app::{GameFrame, GameGpu, Session, Subject};
use dermis_core::game::Screen;
use dermis_core::render::{
    Clock, FrameDriver, Gpu, LiveObjects, Offscreen, Output, OFFSCREEN_FORMAT,
};
use dermis_core::scene::SceneAssets;
use dermis_core::shading::ShadingModel;

#[global_allocator]
static A: dermis_core::heap::Counting = dermis_core::heap::Counting;

#[test]
fn play_creates_nothing_and_wgpu_allocations_do_not_grow() {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    let assets = SceneAssets::load(&root, None).unwrap().with_head(&root);
    let (w, h) = (160, 90);
    let mut gg = GameGpu::new(&gpu, OFFSCREEN_FORMAT, &assets, ShadingModel::DEFAULT).unwrap();
    assert!(gg.has_head(), "the showroom's head did not load");
    let target = Offscreen::new(&gpu, w, h);
    let mut session = Session::new(&assets.character, 7, None, true);
    // From the first model in menu order, whatever the default: both measured windows below
    // then hold one screen-space model each, so their allocation counts compare.
    session.settings.set_shading_model(ShadingModel::ALL[0]);
    // The shells' frame driver, at a fixed step, waiting for the GPU after each frame.
    let mut driver = FrameDriver::new(Clock::Fixed(1.0 / 60.0))
        .with_alloc_counter(dermis_core::heap::allocations);
    driver.sync = true;
    let frames = 1000;
    let warm_up = 100;
    let mut live = None;
    let mut dermis_allocs = Vec::new();
    let mut wgpu_allocs = Vec::new();
    let mut head_frames = 0;
    for frame in 0..frames {
        // Back to the menu in the middle of a model's window (neither its first nor its last
        // measured frames), the showroom on the head until the bot starts the next run.
        if frame == 520 {
            session.game.to_main();
            session.gui.set_subject(Subject::Head);
        }
        // The player switches the model every 50 frames: pipelines exist already.
        if frame % 50 == 49 {
            let next = session.shading().next();
            session.settings.set_shading_model(next);
        }
        let times = GameFrame::new(&mut session, &mut gg, &assets.character)
            .run(&mut driver, &gpu, Output::Offscreen(&target))
            .unwrap();
        if frame > warm_up && session.shown_subject() == Subject::Head {
            head_frames += 1;
        }
        let a = times.allocs;
        let (a0, a1, a2) = (a.start, a.updated, a.submitted);
        if frame == warm_up {
            live = Some(LiveObjects::read(&gpu.device));
        } else if frame > warm_up {
            let now = LiveObjects::read(&gpu.device);
            assert_eq!(Some(now), live, "GPU objects changed at frame {frame}");
            dermis_allocs.push(a1 - a0);
            wgpu_allocs.push((session.shading(), a2 - a1));
        }
    }
    assert!(session.game.ticks() > 0 && ShadingModel::ALL.contains(&session.shading()));
    assert!(head_frames >= 20, "the head was shown {head_frames} frames");
    assert_eq!(session.game.screen(), Screen::Play);
    // dermis' own per-frame code: no heap allocation at all in steady state.
    let worst = dermis_allocs.iter().max().copied().unwrap_or(0);
    assert_eq!(worst, 0, "dermis allocated on some frame: max {worst}");
    // wgpu's allocations per encoder/pass/submit: constant for each model, not growing (the
    // models' frames differ: a screen-space model has two passes, a penumbra model the
    // penumbra map's passes).
    let median = |v: &[u64]| {
        let mut v = v.to_vec();
        v.sort_unstable();
        v[v.len() / 2]
    };
    for model in ShadingModel::ALL {
        let of: Vec<u64> = wgpu_allocs
            .iter()
            .filter(|(m, _)| *m == model)
            .map(|(_, a)| *a)
            .collect();
        if of.len() < 40 {
            continue;
        }
        let (first, last) = (median(&of[..20]), median(&of[of.len() - 20..]));
        println!(
            "{model}: wgpu allocations per frame: median {first} (first 20) vs {last} (last 20)"
        );
        assert!(
            last <= first + 2,
            "{model}: wgpu allocations per frame grew from {first} to {last}"
        );
    }
}
