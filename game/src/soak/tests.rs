use super::*;
use crate::governor::Needs;
use dermis_engine::render::LiveObjects;
use std::time::{Duration, Instant};

fn cfg(seconds: f64, gpu_timed: bool) -> RecorderConfig {
    RecorderConfig {
        seconds,
        target_fps: 60.0,
        tiers: vec![ShadingModel::Oss, ShadingModel::Ward],
        gpu_timed,
    }
}

fn sample(frame: usize, at: Instant, cpu_ms: f64, model: ShadingModel) -> FrameSample {
    FrameSample {
        frame,
        at,
        cpu_ms,
        submit_ms: 0.1,
        allocs: 3,
        model,
        needs: Needs {
            coverage: 0.1,
            lit: true,
        },
        governor_changes: 0,
    }
}

/// Runs `n` frames at 60 fps from `t0`, returning the closed seconds and the next instant.
fn run_frames(
    r: &mut Recorder,
    first: usize,
    n: usize,
    t0: Instant,
    cpu_ms: f64,
) -> (Vec<SecondRec>, Instant) {
    let period = Duration::from_secs_f64(1.0 / 60.0);
    let mut seconds = Vec::new();
    let mut at = t0;
    for i in 0..n {
        at += period;
        seconds.extend(r.frame(sample(first + i, at, cpu_ms, ShadingModel::Oss)));
    }
    (seconds, at)
}

#[test]
fn the_soak_clock_stops_while_paused() {
    let start = Instant::now();
    let mut r = Recorder::new(cfg(20.0, false), start);
    let (mut seconds, at) = run_frames(&mut r, 0, 600, start, 2.0);
    assert!((r.clock_s(at) - 10.0).abs() < 1e-6);
    assert!(!r.done(at));
    // Ten minutes in the background: no frames, and the clock does not move.
    r.pause(at);
    assert!(r.is_paused());
    let back = at + Duration::from_secs(600);
    assert!((r.clock_s(back) - 10.0).abs() < 1e-6, "{}", r.clock_s(back));
    r.resume(back);
    let (more, end) = run_frames(&mut r, 600, 600, back, 2.0);
    seconds.extend(more);
    assert!(r.done(end) && (r.clock_s(end) - 20.0).abs() < 1e-6);
    r.finish_frames();
    let mut frames = Vec::new();
    r.take_final(&mut frames);
    assert_eq!(frames.len(), 1200);
    assert!(frames
        .windows(2)
        .all(|w| w[1].t_s > w[0].t_s && w[1].t_s - w[0].t_s < 0.02));
    // The pause is not a late frame: every interval is one period.
    let s = r.summary(&seconds, r.clock_s(end), LiveObjects::default(), 1);
    let h = &s["present_histogram"];
    assert_eq!(h["late_1"], 0);
    assert_eq!(h["late_3_plus"], 0);
    assert_eq!(s["frames"], 1200);
    assert!((s["mean_fps"].as_f64().unwrap() - 60.0).abs() < 0.5, "{s}");
    assert!(s["stability_pct"].as_f64().unwrap() > 97.0, "{s}");
    assert_eq!(seconds.len(), 20);
}

#[test]
fn late_gpu_times_fill_their_frames_and_missing_ones_go_untimed() {
    let start = Instant::now();
    let mut r = Recorder::new(cfg(10.0, true), start);
    let period = Duration::from_secs_f64(1.0 / 60.0);
    let mut seconds = Vec::new();
    let mut out = Vec::new();
    for i in 0..600usize {
        seconds.extend(r.frame(sample(
            i,
            start + period * (i as u32 + 1),
            1.0,
            ShadingModel::Oss,
        )));
        // GPU times come back 3 frames late; every 10th frame's is lost; 25 ms over budget
        // every 50th.
        if i >= 3 && (i - 3) % 10 != 0 {
            let f = i - 3;
            r.gpu_time(f, if f % 50 == 1 { 25.0 } else { 5.0 });
        }
        r.take_final(&mut out);
    }
    r.finish_frames();
    r.take_final(&mut out);
    assert_eq!(out.len(), 600);
    assert!(out.windows(2).all(|w| w[1].frame == w[0].frame + 1));
    let untimed = out.iter().filter(|f| f.gpu_ms.is_none()).count();
    // 60 lost, plus the last 3 whose times never came.
    assert_eq!(untimed, 63);
    let s = r.summary(&seconds, 10.0, LiveObjects::default(), 0);
    assert_eq!(s["gpu_untimed_frames"], 63);
    assert_eq!(s["gpu_frame_ms"]["max"], 25.0);
    // Over budget: the 25 ms frames after the 1 s warm-up.
    let over = out
        .iter()
        .filter(|f| f.t_s >= 1.0 && f.gpu_ms == Some(25.0))
        .count();
    assert!(over > 0);
    assert_eq!(s["frames_over_budget"], over);
    let p50 = s["gpu_frame_ms"]["p50"].as_f64().unwrap();
    assert!((p50 - 5.0).abs() < 0.02, "{p50}");
    assert!(seconds.iter().skip(1).all(|s| s.gpu_ms_mean.is_some()));
}

#[test]
fn the_recorder_does_not_grow_with_the_frame_count() {
    let start = Instant::now();
    let mut r = Recorder::new(cfg(3600.0, true), start);
    let mut out = Vec::new();
    let (_, at) = run_frames(&mut r, 0, 1000, start, 1.0);
    r.take_final(&mut out);
    let early = r.bytes();
    // An hour at 60 fps, final frames taken away each second as a shell does.
    let mut at = at;
    for k in 0..3580 {
        let (_, next) = run_frames(&mut r, 1000 + k * 60, 60, at, 1.0);
        at = next;
        out.clear();
        r.take_final(&mut out);
    }
    assert!(r.frames() > 200_000);
    assert_eq!(r.bytes(), early, "the recorder grew");
    assert!(r.bytes() < 512 * 1024, "{} bytes", r.bytes());
}

#[test]
fn tiers_changes_and_gpu_objects() {
    let start = Instant::now();
    let mut r = Recorder::new(cfg(4.0, false), start);
    let period = Duration::from_secs_f64(1.0 / 60.0);
    let live = LiveObjects {
        buffers: 10,
        texture_views: 4,
        ..LiveObjects::default()
    };
    for i in 0..240usize {
        let model = if (100..150).contains(&i) {
            ShadingModel::Ward
        } else {
            ShadingModel::Oss
        };
        let at = start + period * (i as u32 + 1);
        if let Some(sec) = r.frame(sample(i, at, 1.0, model)) {
            let buffers = 10 + sec.t_s as isize;
            r.gpu_objects(sec.t_s, LiveObjects { buffers, ..live });
        }
    }
    let s = r.summary(&[], 4.0, LiveObjects { buffers: 9, ..live }, 2);
    assert_eq!(s["tier_frames"], json!([190, 50]));
    assert_eq!(s["tier_changes"], 2);
    // Buffers come and go; the load-time objects stayed.
    assert_eq!(s["gpu_objects_constant"], true);
    assert_eq!(s["gpu_buffers_live_range"], json!([11, 14]));
    let s = r.summary(
        &[],
        4.0,
        LiveObjects {
            texture_views: 5,
            ..live
        },
        2,
    );
    assert_eq!(s["gpu_objects_constant"], false);
}

#[test]
fn report_and_summary_text() {
    let start = Instant::now();
    let mut r = Recorder::new(cfg(3.0, false), start);
    let (seconds, at) = run_frames(&mut r, 0, 180, start, 1.0);
    let seconds: Vec<SecondRec> = seconds
        .into_iter()
        .map(|mut s| {
            s.rss_mb = Some(100.0 + s.t_s);
            s.rust_heap_mb = Some(20.0);
            s
        })
        .collect();
    let s = r.summary(&seconds, r.clock_s(at), LiveObjects::default(), 1);
    let run = RunInfo {
        platform: "desktop",
        adapter: "test".into(),
        cpu_rasterizer: true,
        size: (64, 32),
        uncapped: false,
        seed: 1,
        shading: ShadingModel::Oss,
        governor: true,
        scheduling: true,
        frames_in_flight: Some(2),
    };
    let config = config_json(r.config(), &run);
    let lines = summary_lines(&config, &s);
    for word in [
        "stability",
        "memory",
        "Rust heap",
        "present intervals",
        "tiers",
    ] {
        assert!(lines.iter().any(|l| l.contains(word)), "{word}: {lines:?}");
    }
    assert!((s["memory_growth_mb_per_min"].as_f64().unwrap() - 60.0).abs() < 1e-6);
    assert_eq!(s["memory_parts"]["rust_heap"]["growth_mb_per_min"], 0.0);
    let rep = report("complete", &config, &seconds, Some(&s));
    assert_eq!(rep["format"], FORMAT);
    assert_eq!(rep["summary"]["frames"], 180);
    assert_eq!(rep["config"]["tiers"], json!(["oss", "ward"]));
}
