//! The Android lifecycle state machine (core::lifecycle) driven on the desktop with real GPU
//! objects: 1000 pause / resume / window-loss / resize cycles, each action recreating or
//! resizing real render targets, render a frame into them, and leave wgpu's live-object
//! counts exactly where they started. Window surfaces: `surfaces_under_xvfb`.

use std::path::Path;
use std::process::Command;

use dermis_engine::render::{
    Clock, FrameDriver, FrameStatus, Gpu, LiveObjects, Offscreen, Output, OFFSCREEN_FORMAT,
};
use dermis_engine::scene::SceneAssets;
use dermis_engine::shading::ShadingModel;
use dermis_game::app::{GameFrame, GameGpu, Session};
use dermis_game::lifecycle::{Action, Event, Lifecycle};

#[test]
fn a_thousand_lifecycle_cycles_leak_no_gpu_object() {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let assets =
        SceneAssets::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"), None).unwrap();
    // Device, pipelines and scene live across the whole run, as on a phone.
    let mut gg = GameGpu::new(&gpu, OFFSCREEN_FORMAT, &assets, ShadingModel::DEFAULT).unwrap();
    let mut session = Session::new(&assets.character, 3, None, true);
    // The "window surface": an offscreen colour texture (created on CreateSurface, resized
    // on Reconfigure, dropped on DropSurface) with its MSAA colour and depth targets.
    let mut life = Lifecycle::new();
    let mut targets: Option<Offscreen> = None;
    let apply = |actions: Vec<Action>, targets: &mut Option<Offscreen>| {
        for a in actions {
            match a {
                Action::CreateSurface { width, height }
                | Action::RecreateSurface { width, height }
                | Action::Reconfigure { width, height } => {
                    *targets = Some(Offscreen::new(&gpu, width, height));
                }
                Action::DropSurface => *targets = None,
                _ => {}
            }
        }
    };
    for e in [
        Event::Start,
        Event::Resume,
        Event::InitWindow {
            width: 64,
            height: 48,
        },
        Event::GainedFocus,
    ] {
        apply(life.handle(e), &mut targets);
    }
    // The game's own frame, as the shells run it.
    let mut driver = FrameDriver::new(Clock::Fixed(1.0 / 60.0));
    let mut frame = |targets: &Option<Offscreen>, session: &mut Session, gg: &mut GameGpu| {
        let Some(out) = targets else { return };
        let mut game = GameFrame::new(session, gg, &assets.character);
        game.run(&mut driver, &gpu, Output::Offscreen(out))
            .unwrap_or_else(|s| panic!("frame not drawn: {s:?}"));
    };
    frame(&targets, &mut session, &mut gg);
    gg.finish_loading(&gpu);
    gpu.wait();
    let before = LiveObjects::read(&gpu.device);
    let page = dermis_engine::heap::page_bytes();
    let rss_before = dermis_engine::heap::resident_mb(page);
    let mut rendered = 0;
    for i in 0..1000u32 {
        let (w, h) = (32 + (i * 7) % 64, 24 + (i * 5) % 48);
        let events: &[Event] = match i % 4 {
            0 => &[
                Event::LostFocus,
                Event::Pause,
                Event::Resume,
                Event::GainedFocus,
            ],
            1 => &[Event::Resized {
                width: w,
                height: h,
            }],
            2 => &[
                Event::Pause,
                Event::TermWindow,
                Event::Stop,
                Event::Start,
                Event::Resume,
                Event::InitWindow {
                    width: h,
                    height: w,
                },
            ],
            _ => &[Event::Resized {
                width: h,
                height: w,
            }],
        };
        for &e in events {
            apply(life.handle(e), &mut targets);
        }
        if let Some(a) = life.frame(FrameStatus::Presented) {
            apply(vec![a], &mut targets);
        }
        // Targets are recreated on every cycle; a frame is rendered into them every 10th.
        if life.should_render() && i % 10 == 0 {
            frame(&targets, &mut session, &mut gg);
            rendered += 1;
        }
        if i % 50 == 49 {
            gpu.wait();
        }
    }
    gpu.wait();
    assert!(rendered >= 90, "only {rendered} frames rendered");
    let after = LiveObjects::read(&gpu.device);
    // Resident memory is reported, not asserted (allocator and driver caches vary).
    let rss_after = dermis_engine::heap::resident_mb(page);
    println!("resident memory: {rss_before:?} MiB before, {rss_after:?} MiB after 1000 cycles");
    assert_eq!(
        before, after,
        "GPU objects leaked over 1000 lifecycle cycles"
    );
}

/// 50 real window surfaces created, presented to and dropped under Xvfb, with wgpu's
/// live-object counts equal before and after (the `dermis` binary's hidden self-test).
#[test]
fn surfaces_under_xvfb() {
    if Command::new("xvfb-run").arg("--help").output().is_err() {
        if std::env::var("CI").is_ok_and(|v| v == "true") {
            panic!("xvfb-run is required in CI (apt: xvfb xauth)");
        }
        eprintln!("skipping: xvfb-run not installed");
        return;
    }
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 800x600x24"])
        .arg(env!("CARGO_BIN_EXE_dermis"))
        .args(["surfaces", "--count", "50"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    assert_eq!(report["surfaces"], 50);
    assert_eq!(report["presented"], 50);
    let (before, after) = (&report["before"], &report["after"]);
    for kind in [
        "buffers",
        "texture_views",
        "bind_groups",
        "render_pipelines",
        "shader_modules",
        "samplers",
    ] {
        assert_eq!(before[kind], after[kind], "{kind}: {report}");
    }
}
