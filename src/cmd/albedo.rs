//! `dermis albedo`: the multi-scatter albedo A ↔ reduced albedo α' map checked against the
//! Monte Carlo. For A = 0.05, 0.10, …, 0.95 and each η: the medium the table's inversion
//! (`shading::albedo::single_scatter_albedo`) makes from A, and the one the
//! `KHR_materials_volume_scatter` draft's analytic relation makes, each walked by the plane
//! walker under diffuse light; what each reflects (per incident power) against A. An A above
//! C(η) (what a white medium reflects: 0.923 at η = 1.4) is not a medium's and is skipped.

use dermis_engine::shading::subsurface::exit_normalisation;
use dermis_measure::albedo::{sweep_photons, sweep_row, SweepRow};
use serde_json::json;

use crate::cmd::args::{parse_eta, parse_g, parse_seed, parse_sss_photons};
use crate::cmd::progress::Progress;

#[derive(clap::Args, Debug)]
pub struct AlbedoArgs {
    /// Relative indices of refraction, comma-separated, each 1..=3 (the table spans
    /// 1.0–1.6 and clamps beyond).
    #[arg(long, value_delimiter = ',', default_value = "1.0,1.15,1.3,1.4,1.45,1.6",
          value_parser = parse_eta, allow_hyphen_values = true)]
    pub eta: Vec<f64>,
    /// Henyey–Greenstein anisotropy g, -0.99..=0.99 (σ_s = σ'_s/(1−g) in the Monte Carlo).
    #[arg(long, default_value_t = 0.0, value_parser = parse_g, allow_hyphen_values = true)]
    pub g: f64,
    /// Photons of a check at A = 1, 1000..=1e8 (a check at A uses photons/A).
    #[arg(long, default_value_t = 40_000, value_parser = parse_sss_photons, allow_hyphen_values = true)]
    pub photons: u64,
    /// Seed of the Monte Carlo.
    #[arg(long, default_value_t = 1, value_parser = parse_seed, allow_hyphen_values = true)]
    pub seed: u64,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
    /// The dense check instead, written to this JSON file: η 1.00–1.60 by 0.01 and A 0.05,
    /// 0.10, 0.20, …, 0.90 and C(η) − 0.01 (the table's medium only; `--eta` is ignored).
    #[arg(long, value_name = "F.json")]
    pub sweep: Option<std::path::PathBuf>,
}

/// The multi-scatter albedos checked.
pub fn albedos() -> Vec<f64> {
    (1..=19).map(|i| 0.05 * i as f64).collect()
}

pub fn run(args: AlbedoArgs) -> Result<(), String> {
    if let Some(out) = &args.sweep {
        crate::cmd::args::check_out_file(out, Some("json"))?;
        return super::albedo_sweep::run(out, args.g, args.photons, args.seed);
    }
    let threads = dermis_measure::bake::threads();
    let multis = albedos();
    let reachable = |eta: f64| -> Vec<(usize, f64)> {
        let white = exit_normalisation(eta);
        multis
            .iter()
            .copied()
            .enumerate()
            .filter(|(_, a)| *a < white)
            .collect()
    };
    let total: usize = args.eta.iter().map(|&e| reachable(e).len()).sum();
    let mut progress = Progress::new("albedo", total as u64);
    let mut rows: Vec<SweepRow> = Vec::new();
    for &eta in &args.eta {
        for (i, a) in reachable(eta) {
            progress.begin(&format!("η {eta}: A {a:.2}"));
            let seed = args.seed.wrapping_add(1000 * i as u64);
            rows.push(sweep_row(a, eta, args.g, args.photons, seed, threads));
            progress.step(&format!("η {eta}: A {a:.2}"));
        }
    }
    progress.finish();
    let worst = |f: fn(&SweepRow) -> f64| rows.iter().map(f).fold(0.0f64, f64::max);
    let table_worst = worst(|r| r.errors().0.abs());
    let draft_worst = worst(|r| r.errors().1.abs());
    if args.json {
        let out = json!({
            "g": args.g,
            "photons_at_a_1": args.photons,
            "seed": args.seed,
            "worst_table": table_worst, "worst_draft": draft_worst,
            "rows": rows.iter().map(|r| json!({
                "multi": r.multi, "eta": r.eta, "single": r.single,
                "measured": r.measured.mean, "measured_se": r.measured.std_err,
                "draft_single": r.draft_single,
                "draft_measured": r.draft_measured.mean, "draft_measured_se": r.draft_measured.std_err,
                "photons": sweep_photons(r.multi, args.photons),
            })).collect::<Vec<_>>(),
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&out).map_err(|e| e.to_string())?
        );
        return Ok(());
    }
    println!(
        "A → α' (the measured table's inversion) and the draft's α', each medium's A measured \
         by the plane walker under diffuse light, per incident power (g = {}):",
        args.g
    );
    println!(
        "{:>5} {:>5} {:>10} {:>16} {:>8}   {:>10} {:>16} {:>8}",
        "η", "A", "α'", "measured A", "error", "draft α'", "measured A", "error"
    );
    for r in &rows {
        let (e, d) = r.errors();
        println!(
            "{:>5} {:>5.2} {:>10.6} {:>9.4} ± {:.4} {:>+7.2}%   {:>10.6} {:>9.4} ± {:.4} {:>+7.2}%",
            r.eta,
            r.multi,
            r.single,
            r.measured.mean,
            r.measured.std_err,
            100.0 * e,
            r.draft_single,
            r.draft_measured.mean,
            r.draft_measured.std_err,
            100.0 * d
        );
    }
    println!(
        "largest |error|: table {:.2} %, draft {:.2} %",
        100.0 * table_worst,
        100.0 * draft_worst
    );
    Ok(())
}
