//! `dermis bench shading`: accuracy against cost for every shading model (Markdown, JSON, a
//! Pareto chart).
//!
//! - **Accuracy**: every scene of the path-traced reference set (`tools/reference/`, both
//!   acceptance materials) rendered through the real renderer (`dermis_measure::scenes`) and
//!   scored with `ground_truth::metric` (mean |ln(model/MC)| over the bins above the MC's noise
//!   floor; the integrated error; the MC's own relative SE).
//! - **Cost (a)**: GPU time of a full-screen pass on this adapter (a flat skin patch filling a
//!   1280x720 target, point light, close-up scale), both passes for screen-space models,
//!   interleaved rounds, median and paired ratios with 95 % CIs.
//! - **Cost (b)**: Mali-G52/G57 fragment cycles per pixel from Mesa's compiler
//!   (`dermis shaders --spirv` + `tools/mali/cycles.sh`), the subsurface pass added for the
//!   screen-space models, loops weighted by their iteration counts (see [`mali_cost`]).

use std::path::PathBuf;

use crate::cmd::args::{check_out_dir, parse_reference_photons, parse_rounds};
use crate::cmd::material_args::MaterialArgs;
use crate::cmd::progress::Progress;
use dermis_engine::anim::Pose;
use dermis_engine::asset::shapes::plane_model;
use dermis_engine::asset::Model;
use dermis_engine::render::{Gpu, Offscreen, PassCtx, PassTimer, Renderer, OFFSCREEN_FORMAT};
use dermis_engine::scene::{DrawSet, FramePacket, FrameView, Light, Roles, SubjectPose};
use dermis_engine::shading::{subsurface, Material, ShadingModel};
use dermis_measure::ground_truth::metric::score;
use dermis_measure::ground_truth::{self, ReferenceSet};
use dermis_measure::scenes::SceneRenderer;
use glam::{Mat4, Vec3};
use serde_json::{json, Map, Value};

use crate::cmd::pareto::{self, aggregate, family, SceneScore};
use crate::cmd::shaders::{mali_cost, read_cycles, PenumbraRun};
use crate::cmd::stats::{median, ratio_ci};

#[derive(clap::Args, Debug)]
pub struct ShadingArgs {
    /// Output directory (shading.md, shading.json, pareto.png, governor-front.txt).
    #[arg(long)]
    pub out: PathBuf,
    /// Rounds of GPU timing, 2..=1000 (each round times every model once, in rotating order).
    #[arg(long, default_value_t = 20, value_parser = parse_rounds, allow_hyphen_values = true)]
    pub rounds: usize,
    /// Mali cycle counts: `tools/mali/cycles.sh` JSON over `dermis shaders --spirv DIR`
    /// (default: docs/results/mali-cycles.json; the columns stay empty if that is missing).
    #[arg(long)]
    pub mali: Option<PathBuf>,
    /// One material instead of the presets and the test materials: a name, coefficients,
    /// albedo and mean free path, or a file's skin material (then no governor-front.txt).
    #[command(flatten)]
    pub medium: MaterialArgs,
    /// The reference set of that material (`dermis reference … --out DIR` writes it); without
    /// it a named material's is read from tools/reference/ and any other is computed first by
    /// the Monte Carlo (minutes) and written to the output directory.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Photons per channel and scene of a reference computed first, 1000..=1e9 (default: as
    /// `dermis reference`).
    #[arg(long, value_parser = parse_reference_photons, allow_hyphen_values = true)]
    pub photons: Option<u64>,
    /// Bake the tables and LUT of every material no preset file covers directly by the Monte
    /// Carlo (seconds for the tables, a minute or two for the LUT) instead of interpolating
    /// them from the shipped grids as the game does: the grid's yardstick.
    #[arg(long)]
    pub direct_bake: bool,
}

/// Target of the cost scene.
pub const COST_SIZE: (u32, u32) = (1280, 720);
/// Width of the cost scene's view on the skin (mm): a close-up, 0.2 mm per pixel.
pub const COST_VIEW_MM: f64 = 256.0;
/// Mali GPUs reported.
pub const GPUS: [&str; 2] = ["G52", "G57"];

/// The scored materials with their reference sets.
type References = Vec<(Material, ReferenceSet)>;

/// What is scored: the materials of the main columns, and those scored beside them.
struct Scored {
    primary: Vec<Material>,
    beside: Vec<Material>,
}

impl Scored {
    /// The presets in the main columns and the test materials beside them (the governor's
    /// front), or one material of the user's.
    fn of(args: &ShadingArgs) -> Result<Self, String> {
        let m = &args.medium;
        if !(m.is_custom() || m.material.is_some() || m.eta.is_some() || m.g.is_some()) {
            return Ok(Self {
                primary: ground_truth::acceptance_materials().to_vec(),
                beside: ground_truth::test_materials().to_vec(),
            });
        }
        Ok(Self {
            primary: vec![m.resolve("skin1", crate::cmd::reference::named)?],
            beside: Vec::new(),
        })
    }

    fn single(&self) -> bool {
        self.beside.is_empty()
    }
}

/// `material`'s reference set: `--reference`, else the committed one of a named material
/// with the same optics, else none (computed once the checks are done).
fn find_reference(args: &ShadingArgs, m: &Material) -> Result<Option<ReferenceSet>, String> {
    let path = match &args.reference {
        Some(p) => p.clone(),
        None => ground_truth::file_for(&ground_truth::default_dir(), &m.name),
    };
    if args.reference.is_none() && !path.is_file() {
        return Ok(None);
    }
    let set = ReferenceSet::load(&path)?;
    // (Files written before the optics were saved exactly keep six significant digits.)
    let same = |a: f64, b: f64| (a - b).abs() <= 1e-5 * a.abs().max(b.abs()).max(1e-12);
    let matches = (0..3).all(|c| {
        same(set.sigma_a[c], m.sigma_a[c]) && same(set.sigma_s_prime[c], m.sigma_s_prime[c])
    }) && same(set.eta, m.eta)
        && same(set.g, m.g);
    match (matches, args.reference.is_some()) {
        (true, _) => Ok(Some(set)),
        (false, true) => Err(format!(
            "{}: the reference is of σ_a {:?}, σ'_s {:?}, η {}, g {}, not of the material asked for",
            path.display(),
            set.sigma_a,
            set.sigma_s_prime,
            set.eta,
            set.g
        )),
        (false, false) => Ok(None),
    }
}

/// The checks that need no GPU: output directory, reference files, Mali file (`--rounds`
/// is range-checked by its parser); then the references no file holds, computed.
fn prepare(args: &ShadingArgs, scored: &Scored) -> Result<(References, Option<Value>), String> {
    check_out_dir(&args.out)?;
    let mut found = Vec::new();
    for m in scored.primary.iter().chain(&scored.beside) {
        found.push((m.clone(), find_reference(args, m)?));
    }
    let mali = match &args.mali {
        Some(path) => Some(read_cycles(path)?),
        None => {
            let local = PathBuf::from("docs/results/mali-cycles.json");
            let source = PathBuf::from(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/docs/results/mali-cycles.json"
            ));
            [local, source]
                .iter()
                .find(|p| p.is_file())
                .map(|p| read_cycles(p))
                .transpose()?
        }
    };
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut sets = Vec::new();
    for (m, set) in found {
        let set = match set {
            Some(set) => set,
            None => {
                let photons = args
                    .photons
                    .unwrap_or_else(|| crate::cmd::reference::default_photons(&m));
                let scenes = ground_truth::standard_scenes(&m);
                let mut progress = Progress::new(&format!("reference {}", m.name), 1);
                let set = ReferenceSet::generate(&m, &scenes, photons, 1, threads, |d, t| {
                    progress.set(d as u64, t as u64, "simulations")
                });
                progress.finish();
                let path = args.out.join(format!("reference-{}.json", m.name));
                set.save(&path)?;
                eprintln!(
                    "bench shading: the reference of {} written to {}",
                    m.name,
                    path.display()
                );
                set
            }
        };
        sets.push((m, set));
    }
    Ok((sets, mali))
}

pub fn run(args: ShadingArgs) -> Result<(), String> {
    let scored = Scored::of(&args)?;
    if args.direct_bake {
        dermis_measure::bake::install();
    }
    let (sets, mali) = prepare(&args, &scored)?;
    let models = ShadingModel::ALL;
    let scenes: usize = sets.iter().map(|(_, s)| s.entries.len()).sum();
    let mut progress = Progress::new(
        "bench shading",
        (1 + scenes * models.len() + args.rounds + 2) as u64,
    );
    progress.begin("GPU device");
    let gpu = Gpu::headless().map_err(|e| e.to_string())?;
    progress.step("GPU device");

    // Accuracy: per model, every scene of every material.
    let mut scores: Vec<Vec<SceneScore>> = models.iter().map(|_| Vec::new()).collect();
    let mut probe = SceneRenderer::new(&gpu);
    for (material, set) in &sets {
        for entry in &set.entries {
            for (i, &model) in models.iter().enumerate() {
                let result = probe
                    .render(&gpu, model, material, &entry.scene, &entry.edges)
                    .map(|rendered| score(&rendered, entry));
                scores[i].push(SceneScore {
                    material: material.name.to_string(),
                    scene: entry.scene,
                    result,
                });
                progress.step(&format!("{} {}", material.name, entry.scene.label()));
            }
        }
    }
    drop(probe);

    // Cost (a): this adapter's GPU time of the full-screen pass.
    let material = sets[0].0.clone();
    let mut cost = CostScene::new(&gpu, &material)?;
    progress.step("cost scene");
    let coverage = cost.coverage(&gpu);
    let mut timed: Vec<Option<ShadingModel>> = models.iter().map(|m| Some(*m)).collect();
    timed.push(None);
    let mut times = vec![Vec::new(); timed.len()];
    if cost.timer.is_some() {
        for m in &timed {
            for _ in 0..2 {
                cost.time(&gpu, *m);
            }
        }
        for r in 0..args.rounds {
            for k in 0..timed.len() {
                let i = (k + r) % timed.len();
                times[i].push(cost.time(&gpu, timed[i]).ok_or("timestamp read failed")?);
            }
            progress.step("GPU time (full-screen pass)");
        }
    }
    progress.finish();

    let report = build_report(
        &gpu,
        &args,
        (&scored, &sets),
        &scores,
        &times,
        coverage,
        mali.as_ref(),
    );
    let json_path = args.out.join("shading.json");
    let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
    std::fs::write(&json_path, text).map_err(|e| format!("{}: {e}", json_path.display()))?;
    let md = pareto::markdown(&report);
    let md_path = args.out.join("shading.md");
    std::fs::write(&md_path, &md).map_err(|e| format!("{}: {e}", md_path.display()))?;
    let png = args.out.join("pareto.png");
    pareto::chart(&report, &png)?;
    let mut wrote = vec![json_path, md_path, png];
    // The governor's tiers come from the game's materials, not from one of the user's.
    if !scored.single() {
        let front = args.out.join("governor-front.txt");
        std::fs::write(&front, pareto::front_file(&report))
            .map_err(|e| format!("{}: {e}", front.display()))?;
        wrote.push(front);
    }
    println!("{md}");
    let wrote: Vec<String> = wrote.iter().map(|p| p.display().to_string()).collect();
    println!("wrote {}", wrote.join(", "));
    Ok(())
}

/// The cost scene: a skin patch filling the target, seen from straight above.
struct CostScene {
    renderer: Renderer,
    target: Offscreen,
    timer: Option<PassTimer>,
    patch: (Model, Pose),
    view: FrameView,
}

impl CostScene {
    fn new(gpu: &Gpu, material: &Material) -> Result<Self, String> {
        let (w, h) = COST_SIZE;
        let mut renderer = Renderer::new(gpu, OFFSCREEN_FORMAT);
        let target = Offscreen::new(gpu, w, h);
        let half_w = (COST_VIEW_MM / 2000.0) as f32;
        let half_h = half_w * h as f32 / w as f32;
        // 5 mm thick (translucency terms see a thin part), reaching well past the view.
        let model = plane_model(2.0 * half_w, 0.005);
        renderer.load_character(gpu, &model, &Roles::medium(material))?;
        renderer.resize(gpu, (w, h));
        let mut pose = Pose::new(&model);
        pose.update_world(&model);
        let view = glam::camera::rh::view::look_at_mat4(Vec3::Y, Vec3::ZERO, Vec3::Z);
        let proj = glam::camera::rh::proj::directx::orthographic(
            -half_w, half_w, -half_h, half_h, 0.01, 10.0,
        );
        let view = FrameView {
            view_proj: proj * view,
            camera_pos: Vec3::Y,
            light: Light {
                position: Vec3::new(0.02, 0.05, 0.01),
                intensity: 0.01,
                color: Vec3::ONE,
                ambient: Vec3::splat(0.02),
            },
            exposure: 1.0,
        };
        let timer = PassTimer::new(&gpu.device, &gpu.queue);
        Ok(Self {
            renderer,
            target,
            timer,
            patch: (model, pose),
            view,
        })
    }

    fn encode(&mut self, gpu: &Gpu, shading: Option<ShadingModel>, character: bool, timed: bool) {
        let draw = DrawSet {
            shading,
            character,
            props: false,
            ui: false,
        };
        let t = &self.target;
        let (model, pose) = &self.patch;
        let packet = FramePacket {
            subject: Some(SubjectPose {
                model,
                pose,
                world: Mat4::IDENTITY,
            }),
            ..FramePacket::new((t.targets.width, t.targets.height), self.view, draw)
        };
        let frame = self.renderer.prepare(gpu, &packet);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let timer = self.timer.as_ref().filter(|_| timed);
        let encoded = self.renderer.encode(
            &frame,
            &mut PassCtx {
                encoder: &mut encoder,
                targets: &t.targets,
                output: &t.view,
                timer,
            },
        );
        if let Err(e) = encoded {
            log::error!("{e}");
        }
        if let Some(timer) = timer {
            timer.resolve(&mut encoder);
        } else {
            t.copy_out(&mut encoder);
        }
        gpu.queue.submit([encoder.finish()]);
    }

    /// GPU time (ms) of one frame drawn with `shading` (`None`: unlit).
    fn time(&mut self, gpu: &Gpu, shading: Option<ShadingModel>) -> Option<f64> {
        self.encode(gpu, shading, true, true);
        self.timer.as_ref()?.read_ms(&gpu.device)
    }

    /// Fraction of the target the skin covers (Ward against the empty frame).
    fn coverage(&mut self, gpu: &Gpu) -> f64 {
        self.encode(gpu, None, false, false);
        let empty = self.target.read(gpu);
        self.encode(gpu, Some(ShadingModel::BASELINE), true, false);
        let drawn = self.target.read(gpu);
        let n = empty.pixels.len() / 4;
        let covered = (0..n)
            .filter(|&i| {
                (0..3).any(|c| empty.pixels[4 * i + c].abs_diff(drawn.pixels[4 * i + c]) > 2)
            })
            .count();
        covered as f64 / n.max(1) as f64
    }
}

/// A model's scene scores split into the main columns' materials' and each material scored
/// beside them (in order).
fn split_presets(
    all: &[SceneScore],
    scored: &Scored,
) -> (Vec<SceneScore>, Vec<(String, Vec<SceneScore>)>) {
    let presets: Vec<String> = scored.primary.iter().map(|m| m.name.to_string()).collect();
    let copy = |s: &SceneScore| SceneScore {
        material: s.material.clone(),
        scene: s.scene,
        result: s.result.clone(),
    };
    let mine = all
        .iter()
        .filter(|s| presets.contains(&s.material))
        .map(copy)
        .collect();
    let others = scored
        .beside
        .iter()
        .map(|m| {
            let v = all
                .iter()
                .filter(|s| s.material == *m.name)
                .map(copy)
                .collect();
            (m.name.to_string(), v)
        })
        .collect();
    (mine, others)
}

/// Rings of `model`'s kernel (all, and those the subsurface pass samples at the cost
/// scene's scale: a ring whose outer radius is under half a pixel is taken at the pixel).
fn kernel_rings(model: ShadingModel, material: &Material) -> (usize, usize) {
    let mm_per_px = COST_VIEW_MM / COST_SIZE.0 as f64;
    model.kernel(material).map_or((0, 0), |k| {
        let sampled = k
            .rings
            .iter()
            .filter(|(_, outer)| outer / mm_per_px >= 0.5)
            .count();
        (k.rings.len(), sampled)
    })
}

fn build_report(
    gpu: &Gpu,
    args: &ShadingArgs,
    (scored, sets): (&Scored, &[(Material, ReferenceSet)]),
    scores: &[Vec<SceneScore>],
    times: &[Vec<f64>],
    coverage: f64,
    mali: Option<&Value>,
) -> Value {
    let mut families: Vec<String> = Vec::new();
    for (_, set) in sets {
        for e in &set.entries {
            let f = family(&e.scene);
            if !families.contains(&f) {
                families.push(f);
            }
        }
    }
    let material = &sets[0].0;
    let penumbra = PenumbraRun::runner(dermis_engine::shading::edge_spread::reach_mm(material));
    let n = times.len();
    let (ward, unlit) = (&times[0], &times[n - 1]);
    let mut rows = Vec::new();
    for i in 0..n {
        let model = ShadingModel::ALL.get(i).copied();
        let (r_ward, lo, hi) = ratio_ci(&times[i], ward);
        let (r_unlit, ulo, uhi) = ratio_ci(&times[i], unlit);
        let rings = model.map_or((0, 0), |m| kernel_rings(m, material));
        let mut m_json = Map::new();
        for g in GPUS {
            let c = mali.and_then(|v| {
                mali_cost(
                    v,
                    model,
                    g,
                    rings,
                    subsurface::ANGLES as usize,
                    (COST_SIZE.0 * COST_SIZE.1) as f64,
                    penumbra,
                )
            });
            m_json.insert(
                g.into(),
                json!({"static": c.map(|c| c.0), "per_pixel": c.map(|c| c.1)}),
            );
        }
        let mut row = json!({
            "model": model.map_or("unlit", |m| m.name()),
            "screen_space": model.is_some_and(|m| m.effects().screen_space),
            "lavapipe_ms_median": median(&times[i]),
            "ratio_to_ward": r_ward, "ratio_to_ward_ci95": [lo, hi],
            "ratio_to_unlit": r_unlit, "ratio_to_unlit_ci95": [ulo, uhi],
            "mali": m_json,
            "sss_rings": {"all": rings.0, "sampled": rings.1},
        });
        if let Some(all) = model.map(|_| &scores[i]) {
            // The presets' columns; each test material's overall beside them.
            let (s, others) = split_presets(all, scored);
            let s = &s;
            let mut per_material = Map::new();
            for (name, scores) in &others {
                let (fam, overall) = aggregate(scores, &families, |e| e.mean_log_all);
                let fam: Map<String, Value> = families.iter().cloned().zip(fam).collect();
                per_material.insert(
                    name.to_string(),
                    json!({"overall": overall, "families": fam}),
                );
            }
            row["materials"] = Value::Object(per_material);
            let (fam, overall) = aggregate(s, &families, |e| e.mean_log_all);
            let (_, integrated) = aggregate(s, &families, |e| e.integrated_all);
            let (fam_se, se) = aggregate(s, &families, |e| e.ref_rel_se_all);
            let scenes: Vec<Value> = s
                .iter()
                .map(|x| {
                    json!({"material": x.material, "scene": x.scene.label(),
                           "result": match &x.result {
                               Ok(e) => json!({"mean_log": e.mean_log_all, "integrated": e.integrated_all, "mc_rel_se": e.ref_rel_se_all}),
                               Err(e) => json!(format!("error: {e}")) }})
                })
                .collect();
            row["error"] = json!({
                "families": families.iter().cloned().zip(fam).collect::<Map<_, _>>(),
                "overall": overall, "integrated": integrated,
                "mc_rel_se": families.iter().cloned().zip(fam_se).collect::<Map<_, _>>(),
                "mc_rel_se_overall": se, "scenes": scenes,
            });
        }
        rows.push(row);
    }
    // The face column: every model on the scanned head against the cached Mitsuba 3
    // references (`bench face` has the per-light detail and ꟻLIP).
    match crate::cmd::bench_face::face_scores(gpu) {
        Ok(faces) => {
            for (model, per_light) in faces {
                let mean = per_light.iter().map(|p| p.1).sum::<f64>() / per_light.len() as f64;
                if let Some(row) = rows.iter_mut().find(|r| r["model"] == json!(model.name())) {
                    let mut face: Map<String, Value> =
                        per_light.into_iter().map(|(l, v)| (l, json!(v))).collect();
                    face.insert("mean".into(), json!(mean));
                    row["face"] = Value::Object(face);
                }
            }
        }
        Err(e) => eprintln!("bench shading: no face column: {e}"),
    }
    let ward_g57 = rows[0]["mali"]["G57"]["per_pixel"].as_f64();
    for row in &mut rows {
        let r = row["mali"]["G57"]["per_pixel"]
            .as_f64()
            .zip(ward_g57)
            .map(|(a, b)| a / b);
        row["mali"]["G57_ratio_to_ward"] = json!(r);
    }
    let presets: Vec<String> = scored.primary.iter().map(|m| m.name.to_string()).collect();
    json!({
        "presets": presets,
        "primary_materials": scored.primary.iter().map(|m| json!({
            "material": m.name, "sigma_a": m.sigma_a, "sigma_s_prime": m.sigma_s_prime,
            "eta": m.eta, "g": m.g,
        })).collect::<Vec<_>>(),
        "test_materials": scored.beside.iter().map(|m| json!({
            "material": m.name, "sigma_a": m.sigma_a, "sigma_s_prime": m.sigma_s_prime,
            "multi_scatter_albedo": m.albedo().map(|a| dermis_engine::shading::albedo::multi_scatter_albedo(a, m.eta, m.g)),
        })).collect::<Vec<_>>(),
        "adapter": gpu.adapter_name(),
        "label": if gpu.is_cpu() { "CPU-rasterizer ratios (software Vulkan), not phone GPU ratios" } else { "GPU timestamp ratios" },
        "cost_scene": {"size": [COST_SIZE.0, COST_SIZE.1], "view_mm": COST_VIEW_MM,
                       "mm_per_pixel": COST_VIEW_MM / COST_SIZE.0 as f64, "coverage": coverage,
                       "material": material.name, "timestamps": !times[0].is_empty()},
        "rounds": args.rounds,
        "references": sets.iter().map(|(m, s)| json!({"material": m.name, "eta": s.eta, "g": s.g,
            "photons": s.entries.first().map(|e| e.photons), "scenes": s.entries.len()})).collect::<Vec<_>>(),
        "families": families,
        "sss_angles": subsurface::ANGLES,
        "mali": mali.map(|v| json!({"compiler": v["compiler"], "mesa_debian_version": v["mesa_debian_version"], "options": v["options"]})),
        "models": rows,
    })
}
