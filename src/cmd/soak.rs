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
//! pass (the renderer's pass takes only the blocking `PassTimer`), resolved into the
//! [`TimerRing`]'s query/readback buffer pairs and mapped asynchronously; a frame's GPU time is
//! filled in when its buffer is found mapped a few frames later. Nothing waits for a readback:
//! when every slot is still in flight the frame goes untimed (`gpu_ms: null`).
//!
//! # Output (DIR)
//! - `frames.jsonl`: one JSON object per frame, appended about once a second by a writer
//!   thread: `frame`, `t_s` (submit time since start), `cpu_ms` (update + upload + encode:
//!   the CPU frame time), `submit_ms` (the `queue.submit` call alone: drivers may block in it
//!   while the GPU is busy, lavapipe does), `gpu_ms` (null: not timed), `present_periods` (interval since the previous
//!   submit / target period; null for the first frame), `allocs` (heap allocations during the
//!   frame's work), `tier` (index in `config.tiers`), `model`, `coverage`, `lit`. Each batch
//!   of whole lines is one write; a reader of a killed run's file drops a last line that has
//!   no newline.
//! - `soak.json`: rewritten atomically (temp file + rename) about once a second:
//!   `{"format": "dermis-soak/1", "status": "running" | "complete", "config": {...},
//!   "seconds": [{t_s, frames, fps, cpu_ms_mean, cpu_ms_max, gpu_ms_mean, rss_mb, tier,
//!   governor_changes, allocs}], "summary": {...} (complete only)}`. A killed run keeps
//!   `soak.json` up to its last second and `frames.jsonl` up to its last flush.
//! - `soak.png`: frame time (CPU, GPU), tier and resident memory over time.
//!
//! Resident memory is sampled by the writer thread when it receives a second's record (off the
//! game thread): `/proc/self/statm`'s resident pages × the page size (calibrated once against
//! `/proc/self/status` VmRSS, 4 KiB when that fails); NaN outside Linux/Android.

use std::fs::File;
use std::io::Write;
use std::path::PathBuf;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use dermis_core::game::{GameFrame, GameGpu, Session};
use dermis_core::governor::GovernorConfig;
use dermis_core::render::{
    Clock, FrameDriver, Gpu, LiveObjects, Offscreen, Output, TimerRing, OFFSCREEN_FORMAT,
};
use dermis_core::scene::SceneAssets;
use dermis_core::shading::ShadingModel;
use serde_json::{json, Value};

use crate::alloc_count::allocations;
use crate::cli::parse_model;
use crate::cmd::args::{check_out_dir, parse_fps, parse_seconds, prealloc, shading_help};
use crate::cmd::chart::soak_png;
use crate::cmd::render::parse_size;
use dermis_core::soak::{
    page_bytes, report, resident_mb, summarize, summary_lines, write_atomic, FrameRec, SecondRec,
    SummaryInput,
};

#[derive(clap::Args, Debug, Clone)]
pub struct SoakArgs {
    /// Wall-clock seconds to play (greater than 0, at most 86400).
    #[arg(long, default_value_t = 60.0, value_parser = parse_seconds, allow_negative_numbers = true)]
    pub seconds: f64,
    #[arg(
        long,
        default_value = "oss",
        value_parser = parse_model,
        help = shading_help(
            "The player's chosen shading model: tier 0 (see `governor::Tiers::for_choice`)"
        )
    )]
    pub shading: ShadingModel,
    /// Frame size WxH.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Target frame rate (the frame budget and the simulated vsync), 1..=1000.
    #[arg(long, default_value_t = 60.0, value_parser = parse_fps, allow_negative_numbers = true)]
    pub target_fps: f64,
    /// Submit as fast as possible (measures headroom) instead of pacing to the target.
    #[arg(long)]
    pub uncapped: bool,
    /// Output directory (soak.json, frames.jsonl, soak.png).
    #[arg(long)]
    pub out: PathBuf,
    /// Seed of the run.
    #[arg(long, default_value_t = 1)]
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

enum Msg {
    Frames(Vec<FrameRec>),
    Second(SecondRec),
}

/// The writer thread: appends frames, samples memory, rewrites soak.json each second.
fn writer(dir: PathBuf, config: Value, rx: mpsc::Receiver<Msg>) -> Result<Vec<SecondRec>, String> {
    let page = page_bytes();
    let path = dir.join("frames.jsonl");
    let mut frames = File::create(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut buf = Vec::new();
    let mut seconds = Vec::new();
    for msg in rx {
        match msg {
            Msg::Frames(batch) => {
                // One write per batch of whole lines.
                buf.clear();
                for f in &batch {
                    serde_json::to_writer(&mut buf, f).map_err(|e| e.to_string())?;
                    buf.push(b'\n');
                }
                frames.write_all(&buf).map_err(|e| e.to_string())?;
            }
            Msg::Second(mut s) => {
                s.rss_mb = resident_mb(page);
                seconds.push(s);
                write_atomic(
                    &dir.join("soak.json"),
                    &report("running", &config, &seconds, None),
                )?;
            }
        }
    }
    Ok(seconds)
}

/// Whether the objects created only at load (pipelines, shader modules, bind groups,
/// textures, views, samplers) are unchanged. Buffers are left out: `queue.write_buffer`'s
/// staging buffers come and go with the frames in flight (their range is reported).
fn same_load_objects(a: &LiveObjects, b: &LiveObjects) -> bool {
    LiveObjects { buffers: 0, ..*a } == LiveObjects { buffers: 0, ..*b }
}

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
    let assets = SceneAssets::load(&crate::paths::assets_dir(), None).map_err(|e| e.to_string())?;
    let gpu = Gpu::headless().map_err(|e| e.to_string())?;
    let (w, h) = args.size;
    let mut gg = GameGpu::new(&gpu, OFFSCREEN_FORMAT, &assets)?;
    let target = Offscreen::new(&gpu, w, h);
    let mut session = Session::new(&assets.character, args.seed, None, true);
    session.settings.set_shading_model(args.shading);
    session.configure_governor(
        GovernorConfig::for_fps(args.target_fps),
        !args.no_governor,
        !args.no_scheduling,
    );
    let tiers = *session.governor.tiers();
    let mut driver = FrameDriver::new(Clock::Wall {
        first: 1.0 / args.target_fps,
        min: 1e-4,
        max: 0.1,
    })
    .with_timer(&gpu)
    .with_alloc_counter(allocations);
    driver.max_in_flight = Some(FRAMES_IN_FLIGHT);

    let period = Duration::from_secs_f64(1.0 / args.target_fps);
    let budget_ms = 1000.0 / args.target_fps;
    let duration = Duration::from_secs_f64(args.seconds);
    let warm_up_s = (args.seconds * 0.1).min(2.0);
    let config = json!({
        "adapter": gpu.adapter_name(),
        "cpu_rasterizer": gpu.is_cpu(),
        "seconds": args.seconds,
        "size": [w, h],
        "target_fps": args.target_fps,
        "budget_ms": budget_ms,
        "uncapped": args.uncapped,
        "seed": args.seed,
        "shading": session.shading().name(),
        "tiers": tiers.as_slice().iter().map(|m| m.name()).collect::<Vec<_>>(),
        "governor": session.governor.enabled,
        "scheduling": session.governor.scheduling,
        "gpu_timestamps": driver.timer().is_some(),
        "timer_ring": TimerRing::SLOTS,
        "frames_in_flight": FRAMES_IN_FLIGHT,
        "warm_up_s": warm_up_s,
    });

    let (tx, rx) = mpsc::channel();
    let writer_thread = {
        let dir = args.out.clone();
        let config = config.clone();
        std::thread::Builder::new()
            .name("soak writer".into())
            .spawn(move || writer(dir, config, rx))
            .map_err(|e| e.to_string())?
    };

    let bar = indicatif::ProgressBar::new(args.seconds.ceil() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} s  {msg}")
            .map_err(|e| e.to_string())?,
    );

    let expect_frames = (args.seconds * args.target_fps * 1.1) as u64 + 64;
    let mut frames: Vec<FrameRec> = Vec::with_capacity(prealloc(expect_frames));
    let mut sent = 0usize;
    let mut second_start = 0usize;
    let mut next_second = 1.0f64;
    let mut last_second_t = 0.0f64;
    let mut last_submit: Option<Instant> = None;
    let mut live_warm: Option<LiveObjects> = None;
    let mut live_changes = 0u64;
    let mut buffers = (isize::MAX, isize::MIN);
    let mut tier_changes = 0u64;
    let mut last_tier = usize::MAX;
    let start = Instant::now();
    while start.elapsed() < duration {
        // Swapchain-like back-pressure (not part of the CPU frame time), update (the
        // session selects the tier), upload, encode timed, submit; the governor is fed.
        let times = GameFrame::new(&mut session, &mut gg, &assets.character)
            .run(&mut driver, &gpu, Output::Offscreen(&target))
            .map_err(|s| format!("frame not drawn: {s:?}"))?;
        for &(f, ms) in driver.harvested() {
            if let Some(rec) = frames.get_mut(f) {
                rec.gpu_ms = Some(ms);
            }
        }
        let (tier, model, needs) = (session.tier(), session.drawn_model(), session.needs);
        let frame = times.frame as usize;
        let (cpu_ms, submit_ms) = (times.cpu_ms(), times.submit_ms());
        let submit = times.submitted;
        let allocs = times.allocs.done - times.allocs.start;
        let present_periods =
            last_submit.map(|t| (submit - t).as_secs_f64() / period.as_secs_f64());
        last_submit = Some(submit);
        if tier != last_tier && last_tier != usize::MAX {
            tier_changes += 1;
        }
        last_tier = tier;
        let t_s = (submit - start).as_secs_f64();
        frames.push(FrameRec {
            frame,
            t_s,
            cpu_ms,
            submit_ms,
            gpu_ms: None,
            present_periods,
            allocs,
            tier,
            model: model.name(),
            coverage: needs.coverage,
            lit: needs.lit,
        });

        // About once a second, outside the frame's measured work.
        if t_s >= next_second {
            next_second += 1.0;
            let live = LiveObjects::read(&gpu.device);
            buffers.0 = buffers.0.min(live.buffers);
            buffers.1 = buffers.1.max(live.buffers);
            match live_warm {
                None if t_s >= warm_up_s => live_warm = Some(live),
                Some(w) if !same_load_objects(&w, &live) => live_changes += 1,
                _ => {}
            }
            let rec = SecondRec::of(
                &frames[second_start..],
                t_s,
                last_second_t,
                tier,
                session.governor.changes(),
            );
            second_start = frames.len();
            last_second_t = t_s;
            let upto = driver
                .timer()
                .and_then(|r| r.oldest_pending())
                .unwrap_or(frames.len())
                .min(frames.len());
            if upto > sent {
                let _ = tx.send(Msg::Frames(frames[sent..upto].to_vec()));
                sent = upto;
            }
            let _ = tx.send(Msg::Second(rec));
            bar.set_position(t_s.floor() as u64);
            bar.set_message(format!(
                "{:.0} fps  cpu {:.1} ms  gpu {}  {}",
                rec.fps,
                rec.cpu_ms_mean,
                rec.gpu_ms_mean
                    .map_or("-".to_string(), |g| format!("{g:.1} ms")),
                model.name()
            ));
        }

        if !args.uncapped {
            // The next boundary of the simulated vsync grid.
            let since = (Instant::now() - start).as_secs_f64();
            let k = (since / period.as_secs_f64()).floor() + 1.0;
            sleep_until(start + period.mul_f64(k));
        }
    }
    let elapsed = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    // Drain: wait for the GPU, read the last timestamps.
    driver.drain(&gpu, |f, ms| {
        if let Some(rec) = frames.get_mut(f) {
            rec.gpu_ms = Some(ms);
        }
    });
    let live_end = LiveObjects::read(&gpu.device);
    if let Some(w) = live_warm {
        if !same_load_objects(&w, &live_end) {
            live_changes += 1;
        }
    }
    if sent < frames.len() {
        let _ = tx.send(Msg::Frames(frames[sent..].to_vec()));
    }
    drop(tx);
    let seconds = writer_thread
        .join()
        .map_err(|_| "soak writer thread panicked".to_string())??;

    let summary = summarize(&SummaryInput {
        frames: &frames,
        seconds: &seconds,
        elapsed,
        budget_ms,
        warm_up_s,
        tiers: tiers.as_slice(),
        governor_changes: session.governor.changes(),
        tier_changes,
        live_warm,
        live_end,
        live_changes,
        buffers,
        untimed: driver.timer().map_or(frames.len() as u64, |r| r.skipped),
        runs: session.game.runs(),
    });
    write_atomic(
        &args.out.join("soak.json"),
        &report("complete", &config, &seconds, Some(&summary)),
    )?;
    let chart = args.out.join("soak.png");
    if let Err(e) = soak_png(&frames, &seconds, tiers.as_slice(), budget_ms, &chart) {
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
