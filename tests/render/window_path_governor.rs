//! The window's frame path, headless: the same [`GameFrame::run`] on the same interactive
//! [`FrameDriver`] the desktop window and the Android app use (wall clock, GPU-timed), into an
//! offscreen target instead of a surface (no winit). The session's governor schedules the
//! shading tier as the soak does: told that frames exceed the budget it steps the character
//! down to the cheaper tier, and back up once they fit again.

use std::path::Path;
use std::time::{Duration, Instant};

use dermis_engine::render::{FrameDriver, Gpu, Offscreen, Output, OFFSCREEN_FORMAT};
use dermis_engine::scene::SceneAssets;
use dermis_engine::shading::ShadingModel;
use dermis_game::app::{GameFrame, GameGpu, Session};

#[test]
fn the_window_path_changes_tier_under_a_simulated_budget() {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let assets =
        SceneAssets::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"), None).unwrap();
    let mut gg = GameGpu::new(&gpu, OFFSCREEN_FORMAT, &assets, ShadingModel::DEFAULT).unwrap();
    let target = Offscreen::new(&gpu, 160, 90);
    let mut session = Session::new(&assets.character, 5, None, true);
    session.settings.set_shading_model(ShadingModel::Oss);
    let mut driver = FrameDriver::interactive(&gpu);
    // Runs frames told they cost `cost_ms` until `done` holds (or `limit` of wall time).
    let mut run =
        |session: &mut Session, cost_ms: f64, limit: Duration, done: &dyn Fn(&Session) -> bool| {
            let t0 = Instant::now();
            let mut frames = 0;
            while t0.elapsed() < limit {
                let mut frame = GameFrame::new(session, &mut gg, &assets.character);
                frame.simulated_cost_ms = Some(cost_ms);
                frame
                    .run(&mut driver, &gpu, Output::Offscreen(&target))
                    .unwrap();
                frames += 1;
                if done(session) {
                    return Some(frames);
                }
            }
            None
        };
    // Within budget, the character in view and lit: the chosen model.
    run(&mut session, 1.0, Duration::from_millis(500), &|_| false);
    assert_eq!(
        session.governor.tiers().as_slice(),
        [ShadingModel::Oss, ShadingModel::Ward]
    );
    assert_eq!(session.tier(), 0, "needs {:?}", session.needs);
    assert_eq!(session.draw_set().shading, Some(ShadingModel::Oss));
    assert_eq!(session.governor.changes(), 0);
    // 40 ms frames against the 16.7 ms budget: one step down after the 1 s window.
    let down = run(&mut session, 40.0, Duration::from_secs(20), &|s| {
        s.tier() == 1
    });
    assert!(
        down.is_some(),
        "no step down; governor {:?}",
        session.governor
    );
    assert_eq!(session.governor.budget_tier(), 1);
    assert_eq!(session.drawn_model(), ShadingModel::Ward);
    assert_eq!(session.draw_set().shading, Some(ShadingModel::Ward));
    // The player's choice is untouched; frames that fit again bring the chosen model back.
    assert_eq!(session.shading(), ShadingModel::Oss);
    let up = run(&mut session, 1.0, Duration::from_secs(30), &|s| {
        s.tier() == 0
    });
    assert!(up.is_some(), "no step up; governor {:?}", session.governor);
    assert_eq!(session.governor.changes(), 2);
    assert_eq!(session.draw_set().shading, Some(ShadingModel::Oss));
}
