//! `dermis albedo --sweep F.json`: the A ↔ α' table checked densely, where its η axis is
//! hardest (total internal reflection sets in just above η = 1). For η = 1.00, 1.01, …, 1.60
//! and A = 0.05, 0.10, 0.20, …, 0.90 and C(η) − 0.01 (below what a white medium reflects),
//! the medium the table's inversion makes from A is walked by the plane walker under diffuse
//! light (an estimator independent of the table's white walk) and what it reflects is
//! compared with A. The goal: |error| ≤ 0.74 % + 2 SE everywhere. The committed result is
//! `docs/results/albedo-sweep.json`; `dermis_measure::albedo`'s test reruns a few of its
//! points.

use std::path::Path;
use std::time::Instant;

use dermis_engine::shading::albedo;
use dermis_measure::albedo::{measured_multi, sweep_photons, sweep_points, SWEEP_BOUND as BOUND};
use serde_json::json;

use crate::cmd::progress::Progress;

pub fn run(out: &Path, g: f64, photons: u64, seed: u64) -> Result<(), String> {
    let threads = dermis_measure::bake::threads();
    let points = sweep_points();
    let start = Instant::now();
    let mut progress = Progress::new("albedo sweep", points.len() as u64);
    let mut rows = Vec::new();
    let mut worst: (f64, f64, f64) = (0.0, 0.0, 0.0);
    let mut failed = 0;
    for (i, &(eta, multi)) in points.iter().enumerate() {
        let label = format!("η {eta:.2}: A {multi:.3}");
        progress.begin(&label);
        let single = albedo::single_scatter_albedo(multi, eta, g);
        let n = sweep_photons(multi, photons);
        let m = measured_multi(single, eta, g, n, seed.wrapping_add(i as u64), threads);
        let err = m.mean / multi - 1.0;
        let se = m.std_err / multi;
        let ok = err.abs() <= BOUND + 2.0 * se;
        failed += usize::from(!ok);
        if err.abs() > worst.0.abs() {
            worst = (err, eta, multi);
        }
        rows.push(json!({
            "eta": eta, "multi": multi, "single": single, "photons": n,
            "measured": m.mean, "measured_se": m.std_err,
            "error": err, "error_se": se, "within": ok,
        }));
        progress.step(&label);
    }
    progress.finish();
    let doc = json!({
        "what": "A ↔ α' table: the medium made from A reflects A (plane walker, diffuse light)",
        "bound": BOUND, "g": g, "photons_at_a_1": photons, "seed": seed,
        "points": rows.len(), "outside_bound_plus_2se": failed,
        "worst_error": worst.0, "worst_at": {"eta": worst.1, "multi": worst.2},
        "seconds": start.elapsed().as_secs_f64(),
        "rows": rows,
    });
    let text = serde_json::to_string_pretty(&doc).map_err(|e| e.to_string())?;
    std::fs::write(out, text).map_err(|e| format!("cannot write {}: {e}", out.display()))?;
    println!(
        "{} points, {failed} outside {:.2} % + 2 SE; largest |error| {:+.2} % (η {:.2}, A {:.3}); {}",
        points.len(),
        100.0 * BOUND,
        100.0 * worst.0,
        worst.1,
        worst.2,
        out.display()
    );
    Ok(())
}
