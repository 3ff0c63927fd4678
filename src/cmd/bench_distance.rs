//! `bench frame`'s game frames: the showroom's close-up on the main menu and the runner at the
//! follow camera in play, each frozen (drawn again and again at one instant), measured per
//! shading model: how many pixels the skin covers (the frame drawn with `ward` against the
//! same frame with the first model of the penumbra effect, the tier that reads the penumbra
//! map: nothing else differs), whether the penumbra map runs and
//! with how many jump passes, and the whole frame's GPU time (every pass: shadow map, penumbra
//! map, scene, subsurface, UI) as a ratio to `ward`'s with a 95 % CI. With Mali cycles
//! (`--mali`), each one-pass model's price per skin pixel at each framing: its fragment
//! shader plus the frame's penumbra passes spread over the skin — each pass's cycles per
//! texel times the texels it shaded in that frame, as the renderer counted them
//! (`RenderStats::texels`) — and, for the penumbra tier, those parts apart (the shadow map,
//! drawn for every model alike, is not counted: the ratio to `ward` is the stricter for it).

use dermis_engine::render::passes::NAMES as PASS_NAMES;
use dermis_engine::render::{
    Clock, FrameDriver, FrameOutput, Gpu, Offscreen, Output, RgbaImage, OFFSCREEN_FORMAT,
    PENUMBRA_BLOCK, SHADOW_MAP_SIZE,
};
use dermis_engine::scene::SceneAssets;
use dermis_engine::shading::ShadingModel;
use dermis_game::app::{GameFrame, GameGpu, Session};
use dermis_game::governor::GovernorConfig;
use dermis_game::rules::Screen;
use serde_json::{json, Value};

use crate::cmd::shaders::{mali_cost, penumbra_cycles, PenumbraRun};
use crate::cmd::stats::{median, ratio_ci};

/// Frames the menu plays before the showroom is measured, and frames of play before the
/// follow camera is (the camera's swing from the showroom is long over).
const MENU_FRAMES: usize = 30;
const PLAY_FRAMES: usize = 240;
/// The most frames the menu may take before the bot starts a run.
const START_FRAMES: usize = 600;

/// One framing's measurements.
pub struct Framing {
    pub name: &'static str,
    /// Pixels that differ between the `ward` frame and the penumbra tier's.
    pub skin_pixels: u64,
    /// Jump passes of the penumbra map in the penumbra tier's frame (`None`: not run).
    pub penumbra_jumps: Option<usize>,
    /// The texels its passes shaded in that frame (the seed pass's, the jump passes').
    pub penumbra: PenumbraRun,
    /// Per model (`models` order): GPU ms per round.
    pub gpu_ms: Vec<Vec<f64>>,
}

/// The game, offscreen at `size`, on autoplay with the scheduling and the frame-time governor
/// off (the model drawn is the one chosen), measured at its two framings with `rounds` GPU
/// timings of each of `models` per framing. `tick` is called after each round.
pub fn measure(
    gpu: &Gpu,
    assets: &SceneAssets,
    size: (u32, u32),
    models: &[ShadingModel],
    rounds: usize,
    mut tick: impl FnMut(),
) -> Result<Vec<Framing>, String> {
    let mut gg = GameGpu::new(gpu, OFFSCREEN_FORMAT, assets, ShadingModel::BASELINE)?;
    gg.finish_loading(gpu);
    let target = Offscreen::new(gpu, size.0, size.1);
    let mut session = Session::new(&assets.character, 1, None, true);
    let choose = |session: &mut Session, m: ShadingModel| {
        session.settings.set_shading_model(m);
        session.configure_governor(GovernorConfig::for_fps(60.0), false, false);
    };
    choose(&mut session, ShadingModel::BASELINE);
    let mut play = FrameDriver::new(Clock::Fixed(1.0 / 60.0));
    play.sync = true;
    // Frozen: the same instant again (dt 0), every frame's GPU time taken.
    let mut still = FrameDriver::new(Clock::Fixed(0.0)).with_timer(gpu);
    still.sync = true;
    let penumbra = PASS_NAMES
        .iter()
        .position(|n| *n == "penumbra")
        .ok_or("no penumbra pass")?;
    let penumbra_tier = ShadingModel::ALL
        .into_iter()
        .find(|m| m.effects().penumbra)
        .ok_or("no model reads the penumbra map")?;
    let mut out = Vec::new();
    let mut frames = 0usize;
    for (name, wanted) in [("showroom", Screen::Main), ("follow", Screen::Play)] {
        // Play on until this framing has lasted long enough.
        let mut in_screen = 0usize;
        let needed = if wanted == Screen::Main {
            MENU_FRAMES
        } else {
            PLAY_FRAMES
        };
        while in_screen < needed {
            GameFrame::new(&mut session, &mut gg, &assets.character)
                .run(&mut play, gpu, Output::Offscreen(&target))
                .map_err(|s| format!("frame not drawn: {s:?}"))?;
            frames += 1;
            in_screen = if session.game.screen() == wanted {
                in_screen + 1
            } else {
                0
            };
            if frames > START_FRAMES + PLAY_FRAMES + MENU_FRAMES {
                return Err(format!(
                    "bench frame: no {name} framing after {frames} frames"
                ));
            }
        }
        // The skin: what `ward` and the penumbra tier draw differently at this instant.
        let mut shot = |session: &mut Session, m: ShadingModel| -> Result<_, String> {
            choose(session, m);
            let mut copy =
                |encoder: &mut wgpu::CommandEncoder, _: &Session, _: &FrameOutput<'_>| {
                    target.copy_out(encoder);
                };
            let mut game = GameFrame::new(session, &mut gg, &assets.character);
            game.after_encode = Some(&mut copy);
            game.run(&mut still, gpu, Output::Offscreen(&target))
                .map_err(|s| format!("frame not drawn: {s:?}"))?;
            let runs = game.stats.passes[penumbra];
            let [seed, jumps] = game.stats.texels[penumbra];
            let run = PenumbraRun {
                seed_texels: seed as f64,
                jump_texels: jumps as f64,
            };
            Ok((target.read(gpu), runs, run))
        };
        let (ward, _, _) = shot(&mut session, ShadingModel::BASELINE)?;
        let (pre, runs, run) = shot(&mut session, penumbra_tier)?;
        let skin_pixels = differing(&ward, &pre);
        let penumbra_jumps = (runs > 0).then(|| runs as usize - 1);
        // GPU time per model, in rotating order, after a frame of each.
        let mut gpu_ms = vec![Vec::with_capacity(rounds); models.len()];
        let mut timed = |session: &mut Session, m: ShadingModel| -> Result<Option<f64>, String> {
            choose(session, m);
            GameFrame::new(session, &mut gg, &assets.character)
                .run(&mut still, gpu, Output::Offscreen(&target))
                .map_err(|s| format!("frame not drawn: {s:?}"))?;
            Ok(still.harvested().last().map(|h| h.1))
        };
        for &m in models {
            timed(&mut session, m)?;
        }
        for r in 0..rounds {
            for k in 0..models.len() {
                let i = (k + r) % models.len();
                if let Some(ms) = timed(&mut session, models[i])? {
                    gpu_ms[i].push(ms);
                }
            }
            tick();
        }
        choose(&mut session, ShadingModel::BASELINE);
        out.push(Framing {
            name,
            skin_pixels,
            penumbra_jumps,
            penumbra: run,
            gpu_ms,
        });
    }
    Ok(out)
}

/// Pixels of `a` and `b` that differ by more than 2 in a colour channel.
fn differing(a: &RgbaImage, b: &RgbaImage) -> u64 {
    a.pixels
        .chunks_exact(4)
        .zip(b.pixels.chunks_exact(4))
        .filter(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > 2))
        .count() as u64
}

/// The JSON of `framings` for `models`: skin pixels, the penumbra map's passes, each model's
/// frame time as a ratio to `ward`'s and, with `mali`, its price per skin pixel on each GPU
/// (and as a ratio to `ward`'s).
pub fn report(framings: &[Framing], models: &[ShadingModel], mali: Option<&Value>) -> Value {
    let ward = models
        .iter()
        .position(|m| *m == ShadingModel::BASELINE)
        .unwrap_or(0);
    let grid = SHADOW_MAP_SIZE / PENUMBRA_BLOCK;
    let rows: Vec<Value> = framings
        .iter()
        .map(|f| {
            let run = f.penumbra;
            let px = f.skin_pixels as f64;
            // One-pass models only (a screen-space model's subsurface pass runs over the
            // whole frame, not per skin pixel: `bench shading` prices it at full screen).
            let price = |m: ShadingModel, g: &str| {
                let mali = mali.filter(|_| !m.effects().screen_space)?;
                mali_cost(mali, Some(m), g, (0, 0), 0, px, run).map(|c| c.0)
            };
            // What the price is made of: the fragment shader, the seed and the jump passes
            // spread over the skin.
            let parts = |m: ShadingModel, g: &str| -> Option<Value> {
                let mali = mali.filter(|_| m.effects().penumbra)?;
                let fragment = mali_cost(mali, Some(m), g, (0, 0), 0, px, PenumbraRun::default())?.0;
                let (seed, jumps) = penumbra_cycles(mali, g, run)?;
                Some(json!({"fragment": fragment, "seed": seed / px.max(1.0),
                            "jumps": jumps / px.max(1.0)}))
            };
            let per_model: Vec<Value> = models
                .iter()
                .zip(&f.gpu_ms)
                .map(|(&m, ms)| {
                    let (r, lo, hi) = ratio_ci(ms, &f.gpu_ms[ward]);
                    let mut cycles = serde_json::Map::new();
                    for g in ["G52", "G57"] {
                        let p = price(m, g);
                        let w = price(ShadingModel::BASELINE, g);
                        cycles.insert(
                            g.into(),
                            json!({"per_skin_pixel": p, "ratio_to_ward": p.zip(w).map(|(p, w)| p / w),
                                   "parts": parts(m, g)}),
                        );
                    }
                    json!({"model": m.name(), "gpu_ms_median": median(ms),
                           "frame_ratio_to_ward": r, "frame_ratio_ci95": [lo, hi],
                           "mali": cycles})
                })
                .collect();
            json!({"framing": f.name, "skin_pixels": f.skin_pixels,
                   "penumbra": {"runs": f.penumbra_jumps.is_some(), "jumps": f.penumbra_jumps,
                                "grid_texels": grid * grid, "seed_texels": run.seed_texels,
                                "jump_texels": run.jump_texels},
                   "models": per_model})
        })
        .collect();
    Value::Array(rows)
}

/// The table of [`report`].
pub fn table(report: &Value) -> String {
    let mut s = String::new();
    let f = |v: &Value, d: usize| v.as_f64().map_or("–".into(), |x| format!("{x:.d$}"));
    for fr in report.as_array().into_iter().flatten() {
        let pen = &fr["penumbra"];
        s += &format!(
            "{} framing: skin covers {} pixels; penumbra map {}\n",
            fr["framing"].as_str().unwrap_or("?"),
            fr["skin_pixels"],
            match pen["jumps"].as_u64() {
                Some(j) => format!(
                    "runs (seed over {} and {j} jump passes over {} texels in all, of a grid of {})",
                    pen["seed_texels"], pen["jump_texels"], pen["grid_texels"]
                ),
                None => "not run".into(),
            }
        );
        s += &format!(
            "  {:<15} {:>10} {:>8} {:>18} {:>12} {:>8} {:>12} {:>8}\n",
            "model",
            "frame ms",
            "× ward",
            "95 % CI",
            "G52/skin px",
            "× ward",
            "G57/skin px",
            "× ward"
        );
        for m in fr["models"].as_array().into_iter().flatten() {
            s += &format!(
                "  {:<15} {:>10} {:>8} {:>18} {:>12} {:>8} {:>12} {:>8}\n",
                m["model"].as_str().unwrap_or("?"),
                f(&m["gpu_ms_median"], 3),
                f(&m["frame_ratio_to_ward"], 3),
                format!(
                    "[{}, {}]",
                    f(&m["frame_ratio_ci95"][0], 3),
                    f(&m["frame_ratio_ci95"][1], 3)
                ),
                f(&m["mali"]["G52"]["per_skin_pixel"], 2),
                f(&m["mali"]["G52"]["ratio_to_ward"], 3),
                f(&m["mali"]["G57"]["per_skin_pixel"], 2),
                f(&m["mali"]["G57"]["ratio_to_ward"], 3),
            );
        }
        for m in fr["models"].as_array().into_iter().flatten() {
            let parts = &m["mali"]["G57"]["parts"];
            if parts.is_null() {
                continue;
            }
            let p = &m["mali"]["G52"]["parts"];
            s += &format!(
                "  {} per skin pixel, G52 / G57: fragment {} / {}, penumbra seed {} / {}, jumps {} / {}\n",
                m["model"].as_str().unwrap_or("?"),
                f(&p["fragment"], 2),
                f(&parts["fragment"], 2),
                f(&p["seed"], 3),
                f(&parts["seed"], 3),
                f(&p["jumps"], 3),
                f(&parts["jumps"], 3),
            );
        }
    }
    s
}
