//! Charts drawn with plotters: the font they need (registered at run time) and the soak's
//! chart. (`bench shading` draws its accuracy–cost chart in `pareto.rs`.)

use std::ops::Range;
use std::path::Path;
use std::sync::Once;

use dermis_core::shading::ShadingModel;
use dermis_core::soak::{FrameRec, SecondRec};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::cmd::stats::percentile;

/// Fonts tried, in order (Debian: fonts-dejavu-core).
const FONTS: [&str; 3] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
];

/// Registers "sans-serif" once; charts are drawn without text when no font is found.
pub fn ensure_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        for path in FONTS {
            if let Ok(bytes) = std::fs::read(path) {
                let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
                if plotters::style::register_font(
                    "sans-serif",
                    plotters::style::FontStyle::Normal,
                    bytes,
                )
                .is_ok()
                {
                    return;
                }
            }
        }
        log::warn!("no DejaVuSans.ttf found (apt: fonts-dejavu-core): charts have no text");
    });
}

/// A panel of `area`: a caption, time in seconds on x (0..`t_max`), `y_desc` over `y`.
fn panel<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    caption: &str,
    t_max: f64,
    y: Range<f64>,
    y_desc: &str,
) -> Result<ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>, String> {
    let mut c = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(30)
        .y_label_area_size(55)
        .build_cartesian_2d(0.0..t_max, y)
        .map_err(|x| x.to_string())?;
    c.configure_mesh()
        .x_desc("s")
        .y_desc(y_desc)
        .draw()
        .map_err(|x| x.to_string())?;
    Ok(c)
}

/// The soak's chart (`dermis soak`'s `soak.png`): frame time (CPU, GPU, budget), tier and
/// resident memory over time, three panels.
pub fn soak_png(
    frames: &[FrameRec],
    seconds: &[SecondRec],
    tiers: &[ShadingModel],
    budget_ms: f64,
    path: &Path,
) -> Result<(), String> {
    ensure_font();
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
    let mut c = panel(&panels[0], "Frame time", t_max, 0.0..y_max.max(1.0), "ms")?;
    let budget = vec![(0.0, budget_ms), (t_max, budget_ms)];
    for (points, line, key, label) in [
        (cpu, BLUE.to_rgba(), BLUE, "CPU"),
        (gpu, RED.to_rgba(), RED, "GPU"),
        (budget, BLACK.mix(0.5), BLACK, "budget"),
    ] {
        c.draw_series(LineSeries::new(
            points.into_iter().map(|(t, v)| (t, v.min(y_max))),
            line,
        ))
        .map_err(|x| e(&x))?
        .label(label)
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], key));
    }
    c.configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|x| e(&x))?;

    let names: Vec<&str> = tiers.iter().map(|m| m.name()).collect();
    let top = names.len().max(1) as f64 - 0.5;
    let caption = format!("Shading tier (0 = {})", names.join(", "));
    let mut c = panel(&panels[1], &caption, t_max, -0.5..top, "tier")?;
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
    let mut c = panel(&panels[2], "Resident memory", t_max, lo..hi, "MiB")?;
    c.draw_series(LineSeries::new(mem, &MAGENTA))
        .map_err(|x| e(&x))?;
    root.present().map_err(|x| e(&x))?;
    Ok(())
}
