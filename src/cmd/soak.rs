//! `dermis soak`: the game on autoplay for N seconds of wall time, offscreen, with per-frame
//! records of what each frame cost and a summary of sustained performance.
//!
//! # Pacing
//! Offscreen there is no vsync: a capped run (the default) sleeps to the next boundary of the
//! target period (a simulated vsync grid), so a frame that misses its boundary is presented a
//! whole period late. The present interval is the CPU-side interval between consecutive
//! submits, in target periods; the histogram buckets `round(interval)`: ≤ 1 on time, 2 → one
//! period late, 3 → two, ≥ 4 → three or more. `--uncapped` submits as fast as it can (headroom).
//! Both keep at most [`FRAMES_IN_FLIGHT`] frames queued on the GPU, as a swapchain would: the
//! wait for the oldest one is part of the present interval, not of the CPU frame time.
//!
//! # GPU time
//! Timestamps are written by two empty compute passes bracketing the frame's single render
//! pass, resolved into the frame driver's `TimerRing` and mapped asynchronously; a frame's
//! GPU time reaches the [`Recorder`] a few frames later. Nothing waits for a readback: when
//! every slot is still in flight the frame goes untimed (`gpu_ms: null`).
//!
//! # Output (DIR)
//! The core's [`Recorder`] and [`Writer`] (the phone's soak uses the same two):
//! - `frames.jsonl`: one JSON object per frame, appended about once a second by the writer
//!   thread: `frame`, `t_s` (submit time on the soak clock), `cpu_ms` (update + upload +
//!   encode: the CPU frame time), `submit_ms` (the `queue.submit` call alone: drivers may block
//!   in it while the GPU is busy, lavapipe does), `gpu_ms` (null: not timed),
//!   `present_periods` (interval since the previous submit / target period; null for the
//!   first frame), `allocs` (heap allocations during the frame's work), `tier` (index in
//!   `config.tiers`), `model`, `coverage`, `lit`. Each batch of whole lines is one write; a
//!   reader of a killed run's file drops a last line that has no newline.
//! - `soak.json`: rewritten atomically (temp file + rename) about once a second:
//!   `{"format": "dermis-soak/1", "status": "running" | "complete", "config": {...},
//!   "seconds": [{t_s, frames, fps, cpu_ms_mean, cpu_ms_max, gpu_ms_mean, gpu_ms_max, rss_mb,
//!   rust_heap_mb, malloc_mb, tier, governor_changes, allocs}], "summary": {...} (complete
//!   only)}`. A killed run keeps `soak.json` up to its last second and `frames.jsonl` up to
//!   its last flush.
//! - `soak.png`: frame time (CPU, GPU), tier and memory over time, per second.
//!
//! # Memory
//! Sampled by the writer thread when it receives a second's record (off the game thread):
//! resident (`/proc/self/statm`), the C allocator's bytes in use (glibc `mallinfo2`: the Rust
//! heap plus the GPU driver's allocations) and the Rust heap's live bytes (the counting
//! global allocator, `dermis_engine::heap`). The recorder's own memory is fixed (histograms,
//! frame counts per 0.1 s) and reported apart, so a growth in the first two is the engine's
//! or the driver's, and the resident set adds the allocator's retention (glibc's per-thread
//! arenas grow and trim in steps of megabytes).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use dermis_engine::heap::allocations;
use dermis_engine::render::{
    Clock, FrameDriver, Gpu, LiveObjects, Offscreen, Output, OFFSCREEN_FORMAT,
};
use dermis_engine::scene::SceneAssets;
use dermis_engine::shading::ShadingModel;
use dermis_game::app::{soak_sample, GameFrame, GameGpu, Session};
use dermis_game::governor::GovernorConfig;
use dermis_game::soak::{
    config_json, report, summary_lines, write_atomic, Recorder, RecorderConfig, RunInfo, Writer,
};

use crate::cmd::args::parse_model;
use crate::cmd::args::{
    check_out_dir, parse_fps, parse_seconds, parse_seed, parse_size, shading_help,
};
use crate::cmd::chart::soak_png;
use crate::cmd::progress::Progress;

#[derive(clap::Args, Debug, Clone)]
pub struct SoakArgs {
    /// Wall-clock seconds to play (greater than 0, at most 86400).
    #[arg(long, default_value_t = 60.0, value_parser = parse_seconds, allow_hyphen_values = true)]
    pub seconds: f64,
    #[arg(
        long,
        default_value_t = ShadingModel::DEFAULT,
        value_parser = parse_model,
        help = shading_help(
            "The player's chosen shading model: tier 0 (see `governor::Tiers::for_choice`)"
        )
    )]
    pub shading: ShadingModel,
    /// Frame size WxH.
    #[arg(long, default_value = "1280x720", value_parser = parse_size, allow_hyphen_values = true)]
    pub size: (u32, u32),
    /// Target frame rate (the frame budget and the simulated vsync), 1..=1000.
    #[arg(long, default_value_t = 60.0, value_parser = parse_fps, allow_hyphen_values = true)]
    pub target_fps: f64,
    /// Submit as fast as possible (measures headroom) instead of pacing to the target.
    #[arg(long)]
    pub uncapped: bool,
    /// Output directory (soak.json, frames.jsonl, soak.png).
    #[arg(long)]
    pub out: PathBuf,
    /// Seed of the run.
    #[arg(long, default_value_t = 1, value_parser = parse_seed, allow_hyphen_values = true)]
    pub seed: u64,
    /// Turn the frame-time governor off (the tier follows coverage and light only).
    #[arg(long)]
    pub no_governor: bool,
    /// Turn all effect scheduling off: always the chosen model.
    #[arg(long)]
    pub no_scheduling: bool,
}

/// Frames queued on the GPU at most (swapchain-like back-pressure).
pub const FRAMES_IN_FLIGHT: usize = 2;

/// Sleeps until `deadline` (coarse sleep, then a short spin for precision).
fn sleep_until(deadline: Instant) {
    loop {
        let now = Instant::now();
        if now >= deadline {
            return;
        }
        let left = deadline - now;
        if left > Duration::from_micros(1500) {
            std::thread::sleep(left - Duration::from_micros(1000));
        } else {
            std::hint::spin_loop();
        }
    }
}

pub fn run(args: SoakArgs) -> Result<(), String> {
    // `--seconds` and `--target-fps` are range-checked by their parsers.
    check_out_dir(&args.out)?;
    // The set-up's progress; the run has its own bar (seconds of the soak clock).
    let mut setup = Progress::new("soak", 1);
    setup.begin("GPU device and pipelines");
    let assets = SceneAssets::load(&crate::paths::assets_dir(), None).map_err(|e| e.to_string())?;
    let gpu = Gpu::headless().map_err(|e| e.to_string())?;
    let (w, h) = args.size;
    let mut gg = GameGpu::new(&gpu, OFFSCREEN_FORMAT, &assets, ShadingModel::DEFAULT)?;
    // Every pipeline in place before the first measured frame.
    gg.finish_loading(&gpu);
    setup.finish();
    let target = Offscreen::new(&gpu, w, h);
    let mut session = Session::new(&assets.character, args.seed, None, true);
    session.settings.set_shading_model(args.shading);
    session.configure_governor(
        GovernorConfig::for_fps(args.target_fps),
        !args.no_governor,
        !args.no_scheduling,
    );
    let mut driver = FrameDriver::new(Clock::Wall {
        first: 1.0 / args.target_fps,
        min: 1e-4,
        max: 0.1,
    })
    .with_timer(&gpu)
    .with_alloc_counter(allocations);
    driver.max_in_flight = Some(FRAMES_IN_FLIGHT);

    let rec_cfg = RecorderConfig {
        seconds: args.seconds,
        target_fps: args.target_fps,
        tiers: session.governor.tiers().as_slice().to_vec(),
        gpu_timed: driver.timer().is_some(),
    };
    let run = RunInfo {
        platform: "desktop",
        adapter: gpu.adapter_name(),
        cpu_rasterizer: gpu.is_cpu(),
        size: (w, h),
        uncapped: args.uncapped,
        seed: args.seed,
        shading: session.shading(),
        governor: session.governor.enabled,
        scheduling: session.governor.scheduling,
        frames_in_flight: Some(FRAMES_IN_FLIGHT),
    };
    let config = config_json(&rec_cfg, &run);
    let writer = Writer::start(Some(args.out.clone()), config.clone(), 1, args.seconds)?;

    let bar = indicatif::ProgressBar::new(args.seconds.ceil() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} s  {msg}")
            .map_err(|e| e.to_string())?,
    );

    let period = Duration::from_secs_f64(1.0 / args.target_fps);
    let start = Instant::now();
    let mut rec = Recorder::new(rec_cfg, start);
    while !rec.done(Instant::now()) {
        // Swapchain-like back-pressure (not part of the CPU frame time), update (the
        // session selects the tier), upload, encode timed, submit; the governor is fed.
        let times = GameFrame::new(&mut session, &mut gg, &assets.character)
            .run(&mut driver, &gpu, Output::Offscreen(&target))
            .map_err(|s| format!("frame not drawn: {s:?}"))?;
        for &(f, ms) in driver.harvested() {
            rec.gpu_time(f, ms);
        }
        let closed = rec.frame(soak_sample(&times, &session, false));

        // About once a second, outside the frame's measured work.
        if let Some(second) = closed {
            rec.gpu_objects(second.t_s, LiveObjects::read(&gpu.device));
            let mut batch = Vec::new();
            rec.take_final(&mut batch);
            writer.frames(batch);
            writer.second(second);
            bar.set_position(second.t_s.floor() as u64);
            bar.set_message(format!(
                "{:.0} fps  cpu {:.1} ms  gpu {}  {}",
                second.fps,
                second.cpu_ms_mean,
                second
                    .gpu_ms_mean
                    .map_or("-".to_string(), |g| format!("{g:.1} ms")),
                session.drawn_model().name()
            ));
        }

        if !args.uncapped {
            // The next boundary of the simulated vsync grid.
            let since = (Instant::now() - start).as_secs_f64();
            let k = (since / period.as_secs_f64()).floor() + 1.0;
            sleep_until(start + period.mul_f64(k));
        }
    }
    let elapsed = rec.clock_s(Instant::now());
    bar.finish_and_clear();
    // Drain: wait for the GPU, read the last timestamps.
    driver.drain(&gpu, |f, ms| rec.gpu_time(f, ms));
    rec.finish_frames();
    let mut batch = Vec::new();
    rec.take_final(&mut batch);
    writer.frames(batch);
    let seconds = writer.finish()?;
    let summary = rec.summary(
        &seconds,
        elapsed,
        LiveObjects::read(&gpu.device),
        session.game.runs(),
    );
    write_atomic(
        &args.out.join("soak.json"),
        &report("complete", &config, &seconds, Some(&summary)),
    )?;
    let chart = args.out.join("soak.png");
    if let Err(e) = soak_png(
        &seconds,
        rec.config().tiers.as_slice(),
        rec.config().budget_ms(),
        &chart,
    ) {
        log::warn!("chart not drawn: {e}");
    }
    for line in summary_lines(&config, &summary) {
        println!("{line}");
    }
    println!(
        "report: {}  chart: {}",
        args.out.join("soak.json").display(),
        chart.display()
    );
    Ok(())
}
