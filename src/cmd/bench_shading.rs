//! `dermis bench shading`: the accuracy-vs-time table (Markdown, JSON, Pareto chart PNG).
//!
//! Accuracy: each model renders a flat semi-infinite medium lit by a point light at height h
//! (the same shaders the game uses, through the character pipeline), and its radial radiance
//! is compared with the Monte Carlo exitance for the same set-up; and each model's own total
//! diffuse reflectance with the Monte Carlo's. Cost: GPU time of the close-up character pass
//! as a ratio to `ward` and to an unlit shader, plus the paper's Table 2 protocol; shader
//! size as in Table 3.

use std::path::{Path, PathBuf};

use dermis_core::flat::FlatScene;
use dermis_core::mc::{self, Medium};
use dermis_core::render::Gpu;
use dermis_core::scene::SceneAssets;
use dermis_core::shader::compose;
use dermis_core::shading::{material, prediction, Material, ShadingModel};
use dermis_core::still::{Shot, StillRenderer};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{json, Value};

use crate::cmd::gputime::{frame_close_up, time_models};
use crate::cmd::stats::{median, ratio_ci};

#[derive(clap::Args, Debug)]
pub struct ShadingArgs {
    /// Output directory (shading.md, shading.json, pareto.png).
    #[arg(long)]
    pub out: PathBuf,
    /// Photons per channel for each Monte Carlo run.
    #[arg(long, default_value_t = 20_000)]
    pub photons: u64,
    /// Rounds of GPU timing.
    #[arg(long, default_value_t = 20)]
    pub rounds: usize,
}

/// Light height (mm) and radial bins (mm) of the flat-medium comparison.
const H_MM: f64 = 5.0;
const EDGES_MM: [f64; 15] = [
    0.0, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.5, 15.0, 20.0, 25.0,
];
/// Radii over which errors are averaged (mm).
const RANGE_MM: (f64, f64) = (1.0, 20.0);
/// Light intensity in the flat scene (keeps radiance inside f16's comfortable range).
const INTENSITY: f32 = 1e-4;

struct Accuracy {
    profile_mean: f64,
    profile_max: f64,
    integral: f64,
    total_mean: f64,
    total_max: f64,
}

fn configs() -> Vec<Material> {
    let mut out = Vec::new();
    for base in [material::SKIN1, material::WHITE_COAT] {
        for eta in [1.0936, 1.4] {
            for g in [0.0, 0.8] {
                out.push(Material { eta, g, ..base });
            }
        }
    }
    out
}

fn medium(m: &Material, c: usize) -> Medium {
    Medium {
        sigma_a: m.sigma_a[c],
        sigma_s_prime: m.sigma_s_prime[c],
        g: m.g,
        eta: m.eta,
    }
}

/// SPIR-V words → instruction count (each instruction's first word holds its word count).
fn spirv_instructions(words: &[u32]) -> usize {
    let (mut i, mut n) = (5, 0);
    while i < words.len() {
        let len = (words[i] >> 16) as usize;
        if len == 0 {
            break;
        }
        i += len;
        n += 1;
    }
    n
}

/// (WGSL bytes, SPIR-V bytes, SPIR-V instructions) of the composed character shader.
pub fn shader_size(model: ShadingModel) -> Result<(usize, usize, usize), String> {
    let src = compose("character", &model.defs()).map_err(|e| e.to_string())?;
    let module = naga::front::wgsl::parse_str(&src).map_err(|e| e.emit_to_string(&src))?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .map_err(|e| e.emit_to_string(&src))?;
    let words =
        naga::back::spv::write_vec(&module, &info, &naga::back::spv::Options::default(), None)
            .map_err(|e| e.to_string())?;
    Ok((src.len(), words.len() * 4, spirv_instructions(&words)))
}

pub fn run(args: ShadingArgs) -> Result<(), String> {
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let gpu = Gpu::headless().map_err(|e| e.to_string())?;
    let configs = configs();
    let models = ShadingModel::ALL;
    let steps = (configs.len() * (models.len() + 1) + args.rounds + 10) as u64;
    let bar = ProgressBar::new(steps);
    bar.set_style(
        ProgressStyle::with_template("{msg:28} [{bar:40}] {pos}/{len} {elapsed}")
            .map_err(|e| e.to_string())?,
    );

    // Accuracy.
    let mut flat = FlatScene::new(&gpu, 30.0)?;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut errors: Vec<Vec<Accuracy>> = models.iter().map(|_| Vec::new()).collect();
    let mut per_config = Vec::new();
    for (ci, m) in configs.iter().enumerate() {
        bar.set_message(format!("{} η={} g={}", m.name, m.eta, m.g));
        let mut expected = vec![[0.0f64; 3]; EDGES_MM.len() - 1];
        let mut total = [0.0f64; 3];
        let entered = 1.0 / (1.0 - mc::fresnel::fresnel(1.0, m.eta).0);
        for c in 0..3 {
            let seed = 1000 + ci as u64 * 10 + c as u64;
            let profile = mc::point_light_profile(
                &medium(m, c),
                H_MM,
                &EDGES_MM,
                args.photons,
                seed,
                threads,
            );
            for (b, v) in profile.values.iter().enumerate() {
                // L = M/π with M = M_MC [mm⁻²] · 1e6 [mm²/m²] · 4π I.
                expected[b][c] = v * 1e6 * 4.0 * INTENSITY as f64;
            }
            total[c] = mc::total_reflectance(&medium(m, c), args.photons, seed + 5, threads).mean
                * entered;
        }
        bar.inc(1);
        let mut row = serde_json::Map::new();
        for (mi, &model) in models.iter().enumerate() {
            let rendered = flat.radial_radiance(&gpu, model, m, H_MM, INTENSITY, &EDGES_MM);
            let mut rels = Vec::new();
            let (mut int_r, mut int_e) = ([0.0; 3], [0.0; 3]);
            for (b, w) in EDGES_MM.windows(2).enumerate() {
                let mid = 0.5 * (w[0] + w[1]);
                let area = std::f64::consts::PI * (w[1] * w[1] - w[0] * w[0]);
                for c in 0..3 {
                    int_r[c] += rendered[b][c] * area;
                    int_e[c] += expected[b][c] * area;
                    if mid >= RANGE_MM.0 && mid <= RANGE_MM.1 && expected[b][c] > 0.0 {
                        rels.push((rendered[b][c] / expected[b][c] - 1.0).abs());
                    }
                }
            }
            let predicted = prediction::total_reflectance(model, m, None);
            let tot: Vec<f64> = (0..3)
                .map(|c| (predicted[c] / total[c] - 1.0).abs())
                .collect();
            let acc = Accuracy {
                profile_mean: rels.iter().sum::<f64>() / rels.len().max(1) as f64,
                profile_max: rels.iter().copied().fold(0.0, f64::max),
                integral: (0..3)
                    .map(|c| (int_r[c] / int_e[c] - 1.0).abs())
                    .sum::<f64>()
                    / 3.0,
                total_mean: tot.iter().sum::<f64>() / 3.0,
                total_max: tot.iter().copied().fold(0.0, f64::max),
            };
            row.insert(
                model.name().into(),
                json!({"profile_mean_rel_err": acc.profile_mean, "profile_max_rel_err": acc.profile_max,
                       "integral_rel_err": acc.integral, "total_reflectance": predicted,
                       "total_mean_rel_err": acc.total_mean}),
            );
            errors[mi].push(acc);
            bar.inc(1);
        }
        per_config.push(
            json!({"material": m.name, "eta": m.eta, "g": m.g, "mc_total": total, "models": row}),
        );
    }

    // Cost.
    bar.set_message("GPU time (close-up pass)");
    let assets = SceneAssets::load(&crate::paths::assets_dir(), None).map_err(|e| e.to_string())?;
    let mut still = StillRenderer::new(&gpu, &assets, 1280, 720)?;
    let mut close = Shot {
        clip: 1,
        time: 0.2,
        props: false,
        ..Shot::new(ShadingModel::Ward, material::SKIN1)
    };
    let coverage = frame_close_up(&gpu, &mut still, &assets, &mut close, 0.4)?;
    still.setup(&gpu, &assets, &close)?;
    let mut timed: Vec<Option<ShadingModel>> = models.iter().map(|m| Some(*m)).collect();
    timed.push(None);
    let times = if gpu.timestamps {
        time_models(&gpu, &mut still, &timed, args.rounds, || bar.inc(1))?
    } else {
        vec![Vec::new(); timed.len()]
    };
    // The paper's protocol (Table 2): the animated character, a sample every 30 frames, the
    // peak of 3 consecutive frames at each of 10 samples, averaged.
    bar.set_message("GPU time (paper protocol)");
    let mut paper = vec![Vec::new(); timed.len()];
    if gpu.timestamps {
        for sample in 0..10 {
            let t = sample as f32 * 30.0 / 60.0;
            still.setup(
                &gpu,
                &assets,
                &Shot {
                    time: t % 0.7,
                    ..close
                },
            )?;
            for (i, m) in timed.iter().enumerate() {
                let peak = (0..3)
                    .filter_map(|_| still.time_character_pass(&gpu, *m))
                    .fold(0.0, f64::max);
                paper[i].push(peak);
            }
            bar.inc(1);
        }
    }
    bar.finish_and_clear();

    let label = if gpu.is_cpu() {
        "CPU-rasterizer ratios (software Vulkan), not phone GPU ratios"
    } else {
        "GPU timestamp ratios"
    };
    let ward = times[0].clone();
    let unlit = times[timed.len() - 1].clone();
    let mut rows = Vec::new();
    for (i, model) in timed.iter().enumerate() {
        let name = model.map_or("unlit", |m| m.name());
        let (r_ward, lo, hi) = ratio_ci(&times[i], &ward);
        let (r_unlit, ulo, uhi) = ratio_ci(&times[i], &unlit);
        let size = shader_size(model.unwrap_or(ShadingModel::Ward))
            .ok()
            .filter(|_| model.is_some());
        let acc = model.map(|_| &errors[i]);
        let mean =
            |f: fn(&Accuracy) -> f64| acc.map(|a| a.iter().map(f).sum::<f64>() / a.len() as f64);
        let max = |f: fn(&Accuracy) -> f64| acc.map(|a| a.iter().map(f).fold(0.0, f64::max));
        rows.push(json!({
            "model": name,
            "profile_mean_rel_err": mean(|a| a.profile_mean),
            "profile_max_rel_err": max(|a| a.profile_max),
            "integral_mean_rel_err": mean(|a| a.integral),
            "total_mean_rel_err": mean(|a| a.total_mean),
            "total_max_rel_err": max(|a| a.total_max),
            "gpu_ms_median": median(&times[i]),
            "ratio_to_ward": r_ward, "ratio_to_ward_ci95": [lo, hi],
            "ratio_to_unlit": r_unlit, "ratio_to_unlit_ci95": [ulo, uhi],
            "paper_protocol_ms": if paper[i].is_empty() { f64::NAN } else { paper[i].iter().sum::<f64>() / paper[i].len() as f64 },
            "wgsl_bytes": size.map(|s| s.0), "spirv_bytes": size.map(|s| s.1), "spirv_instructions": size.map(|s| s.2),
        }));
    }
    let report = json!({
        "adapter": gpu.adapter_name(),
        "label": label,
        "light_height_mm": H_MM,
        "error_radius_range_mm": [RANGE_MM.0, RANGE_MM.1],
        "photons_per_channel": args.photons,
        "close_up_coverage": coverage,
        "rounds": args.rounds,
        "models": rows,
        "configs": per_config,
    });
    let json_path = args.out.join("shading.json");
    std::fs::write(
        &json_path,
        serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?,
    )
    .map_err(|e| format!("{}: {e}", json_path.display()))?;
    let md = markdown(&report);
    std::fs::write(args.out.join("shading.md"), &md).map_err(|e| e.to_string())?;
    pareto_png(&report, &args.out.join("pareto.png"))?;
    println!("{md}");
    println!("wrote {}, shading.md and pareto.png", json_path.display());
    Ok(())
}

fn f(v: &Value, digits: usize) -> String {
    v.as_f64().map_or("–".into(), |x| {
        if x.is_finite() {
            format!("{x:.digits$}")
        } else {
            "–".into()
        }
    })
}

fn pct(v: &Value) -> String {
    v.as_f64()
        .map_or("–".into(), |x| format!("{:.1} %", x * 100.0))
}

pub fn markdown(report: &Value) -> String {
    let mut s = format!(
        "Adapter: {} — {}. Close-up character pass at 1280x720 (character covers {:.0} %), {} rounds. \
         Errors: flat semi-infinite medium, point light at h = {} mm, radii {}–{} mm, over skin1 and white coat × \
         η ∈ {{1.0936, 1.4}} × g ∈ {{0, 0.8}}; Monte Carlo {} photons per channel.\n\n",
        report["adapter"].as_str().unwrap_or("?"),
        report["label"].as_str().unwrap_or(""),
        report["close_up_coverage"].as_f64().unwrap_or(0.0) * 100.0,
        report["rounds"],
        report["light_height_mm"],
        report["error_radius_range_mm"][0],
        report["error_radius_range_mm"][1],
        report["photons_per_channel"],
    );
    s.push_str("| model | profile err mean | profile err max | total R err mean | total R err max | GPU ms | × ward (95 % CI) | × unlit | Table 2 ms | WGSL B | SPIR-V B | SPIR-V instr |\n");
    s.push_str("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for r in report["models"].as_array().into_iter().flatten() {
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} ({}–{}) | {} | {} | {} | {} | {} |\n",
            r["model"].as_str().unwrap_or("?"),
            pct(&r["profile_mean_rel_err"]),
            pct(&r["profile_max_rel_err"]),
            pct(&r["total_mean_rel_err"]),
            pct(&r["total_max_rel_err"]),
            f(&r["gpu_ms_median"], 2),
            f(&r["ratio_to_ward"], 3),
            f(&r["ratio_to_ward_ci95"][0], 3),
            f(&r["ratio_to_ward_ci95"][1], 3),
            f(&r["ratio_to_unlit"], 3),
            f(&r["paper_protocol_ms"], 2),
            r["wgsl_bytes"],
            r["spirv_bytes"],
            r["spirv_instructions"],
        ));
    }
    s
}

/// Error (log scale) against GPU cost, one labelled point per model.
fn pareto_png(report: &Value, path: &Path) -> Result<(), String> {
    use plotters::prelude::*;
    crate::cmd::chart::ensure_font();
    let points: Vec<(String, f64, f64)> = report["models"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|r| {
            let e = r["profile_mean_rel_err"].as_f64()?.max(1e-4);
            let c = r["ratio_to_ward"].as_f64()?;
            (e.is_finite() && c.is_finite())
                .then(|| (r["model"].as_str().unwrap_or("?").to_string(), c, e))
        })
        .collect();
    let root = BitMapBackend::new(path, (900, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (cmin, cmax) = points
        .iter()
        .fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.1), a.1.max(p.1)));
    let (emin, emax) = points
        .iter()
        .fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.2), a.1.max(p.2)));
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Accuracy vs GPU cost (rendered flat-medium profile vs Monte Carlo)",
            ("sans-serif", 20),
        )
        .margin(20)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(
            (cmin * 0.9)..(cmax * 1.1),
            (emin * 0.5..emax * 2.0).log_scale(),
        )
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc("GPU time of the close-up character pass / ward")
        .y_desc("mean relative error of the rendered profile")
        .draw()
        .map_err(|e| e.to_string())?;
    chart
        .draw_series(points.iter().map(|(name, c, e)| {
            EmptyElement::at((*c, *e))
                + Circle::new((0, 0), 5, BLUE.filled())
                + Text::new(name.clone(), (8, -8), ("sans-serif", 15))
        }))
        .map_err(|e| e.to_string())?;
    root.present().map_err(|e| e.to_string())?;
    Ok(())
}
