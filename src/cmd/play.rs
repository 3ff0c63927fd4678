//! `dermis play`: the game headless (offscreen), with a summary of what each frame cost.

use std::path::PathBuf;

use dermis_engine::render::{
    Clock, FrameDriver, FrameOutput, Gpu, LiveObjects, Offscreen, Output, OFFSCREEN_FORMAT,
};
use dermis_engine::shading::ShadingModel;
use dermis_game::app::{GameFrame, GameGpu, GameSetup, Session};
use dermis_game::rules::Screen;
use serde_json::json;

use crate::cmd::args::parse_model;
use crate::cmd::args::{
    check_out_dir, parse_fps, parse_play_frames, parse_seed, parse_size, prealloc, shading_help,
};
use crate::cmd::progress::Progress;
use crate::cmd::stats::{median, percentile};
use dermis_engine::heap::allocations;

#[derive(clap::Args, Debug)]
pub struct PlayArgs {
    /// A glTF character instead of the project's own (fitted to the runner's height; its
    /// clips found by name).
    #[arg(long)]
    pub model: Option<PathBuf>,
    #[command(flatten)]
    pub character: crate::cmd::args::CharacterArgs,
    /// Let the autoplay bot play (it starts runs and restarts after game over).
    #[arg(long)]
    pub autoplay: bool,
    /// Frames to run, at least 121 (120 warm-up frames plus one measured).
    #[arg(long, default_value_t = 600, value_parser = parse_play_frames, allow_hyphen_values = true)]
    pub frames: u64,
    /// Seed of the run.
    #[arg(long, default_value_t = 1, value_parser = parse_seed, allow_hyphen_values = true)]
    pub seed: u64,
    #[arg(long, value_parser = parse_model, help = shading_help("Shading model of the character"))]
    pub shading: Option<ShadingModel>,
    /// Frame size WxH.
    #[arg(long, default_value = "1280x720", value_parser = parse_size, allow_hyphen_values = true)]
    pub size: (u32, u32),
    /// Simulated frame rate, 1..=1000 (the game's fixed step makes results independent of it).
    #[arg(long, default_value_t = 60.0, value_parser = parse_fps, allow_hyphen_values = true)]
    pub fps: f64,
    /// Save PNGs of the main, play and game-over screens here (needs --autoplay). Once the
    /// play screen is saved the bot stops dodging, so the run ends; frames go on past
    /// --frames (not measured) until all three are saved, or the command fails.
    #[arg(long)]
    pub screenshots: Option<PathBuf>,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Frames before steady state (pipelines warm, pools filled).
pub const WARM_UP: u64 = 120;

/// With `--screenshots`: at most this many simulated seconds of frames after `--frames` to
/// reach the screens not yet saved.
pub const SCREENSHOT_EXTRA_S: f64 = 30.0;

pub fn run(args: PlayArgs) -> Result<(), String> {
    if let Some(dir) = &args.screenshots {
        check_out_dir(dir)?;
        if !args.autoplay {
            return Err(
                "--screenshots needs --autoplay (without the bot no run starts, so only the \
                 main screen could be saved)"
                    .into(),
            );
        }
    }
    let mut progress = Progress::new("play", args.frames);
    progress.begin("GPU device and pipelines");
    // The character as the window loads it: its skin, its clips by name, no settings file.
    let setup = GameSetup {
        character: args.model.clone(),
        seed: args.seed,
        autoplay: args.autoplay,
        shading: args.shading,
        head: false,
        skin: args.character.skin.clone(),
        clips: args.character.clips(),
        ..GameSetup::new(crate::paths::assets_dir())
    };
    let (assets, mut session) = setup.load()?;
    let gpu = Gpu::headless().map_err(|e| e.to_string())?;
    let (w, h) = args.size;
    let mut gg = GameGpu::new(&gpu, OFFSCREEN_FORMAT, &assets, ShadingModel::DEFAULT)?;
    // Every pipeline in place before the first measured frame.
    gg.finish_loading(&gpu);
    let target = Offscreen::new(&gpu, w, h);
    // `play` measures the chosen model: no tier scheduling.
    session.configure_governor(session.governor.config, false, false);
    // The game's fixed step makes results independent of the frame rate.
    let mut driver = FrameDriver::new(Clock::Fixed((1.0 / args.fps) as f32 as f64))
        .with_alloc_counter(allocations);
    driver.sync = true;
    let mut cpu_ms = Vec::with_capacity(prealloc(args.frames));
    let mut dermis_allocs = Vec::with_capacity(prealloc(args.frames));
    let mut wgpu_allocs = Vec::with_capacity(prealloc(args.frames));
    let mut draw_calls = 0;
    let mut uploads = Vec::with_capacity(prealloc(args.frames));
    let mut max_ticks = 0;
    let mut live_warm = None;
    let mut live_changes = 0u64;
    let mut shots: Vec<(&str, bool)> = vec![("main", false), ("play", false), ("game-over", false)];
    let mut play_frames = 0u64;
    // Every 60th frame, after the frame's measured work (its allocations are counted inside
    // the driver's frame only).
    let extra = if args.screenshots.is_some() {
        (SCREENSHOT_EXTRA_S * args.fps).ceil() as u64
    } else {
        0
    };
    let mut frame = 0u64;
    loop {
        let missing = args.screenshots.is_some() && shots.iter().any(|s| !s.1);
        if frame >= args.frames && !(missing && frame < args.frames + extra) {
            break;
        }
        let measured = frame < args.frames;
        let mut shoot = None;
        // After the frame's passes: copy out the first frame of each screen not yet saved.
        let mut screenshot =
            |encoder: &mut wgpu::CommandEncoder, session: &Session, _: &FrameOutput<'_>| {
                let screen = session.game.screen();
                play_frames = if screen == Screen::Play {
                    play_frames + 1
                } else {
                    0
                };
                let want = match screen {
                    Screen::Main => 0,
                    Screen::Play if play_frames > 90 => 1,
                    Screen::GameOver => 2,
                    _ => usize::MAX,
                };
                if args.screenshots.is_some() && want < shots.len() && !shots[want].1 {
                    target.copy_out(encoder);
                    shoot = Some(want);
                }
            };
        let mut game = GameFrame::new(&mut session, &mut gg, &assets.character);
        game.after_encode = Some(&mut screenshot);
        let times = game
            .run(&mut driver, &gpu, Output::Offscreen(&target))
            .map_err(|s| format!("frame not drawn: {s:?}"))?;
        let (info, stats) = (game.info, game.stats);
        let frame_uploads = game.prepared.map_or(0, |f| f.uploads);
        if let Some(want) = shoot {
            let dir = args.screenshots.as_ref().expect("checked above");
            let path = dir.join(format!("{}.png", shots[want].0));
            target.read(&gpu).save_png(&path)?;
            shots[want].1 = true;
            // The play screen is saved: the bot lets the run end, for the game-over screen.
            if shots[want].0 == "play" {
                if let Some(bot) = &mut session.bot {
                    bot.give_up();
                }
            }
        }
        frame += 1;
        if !measured {
            continue;
        }
        cpu_ms.push((times.submitted - times.start).as_secs_f64() * 1e3);
        uploads.push(frame_uploads as f64);
        let a = times.allocs;
        dermis_allocs.push((a.updated - a.start) as f64);
        wgpu_allocs.push((a.submitted - a.updated) as f64);
        draw_calls = draw_calls.max(stats.draw_calls);
        max_ticks = max_ticks.max(info.ticks);
        if frame.is_multiple_of(60) {
            progress.set(frame, args.frames, "frames");
        }
        if frame - 1 == WARM_UP {
            live_warm = Some(LiveObjects::read(&gpu.device));
        } else if let Some(warm) = live_warm {
            if LiveObjects::read(&gpu.device) != warm {
                live_changes += 1;
            }
        }
    }
    progress.finish();
    let missing: Vec<&str> = shots.iter().filter(|s| !s.1).map(|s| s.0).collect();
    if args.screenshots.is_some() && !missing.is_empty() {
        return Err(format!(
            "--screenshots: no {} screen within {frame} frames ({} + {extra} more); saved: {}",
            missing.join(", "),
            args.frames,
            shots
                .iter()
                .filter(|s| s.1)
                .map(|s| s.0)
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    let steady = |v: &[f64]| -> Vec<f64> { v.iter().skip(WARM_UP as usize).copied().collect() };
    let (d, wg, cpu) = (
        steady(&dermis_allocs),
        steady(&wgpu_allocs),
        steady(&cpu_ms),
    );
    let g = &session.game;
    let report = json!({
        "adapter": gpu.adapter_name(),
        "frames": args.frames,
        "seed": args.seed,
        "shading": session.shading().name(),
        "runs": g.runs(),
        "ticks": g.ticks(),
        "score": g.score(),
        "best": g.best(),
        "dermis_allocations_per_frame": d.iter().copied().fold(0.0, f64::max),
        "wgpu_allocations_per_frame": {"median": median(&wg), "max": wg.iter().copied().fold(0.0, f64::max)},
        "ui_rebuilds": session.ui.rebuilds(),
        "buffer_uploads_per_frame": {"median": median(&steady(&uploads)), "max": steady(&uploads).iter().copied().fold(0.0, f64::max)},
        "draw_calls_per_frame": draw_calls,
        "cpu_frame_ms": {"p50": percentile(&cpu, 0.5), "p95": percentile(&cpu, 0.95), "p99": percentile(&cpu, 0.99)},
        "gpu_objects_live_after_warm_up": live_warm,
        "frames_with_gpu_object_count_changes": live_changes,
        "screenshots": shots.iter().filter(|s| s.1).map(|s| s.0).collect::<Vec<_>>(),
        "frames_after_measured_for_screenshots": frame - args.frames,
    });
    if args.json {
        return crate::cmd::stats::print_json(&report);
    }
    println!("adapter: {}", gpu.adapter_name());
    println!(
        "{} frames, {} runs, score {}, best {}, shading {}",
        args.frames,
        g.runs(),
        g.score(),
        g.best(),
        session.shading()
    );
    if let Some(dir) = &args.screenshots {
        println!(
            "saved main.png, play.png, game-over.png in {} ({} frames past --frames, not measured)",
            dir.display(),
            frame - args.frames
        );
    }
    println!("after {WARM_UP} warm-up frames:");
    println!(
        "  dermis allocations per frame (max): {}",
        report["dermis_allocations_per_frame"]
    );
    println!(
        "  wgpu allocations per frame: median {} max {}",
        median(&wg),
        report["wgpu_allocations_per_frame"]["max"]
    );
    println!("  GPU objects changed on {live_changes} frames; UI rebuilds {}; draw calls/frame {draw_calls}", session.ui.rebuilds());
    println!(
        "  CPU frame ms: p50 {:.3} p95 {:.3} p99 {:.3}",
        percentile(&cpu, 0.5),
        percentile(&cpu, 0.95),
        percentile(&cpu, 0.99)
    );
    Ok(())
}
