//! The report side of `dermis bench shading`: per-family aggregation of the scene scores,
//! the Pareto front, the Markdown table and the chart (error against Mali cycles and against
//! this adapter's GPU time). Every chart axis is guarded against NaN, ∞, non-positive values
//! on log axes and single points (plotters loops forever on a degenerate range).

use std::path::Path;

use dermis_engine::shading::ShadingModel;
use dermis_measure::ground_truth::metric::ErrorStats;
use dermis_measure::ground_truth::Scene;
use serde_json::{json, Value};

/// One scene's score for one model (or why it has none).
pub struct SceneScore {
    pub material: String,
    pub scene: Scene,
    pub result: Result<ErrorStats, String>,
}

/// The table column a scene belongs to: point light per height, then edge, sphere, slab.
pub fn family(scene: &Scene) -> String {
    match *scene {
        Scene::PointLight { h_mm } => format!("point h={h_mm}mm"),
        Scene::ShadowEdge { .. } => "edge".into(),
        Scene::Sphere { .. } => "sphere".into(),
        Scene::SlabBacklit { .. } => "slab".into(),
    }
}

fn mean(xs: &[f64]) -> f64 {
    if xs.is_empty() {
        f64::NAN
    } else {
        xs.iter().sum::<f64>() / xs.len() as f64
    }
}

/// Per family (in `families` order) and overall (the four kinds, point light over its
/// heights, weighted equally): the mean
/// of `f` over the scenes, or an error string if a scene of it failed.
pub fn aggregate(
    scores: &[SceneScore],
    families: &[String],
    f: fn(&ErrorStats) -> f64,
) -> (Vec<Value>, Value) {
    let failed = |sel: &dyn Fn(&SceneScore) -> bool| -> Option<String> {
        let bad: Vec<&SceneScore> = scores
            .iter()
            .filter(|s| sel(s) && s.result.is_err())
            .collect();
        let all = scores.iter().filter(|s| sel(s)).count();
        bad.first().map(|s| {
            format!(
                "error: {} of {all} scenes failed ({} {}: {})",
                bad.len(),
                s.material,
                s.scene.label(),
                s.result.as_ref().err().map_or("", |e| e.as_str())
            )
        })
    };
    let values = |sel: &dyn Fn(&SceneScore) -> bool| -> Vec<f64> {
        scores
            .iter()
            .filter(|s| sel(s))
            .filter_map(|s| s.result.as_ref().ok().map(f))
            .collect()
    };
    let per_family = families
        .iter()
        .map(|fam| {
            let sel = |s: &SceneScore| family(&s.scene) == *fam;
            failed(&sel).map_or_else(|| json!(mean(&values(&sel))), Value::from)
        })
        .collect();
    let overall = failed(&|_| true).map_or_else(
        || {
            let kinds = ["point", "edge", "sphere", "slab"];
            let means: Vec<f64> = kinds
                .iter()
                .map(|k| mean(&values(&|s: &SceneScore| family(&s.scene).starts_with(k))))
                .filter(|m| !m.is_nan())
                .collect();
            json!(mean(&means))
        },
        Value::from,
    );
    (per_family, overall)
}

/// Indices of the points on the Pareto front (no other point has lower-or-equal cost and
/// error with one strictly lower), ordered by cost. Non-finite points are never on it.
pub fn front(points: &[(f64, f64)]) -> Vec<usize> {
    let ok = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite();
    let mut on: Vec<usize> = (0..points.len())
        .filter(|&i| ok(&points[i]))
        .filter(|&i| {
            let (c, e) = points[i];
            !points
                .iter()
                .any(|q| ok(q) && q.0 <= c && q.1 <= e && (q.0 < c || q.1 < e))
        })
        .collect();
    on.sort_by(|&a, &b| points[a].0.total_cmp(&points[b].0));
    on
}

fn arr(v: &Value) -> impl Iterator<Item = &Value> {
    v.as_array().into_iter().flatten()
}

fn models(report: &Value) -> impl Iterator<Item = &Value> {
    arr(&report["models"])
}

/// The governor's tiers (`governor-front.txt`, embedded by the core), richest (most accurate,
/// costliest) first: the models on the error–G57-cycles front, less any that is worse on the
/// scanned face (the report's `face` mean, where it has one) than a cheaper tier kept below
/// it, so stepping down never makes the face better. The last tier is always a plain BRDF
/// (no subsurface transport): the governor's floor, for an unlit or tiny character whose
/// transport shows nothing and which then needs no LUT, penumbra map or subsurface pass.
/// Where the front dominates every BRDF (a one-pass subsurface model can cost fewer G57 cycles
/// than the cheapest BRDF), the cheapest BRDF is the floor below the front.
pub fn front_models(report: &Value) -> Vec<String> {
    let points = panel_points(report, true).0;
    let plain = |name: &str| {
        name.parse::<ShadingModel>()
            .is_ok_and(|m| !m.effects().subsurface)
    };
    let mut on: Vec<_> = points.iter().filter(|p| p.3).cloned().collect();
    on.sort_by(|a, b| a.1.total_cmp(&b.1));
    // Cheapest first: the floor, then the front by cost.
    let mut names: Vec<String> = on.into_iter().map(|p| p.0).collect();
    if !names.iter().any(|n| plain(n)) {
        let floor = points
            .iter()
            .filter(|p| plain(&p.0) && p.1.is_finite())
            .min_by(|a, b| a.1.total_cmp(&b.1));
        if let Some(f) = floor {
            names.insert(0, f.0.clone());
        }
    }
    let mut kept: Vec<(String, Option<f64>)> = Vec::new();
    for name in names {
        let face = face_mean(report, &name);
        let no_worse = |below: &(String, Option<f64>)| match (face, below.1) {
            (Some(f), Some(b)) => f <= b,
            _ => true,
        };
        if kept.iter().all(no_worse) {
            kept.push((name, face));
        }
    }
    kept.into_iter().rev().map(|k| k.0).collect()
}

/// `model`'s mean error on the scanned face in `report`, where it has one.
fn face_mean(report: &Value, model: &str) -> Option<f64> {
    models(report)
        .find(|r| r["model"] == json!(model))
        .and_then(|r| r["face"]["mean"].as_f64())
        .filter(|f| f.is_finite())
}

/// `governor-front.txt`: a comment, then [`front_models`] one per line.
pub fn front_file(report: &Value) -> String {
    let mut out = String::from(
        "# The governor's tiers, richest first: the measured accuracy–cost front (overall\n\
         # error vs Mali-G57 cycles) less any model worse on the scanned face than a cheaper\n\
         # tier. Written by `dermis bench shading --out DIR`; embedded by game/src/governor.rs.\n",
    );
    for m in front_models(report) {
        out.push_str(&m);
        out.push('\n');
    }
    out
}

/// The models on the front, cheapest first.
fn front_names(report: &Value, mali: bool) -> String {
    let mut on: Vec<_> = panel_points(report, mali)
        .0
        .into_iter()
        .filter(|p| p.3)
        .collect();
    on.sort_by(|a, b| a.1.total_cmp(&b.1));
    on.into_iter().map(|p| p.0).collect::<Vec<_>>().join(" → ")
}

fn num(v: &Value, digits: usize) -> String {
    match v {
        Value::String(_) => "err".into(),
        _ => match v.as_f64() {
            Some(x) if x.is_finite() => format!("{x:.digits$}"),
            _ => "–".into(),
        },
    }
}

fn cycles(m: &Value) -> String {
    let (s, p) = (&m["static"], &m["per_pixel"]);
    match (s.as_f64(), p.as_f64()) {
        (Some(s), Some(p)) if (s - p).abs() > 0.01 => format!("{p:.1} (static {s:.1})"),
        _ => num(p, 2),
    }
}

/// The one table (plus the notes a reader needs to read it).
pub fn markdown(report: &Value) -> String {
    let fams: Vec<&str> = arr(&report["families"]).filter_map(Value::as_str).collect();
    // The main table averages the presets (the test materials have their own table below).
    let refs: Vec<&str> = arr(&report["presets"]).filter_map(Value::as_str).collect();
    let cs = &report["cost_scene"];
    let mut s = format!(
        "Adapter: {} — {}. Errors: mean |ln(model/MC)| over the bins above the Monte Carlo's noise floor, \
         per scene family, averaged over {} (η = 1.4, g = 0); overall = the four kinds (point, edge, sphere, slab) weighted equally; \
         integrated = |ln(∫model/∫MC)|, same weighting; face = mean |ln(model/truth)| on the scanned head under front, side and back light against the project's Monte Carlo on its mesh (`dermis bench face`). Cost: {}x{} target filled by a flat skin patch \
         ({} mm wide, {:.2} mm/pixel, coverage {:.0} %), point light, both passes for screen-space models, {} rounds. \
         Mali: fragment cycles per pixel (`bound`, Mesa {}), the subsurface pass added for screen-space models; \
         loops weighted by their iteration counts ({} samples per sampled ring), Mesa's static figure in parentheses.\n\n",
        report["adapter"].as_str().unwrap_or("?"),
        report["label"].as_str().unwrap_or(""),
        refs.join(" and "),
        cs["size"][0], cs["size"][1], cs["view_mm"], cs["mm_per_pixel"].as_f64().unwrap_or(0.0),
        cs["coverage"].as_f64().unwrap_or(0.0) * 100.0,
        report["rounds"],
        report["mali"]["mesa_debian_version"].as_str().unwrap_or("–"),
        report["sss_angles"],
    );
    s += "| model | ";
    s += &fams.join(" | ");
    s += " | overall | integrated | face | lavapipe ms | × ward (95 % CI) | × unlit | G52 cycles | G57 cycles | G57 × ward |\n|---|";
    s += &"---|".repeat(fams.len() + 9);
    s += "\n";
    // The Monte Carlo's own noise, per family (the same for every model).
    if let Some(first) = models(report).find(|r| r["error"].is_object()) {
        let e = &first["error"];
        s += "| *MC rel. SE* | ";
        s += &fams
            .iter()
            .map(|f| num(&e["mc_rel_se"][*f], 4))
            .collect::<Vec<_>>()
            .join(" | ");
        s += &format!(" | {} | | | | | | | | |\n", num(&e["mc_rel_se_overall"], 4));
    }
    for r in models(report) {
        let e = &r["error"];
        let errs: Vec<String> = fams.iter().map(|f| num(&e["families"][*f], 3)).collect();
        let m = &r["mali"];
        s += &format!(
            "| {} | {} | {} | {} | {} | {} | {} ({}–{}) | {} | {} | {} | {} |\n",
            r["model"].as_str().unwrap_or("?"),
            errs.join(" | "),
            num(&e["overall"], 3),
            num(&e["integrated"], 3),
            num(&r["face"]["mean"], 3),
            num(&r["lavapipe_ms_median"], 2),
            num(&r["ratio_to_ward"], 3),
            num(&r["ratio_to_ward_ci95"][0], 3),
            num(&r["ratio_to_ward_ci95"][1], 3),
            num(&r["ratio_to_unlit"], 3),
            cycles(&m["G52"]),
            cycles(&m["G57"]),
            num(&m["G57_ratio_to_ward"], 2),
        );
    }
    s += &format!(
        "\nPareto front (overall error vs G57 cycles): {}. Against lavapipe time: {}. \
         The governor's tiers (that front less any model worse on the face than a cheaper \
         tier below it): {}.\n",
        front_names(report, true),
        front_names(report, false),
        front_models(report).join(" → ")
    );
    s += &test_materials(report);
    s
}

/// The second table: each model's overall error on the materials that are not a preset
/// (made from a multi-scatter albedo and a mean free path), against its presets' overall.
fn test_materials(report: &Value) -> String {
    let names: Vec<&str> = arr(&report["test_materials"])
        .filter_map(|m| m["material"].as_str())
        .collect();
    if names.is_empty() {
        return String::new();
    }
    let mut s = String::from(
        "\nMaterials that are not a preset (η = 1.4, g = 0; made from their multi-scatter albedo \
         and mean free path through the measured inversion): overall error per material, and the \
         largest as a multiple of the model's overall on the presets.\n\n| model | presets | ",
    );
    s += &names.join(" | ");
    s += " | worst × presets |\n|---|---|";
    s += &"---|".repeat(names.len() + 1);
    s += "\n";
    for r in models(report).filter(|r| r["error"].is_object()) {
        let presets = &r["error"]["overall"];
        let overall: Vec<&Value> = names
            .iter()
            .map(|n| &r["materials"][*n]["overall"])
            .collect();
        let worst = overall
            .iter()
            .filter_map(|v| v.as_f64())
            .fold(f64::NAN, |a: f64, b| if a.is_nan() { b } else { a.max(b) });
        let ratio = presets.as_f64().map_or(f64::NAN, |p| worst / p);
        s += &format!(
            "| {} | {} | {} | {} |\n",
            r["model"].as_str().unwrap_or("?"),
            num(presets, 3),
            overall
                .iter()
                .map(|v| num(v, 3))
                .collect::<Vec<_>>()
                .join(" | "),
            num(&json!(ratio), 2)
        );
    }
    s
}

/// A padded log-axis range: finite, positive, `lo < hi` whatever the values (NaN, ∞, ≤ 0,
/// none, one).
pub fn log_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|x| x.is_finite() && *x > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |a, x| {
            (a.0.min(x), a.1.max(x))
        });
    let pad = if hi / lo < 1.05 { 2.0 } else { 1.4 };
    let (lo, hi) = (lo / pad, hi * pad);
    if lo.is_finite() && hi.is_finite() && lo > 0.0 && lo < hi {
        (lo, hi)
    } else {
        (1.0, 10.0)
    }
}

/// One panel's points: (label, cost, error, on the front, static cost if different).
type Points = Vec<(String, f64, f64, bool, Option<f64>)>;

fn panel_points(report: &Value, mali: bool) -> (Points, Option<f64>) {
    let f = |v: &Value| v.as_f64().unwrap_or(f64::NAN);
    let cost = |r: &Value| {
        f(if mali {
            &r["mali"]["G57"]["per_pixel"]
        } else {
            &r["ratio_to_ward"]
        })
    };
    let ok = |x: f64| x.is_finite() && x > 0.0;
    let rows: Vec<&Value> = models(report)
        .filter(|r| r["error"].is_object() && ok(cost(r)) && ok(f(&r["error"]["overall"])))
        .collect();
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (cost(r), f(&r["error"]["overall"])))
        .collect();
    let on = front(&pts);
    let points = rows
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let stat = f(&r["mali"]["G57"]["static"]);
            let alt = (mali && ok(stat) && (stat - pts[i].0).abs() > 0.01).then_some(stat);
            let name = r["model"].as_str().unwrap_or("?").to_string();
            (name, pts[i].0, pts[i].1, on.contains(&i), alt)
        })
        .collect();
    let unlit = models(report)
        .find(|r| r["model"] == json!("unlit"))
        .map(cost)
        .filter(|x| ok(*x));
    (points, unlit)
}

/// `pareto.png`: error against G57 cycles (left) and against lavapipe time (right).
pub fn chart(report: &Value, path: &Path) -> Result<(), String> {
    crate::cmd::chart::ensure_font();
    crate::cmd::chart::png(path, (1500, 650), |root| {
        draw_chart(report, root).map_err(|e| format!("{}: {e}", path.display()))
    })
}

fn draw_chart(
    report: &Value,
    root: &plotters::prelude::DrawingArea<
        plotters::prelude::BitMapBackend<'_>,
        plotters::coord::Shift,
    >,
) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    root.fill(&WHITE)?;
    let specs = [
        (
            true,
            "Accuracy vs Mali-G57 cost",
            "Mali-G57 fragment cycles per pixel (loop-weighted; grey: Mesa static)",
        ),
        (
            false,
            "Accuracy vs lavapipe GPU time",
            "lavapipe GPU time of the full-screen pass / ward",
        ),
    ];
    for (area, (mali, title, x_desc)) in root.split_evenly((1, 2)).iter().zip(specs) {
        let (points, unlit) = panel_points(report, mali);
        let xs = points
            .iter()
            .flat_map(|p| [Some(p.1), p.4])
            .flatten()
            .chain(unlit);
        let (x0, x1) = log_range(xs);
        let (y0, y1) = log_range(points.iter().map(|p| p.2));
        let mut chart = ChartBuilder::on(area)
            .caption(title, ("sans-serif", 22))
            .margin(18)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
        chart
            .configure_mesh()
            .x_labels(8)
            .x_desc(x_desc)
            .y_desc("overall mean |ln(model / Monte Carlo)|")
            .draw()?;
        if points.is_empty() {
            area.draw(&Text::new("no data", (200, 300), ("sans-serif", 24)))?;
            continue;
        }
        if let Some(u) = unlit {
            let grey = BLACK.mix(0.6).stroke_width(2);
            chart
                .draw_series(LineSeries::new([(u, y0), (u, y1)], grey))?
                .label("unlit baseline")
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], grey));
        }
        // The front as a staircase.
        let mut on: Vec<_> = points.iter().filter(|p| p.3).collect();
        on.sort_by(|a, b| a.1.total_cmp(&b.1));
        let mut stairs = Vec::new();
        for (k, p) in on.iter().enumerate() {
            if k > 0 {
                stairs.push((p.1, on[k - 1].2));
            }
            stairs.push((p.1, p.2));
        }
        let red = RED.stroke_width(2);
        chart
            .draw_series(LineSeries::new(stairs, red))?
            .label("Pareto front")
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], red));
        for p in &points {
            if let Some(s) = p.4 {
                chart.draw_series(LineSeries::new([(s, p.2), (p.1, p.2)], BLACK.mix(0.25)))?;
                chart.draw_series([Circle::new((s, p.2), 5, BLACK.mix(0.4))])?;
            }
        }
        // Labels of points within a few per cent of the axes of an earlier one stack below it.
        let near =
            |a: f64, b: f64, lo: f64, hi: f64, tol: f64| (a / b).ln().abs() < tol * (hi / lo).ln();
        let stack: Vec<i32> = (0..points.len())
            .map(|i| {
                let (p, before) = (&points[i], &points[..i]);
                before
                    .iter()
                    .filter(|q| near(p.1, q.1, x0, x1, 0.06) && near(p.2, q.2, y0, y1, 0.04))
                    .count() as i32
            })
            .collect();
        chart.draw_series(points.iter().zip(&stack).map(|(p, k)| {
            let colour = if p.3 { RED.filled() } else { BLUE.filled() };
            EmptyElement::at((p.1, p.2))
                + Circle::new((0, 0), 6, colour)
                + Text::new(p.0.clone(), (9, -16 + 18 * k), ("sans-serif", 16))
        }))?;
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_governors_front_is_the_measured_tables() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/results");
        let report: Value = serde_json::from_str(
            &std::fs::read_to_string(root.join("shading.json")).expect("shading.json"),
        )
        .expect("JSON");
        let file = std::fs::read_to_string(root.join("governor-front.txt")).expect("front file");
        assert_eq!(
            file,
            front_file(&report),
            "rerun `dermis bench shading --out docs/results`"
        );
        let names: Vec<String> = dermis_game::governor::front()
            .iter()
            .map(|m| m.name().to_string())
            .collect();
        assert_eq!(names, front_models(&report));
    }

    /// A front that dominates every BRDF still ends on one: the cheapest, the governor's floor.
    #[test]
    fn the_front_file_ends_on_a_plain_brdf() {
        let row = |model: &str, err: f64, cycles: f64| {
            json!({"model": model, "error": {"overall": err},
                   "mali": {"G57": {"per_pixel": cycles, "static": cycles}}})
        };
        let dominated = json!({"models": [
            row("ward", 4.7, 3.3), row("ward-printed", 4.7, 3.7),
            row("tabulated", 0.14, 120.0), row("preintegrated", 0.08, 3.0)]});
        assert_eq!(front_models(&dominated), ["preintegrated", "ward"]);
        // On the front already: nothing is appended.
        let plain = json!({"models": [row("ward", 4.7, 2.0), row("preintegrated", 0.08, 3.0)]});
        assert_eq!(front_models(&plain), ["preintegrated", "ward"]);
    }

    /// The shipped tiers (the front the game embeds): each tier is at least as good on the
    /// probes and on the scanned face as every cheaper tier below it.
    #[test]
    fn no_shipped_tier_is_worse_on_the_face_than_a_cheaper_one() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/results");
        let report: Value = serde_json::from_str(
            &std::fs::read_to_string(root.join("shading.json")).expect("shading.json"),
        )
        .expect("JSON");
        let tiers = dermis_game::governor::front();
        assert!(tiers.len() >= 2, "{tiers:?}");
        let row = |m: &ShadingModel| {
            models(&report)
                .find(|r| r["model"] == json!(m.name()))
                .unwrap_or_else(|| panic!("{m}: no row"))
        };
        for (i, rich) in tiers.iter().enumerate() {
            for cheap in &tiers[i + 1..] {
                let face = |m| row(m)["face"]["mean"].as_f64().expect("face mean");
                let overall = |m| row(m)["error"]["overall"].as_f64().expect("overall");
                assert!(
                    face(rich) <= face(cheap),
                    "{rich} (face {}) above {cheap} (face {})",
                    face(rich),
                    face(cheap)
                );
                assert!(overall(rich) <= overall(cheap), "{rich} above {cheap}");
            }
        }
    }

    /// A model on the probes' front that is worse on the face than a cheaper tier is no tier;
    /// without face scores the front is the probes' alone.
    #[test]
    fn a_tier_worse_on_the_face_than_a_cheaper_one_is_dropped() {
        let row = |model: &str, err: f64, cycles: f64, face: Option<f64>| {
            let mut r = json!({"model": model, "error": {"overall": err},
                   "mali": {"G57": {"per_pixel": cycles, "static": cycles}}});
            if let Some(f) = face {
                r["face"] = json!({"mean": f});
            }
            r
        };
        let with_face = json!({"models": [
            row("ward", 4.7, 2.9, Some(0.53)), row("oss-stable", 2.8, 4.5, Some(0.99)),
            row("preintegrated", 0.07, 5.0, Some(0.05))]});
        assert_eq!(front_models(&with_face), ["preintegrated", "ward"]);
        // Better on the face than the floor: kept.
        let better = json!({"models": [
            row("ward", 4.7, 2.9, Some(0.53)), row("oss-stable", 2.8, 4.5, Some(0.4)),
            row("preintegrated", 0.07, 5.0, Some(0.05))]});
        assert_eq!(
            front_models(&better),
            ["preintegrated", "oss-stable", "ward"]
        );
        let none = json!({"models": [
            row("ward", 4.7, 2.9, None), row("oss-stable", 2.8, 4.5, None),
            row("preintegrated", 0.07, 5.0, None)]});
        assert_eq!(front_models(&none), ["preintegrated", "oss-stable", "ward"]);
        // A floor appended below a front that dominates it is compared too.
        let floor = json!({"models": [
            row("ward", 4.7, 3.3, Some(0.53)), row("oss-stable", 2.8, 2.0, Some(0.99)),
            row("preintegrated", 0.07, 3.0, Some(0.05))]});
        assert_eq!(front_models(&floor), ["preintegrated", "ward"]);
    }

    #[test]
    fn front_of_points() {
        let p = [
            (1.0, 5.0),
            (2.0, 1.0),
            (3.0, 2.0),
            (1.5, 5.0),
            (f64::NAN, 0.1),
            (4.0, 0.5),
        ];
        assert_eq!(front(&p), vec![0, 1, 5]);
        assert!(front(&[]).is_empty());
    }

    #[test]
    fn log_ranges_are_never_degenerate() {
        let cases: [&[f64]; 5] = [
            &[],
            &[f64::NAN, f64::INFINITY],
            &[3.0],
            &[0.0, 0.0],
            &[-1.0, 2.0],
        ];
        for v in cases {
            let (lo, hi) = log_range(v.iter().copied());
            assert!(
                lo.is_finite() && lo > 0.0 && lo < hi && hi.is_finite(),
                "{v:?}: {lo} {hi}"
            );
        }
    }

    #[test]
    fn chart_survives_an_empty_and_a_degenerate_report() {
        let dir = std::env::temp_dir().join(format!("dermis-pareto-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let empty = json!({"models": []});
        chart(&empty, &dir.join("a.png")).unwrap();
        let one = json!({"models": [
            {"model": "ward", "error": {"overall": 0.2}, "ratio_to_ward": 1.0,
             "mali": {"G57": {"per_pixel": 2.0, "static": 2.0}}},
            {"model": "x", "error": {"overall": f64::NAN}, "ratio_to_ward": null, "mali": {}}]});
        chart(&one, &dir.join("b.png")).unwrap();
        assert!(markdown(&one).contains("| ward |"));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
