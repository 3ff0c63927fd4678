//! §4.3, measured on the real renderer over the whole frame the game runs — update, upload
//! (the renderer's prepare) and encode, through the shells' frame driver: during play — the
//! bot playing, the player switching the shading model — no GPU object (buffer, texture, view,
//! bind group, pipeline, shader, sampler) is created, dermis' own code allocates nothing, and
//! wgpu's own allocations per frame do not grow over 1000 frames — the menu's showroom showing
//! the scanned head for a while in between (uploaded at load).
//!
//! Whose an allocation is: the update step is dermis' alone (counted); upload and encode call
//! into wgpu, which allocates inside its encoder, passes and submit, so each of their
//! allocations in sampled frames is attributed by its backtrace — to the innermost frame
//! outside the standard library: dermis' (`dermis_engine::`, `dermis_game::`, `dermis::`) or not.
//! It reads the process-wide counts, so it runs alone in its binary ([`crate::exclusive`]).

use std::cell::Cell;
use std::path::Path;
use std::sync::Mutex;

use dermis_engine::render::{
    Clock, FrameDriver, Gpu, LiveObjects, Offscreen, Output, OFFSCREEN_FORMAT,
};
use dermis_engine::scene::SceneAssets;
use dermis_engine::shading::ShadingModel;
use dermis_game::app::{GameFrame, GameGpu, Session, Subject};
use dermis_game::rules::Screen;

thread_local! {
    static WATCHED: Cell<bool> = const { Cell::new(false) };
    static CAPTURING: Cell<bool> = const { Cell::new(false) };
}

/// The allocations attributed to dermis' code (the frame that made each one), and how many
/// were not.
static OURS: Mutex<Vec<String>> = Mutex::new(Vec::new());
static THEIRS: Mutex<u64> = Mutex::new(0);

/// The innermost frame of `trace` (std's `Debug` form) outside the standard library and this
/// allocator, as its function's path.
fn allocating_frame(trace: &str) -> Option<String> {
    let std_paths = [
        "std::",
        "core::",
        "alloc::",
        "__rust",
        "<alloc::",
        "<core::",
        "<std::",
        "hashbrown::",
        "<hashbrown::",
        "allocs::",
        "<allocs::",
        "dermis_engine::heap::",
        "<dermis_engine::heap::",
    ];
    trace
        .split("fn: \"")
        .skip(1)
        .filter_map(|s| s.split('"').next())
        .find(|f| !std_paths.iter().any(|p| f.starts_with(p)))
        .map(str::to_string)
}

fn attribute() {
    let trace = format!("{:?}", std::backtrace::Backtrace::force_capture());
    match allocating_frame(&trace) {
        Some(f) if f.trim_start_matches('<').starts_with("dermis") => {
            OURS.lock().unwrap_or_else(|e| e.into_inner()).push(f);
        }
        _ => *THEIRS.lock().unwrap_or_else(|e| e.into_inner()) += 1,
    }
}

/// Runs `attribute` for an allocation on a watched thread (not for those it makes itself):
/// the binary's allocator calls it for every allocation.
pub fn watch() {
    if WATCHED.with(Cell::get) && !CAPTURING.with(Cell::get) {
        CAPTURING.with(|c| c.set(true));
        attribute();
        CAPTURING.with(|c| c.set(false));
    }
}

#[test]
fn the_whole_game_frame_allocates_nothing_of_its_own_and_play_creates_nothing() {
    let _alone = crate::exclusive();
    // wgpu's debug builds trace their locks with `Backtrace::capture` when backtraces are on
    // (RUST_BACKTRACE): its captures would allocate inside std's backtrace lock, where the
    // attribution's own capture would wait for it. Library backtraces off (before any is
    // taken); the attribution's `force_capture` ignores the setting.
    std::env::set_var("RUST_LIB_BACKTRACE", "0");
    attribution_reads_backtraces();
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets");
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
        .with_alloc_counter(dermis_engine::heap::allocations);
    driver.sync = true;
    let frames = 1000;
    let warm_up = 100;
    let mut live = None;
    let mut update_allocs = Vec::new();
    let mut wgpu_allocs = Vec::new();
    let mut head_frames = 0;
    let mut watched = 0;
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
        // Every 17th frame after the warm-up (every model, the menu and play among them), the
        // whole frame's allocations are attributed.
        let watch = frame > warm_up && frame % 17 == 0;
        WATCHED.with(|c| c.set(watch));
        let times = GameFrame::new(&mut session, &mut gg, &assets.character)
            .run(&mut driver, &gpu, Output::Offscreen(&target))
            .unwrap();
        WATCHED.with(|c| c.set(false));
        watched += usize::from(watch);
        if frame > warm_up && session.shown_subject() == Subject::Head {
            head_frames += 1;
        }
        let a = times.allocs;
        if frame == warm_up {
            live = Some(LiveObjects::read(&gpu.device));
        } else if frame > warm_up {
            let now = LiveObjects::read(&gpu.device);
            assert_eq!(Some(now), live, "GPU objects changed at frame {frame}");
            if !watch {
                update_allocs.push(a.updated - a.start);
                // By the model drawn (the governor's tier, which the frame's passes follow).
                wgpu_allocs.push((session.drawn_model(), a.submitted - a.updated));
            }
        }
    }
    assert!(session.game.ticks() > 0 && ShadingModel::ALL.contains(&session.shading()));
    assert!(head_frames >= 20, "the head was shown {head_frames} frames");
    assert_eq!(session.game.screen(), Screen::Play);
    // The update step: no heap allocation at all in steady state.
    let worst = update_allocs.iter().max().copied().unwrap_or(0);
    assert_eq!(worst, 0, "the update allocated on some frame: max {worst}");
    // Upload and encode: every allocation in the watched frames is wgpu's (and the
    // attribution saw them: a frame with no allocation at all would prove nothing).
    let ours = OURS.lock().unwrap().clone();
    let theirs = *THEIRS.lock().unwrap();
    println!(
        "{watched} frames attributed: {theirs} allocations by wgpu, {} by dermis",
        ours.len()
    );
    assert!(
        watched >= 40 && theirs > watched as u64,
        "{theirs} in {watched} frames"
    );
    assert!(
        ours.is_empty(),
        "dermis allocated in the frame: {:?}",
        &ours[..ours.len().min(8)]
    );
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

/// The attribution tells dermis' frames from others (a check of the parser above, run first
/// in the one test: a second test would run on another thread beside it).
fn attribution_reads_backtraces() {
    let ours = "Backtrace [{ fn: \"std::backtrace::Backtrace::force_capture\" }, \
                { fn: \"alloc::raw_vec::finish_grow\" }, \
                { fn: \"dermis_engine::render::renderer::Renderer::prepare\" }, \
                { fn: \"wgpu::api::queue::Queue::write_buffer\" }]";
    let theirs = "Backtrace [{ fn: \"alloc::alloc::alloc\" }, \
                  { fn: \"<wgpu_core::device::Device>::create_buffer\" }, \
                  { fn: \"dermis_engine::render::renderer::Renderer::prepare\" }]";
    assert_eq!(
        allocating_frame(ours).as_deref(),
        Some("dermis_engine::render::renderer::Renderer::prepare")
    );
    assert_eq!(
        allocating_frame(theirs).as_deref(),
        Some("<wgpu_core::device::Device>::create_buffer")
    );
}
