//! `dermis bench effects`: what each effect-scheduling decision saves, on the runner scene on
//! autoplay, offscreen, every frame's GPU pass timed ([`TimerRing`]) and waited for.

use dermis_engine::render::{Clock, FrameDriver, Gpu, Offscreen, Output, OFFSCREEN_FORMAT};
use dermis_engine::scene::SceneAssets;
use dermis_engine::shading::ShadingModel;
use dermis_game::app::{GameFrame, GameGpu, Session};
use dermis_game::governor::{Governor, GovernorConfig, Tiers};
use serde_json::{json, Value};

use crate::cmd::args::parse_model;
use crate::cmd::args::{parse_bench_frames, parse_rounds, parse_size, shading_help};
use crate::cmd::progress::Progress;
use crate::cmd::stats::ratio_ci;

/// `dermis bench effects` arguments.
#[derive(clap::Args, Debug)]
pub struct EffectsArgs {
    /// Rounds (at least 2); each round plays `frames` frames in each mode, in rotating order.
    #[arg(long, default_value_t = 10, value_parser = parse_rounds, allow_hyphen_values = true)]
    pub rounds: usize,
    /// Frames per mode per round (at least 10).
    #[arg(long, default_value_t = 60, value_parser = parse_bench_frames, allow_hyphen_values = true)]
    pub frames: usize,
    #[arg(
        long,
        default_value = "oss",
        value_parser = parse_model,
        help = shading_help("The player's shading model (tier 0)")
    )]
    pub shading: ShadingModel,
    /// Frame size WxH.
    #[arg(long, default_value = "1280x720", value_parser = parse_size, allow_hyphen_values = true)]
    pub size: (u32, u32),
    /// Print JSON instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// GPU and CPU time saved by each scheduling decision, as ratios to scheduling off, all
/// measured in one run: the runner scene on autoplay played in rotating blocks of three modes
/// (off: always the chosen model; coverage + light; coverage + light + frame-time governor),
/// each frame's GPU pass timed and waited for (so blocks do not overlap on the GPU).
pub fn run(args: EffectsArgs) -> Result<(), String> {
    // Steps: the set-up (GPU, pipelines, warm-up), then each block.
    let mut progress = Progress::new("bench effects", 1 + 3 * args.rounds as u64);
    progress.begin("GPU device, pipelines, warm-up");
    let assets = SceneAssets::load(&crate::paths::assets_dir(), None).map_err(|e| e.to_string())?;
    let gpu = Gpu::headless().map_err(|e| e.to_string())?;
    let (w, h) = args.size;
    let mut gg = GameGpu::new(&gpu, OFFSCREEN_FORMAT, &assets, ShadingModel::DEFAULT)?;
    // Every pipeline in place before the first measured frame.
    gg.finish_loading(&gpu);
    let target = Offscreen::new(&gpu, w, h);
    let mut session = Session::new(&assets.character, 1, None, true);
    session.settings.set_shading_model(args.shading);
    let tiers = Tiers::for_choice(args.shading);
    // One governor per mode, so each keeps its own state across its blocks (swapped into
    // the session for its blocks).
    let config = GovernorConfig::for_fps(60.0);
    let mut governors: Vec<Governor> = (0..3)
        .map(|k| {
            let mut g = Governor::new(tiers, config);
            g.scheduling = k >= 1;
            g.enabled = k == 2;
            g
        })
        .collect();
    // Every frame's GPU pass timed and waited for.
    let mut driver = FrameDriver::new(Clock::Fixed(1.0 / 60.0)).with_timer(&gpu);
    driver.sync = true;
    // Per mode, per round: mean CPU ms, mean GPU ms; frames not at tier 0.
    let mut cpu = [Vec::new(), Vec::new(), Vec::new()];
    let mut gpu_ms = [Vec::new(), Vec::new(), Vec::new()];
    let mut cheaper = [0u64; 3];
    let mut play = |k: usize, n: usize, record: bool| -> Result<(f64, f64), String> {
        std::mem::swap(&mut session.governor, &mut governors[k]);
        let (mut c_sum, mut g_sum, mut g_n) = (0.0, 0.0, 0usize);
        for _ in 0..n {
            let times = GameFrame::new(&mut session, &mut gg, &assets.character)
                .run(&mut driver, &gpu, Output::Offscreen(&target))
                .map_err(|s| format!("frame not drawn: {s:?}"))?;
            c_sum += (times.submitted - times.start).as_secs_f64() * 1e3;
            if let Some(&(_, g)) = driver.harvested().last() {
                g_sum += g;
                g_n += 1;
            }
            if record && session.tier() > 0 {
                cheaper[k] += 1;
            }
        }
        std::mem::swap(&mut session.governor, &mut governors[k]);
        Ok((c_sum / n as f64, g_sum / g_n.max(1) as f64))
    };
    // Warm up every mode.
    for k in 0..3 {
        play(k, 30, false)?;
    }
    let (rounds, n) = (args.rounds, args.frames);
    progress.step("warm-up");
    for r in 0..rounds {
        for j in 0..3 {
            let k = (j + r) % 3;
            let (c, g) = play(k, n, true)?;
            cpu[k].push(c);
            gpu_ms[k].push(g);
            progress.step("rounds × modes");
        }
    }
    progress.finish();
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
        "gpu_timestamps": driver.timer().is_some(),
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
