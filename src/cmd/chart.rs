//! Charts drawn with plotters: the font they need (registered at run time) and the soak's
//! chart. (`bench shading` draws its accuracy–cost chart in `pareto.rs`.)

use std::ops::Range;
use std::path::Path;
use std::sync::Once;

use dermis_engine::shading::ShadingModel;
use dermis_game::soak::SecondRec;
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

/// Draws a `size` chart with `draw` into an RGB buffer and writes it to `path` as PNG (plotters
/// draws, the project's `image` encodes: plotters' own encoder would build a second `image`).
pub fn png(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&DrawingArea<BitMapBackend<'_>, Shift>) -> Result<(), String>,
) -> Result<(), String> {
    let mut rgb = vec![255u8; (size.0 * size.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        draw(&root)?;
        root.present().map_err(|e| e.to_string())?;
    }
    image::save_buffer(path, &rgb, size.0, size.1, image::ExtendedColorType::Rgb8)
        .map_err(|e| format!("{}: {e}", path.display()))
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

/// The soak's chart (`dermis soak`'s `soak.png`), from the per-second records: frame time
/// (CPU mean and max, GPU mean and max, the budget), the tier, and memory (resident, C
/// allocator in use, Rust heap) over time, three panels.
pub fn soak_png(
    seconds: &[SecondRec],
    tiers: &[ShadingModel],
    budget_ms: f64,
    path: &Path,
) -> Result<(), String> {
    ensure_font();
    png(path, (1200, 900), |root| {
        soak_panels(root, seconds, tiers, budget_ms)
    })
}

/// The soak chart's three panels on `root`.
fn soak_panels(
    root: &DrawingArea<BitMapBackend<'_>, Shift>,
    seconds: &[SecondRec],
    tiers: &[ShadingModel],
    budget_ms: f64,
) -> Result<(), String> {
    let e = |e: &dyn std::fmt::Display| e.to_string();
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let panels = root.split_evenly((3, 1));
    let t_max = seconds.last().map_or(1.0, |s| s.t_s).max(1.0);
    let series = |pick: fn(&SecondRec) -> Option<f64>| -> Vec<(f64, f64)> {
        seconds
            .iter()
            .filter_map(|s| pick(s).filter(|v| v.is_finite()).map(|v| (s.t_s, v)))
            .collect()
    };
    let cpu_mean = series(|s| Some(s.cpu_ms_mean));
    let cpu_max = series(|s| Some(s.cpu_ms_max));
    let gpu_mean = series(|s| s.gpu_ms_mean);
    let gpu_max = series(|s| s.gpu_ms_max);
    let all: Vec<f64> = cpu_max.iter().chain(&gpu_max).map(|p| p.1).collect();
    let y_max = percentile(&all, 0.99).max(budget_ms) * 1.3;
    let mut c = panel(
        &panels[0],
        "Frame time (per second)",
        t_max,
        0.0..y_max.max(1.0),
        "ms",
    )?;
    let budget = vec![(0.0, budget_ms), (t_max, budget_ms)];
    for (points, line, key, label) in [
        (cpu_max, BLUE.mix(0.35), BLUE.mix(0.35), "CPU max"),
        (cpu_mean, BLUE.to_rgba(), BLUE.to_rgba(), "CPU mean"),
        (gpu_max, RED.mix(0.35), RED.mix(0.35), "GPU max"),
        (gpu_mean, RED.to_rgba(), RED.to_rgba(), "GPU mean"),
        (budget, BLACK.mix(0.5), BLACK.mix(0.5), "budget"),
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
        seconds.iter().map(|s| (s.t_s, s.tier as f64)),
        &GREEN,
    ))
    .map_err(|x| e(&x))?;

    let mem = [
        (series(|s| s.rss_mb), MAGENTA.to_rgba(), "resident"),
        (
            series(|s| s.malloc_mb),
            RGBColor(230, 120, 0).to_rgba(),
            "C allocator in use",
        ),
        (series(|s| s.rust_heap_mb), CYAN.to_rgba(), "Rust heap"),
    ];
    let (lo, hi) = mem
        .iter()
        .flat_map(|m| m.0.iter())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
            (a.0.min(p.1), a.1.max(p.1))
        });
    let (lo, hi) = if lo.is_finite() {
        (
            (lo - 1.0 - 0.05 * (hi - lo)).max(0.0),
            hi + 1.0 + 0.05 * (hi - lo),
        )
    } else {
        (0.0, 1.0)
    };
    let mut c = panel(&panels[2], "Memory", t_max, lo..hi, "MiB")?;
    for (points, color, label) in mem {
        c.draw_series(LineSeries::new(points, color))
            .map_err(|x| e(&x))?
            .label(label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
    }
    c.configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|x| e(&x))?;
    Ok(())
}
