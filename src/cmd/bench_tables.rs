//! `dermis bench tables`: every material's tables and LUT as the runtime makes them from the
//! shipped grids (`shading::grid`, `shading::sphere_grid`) against the material's direct Monte
//! Carlo bake at the shipped budget (`dermis_measure::bake::measure`,
//! `dermis_measure::lut::bake_lut`): the largest relative difference per table, and the CPU
//! time the runtime spends making one material's tables from the grids.

use std::borrow::Cow;
use std::path::PathBuf;
use std::time::Instant;

use dermis_engine::shading::bake::{self, DEFAULT_BUDGET};
use dermis_engine::shading::material::{Origin, PRESETS};
use dermis_engine::shading::{albedo, edge_spread, preintegrated, Material};
use dermis_measure::bake::{measure, measure_seeded, threads};
use dermis_measure::grid::{difference, interpolated};
use dermis_measure::ground_truth::{acceptance_material, test_materials};
use dermis_measure::lut::bake_lut;
use serde_json::{json, Value};

use crate::cmd::args::check_out_file;
use crate::cmd::progress::Progress;

#[derive(clap::Args, Debug)]
pub struct TablesArgs {
    /// Print JSON instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Also write the JSON report to this `.json` file (checked before the work starts).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Only the first N materials of the list (the Monte Carlo's sphere rows take a minute or
    /// two per material on 2 cores).
    #[arg(long, value_parser = crate::cmd::args::parse_material_count, allow_hyphen_values = true)]
    pub materials: Option<usize>,
}

/// A material of per-channel reduced albedo α' and σ'_t (mm⁻¹).
fn made(name: &'static str, alpha: [f64; 3], sigma_t: [f64; 3], eta: f64, g: f64) -> Material {
    Material {
        name: Cow::Borrowed(name),
        origin: Origin::Builtin,
        sigma_a: std::array::from_fn(|c| (1.0 - alpha[c]) * sigma_t[c]),
        sigma_s_prime: std::array::from_fn(|c| alpha[c] * sigma_t[c]),
        eta,
        g,
        textured: true,
    }
}

/// The materials compared: the presets (their shipped files are direct bakes: how far the
/// grid is from them), the test materials, and media spread over α' 0.3–0.9999, η 1.0–1.6
/// and σ'_t 0.3–5 mm⁻¹, two of them again with the real phase function at g = 0.8 (the grid
/// serves their similar g = 0 medium).
pub fn materials() -> Vec<Material> {
    let mut v: Vec<Material> = PRESETS
        .iter()
        .flat_map(|m| [m.clone(), acceptance_material(m)])
        .collect();
    v.extend(test_materials());
    // A file's skin: A 0.55/0.33/0.21 (per incident power), 3 mm mean free path, η 1.4.
    v.push(albedo::material(
        "file-skin",
        [0.55, 0.33, 0.21],
        [3.0; 3],
        1.4,
        0.0,
    ));
    let spread = [
        made("matched", [0.3, 0.7, 0.95], [0.3, 1.0, 5.0], 1.0, 0.0),
        made("low-index", [0.9999, 0.99, 0.5], [5.0, 2.0, 0.5], 1.05, 0.0),
        made("mid-index", [0.98, 0.8, 0.6], [2.0, 0.7, 4.0], 1.2, 0.0),
        made("high-index", [0.999, 0.9, 0.4], [1.0, 3.0, 0.3], 1.6, 0.0),
        made("between", [0.995, 0.93, 0.75], [0.8, 1.5, 2.5], 1.33, 0.0),
        made(
            "mid-index-g0.8",
            [0.98, 0.8, 0.6],
            [2.0, 0.7, 4.0],
            1.2,
            0.8,
        ),
        made(
            "between-g0.8",
            [0.995, 0.93, 0.75],
            [0.8, 1.5, 2.5],
            1.33,
            0.8,
        ),
    ];
    v.extend(spread);
    v
}

/// CPU time (ms) the runtime spends on `m`'s tables and LUT from the grids (tables, sphere
/// and factor rows, the edge-spread row): the best of `rounds`.
fn grid_ms(m: &Material, rounds: usize) -> f64 {
    (0..rounds)
        .map(|_| {
            let start = Instant::now();
            if let Some((b, Some(mut lut))) = interpolated(m) {
                lut.texels
                    .extend(edge_spread::lut_row(&b, preintegrated::LUT_U));
                std::hint::black_box(&lut);
            }
            start.elapsed().as_secs_f64() * 1e3
        })
        .fold(f64::INFINITY, f64::min)
}

pub fn run(args: TablesArgs) -> Result<(), String> {
    if let Some(out) = &args.out {
        check_out_file(out, Some("json"))?;
    }
    let threads = threads();
    let mut mats = materials();
    if let Some(n) = args.materials {
        mats.truncate(n);
    }
    let with_lut =
        match interpolated(&mats[0]) {
            None => return Err(
                "the shipped tables grid does not match this build (`dermis lut --grid tables`)"
                    .into(),
            ),
            Some((_, lut)) => lut.is_some(),
        };
    if !with_lut {
        eprintln!("bench tables: the shipped sphere grid does not match this build: tables only");
    }
    let mut progress = Progress::new("bench tables", 2 * mats.len() as u64);
    let mut rows: Vec<Value> = Vec::new();
    for m in &mats {
        // A preset's shipped files are its direct bake at the shipped budget (bit for bit:
        // `the_shipped_tables_are_what_the_bake_measures`).
        progress.begin(&format!("{} η={} g={}: direct tables", m.name, m.eta, m.g));
        let direct = bake::shipped(m).unwrap_or_else(|| measure(m, DEFAULT_BUDGET, threads));
        progress.step(&format!(
            "{} η={} g={}: direct sphere rows",
            m.name, m.eta, m.g
        ));
        let direct_lut = with_lut.then(|| {
            preintegrated::shipped(m)
                .unwrap_or_else(|| bake_lut(&direct, m, &DEFAULT_BUDGET, threads))
        });
        progress.step(&format!("{}: compared", m.name));
        let Some((grid, grid_lut)) = interpolated(m) else {
            continue;
        };
        let luts = grid_lut.as_ref().zip(direct_lut.as_ref());
        let d = difference(&grid, &direct, luts);
        // The direct bake's own noise: the same bake with other seeds (tables only).
        let again = measure_seeded(m, DEFAULT_BUDGET, threads, 0x5EED_0DD5);
        let noise = difference(&again, &direct, None);
        if std::env::var_os("DERMIS_BENCH_DUMP").is_some() {
            eprintln!(
                "{}: grid {grid:?}\ndirect {direct:?}\nagain {again:?}",
                m.name
            );
        }
        let mut row = json!({
            "material": m.name,
            "eta": m.eta,
            "g": m.g,
            "alpha_prime": m.albedo(),
            "sigma_t_prime": m.sigma_t_prime(),
            "grid_ms": grid_ms(m, 5),
        });
        for (k, v) in d.named() {
            row[k] = json!(v);
        }
        for (k, v) in noise.named().into_iter().take(6) {
            row[format!("{k}_noise")] = json!(v);
        }
        rows.push(row);
    }
    progress.finish();
    let report = json!({
        "budget": format!("{DEFAULT_BUDGET:?}"),
        "threads": threads,
        "rows": rows,
    });
    let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
    if let Some(out) = &args.out {
        std::fs::write(out, &text).map_err(|e| format!("cannot write {}: {e}", out.display()))?;
    }
    if args.json {
        println!("{text}");
    } else {
        print!("{}", markdown(&rows));
    }
    Ok(())
}

/// The report as a markdown table (relative differences in %).
fn markdown(rows: &[Value]) -> String {
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
    let mut s = String::from(
        "Grid against direct bake at the shipped budget: largest relative difference per \
         table, % (rings holding ≥ 1 % of the total, δ > 0.01 mm, T > 1e-6, sphere-row texels \
         within 2^-6 of the row's peak); in parentheses the direct bake's own noise (the same \
         bake with other seeds); grid ms: CPU time for one material's tables and LUT\n\n\
         | material | η | g | α' | σ'_t mm⁻¹ |",
    );
    for k in keys {
        s += &format!(" {k} |");
    }
    s += " grid ms |\n|---|---|---|---|---|";
    s += &"---|".repeat(keys.len() + 1);
    s += "\n";
    let triple = |v: &Value, digits: usize| -> String {
        (0..3)
            .map(|c| format!("{:.*}", digits, v[c].as_f64().unwrap_or(f64::NAN)))
            .collect::<Vec<_>>()
            .join(" ")
    };
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {} | {} |",
            r["material"].as_str().unwrap_or(""),
            r["eta"],
            r["g"],
            triple(&r["alpha_prime"], 4),
            triple(&r["sigma_t_prime"], 2)
        );
        for k in keys {
            let v = 100.0 * r[k].as_f64().unwrap_or(f64::NAN);
            match r.get(format!("{k}_noise")).and_then(Value::as_f64) {
                Some(n) => s += &format!(" {v:.1} ({:.1}) |", 100.0 * n),
                None => s += &format!(" {v:.1} |"),
            }
        }
        s += &format!(" {:.2} |\n", r["grid_ms"].as_f64().unwrap_or(f64::NAN));
    }
    s
}
