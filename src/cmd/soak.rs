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
//! pass (the renderer's pass takes only the blocking `PassTimer`), resolved into a ring of
//! [`RING`] query/readback buffer pairs and mapped asynchronously; a frame's GPU time is filled
//! in when its buffer is found mapped a few frames later. Nothing waits for a readback: when
//! every slot is still in flight the frame goes untimed (`gpu_ms: null`).
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

use std::collections::VecDeque;
use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

use dermis_core::game::{GameGpu, Session, Viewport};
use dermis_core::governor::{
    light_reaches, projected_coverage, Governor, GovernorConfig, Needs, Tiers,
};
use dermis_core::render::{DrawSet, Gpu, LiveObjects, Offscreen, OFFSCREEN_FORMAT};
use dermis_core::scene::SceneAssets;
use dermis_core::shading::ShadingModel;
use dermis_core::ui::Insets;
use glam::Vec3;
use serde_json::{json, Value};

use crate::alloc_count::allocations;
use crate::cli::parse_model;
use crate::cmd::args::{
    check_out_dir, parse_bench_frames, parse_fps, parse_rounds, parse_seconds, prealloc,
    shading_help, BENCH_FRAMES, ROUNDS,
};
use crate::cmd::render::parse_size;
use crate::cmd::stats::{percentile, ratio_ci};
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

/// Timestamp readback ring size (≥ 3: a frame's time arrives a few frames later).
pub const RING: usize = 4;
/// Frames queued on the GPU at most (swapchain-like back-pressure).
pub const FRAMES_IN_FLIGHT: usize = 2;
/// Minimum irradiance (W/m² at the character's chest) for "a light reaches it".
const MIN_IRRADIANCE: f32 = 0.2;

const FREE: u8 = 0;
const PENDING: u8 = 1;
const MAPPED: u8 = 2;
const FAILED: u8 = 3;

struct Slot {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    state: Arc<AtomicU8>,
    frame: usize,
}

/// Non-stalling GPU pass timing: a ring of query sets and readback buffers.
pub struct TimerRing {
    slots: Vec<Slot>,
    period_ns: f64,
    next: usize,
    /// Frames that went untimed because every slot was in flight.
    pub skipped: u64,
}

impl TimerRing {
    /// `None` without TIMESTAMP_QUERY.
    pub fn new(gpu: &Gpu) -> Option<Self> {
        if !gpu.timestamps {
            return None;
        }
        let device = &gpu.device;
        let slots = (0..RING)
            .map(|_| {
                let buffer = |usage| {
                    device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("soak timer"),
                        size: 16,
                        usage,
                        mapped_at_creation: false,
                    })
                };
                Slot {
                    set: device.create_query_set(&wgpu::QuerySetDescriptor {
                        label: Some("soak timer"),
                        ty: wgpu::QueryType::Timestamp,
                        count: 2,
                    }),
                    resolve: buffer(
                        wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    ),
                    readback: buffer(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST),
                    state: Arc::new(AtomicU8::new(FREE)),
                    frame: 0,
                }
            })
            .collect();
        Some(Self {
            slots,
            period_ns: gpu.queue.get_timestamp_period() as f64,
            next: 0,
            skipped: 0,
        })
    }

    /// A free slot for `frame`, or `None` (frame untimed) when all are in flight.
    pub fn begin(&mut self, frame: usize) -> Option<usize> {
        let i = self.next;
        if self.slots[i].state.load(Ordering::Acquire) != FREE {
            self.skipped += 1;
            return None;
        }
        self.next = (i + 1) % RING;
        self.slots[i].frame = frame;
        Some(i)
    }

    fn marker(&self, encoder: &mut wgpu::CommandEncoder, slot: usize, index: u32) {
        let s = &self.slots[slot];
        let _ = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("soak timestamp"),
            timestamp_writes: Some(wgpu::ComputePassTimestampWrites {
                query_set: &s.set,
                beginning_of_pass_write_index: (index == 0).then_some(0),
                end_of_pass_write_index: (index == 1).then_some(1),
            }),
        });
    }

    /// Before the timed pass.
    pub fn start(&self, encoder: &mut wgpu::CommandEncoder, slot: usize) {
        self.marker(encoder, slot, 0);
    }

    /// After the timed pass: the end timestamp, resolve and copy to the readback buffer.
    pub fn end(&self, encoder: &mut wgpu::CommandEncoder, slot: usize) {
        self.marker(encoder, slot, 1);
        let s = &self.slots[slot];
        encoder.resolve_query_set(&s.set, 0..2, &s.resolve, 0);
        encoder.copy_buffer_to_buffer(&s.resolve, 0, &s.readback, 0, 16);
    }

    /// After the submit: request the asynchronous map.
    pub fn submitted(&self, slot: usize) {
        let s = &self.slots[slot];
        s.state.store(PENDING, Ordering::Release);
        let state = Arc::clone(&s.state);
        s.readback.map_async(wgpu::MapMode::Read, .., move |r| {
            state.store(if r.is_ok() { MAPPED } else { FAILED }, Ordering::Release);
        });
    }

    /// Reads every slot found mapped (never waits): `f(frame, gpu_ms)`.
    pub fn harvest(&mut self, mut f: impl FnMut(usize, f64)) {
        for s in &mut self.slots {
            match s.state.load(Ordering::Acquire) {
                MAPPED => {
                    let ticks = s.readback.get_mapped_range(..).ok().map(|d| {
                        let t0 = u64::from_le_bytes(d[0..8].try_into().unwrap_or([0; 8]));
                        let t1 = u64::from_le_bytes(d[8..16].try_into().unwrap_or([0; 8]));
                        (t0, t1)
                    });
                    s.readback.unmap();
                    s.state.store(FREE, Ordering::Release);
                    if let Some((t0, t1)) = ticks {
                        if let Some(dt) = t1.checked_sub(t0) {
                            f(s.frame, dt as f64 * self.period_ns * 1e-6);
                        }
                    }
                }
                FAILED => s.state.store(FREE, Ordering::Release),
                _ => {}
            }
        }
    }

    /// The oldest frame still in flight.
    pub fn oldest_pending(&self) -> Option<usize> {
        self.slots
            .iter()
            .filter(|s| s.state.load(Ordering::Acquire) != FREE)
            .map(|s| s.frame)
            .min()
    }
}

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

/// The character's bounding box (feet at the origin of the player transform).
fn character_box(feet: Vec3) -> (Vec3, Vec3) {
    (
        feet + Vec3::new(-0.45, 0.0, -0.45),
        feet + Vec3::new(0.45, 1.85, 0.45),
    )
}

/// What this frame needs: coverage of the character's box and whether the light reaches it.
pub fn frame_needs(session: &Session, viewport: &Viewport) -> Needs {
    let aspect = viewport.width as f32 / viewport.height.max(1) as f32;
    let (feet, _) = session.game.player_transform();
    let (min, max) = character_box(feet);
    let coverage = projected_coverage(session.camera.view_proj(aspect), min, max);
    let chest = feet + Vec3::Y * 1.3;
    let lit = light_reaches(
        session.light.position,
        session.light.intensity,
        chest,
        MIN_IRRADIANCE,
    );
    Needs { coverage, lit }
}

/// Sleeps until `deadline` (coarse sleep, then a short spin for precision).
/// Records one game frame drawing the character with `model`, bracketed by timestamps from
/// `ring` when a slot is free for `frame`; returns the commands and the slot used.
fn encode_timed(
    gpu: &Gpu,
    gg: &GameGpu,
    target: &Offscreen,
    session: &Session,
    model: ShadingModel,
    ring: &mut Option<TimerRing>,
    frame: usize,
) -> (wgpu::CommandBuffer, Option<usize>) {
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    let slot = ring.as_mut().and_then(|r| r.begin(frame));
    if let (Some(r), Some(s)) = (ring.as_ref(), slot) {
        r.start(&mut encoder, s);
    }
    let draw = DrawSet {
        shading: Some(model),
        ..session.draw_set()
    };
    gg.renderer.encode(
        &mut encoder,
        &target.targets,
        &target.view,
        draw,
        Some(&gg.ui),
        None,
    );
    if let (Some(r), Some(s)) = (ring.as_ref(), slot) {
        r.end(&mut encoder, s);
    }
    (encoder.finish(), slot)
}

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
    let viewport = Viewport {
        width: w,
        height: h,
        scale: 1.0,
        insets: Insets::default(),
    };
    let tiers = Tiers::for_choice(session.shading());
    let mut governor = Governor::new(tiers, GovernorConfig::for_fps(args.target_fps));
    governor.enabled = !args.no_governor && !args.no_scheduling;
    governor.scheduling = !args.no_scheduling;
    let mut ring = TimerRing::new(&gpu);

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
        "governor": governor.enabled,
        "scheduling": governor.scheduling,
        "gpu_timestamps": ring.is_some(),
        "timer_ring": RING,
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
    let mut in_flight: VecDeque<wgpu::SubmissionIndex> = VecDeque::with_capacity(4);
    let mut sent = 0usize;
    let mut second_start = 0usize;
    let mut next_second = 1.0f64;
    let mut last_second_t = 0.0f64;
    let mut last_gpu_ms = f64::NAN;
    let mut last_submit: Option<Instant> = None;
    let mut last_frame_start: Option<Instant> = None;
    let mut live_warm: Option<LiveObjects> = None;
    let mut live_changes = 0u64;
    let mut buffers = (isize::MAX, isize::MIN);
    let mut tier_changes = 0u64;
    let mut last_tier = usize::MAX;
    let start = Instant::now();
    while start.elapsed() < duration {
        // Swapchain-like back-pressure (not part of the CPU frame time).
        while in_flight.len() >= FRAMES_IN_FLIGHT {
            if let Some(idx) = in_flight.pop_front() {
                let _ = gpu.device.poll(wgpu::PollType::Wait {
                    submission_index: Some(idx),
                    timeout: None,
                });
            }
        }
        let t0 = Instant::now();
        let dt = last_frame_start.map_or(1.0 / args.target_fps, |t| {
            (t0 - t).as_secs_f64().clamp(1e-4, 0.1)
        });
        last_frame_start = Some(t0);
        let a0 = allocations();
        session.update(dt as f32, &assets.character, viewport);
        let needs = frame_needs(&session, &viewport);
        let tier = governor.select(needs);
        let model = governor.tiers().model(tier);
        gg.upload(&gpu.queue, &mut session, &assets.character);
        let frame = frames.len();
        let (commands, slot) = encode_timed(&gpu, &gg, &target, &session, model, &mut ring, frame);
        let t_submit = Instant::now();
        in_flight.push_back(gpu.queue.submit([commands]));
        if let (Some(r), Some(s)) = (&ring, slot) {
            r.submitted(s);
        }
        let submit = Instant::now();
        let cpu_ms = (t_submit - t0).as_secs_f64() * 1e3;
        let submit_ms = (submit - t_submit).as_secs_f64() * 1e3;
        let _ = gpu.device.poll(wgpu::PollType::Poll);
        if let Some(r) = &mut ring {
            r.harvest(|f, ms| {
                if let Some(rec) = frames.get_mut(f) {
                    rec.gpu_ms = Some(ms);
                }
                last_gpu_ms = ms;
            });
        }
        let allocs = allocations() - a0;
        let present_periods =
            last_submit.map(|t| (submit - t).as_secs_f64() / period.as_secs_f64());
        last_submit = Some(submit);
        // The governor sees the sustained cost: the larger of this frame's CPU time and the
        // latest GPU time known (a few frames old).
        let cost = if last_gpu_ms.is_finite() {
            cpu_ms.max(last_gpu_ms)
        } else {
            cpu_ms
        };
        governor.record(cost, dt);
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
                governor.changes(),
            );
            second_start = frames.len();
            last_second_t = t_s;
            let upto = ring
                .as_ref()
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
    gpu.wait();
    if let Some(r) = &mut ring {
        for _ in 0..100 {
            let _ = gpu.device.poll(wgpu::PollType::wait_indefinitely());
            r.harvest(|f, ms| {
                if let Some(rec) = frames.get_mut(f) {
                    rec.gpu_ms = Some(ms);
                }
            });
            if r.oldest_pending().is_none() {
                break;
            }
        }
    }
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
        governor_changes: governor.changes(),
        tier_changes,
        live_warm,
        live_end,
        live_changes,
        buffers,
        untimed: ring.as_ref().map_or(frames.len() as u64, |r| r.skipped),
        runs: session.game.runs(),
    });
    write_atomic(
        &args.out.join("soak.json"),
        &report("complete", &config, &seconds, Some(&summary)),
    )?;
    let chart = args.out.join("soak.png");
    if let Err(e) = chart_png(&frames, &seconds, tiers.as_slice(), budget_ms, &chart) {
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

/// Frame time, tier and resident memory over time, three panels.
fn chart_png(
    frames: &[FrameRec],
    seconds: &[SecondRec],
    tiers: &[ShadingModel],
    budget_ms: f64,
    path: &Path,
) -> Result<(), String> {
    use plotters::prelude::*;
    crate::cmd::chart::ensure_font();
    let e = |e: &dyn std::fmt::Display| e.to_string();
    let root = BitMapBackend::new(path, (1200, 900)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let panels = root.split_evenly((3, 1));
    let t_max = frames.last().map_or(1.0, |f| f.t_s).max(1.0);
    let cpu: Vec<(f64, f64)> = frames.iter().map(|f| (f.t_s, f.cpu_ms)).collect();
    let gpu: Vec<(f64, f64)> = frames
        .iter()
        .filter_map(|f| f.gpu_ms.map(|g| (f.t_s, g)))
        .collect();
    let all: Vec<f64> = cpu.iter().chain(&gpu).map(|p| p.1).collect();
    let y_max = percentile(&all, 0.995).max(budget_ms) * 1.3;
    let mut c = ChartBuilder::on(&panels[0])
        .caption("Frame time", ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(30)
        .y_label_area_size(55)
        .build_cartesian_2d(0.0..t_max, 0.0..y_max.max(1.0))
        .map_err(|x| e(&x))?;
    c.configure_mesh()
        .x_desc("s")
        .y_desc("ms")
        .draw()
        .map_err(|x| e(&x))?;
    c.draw_series(LineSeries::new(
        cpu.iter().map(|&(t, v)| (t, v.min(y_max))),
        &BLUE,
    ))
    .map_err(|x| e(&x))?
    .label("CPU")
    .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE));
    c.draw_series(LineSeries::new(
        gpu.iter().map(|&(t, v)| (t, v.min(y_max))),
        &RED,
    ))
    .map_err(|x| e(&x))?
    .label("GPU")
    .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED));
    c.draw_series(LineSeries::new(
        [(0.0, budget_ms), (t_max, budget_ms)],
        BLACK.mix(0.5),
    ))
    .map_err(|x| e(&x))?
    .label("budget")
    .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
    c.configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|x| e(&x))?;

    let names: Vec<&str> = tiers.iter().map(|m| m.name()).collect();
    let top = names.len().max(1) as f64 - 0.5;
    let mut c = ChartBuilder::on(&panels[1])
        .caption(
            format!("Shading tier (0 = {})", names.join(", ")),
            ("sans-serif", 18),
        )
        .margin(10)
        .x_label_area_size(30)
        .y_label_area_size(55)
        .build_cartesian_2d(0.0..t_max, -0.5..top)
        .map_err(|x| e(&x))?;
    c.configure_mesh()
        .x_desc("s")
        .y_desc("tier")
        .draw()
        .map_err(|x| e(&x))?;
    c.draw_series(LineSeries::new(
        frames.iter().map(|f| (f.t_s, f.tier as f64)),
        &GREEN,
    ))
    .map_err(|x| e(&x))?;

    let mem: Vec<(f64, f64)> = seconds
        .iter()
        .filter_map(|s| s.rss_mb.map(|m| (s.t_s, m)))
        .collect();
    let (lo, hi) = mem.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
        (a.0.min(p.1), a.1.max(p.1))
    });
    let (lo, hi) = if lo.is_finite() {
        (lo - 1.0 - 0.05 * (hi - lo), hi + 1.0 + 0.05 * (hi - lo))
    } else {
        (0.0, 1.0)
    };
    let mut c = ChartBuilder::on(&panels[2])
        .caption("Resident memory", ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(30)
        .y_label_area_size(55)
        .build_cartesian_2d(0.0..t_max, lo..hi)
        .map_err(|x| e(&x))?;
    c.configure_mesh()
        .x_desc("s")
        .y_desc("MiB")
        .draw()
        .map_err(|x| e(&x))?;
    c.draw_series(LineSeries::new(mem, &MAGENTA))
        .map_err(|x| e(&x))?;
    root.present().map_err(|x| e(&x))?;
    Ok(())
}

/// `dermis bench effects` arguments.
#[derive(clap::Args, Debug)]
pub struct EffectsArgs {
    /// Rounds (at least 2); each round plays `frames` frames in each mode, in rotating order.
    #[arg(long, default_value_t = 10, value_parser = parse_rounds, allow_negative_numbers = true)]
    pub rounds: usize,
    /// Frames per mode per round (at least 10).
    #[arg(long, default_value_t = 60, value_parser = parse_bench_frames, allow_negative_numbers = true)]
    pub frames: usize,
    #[arg(
        long,
        default_value = "oss",
        value_parser = parse_model,
        help = shading_help("The player's shading model (tier 0)")
    )]
    pub shading: ShadingModel,
    /// Frame size WxH.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Print JSON instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// GPU and CPU time saved by each scheduling decision, as ratios to scheduling off, all
/// measured in one run: the runner scene on autoplay played in rotating blocks of three modes
/// (off: always the chosen model; coverage + light; coverage + light + frame-time governor),
/// each frame's GPU pass timed and waited for (so blocks do not overlap on the GPU).
pub fn bench_effects(args: EffectsArgs) -> Result<(), String> {
    if !(ROUNDS.0..=ROUNDS.1).contains(&args.rounds)
        || !(BENCH_FRAMES.0..=BENCH_FRAMES.1).contains(&args.frames)
    {
        return Err(format!(
            "--rounds {} / --frames {} out of range ({}..={} / {}..={})",
            args.rounds, args.frames, ROUNDS.0, ROUNDS.1, BENCH_FRAMES.0, BENCH_FRAMES.1
        ));
    }
    let assets = SceneAssets::load(&crate::paths::assets_dir(), None).map_err(|e| e.to_string())?;
    let gpu = Gpu::headless().map_err(|e| e.to_string())?;
    let (w, h) = args.size;
    let mut gg = GameGpu::new(&gpu, OFFSCREEN_FORMAT, &assets)?;
    let target = Offscreen::new(&gpu, w, h);
    let mut session = Session::new(&assets.character, 1, None, true);
    session.settings.set_shading_model(args.shading);
    let viewport = Viewport {
        width: w,
        height: h,
        scale: 1.0,
        insets: Insets::default(),
    };
    let tiers = Tiers::for_choice(args.shading);
    // One governor per mode, so each keeps its own state across its blocks.
    let config = GovernorConfig::for_fps(60.0);
    let mut governors: Vec<Governor> = (0..3)
        .map(|k| {
            let mut g = Governor::new(tiers, config);
            g.scheduling = k >= 1;
            g.enabled = k == 2;
            g
        })
        .collect();
    let mut ring = TimerRing::new(&gpu);
    let dt = 1.0f32 / 60.0;
    // Per mode, per round: mean CPU ms, mean GPU ms; frames not at tier 0.
    let mut cpu = [Vec::new(), Vec::new(), Vec::new()];
    let mut gpu_ms = [Vec::new(), Vec::new(), Vec::new()];
    let mut cheaper = [0u64; 3];
    let mut play = |k: usize, n: usize, record: bool| {
        let governor = &mut governors[k];
        let (mut c_sum, mut g_sum, mut g_n) = (0.0, 0.0, 0usize);
        for f in 0..n {
            let t0 = Instant::now();
            session.update(dt, &assets.character, viewport);
            let needs = frame_needs(&session, &viewport);
            let tier = governor.select(needs);
            gg.upload(&gpu.queue, &mut session, &assets.character);
            let model = governor.tiers().model(tier);
            let (commands, slot) = encode_timed(&gpu, &gg, &target, &session, model, &mut ring, f);
            gpu.queue.submit([commands]);
            let c = t0.elapsed().as_secs_f64() * 1e3;
            c_sum += c;
            if let (Some(r), Some(s)) = (&ring, slot) {
                r.submitted(s);
            }
            gpu.wait();
            let mut g_frame = f64::NAN;
            if let Some(r) = &mut ring {
                let _ = gpu.device.poll(wgpu::PollType::wait_indefinitely());
                r.harvest(|_, ms| g_frame = ms);
            }
            if g_frame.is_finite() {
                g_sum += g_frame;
                g_n += 1;
            }
            governor.record(
                if g_frame.is_finite() {
                    c.max(g_frame)
                } else {
                    c
                },
                dt as f64,
            );
            if record && tier > 0 {
                cheaper[k] += 1;
            }
        }
        (c_sum / n as f64, g_sum / g_n.max(1) as f64)
    };
    // Warm up every mode.
    for k in 0..3 {
        play(k, 30, false);
    }
    let (rounds, n) = (args.rounds, args.frames);
    for r in 0..rounds {
        for j in 0..3 {
            let k = (j + r) % 3;
            let (c, g) = play(k, n, true);
            cpu[k].push(c);
            gpu_ms[k].push(g);
        }
    }
    let total = (rounds * n) as f64;
    let modes = ["off", "coverage+light", "coverage+light+governor"];
    let rows: Vec<Value> = (0..3)
        .map(|k| {
            let (cr, clo, chi) = ratio_ci(&cpu[k], &cpu[0]);
            let (gr, glo, ghi) = ratio_ci(&gpu_ms[k], &gpu_ms[0]);
            json!({
                "mode": modes[k],
                "frames_at_cheaper_tier_pct": 100.0 * cheaper[k] as f64 / total,
                "cpu_ms_mean": cpu[k].iter().sum::<f64>() / cpu[k].len() as f64,
                "gpu_ms_mean": gpu_ms[k].iter().sum::<f64>() / gpu_ms[k].len() as f64,
                "cpu_ratio_to_off": cr, "cpu_ratio_ci95": [clo, chi],
                "gpu_ratio_to_off": gr, "gpu_ratio_ci95": [glo, ghi],
            })
        })
        .collect();
    let report = json!({
        "adapter": gpu.adapter_name(),
        "cpu_rasterizer": gpu.is_cpu(),
        "size": [w, h],
        "tiers": tiers.as_slice().iter().map(|m| m.name()).collect::<Vec<_>>(),
        "rounds": rounds,
        "frames_per_block": n,
        "gpu_timestamps": ring.is_some(),
        "modes": rows,
    });
    if args.json {
        return crate::cmd::stats::print_json(&report);
    }
    println!("adapter: {}", gpu.adapter_name());
    println!(
        "effect scheduling, tiers {}, runner scene on autoplay, {w}x{h}, {rounds} rounds × {n} frames per mode:",
        report["tiers"]
    );
    println!(
        "  {:<26} {:>9} {:>9} {:>9} {:>20} {:>9} {:>20}",
        "mode", "cheaper %", "CPU ms", "CPU/off", "95 % CI", "GPU/off", "95 % CI"
    );
    let f = |v: &Value| v.as_f64().unwrap_or(f64::NAN);
    for r in &rows {
        println!(
            "  {:<26} {:>9.1} {:>9.3} {:>9.3} {:>20} {:>9.3} {:>20}",
            r["mode"].as_str().unwrap_or("?"),
            f(&r["frames_at_cheaper_tier_pct"]),
            f(&r["cpu_ms_mean"]),
            f(&r["cpu_ratio_to_off"]),
            format!(
                "[{:.3}, {:.3}]",
                f(&r["cpu_ratio_ci95"][0]),
                f(&r["cpu_ratio_ci95"][1])
            ),
            f(&r["gpu_ratio_to_off"]),
            format!(
                "[{:.3}, {:.3}]",
                f(&r["gpu_ratio_ci95"][0]),
                f(&r["gpu_ratio_ci95"][1])
            ),
        );
    }
    Ok(())
}
