//! `dermis bench tables`: the tables and LUT the runtime interpolates from the shipped grids
//! (`shading::grid`, `shading::sphere_grid`) against each material's direct Monte Carlo bake
//! at the same budget (`dermis_measure::bake::measure`, `dermis_measure::lut::bake_lut`): the
//! largest relative difference per table.

use dermis_core::shading::bake::{self, Bake, DEFAULT_BUDGET, OBLIQUE_NODES, SLAB_NODES};
use dermis_core::shading::preintegrated::{self, Lut, LUT_U, LUT_V};
use dermis_core::shading::Material;
use dermis_measure::bake::{measure, threads};
use dermis_measure::ground_truth::acceptance_material;
use dermis_measure::lut::bake_lut;
use serde_json::{json, Value};

use crate::cmd::progress::Progress;

/// The materials compared: every preset at its own η and at the reference scenes' η.
pub fn materials() -> Vec<Material> {
    dermis_core::shading::material::PRESETS
        .iter()
        .flat_map(|m| [*m, acceptance_material(m)])
        .collect()
}

/// Largest |a/b − 1| over the pairs whose reference `b` passes `keep`.
fn worst(pairs: impl Iterator<Item = (f64, f64)>, keep: impl Fn(f64) -> bool) -> f64 {
    pairs
        .filter(|(_, b)| keep(*b))
        .map(|(a, b)| (a / b - 1.0).abs())
        .fold(0.0, f64::max)
}

/// Per table: the largest relative difference of the interpolated `g` from the direct `d`.
pub fn compare(g: &Bake, d: &Bake, gl: &Lut, dl: &Lut) -> Value {
    let per_channel = |f: &dyn Fn(usize) -> f64| (0..3).map(f).fold(0.0, f64::max);
    let rings = per_channel(&|c| {
        let total: f64 = d.mass.iter().map(|m| m[c]).sum();
        worst(
            g.mass.iter().zip(&d.mass).map(|(a, b)| (a[c], b[c])),
            |b| b > 0.01 * total,
        )
    });
    let total = worst(g.reflectance().into_iter().zip(d.reflectance()), |_| true);
    let oblique = per_channel(&|c| {
        worst(
            (1..OBLIQUE_NODES - 1).map(|k| (g.oblique[k][c], d.oblique[k][c])),
            |b| b > 0.0,
        )
    });
    let shift = per_channel(&|c| {
        worst(
            (1..OBLIQUE_NODES - 1).map(|k| (g.shift[k][c], d.shift[k][c])),
            |b| b > 0.01,
        )
    });
    let slab = per_channel(&|c| {
        worst(
            (0..SLAB_NODES).map(|k| (g.slab[k][c], d.slab[k][c])),
            |b| b > 1e-6,
        )
    });
    let median = per_channel(&|c| (g.median_radius(c) / d.median_radius(c) - 1.0).abs());
    // Sphere rows: |Δ log2 M| over the texels that carry light (within 2^-12 of the row's
    // brightest), as a relative difference; and its mean.
    let (mut lut_max, mut lut_sum, mut lut_n) = (0.0f64, 0.0f64, 0usize);
    for j in 0..LUT_V {
        for c in 0..3 {
            let peak = (0..LUT_U).map(|i| dl.at(i, j, c)).fold(f32::MIN, f32::max);
            for i in 0..LUT_U {
                let (a, b) = (gl.at(i, j, c), dl.at(i, j, c));
                if b > peak - 12.0 {
                    let rel = 2f64.powf(f64::from((a - b).abs())) - 1.0;
                    lut_max = lut_max.max(rel);
                    lut_sum += rel;
                    lut_n += 1;
                }
            }
        }
    }
    json!({
        "kernel_rings": rings, "total_reflectance": total, "median_radius": median,
        "q_mu": oblique, "shift_mu": shift, "slab": slab,
        "sphere_rows_max": lut_max, "sphere_rows_mean": lut_sum / lut_n.max(1) as f64,
    })
}

pub fn run(json_out: bool) -> Result<(), String> {
    let threads = threads();
    let mats = materials();
    let mut progress = Progress::new("bench tables", 2 * mats.len() as u64);
    let mut rows = Vec::new();
    for m in &mats {
        progress.begin(&format!("{} η={}: direct tables", m.name, m.eta));
        let direct = measure(m, DEFAULT_BUDGET, threads);
        progress.step(&format!("{} η={}: direct sphere rows", m.name, m.eta));
        let direct_lut = bake_lut(&direct, m, &DEFAULT_BUDGET, threads);
        progress.step(&format!("{} η={}: compared", m.name, m.eta));
        let grid = bake::for_material(m);
        let grid_lut = preintegrated::lut(m);
        let mut row = compare(&grid, &direct, &grid_lut, &direct_lut);
        row["material"] = json!(m.name);
        row["eta"] = json!(m.eta);
        rows.push(row);
    }
    progress.finish();
    if json_out {
        let text = serde_json::to_string_pretty(&json!({"budget": format!("{DEFAULT_BUDGET:?}"), "rows": rows}))
            .map_err(|e| e.to_string())?;
        println!("{text}");
        return Ok(());
    }
    println!(
        "Interpolated (grid) against direct bakes at the shipped budget: largest relative \
         difference per table (rings holding ≥ 1 % of the total, δ > 0.01 mm, T > 1e-6; sphere \
         rows over texels within 2^-12 of the row's peak)"
    );
    let keys = [
        "total_reflectance",
        "kernel_rings",
        "median_radius",
        "q_mu",
        "shift_mu",
        "slab",
        "sphere_rows_max",
        "sphere_rows_mean",
    ];
    print!("{:<12} {:>7}", "material", "η");
    for k in keys {
        print!(" {k:>17}");
    }
    println!();
    for r in &rows {
        print!(
            "{:<12} {:>7}",
            r["material"].as_str().unwrap_or(""),
            r["eta"]
        );
        for k in keys {
            print!(" {:>16.2}%", 100.0 * r[k].as_f64().unwrap_or(f64::NAN));
        }
        println!();
    }
    Ok(())
}
