//! `dermis bench face --sweep DIR`: the face under many lights. DIR holds cached face truths
//! (`dermis reference --scene head --light X,Y,Z --out DIR/NAME`, one light per folder, or
//! several lights in one cache); every model is scored under each, strictly (the blocks whose
//! truth has relative SE ≤ `MAX_REL_SE`) and widely (≤ `WIDE_REL_SE`: the terminator, the cast
//! shadows, the sockets), and each light's result is held against the goal for its direction:
//! within [`FRONT_DEG`] of the camera ≤ [`FRONT_GOAL`], further behind ≤ [`BACK_GOAL`] (strict,
//! wide). A light counts where the truth admits ≥ [`MIN_CHANNELS`] strict block channels.
//! Writes `sweep.json`, `sweep.md` and, for each spatial model, a contact sheet
//! `sweep-<model>.png`: per light, the model | the truth | ln(model/truth) per block (red too
//! bright, blue too dark, ±0.5 full scale; grey not scored), each tone-mapped at the truth's
//! own exposure.

use std::path::{Path, PathBuf};

use dermis_engine::asset::head;
use dermis_engine::render::pfm::FloatImage;
use dermis_engine::render::Gpu;
use dermis_engine::scene::face::{self, HEAD_CENTRE};
use dermis_engine::shading::ShadingModel;
use dermis_measure::face::regions::ln_error_png;
use dermis_measure::face::render::HeadRenderer;
use dermis_measure::face::score::{tone_map, BLOCK, WIDE_REL_SE};
use dermis_measure::face::truth::FaceScene;
use dermis_measure::face::truth_cache::{self, CachedTruth};
use glam::Vec3;
use serde_json::json;

use crate::cmd::bench_face::{exposure, FaceArgs};
use crate::cmd::face_diagnosis::mapped;

/// Lights within this angle of the camera (seen from the head's centre) are "in front".
pub const FRONT_DEG: f64 = 120.0;
/// Goals (strict, wide) for a light in front, and for one further behind.
pub const FRONT_GOAL: (f64, f64) = (0.05, 0.12);
pub const BACK_GOAL: (f64, f64) = (0.10, 0.25);
/// Strict block channels a light's truth must admit for the light to count.
pub const MIN_CHANNELS: usize = 200;

/// One cached light of the sweep.
struct Light {
    name: String,
    position: Vec3,
    truth: CachedTruth,
    alpha: Vec<f32>,
}

impl Light {
    /// Degrees between the light and the camera, seen from the head's centre.
    fn degrees_off_camera(&self) -> f64 {
        let cam = (face::camera().eye - HEAD_CENTRE).normalize();
        let dir = (self.position - HEAD_CENTRE).normalize();
        f64::from(cam.dot(dir).clamp(-1.0, 1.0)).acos().to_degrees()
    }

    fn goal(&self) -> (f64, f64) {
        match self.degrees_off_camera() <= FRONT_DEG {
            true => FRONT_GOAL,
            false => BACK_GOAL,
        }
    }
}

/// Every light cached in `dir` and in its sub-folders, by name (a sub-folder's one light
/// takes the folder's name).
fn load_lights(dir: &Path, scene: &FaceScene) -> Result<Vec<Light>, String> {
    let mut caches: Vec<PathBuf> = Vec::new();
    if dir.join(truth_cache::INDEX).is_file() {
        caches.push(dir.to_path_buf());
    }
    let entries = std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut subs: Vec<PathBuf> = entries
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.join(truth_cache::INDEX).is_file())
        .collect();
    subs.sort();
    caches.extend(subs);
    let mut lights = Vec::new();
    for cache in caches {
        let alpha = truth_cache::load_alpha(&cache)?;
        let all = truth_cache::load_all(&cache, scene)?;
        let single = all.len() == 1 && cache != dir;
        for (position, truth) in all {
            let name = match single {
                true => cache.file_name().map_or_else(
                    || truth.record.name.clone(),
                    |n| n.to_string_lossy().into_owned(),
                ),
                false => truth.record.name.clone(),
            };
            lights.push(Light {
                name,
                position,
                truth,
                alpha: alpha.clone(),
            });
        }
    }
    if lights.is_empty() {
        return Err(format!(
            "{}: no cached face truth in it or its folders",
            dir.display()
        ));
    }
    lights.sort_by(|a, b| a.degrees_off_camera().total_cmp(&b.degrees_off_camera()));
    Ok(lights)
}

/// One model under one light: strict and wide mean |ln| (NaN: no block scored), and the
/// strict channels.
#[derive(Clone, Copy)]
struct Cell {
    strict: f64,
    wide: f64,
    channels: usize,
}

/// The side of one panel of a contact sheet (the truth's size) and the gap between cells.
const GAP: u32 = 6;
/// Light cells per row of a contact sheet.
const PER_ROW: u32 = 4;

/// A contact sheet under construction: panels of `side`² pixels, three per light.
struct Sheet {
    side: u32,
    width: u32,
    height: u32,
    rgb: Vec<u8>,
}

impl Sheet {
    fn new(side: u32, lights: usize) -> Self {
        let rows = (lights as u32).div_ceil(PER_ROW);
        let (width, height) = (
            PER_ROW * (3 * side + GAP) + GAP,
            rows * (side + 2 * GAP + 14),
        );
        Self {
            side,
            width,
            height,
            rgb: vec![24; (width * height * 3) as usize],
        }
    }

    /// Pastes `rgb` (`w`×`h`, scaled to the panel's side by nearest neighbour) as panel
    /// `panel` (0 model, 1 truth, 2 ln error) of light cell `i`.
    fn paste(&mut self, i: usize, panel: u32, (w, h, rgb): (u32, u32, &[u8])) {
        let (cx, cy) = (i as u32 % PER_ROW, i as u32 / PER_ROW);
        let x0 = GAP + cx * (3 * self.side + GAP) + panel * self.side;
        let y0 = cy * (self.side + 2 * GAP + 14) + 14 + GAP;
        for y in 0..self.side {
            for x in 0..self.side {
                let (sx, sy) = (x * w / self.side, y * h / self.side);
                let s = ((sy * w + sx) * 3) as usize;
                let d = (((y0 + y) * self.width + x0 + x) * 3) as usize;
                self.rgb[d..d + 3].copy_from_slice(&rgb[s..s + 3]);
            }
        }
    }

    /// Writes the sheet with each cell's label above it.
    fn save(mut self, path: &Path, labels: &[String]) -> Result<(), String> {
        use plotters::prelude::*;
        crate::cmd::chart::ensure_font();
        {
            let area = BitMapBackend::with_buffer(&mut self.rgb, (self.width, self.height))
                .into_drawing_area();
            let style = ("sans-serif", 12).into_font().color(&WHITE);
            for (i, label) in labels.iter().enumerate() {
                let (cx, cy) = (i as u32 % PER_ROW, i as u32 / PER_ROW);
                let x = (GAP + cx * (3 * self.side + GAP)) as i32;
                let y = (cy * (self.side + 2 * GAP + 14) + 2) as i32;
                area.draw(&Text::new(label.as_str(), (x, y), style.clone()))
                    .map_err(|e| e.to_string())?;
            }
            area.present().map_err(|e| e.to_string())?;
        }
        image::save_buffer(
            path,
            &self.rgb,
            self.width,
            self.height,
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| format!("{}: {e}", path.display()))
    }
}

pub fn run(args: &FaceArgs, dir: &Path) -> Result<(), String> {
    let scene = FaceScene::head(&crate::paths::assets_dir())?;
    let lights = load_lights(dir, &scene)?;
    let maps = head::Maps {
        albedo: false,
        normal: !args.no_normal_map,
    };
    let model = head::load_with(&crate::paths::assets_dir(), maps).map_err(|e| e.to_string())?;
    let gpu = Gpu::headless().map_err(|e| e.to_string())?;
    let (w, h) = (scene.width, scene.height);
    let mut renderer = HeadRenderer::new(&gpu, &model, &scene.material, w, h, true)?;
    let camera = face::camera();
    let models = ShadingModel::ALL;
    let mut cells = vec![Vec::with_capacity(lights.len()); models.len()];
    let mut sheets: Vec<Option<Sheet>> = models
        .iter()
        .map(|m| mapped(*m).then(|| Sheet::new(w, lights.len())))
        .collect();
    for (i, light) in lights.iter().enumerate() {
        let reference = &light.truth.reference;
        let wide = reference.clone().with_max_rel_se(WIDE_REL_SE);
        let exposure = exposure(reference, &light.alpha);
        let truth_png = tone_map(&light.truth.reference.full, exposure);
        for (k, &shading) in models.iter().enumerate() {
            let pixels = renderer.radiance(
                &gpu,
                shading,
                &camera,
                light.position,
                light.truth.record.intensity,
            )?;
            let image = FloatImage::new(w, h, pixels)?;
            // A light whose truth admits no block (one from below and behind lights
            // nothing the camera sees) has no score (and does not count).
            let (strict, broad) = (reference.score(&image).ok(), wide.score(&image).ok());
            cells[k].push(Cell {
                strict: strict.map_or(f64::NAN, |s| s.mean_abs_ln),
                wide: broad.map_or(f64::NAN, |s| s.mean_abs_ln),
                channels: strict.map_or(0, |s| s.count),
            });
            if let Some(sheet) = &mut sheets[k] {
                sheet.paste(i, 0, (w, h, &tone_map(&image, exposure)));
                sheet.paste(i, 1, (w, h, &truth_png));
                let (ew, eh, err) = ln_error_png(&wide, &image, BLOCK, None, 0.5, 1);
                sheet.paste(i, 2, (ew, eh, &err));
            }
        }
    }
    let labels: Vec<String> = lights
        .iter()
        .map(|l| {
            format!(
                "{} ({:.0}° from the camera)",
                l.name,
                l.degrees_off_camera()
            )
        })
        .collect();
    for (k, sheet) in sheets.into_iter().enumerate() {
        if let Some(sheet) = sheet {
            let path = args.out.join(format!("sweep-{}.png", models[k].name()));
            sheet.save(&path, &labels)?;
        }
    }
    let report = report(&lights, &cells);
    let md = markdown(&lights, &cells);
    let write = |name: &str, text: &str| {
        let p = args.out.join(name);
        std::fs::write(&p, text).map_err(|e| format!("{}: {e}", p.display()))
    };
    write(
        "sweep.json",
        &(serde_json::to_string_pretty(&report).map_err(|e| e.to_string())? + "\n"),
    )?;
    write("sweep.md", &md)?;
    println!("{md}\n{}", head::ATTRIBUTION);
    Ok(())
}

/// Whether `cell` meets `goal` (strict, wide).
fn meets(cell: &Cell, goal: (f64, f64)) -> bool {
    cell.strict <= goal.0 && cell.wide <= goal.1
}

fn report(lights: &[Light], cells: &[Vec<Cell>]) -> serde_json::Value {
    json!({
        "front_deg": FRONT_DEG, "front_goal": FRONT_GOAL, "back_goal": BACK_GOAL,
        "min_strict_block_channels": MIN_CHANNELS,
        "lights": lights.iter().map(|l| json!({
            "name": l.name, "position_m": l.position.to_array(),
            "degrees_off_camera": l.degrees_off_camera(),
            "photons_per_channel": l.truth.record.photons_per_channel,
            "strict_block_channels": l.truth.reference.scored(),
            "counts": l.truth.reference.scored() >= MIN_CHANNELS,
        })).collect::<Vec<_>>(),
        "models": ShadingModel::ALL.iter().zip(cells).map(|(m, per)| {
            let counted: Vec<(&Light, &Cell)> = lights.iter().zip(per)
                .filter(|(l, _)| l.truth.reference.scored() >= MIN_CHANNELS).collect();
            json!({
                "model": m.name(),
                "lights": per.iter().map(|c| json!({
                    "strict": c.strict, "wide": c.wide, "strict_block_channels": c.channels,
                })).collect::<Vec<_>>(),
                "counted_lights": counted.len(),
                "lights_meeting_goal": counted.iter().filter(|(l, c)| meets(c, l.goal())).count(),
                "worst_strict": counted.iter().map(|(_, c)| c.strict).fold(0.0, f64::max),
                "worst_wide": counted.iter().map(|(_, c)| c.wide).fold(0.0, f64::max),
            })
        }).collect::<Vec<_>>(),
    })
}

fn markdown(lights: &[Light], cells: &[Vec<Cell>]) -> String {
    let models = ShadingModel::ALL;
    let mut md = format!(
        "Strict / wide mean |ln(model/truth)| per light (lights by their angle from the camera; \
         goal within {FRONT_DEG}°: ≤ {} / {}, behind: ≤ {} / {}; a light counts with ≥ \
         {MIN_CHANNELS} strict block channels; ✓ meets its goal):\n\n| light | ° | strict ch. |",
        FRONT_GOAL.0, FRONT_GOAL.1, BACK_GOAL.0, BACK_GOAL.1
    );
    for m in models {
        md += &format!(" {} |", m.name());
    }
    md += &format!("\n|---|---|---|{}\n", "---|".repeat(models.len()));
    for (i, l) in lights.iter().enumerate() {
        let n = l.truth.reference.scored();
        md += &format!("| {} | {:.0} | {n} |", l.name, l.degrees_off_camera());
        for per in cells {
            let c = &per[i];
            let mark = match (n >= MIN_CHANNELS, meets(c, l.goal())) {
                (false, _) => " (not counted)",
                (true, true) => " ✓",
                (true, false) => "",
            };
            let score = |v: f64| match v.is_nan() {
                true => "–".to_string(),
                false => format!("{v:.3}"),
            };
            md += &format!(" {} / {}{mark} |", score(c.strict), score(c.wide));
        }
        md += "\n";
    }
    md += "| **counted lights meeting the goal** | | |";
    for per in cells {
        let counted: Vec<(&Light, &Cell)> = lights
            .iter()
            .zip(per)
            .filter(|(l, _)| l.truth.reference.scored() >= MIN_CHANNELS)
            .collect();
        let ok = counted.iter().filter(|(l, c)| meets(c, l.goal())).count();
        md += &format!(" {ok} of {} |", counted.len());
    }
    md + "\n"
}
