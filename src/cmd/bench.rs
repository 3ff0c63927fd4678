//! `dermis bench`: numbers, not assertions (JSON + a human table).

use std::path::PathBuf;
use std::time::Instant;

use dermis_engine::render::{Clock, FrameDriver, Gpu, Offscreen, Output, OFFSCREEN_FORMAT};
use dermis_engine::shading::{material::SKIN1, ShadingModel};
use dermis_engine::still::{Shot, StillRenderer};
use dermis_game::app::{GameFrame, GameGpu, GameLoad, GameSetup};
use serde_json::json;

use crate::cmd::args::{check_out_dir, check_out_file, parse_bench_frames, parse_rounds};
use crate::cmd::gputime::{blob_shadow_coverage, frame_close_up, time_blob_shadows, time_models};
use crate::cmd::progress::Progress;
use crate::cmd::stats::{median, percentile, ratio_ci};

#[derive(clap::Args, Debug)]
pub struct BenchArgs {
    #[command(subcommand)]
    pub what: BenchKind,
}

#[derive(clap::Subcommand, Debug)]
pub enum BenchKind {
    /// Time to first frame, CPU time per frame, each model's GPU time for a close-up
    /// character pass as a ratio to `ward`, the cost of blob shadows on that pass with the
    /// floor (on/off ratio), and the game's own frames (the showroom's close-up, the runner at
    /// the follow camera): skin pixels, the penumbra map's passes, each model's whole frame
    /// as a ratio to `ward`'s and, with `--mali`, its Mali cycles per skin pixel.
    Frame {
        /// Rounds of GPU timing, at least 2 (each round times every model once, in rotating
        /// order, then the blob-shadow models off and on, in alternating order).
        #[arg(long, default_value_t = 30, value_parser = parse_rounds, allow_hyphen_values = true)]
        rounds: usize,
        /// Frames for the CPU timing (at least 10).
        #[arg(long, default_value_t = 300, value_parser = parse_bench_frames, allow_hyphen_values = true)]
        frames: usize,
        /// Write the JSON report to this `.json` file (it is also printed with --json;
        /// checked before the work starts).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Print JSON instead of the table.
        #[arg(long)]
        json: bool,
        /// Only the time to first frame and its breakdown (no CPU or GPU rounds), measured
        /// over two launches (two processes) sharing a fresh pipeline cache: the first builds
        /// every pipeline and saves the cache, the second starts from it; prints both and the
        /// ratio second / first.
        #[arg(long)]
        first_frame_only: bool,
        /// With --first-frame-only: one launch in this process, its pipeline cache kept in
        /// this directory (loaded, then saved once every pipeline is built).
        #[arg(long, requires = "first_frame_only")]
        pipeline_cache: Option<PathBuf>,
        /// Mali cycles (`tools/mali/cycles.sh` JSON of `dermis shaders --spirv`): price each
        /// model per skin pixel at the game's framings.
        #[arg(long)]
        mali: Option<PathBuf>,
    },
    /// The scene's textures loaded and uploaded three ways (block encodings as stored, ETC2
    /// decoded on the CPU, the PNG/JPEG sources decoded): CPU time and GPU bytes of each.
    Textures(crate::cmd::bench_textures::TexturesArgs),
    /// The accuracy-vs-time table: errors against Monte Carlo, GPU cost, shader size.
    Shading(Box<crate::cmd::bench_shading::ShadingArgs>),
    /// GPU and CPU time saved by effect scheduling (tier by coverage and light), on/off ratios.
    Effects(crate::cmd::bench_effects::EffectsArgs),
    /// Every model on the scanned head against its cached Monte Carlo truth (`dermis reference --scene head`).
    Face(crate::cmd::bench_face::FaceArgs),
    /// Every material's tables and LUT from the shipped grids against direct Monte Carlo
    /// bakes: the largest relative difference per table, and the grids' CPU time per material.
    Tables(crate::cmd::bench_tables::TablesArgs),
}

pub fn run(args: BenchArgs) -> Result<(), String> {
    match args.what {
        BenchKind::Frame {
            rounds,
            frames,
            out,
            json,
            first_frame_only,
            pipeline_cache,
            mali,
        } => match (first_frame_only, pipeline_cache) {
            (true, None) => two_launches(out, json),
            (first_frame_only, cache) => {
                let mali = mali
                    .map(|p| crate::cmd::shaders::read_cycles(&p))
                    .transpose()?;
                let opts = FrameOpts {
                    rounds,
                    frames,
                    out,
                    print_json: json,
                    first_frame_only,
                    pipeline_cache: cache,
                    mali,
                };
                frame(opts)
            }
        },
        BenchKind::Textures(args) => crate::cmd::bench_textures::run(args),
        BenchKind::Shading(args) => crate::cmd::bench_shading::run(*args),
        BenchKind::Effects(args) => crate::cmd::bench_effects::run(args),
        BenchKind::Tables(args) => crate::cmd::bench_tables::run(args),
        BenchKind::Face(args) => crate::cmd::bench_face::run(args),
    }
}

/// `--first-frame-only`: two launches of this program, each a process of its own, sharing a
/// pipeline cache directory made fresh for them (and removed after).
fn two_launches(out: Option<PathBuf>, print_json: bool) -> Result<(), String> {
    if let Some(path) = &out {
        check_out_file(path, Some("json"))?;
    }
    let dir = std::env::temp_dir().join(format!("dermis-pipeline-cache-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let exe = std::env::current_exe().map_err(|e| format!("cannot find this program: {e}"))?;
    let mut launches = Vec::new();
    for launch in 1..=2 {
        let run = std::process::Command::new(&exe)
            .args([
                "bench",
                "frame",
                "--first-frame-only",
                "--json",
                "--pipeline-cache",
            ])
            .arg(&dir)
            .stderr(std::process::Stdio::inherit())
            .output()
            .map_err(|e| format!("launch {launch}: {e}"))?;
        if !run.status.success() {
            let _ = std::fs::remove_dir_all(&dir);
            return Err(format!("launch {launch} failed ({})", run.status));
        }
        let report: serde_json::Value = serde_json::from_slice(&run.stdout)
            .map_err(|e| format!("launch {launch}: not a report: {e}"))?;
        launches.push(report);
    }
    let _ = std::fs::remove_dir_all(&dir);
    let ms = |r: &serde_json::Value, k: &str| r["first_frame"][k].as_f64().unwrap_or(f64::NAN);
    let total = |r: &serde_json::Value| r["time_to_first_frame_ms"].as_f64().unwrap_or(f64::NAN);
    let ratio = total(&launches[1]) / total(&launches[0]);
    let render_ratio = ms(&launches[1], "first_render_ms") / ms(&launches[0], "first_render_ms");
    let ready_ratio =
        ms(&launches[1], "everything_ready_ms") / ms(&launches[0], "everything_ready_ms");
    let report = json!({
        "launches": launches,
        "second_over_first": {
            "time_to_first_frame": ratio,
            "first_render": render_ratio,
            "everything_ready": ready_ratio,
        },
        "mesa_shader_cache_disabled": std::env::var("MESA_SHADER_CACHE_DISABLE").is_ok_and(|v| v == "true" || v == "1"),
    });
    let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
    if let Some(path) = &out {
        std::fs::write(path, &text).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    if print_json {
        println!("{text}");
        return Ok(());
    }
    println!(
        "adapter: {}",
        launches[0]["adapter"].as_str().unwrap_or("?")
    );
    for (i, r) in launches.iter().enumerate() {
        println!(
            "launch {} (pipeline cache {}): time to first frame {:.0} ms (device {:.0}, first \
             pipeline and scene upload {:.0}, first frame {:.0}); every pipeline ready at {:.0}; \
             textures on the GPU {:.1} MiB",
            i + 1,
            r["pipeline_cache"]["state"].as_str().unwrap_or("?"),
            total(r),
            ms(r, "device_ms"),
            ms(r, "pipelines_ms"),
            ms(r, "first_render_ms"),
            ms(r, "everything_ready_ms"),
            r["texture_bytes"].as_f64().unwrap_or(f64::NAN) / (1 << 20) as f64,
        );
    }
    println!(
        "second / first: time to first frame {ratio:.3}, first frame {render_ratio:.3}, every \
         pipeline ready {ready_ratio:.3}"
    );
    Ok(())
}

/// `bench frame`'s options (checked, the Mali cycles read).
struct FrameOpts {
    rounds: usize,
    frames: usize,
    out: Option<PathBuf>,
    print_json: bool,
    first_frame_only: bool,
    pipeline_cache: Option<PathBuf>,
    mali: Option<serde_json::Value>,
}

fn frame(opts: FrameOpts) -> Result<(), String> {
    let FrameOpts {
        rounds,
        frames,
        out,
        print_json,
        first_frame_only,
        pipeline_cache,
        mali,
    } = opts;
    if let Some(path) = &out {
        check_out_file(path, Some("json"))?;
    }
    if let Some(dir) = &pipeline_cache {
        check_out_dir(dir)?;
    }
    // The game's own start-up, as the window runs it: the assets, the device, the tables,
    // the game's GPU objects (the player's model's pipeline now, the others' on the background
    // builder) and its first frame (the menu over the showroom), at 1280×720 offscreen.
    let start = Instant::now();
    let mut lap = Instant::now();
    let mut split = || {
        let ms = lap.elapsed().as_secs_f64() * 1e3;
        lap = Instant::now();
        ms
    };
    // As the game window starts: the assets and the session on the loader thread (the
    // showroom's head after them) while the device is created.
    let first_model = ShadingModel::DEFAULT;
    let loading = GameLoad::start(GameSetup {
        shading: Some(first_model),
        ..GameSetup::new(crate::paths::assets_dir())
    });
    let mut gpu = Gpu::headless().map_err(|e| e.to_string())?;
    if let Some(dir) = &pipeline_cache {
        gpu.use_pipeline_cache(dir);
    }
    let device_ms = split();
    let (assets, mut session) = loading.wait()?;
    // Whatever of the load the device did not cover.
    let load_ms = split();
    // The first model's tables for the material (the shipped kernels and LUTs, read once and
    // cached): what loading the scene then finds ready.
    first_model.params(&SKIN1);
    first_model.kernel(&SKIN1);
    first_model.lut(&SKIN1);
    let tables_ms = split();
    let (w, h) = (1280, 720);
    // The frame's targets, then the game's GPU side, in the window's order (its surface and
    // targets come with the device).
    let target = Offscreen::new(&gpu, w, h);
    let mut game_gpu = GameGpu::new(&gpu, OFFSCREEN_FORMAT, &assets, first_model)?;
    let pipelines_ms = split();
    let mut driver = FrameDriver::new(Clock::Fixed(1.0 / 60.0));
    driver.sync = true;
    GameFrame::new(&mut session, &mut game_gpu, &assets.character)
        .run(&mut driver, &gpu, Output::Offscreen(&target))
        .map_err(|e| format!("first frame: {e:?}"))?;
    let render_ms = split();
    let first_frame_ms = start.elapsed().as_secs_f64() * 1e3;
    // The second frame uploads the showroom's head and starts the background builder;
    // then every other pipeline (the head's normal-mapped variants too) arrives.
    GameFrame::new(&mut session, &mut game_gpu, &assets.character)
        .run(&mut driver, &gpu, Output::Offscreen(&target))
        .map_err(|e| format!("second frame: {e:?}"))?;
    game_gpu.finish_loading(&gpu);
    let all_pipelines_ms = start.elapsed().as_secs_f64() * 1e3;
    let texture_bytes = dermis_engine::render::uploaded_bytes();
    drop(game_gpu);
    let cache_state = match &gpu.pipeline_cache {
        None => "none",
        Some(c) if c.loaded => "loaded",
        Some(_) => "empty",
    };
    let cache_saved = gpu.save_pipeline_cache();
    let breakdown = json!({
        "load_ms": load_ms,
        "device_ms": device_ms,
        "tables_ms": tables_ms,
        "pipelines_ms": pipelines_ms,
        "first_render_ms": render_ms,
        "model": first_model.name(),
        "everything_ready_ms": all_pipelines_ms,
    });
    let breakdown_text = format!(
        "device {device_ms:.0} (the assets load meanwhile) + the load's rest {load_ms:.0} + \
         tables {tables_ms:.0} + first pipeline and scene upload {pipelines_ms:.0} + first \
         frame ({}) {render_ms:.0}; a second frame, the head and every pipeline ready at \
         {all_pipelines_ms:.0}",
        first_model.name()
    );
    if first_frame_only {
        let report = json!({
            "adapter": gpu.adapter_name(),
            "time_to_first_frame_ms": first_frame_ms,
            "first_frame": breakdown,
            "texture_bytes": texture_bytes,
            "pipeline_cache": {"state": cache_state, "saved_bytes": cache_saved},
        });
        let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
        if let Some(path) = &out {
            std::fs::write(path, &text).map_err(|e| format!("{}: {e}", path.display()))?;
        }
        if print_json {
            println!("{text}");
        } else {
            println!("adapter: {}", gpu.adapter_name());
            println!("time to first frame: {first_frame_ms:.0} ms ({breakdown_text} ms)");
            println!("textures on the GPU: {texture_bytes} bytes; pipeline cache: {cache_state}");
        }
        return Ok(());
    }
    let mut still = StillRenderer::new(&gpu, &assets, w, h)?;
    let first = Shot {
        clip: 1,
        time: 0.2,
        ..Shot::new(ShadingModel::DEFAULT, SKIN1)
    };
    // Steps: close-up, the CPU frames (in eighths), the GPU rounds, the blob shadows'
    // coverage and their rounds.
    let mut progress = Progress::new("bench frame", (2 + 8 + 4 * rounds) as u64);

    // Close-up: the character alone, zoomed until it covers at least 40 % of the frame.
    let mut close = Shot {
        props: false,
        ..first
    };
    let coverage = frame_close_up(&gpu, &mut still, &assets, &mut close, 0.4)?;
    progress.step("close-up framed");

    // CPU per frame, as a game's frame spends it: the pose + joint palettes + the prepared
    // frame's uniforms and instances + command encoding, the camera framed once (a still's
    // per-shot framing skins every vertex on the CPU for the pose's exact bounds: not a
    // frame's work).
    let clip = usize::from(assets.character.animations.len() > 1);
    let mut shot = Shot {
        shading: Some(ShadingModel::DEFAULT),
        props: true,
        clip,
        ..close.clone()
    };
    let framing = still.framing(&assets, &shot)?;
    let mut cpu_ms = Vec::with_capacity(frames);
    for f in 0..frames {
        let t = Instant::now();
        shot.time = f as f32 / 60.0;
        let frame = still.frame_in(&gpu, &assets, &shot, &framing)?;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        still.encode(&mut encoder, &frame)?;
        let cmd = encoder.finish();
        cpu_ms.push(t.elapsed().as_secs_f64() * 1e3);
        gpu.queue.submit([cmd]);
        if f % 8 == 7 {
            gpu.wait();
        }
        if (f + 1) % frames.div_ceil(8) == 0 {
            progress.step("CPU frames");
        }
    }
    gpu.wait();

    // GPU time per model, interleaved so drift affects every model alike.
    let mut models: Vec<Option<ShadingModel>> =
        ShadingModel::ALL.iter().map(|m| Some(*m)).collect();
    models.push(None);
    let gpu_ms = if gpu.timestamps {
        time_models(&gpu, (&mut still, &assets), &close, &models, rounds, || {
            progress.step("GPU rounds")
        })?
    } else {
        vec![Vec::new(); models.len()]
    };

    // Blob shadows: the same close-up with the showroom floor (and its props), shadows off
    // vs on, for the first one-pass and the first screen-space model of the registry.
    let first_with = |screen_space: bool| {
        ShadingModel::ALL
            .into_iter()
            .find(|m| m.effects().screen_space == screen_space)
            .unwrap_or(ShadingModel::DEFAULT)
    };
    let blob_models = [first_with(false), first_with(true)];
    let (blob_pixels, blob_ms) = if still.enable_blob_shadows(&gpu) {
        let pixels = blob_shadow_coverage(&gpu, &mut still, &assets, &close)?;
        progress.step("blob shadows framed");
        let ms = if gpu.timestamps {
            time_blob_shadows(
                &gpu,
                (&mut still, &assets),
                &close,
                &blob_models,
                rounds,
                || progress.step("blob-shadow rounds"),
            )?
        } else {
            Vec::new()
        };
        (Some(pixels), ms)
    } else {
        (None, Vec::new())
    };
    // The game's own frames at its two framings, every model.
    let game_frames = if gpu.timestamps {
        let framings = crate::cmd::bench_distance::measure(
            &gpu,
            &assets,
            (w, h),
            &ShadingModel::ALL,
            rounds,
            || progress.step("game frames"),
        )?;
        crate::cmd::bench_distance::report(&framings, &ShadingModel::ALL, mali.as_ref())
    } else {
        serde_json::Value::Null
    };
    progress.finish();
    let name = |m: &Option<ShadingModel>| m.map_or("unlit", |m| m.name());
    let ward_at = models
        .iter()
        .position(|m| *m == Some(ShadingModel::BASELINE));
    let ward = &gpu_ms[ward_at.unwrap_or(0)];
    let per_model: Vec<serde_json::Value> = models
        .iter()
        .zip(&gpu_ms)
        .map(|(m, ms)| {
            let (ratio, lo, hi) = ratio_ci(ms, ward);
            json!({"model": name(m), "gpu_ms_median": median(ms), "ratio_to_ward": ratio, "ratio_ci95": [lo, hi]})
        })
        .collect();
    let blob_shadows: Vec<serde_json::Value> = blob_models
        .iter()
        .zip(&blob_ms)
        .map(|(m, [off, on])| {
            let (ratio, lo, hi) = ratio_ci(on, off);
            json!({
                "model": m.name(),
                "off_ms_median": median(off),
                "on_ms_median": median(on),
                "ratio_on_off": ratio,
                "ratio_ci95": [lo, hi],
                "ci_contains_1": lo <= 1.0 && 1.0 <= hi,
            })
        })
        .collect();
    let label = if gpu.is_cpu() {
        "CPU-rasterizer ratios (software Vulkan), not phone GPU ratios"
    } else {
        "GPU timestamp ratios"
    };
    let report = json!({
        "adapter": gpu.adapter_name(),
        "label": label,
        "size": [w, h],
        "character_coverage": coverage,
        "time_to_first_frame_ms": first_frame_ms,
        "first_frame": breakdown,
        "cpu_frame_ms": {"p50": percentile(&cpu_ms, 0.5), "p95": percentile(&cpu_ms, 0.95), "mean": cpu_ms.iter().sum::<f64>() / cpu_ms.len() as f64},
        "gpu_rounds": if gpu.timestamps { rounds } else { 0 },
        "models": per_model,
        "blob_shadow_pixels": blob_pixels,
        "blob_shadows": blob_shadows,
        "game_frames": game_frames,
    });
    let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
    if let Some(path) = &out {
        std::fs::write(path, &text).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    if print_json {
        println!("{text}");
        return Ok(());
    }
    println!("adapter: {}  ({label})", gpu.adapter_name());
    println!("time to first frame: {first_frame_ms:.0} ms ({breakdown_text} ms)");
    println!(
        "CPU per frame (pose + palettes + prepare + encode, the camera framed once): p50 {:.3} ms, p95 {:.3} ms over {frames} frames",
        percentile(&cpu_ms, 0.5),
        percentile(&cpu_ms, 0.95)
    );
    println!(
        "close-up character pass, {w}x{h}, character covers {:.0} % of the frame:",
        coverage * 100.0
    );
    if !gpu.timestamps {
        println!("  (no TIMESTAMP_QUERY on this adapter: no GPU times)");
        return Ok(());
    }
    println!(
        "  {:<15} {:>12} {:>10} {:>18}",
        "model", "median ms", "× ward", "95 % CI"
    );
    for v in report["models"].as_array().into_iter().flatten() {
        println!(
            "  {:<15} {:>12.3} {:>10.3} {:>18}",
            v["model"].as_str().unwrap_or("?"),
            v["gpu_ms_median"].as_f64().unwrap_or(f64::NAN),
            v["ratio_to_ward"].as_f64().unwrap_or(f64::NAN),
            format!(
                "[{:.3}, {:.3}]",
                v["ratio_ci95"][0].as_f64().unwrap_or(f64::NAN),
                v["ratio_ci95"][1].as_f64().unwrap_or(f64::NAN)
            ),
        );
    }
    match blob_pixels {
        None => println!("blob shadows: none (nothing casts)"),
        Some(pixels) => println!(
            "close-up pass with the floor, blob shadows off vs on (they shade {:.1} % of the frame):",
            pixels * 100.0
        ),
    }
    if !blob_shadows.is_empty() {
        println!(
            "  {:<15} {:>9} {:>9} {:>8} {:>18}  cost",
            "model", "off ms", "on ms", "on/off", "95 % CI"
        );
    }
    for v in &blob_shadows {
        let f = |k: &str| v[k].as_f64().unwrap_or(f64::NAN);
        let (lo, hi) = (
            v["ratio_ci95"][0].as_f64().unwrap_or(f64::NAN),
            v["ratio_ci95"][1].as_f64().unwrap_or(f64::NAN),
        );
        println!(
            "  {:<15} {:>9.3} {:>9.3} {:>8.3} {:>18}  {}",
            v["model"].as_str().unwrap_or("?"),
            f("off_ms_median"),
            f("on_ms_median"),
            f("ratio_on_off"),
            format!("[{lo:.3}, {hi:.3}]"),
            if v["ci_contains_1"].as_bool() == Some(true) {
                "none measurable (CI contains 1)"
            } else {
                "measurable (CI excludes 1)"
            },
        );
    }
    print!(
        "{}",
        crate::cmd::bench_distance::table(&report["game_frames"])
    );
    Ok(())
}
