//! `dermis lut`: bakes what the core ships in `assets/sss/`: the A ↔ α' table
//! (`albedo.table`, `dermis_engine::shading::albedo`), the presets' spatial-model tables and
//! pre-integrated skin LUTs (`<material>-eta<η>.tables` and `.lut`, see
//! `dermis_engine::shading::bake` and `dermis_engine::shading::preintegrated`), and with
//! `--grid` the nondimensional grids every other material's tables and LUT are interpolated
//! from (`optics.tables`, `optics.lut`: `dermis_engine::shading::grid`, `sphere_grid`).

use std::path::PathBuf;
use std::time::Instant;

use crate::cmd::args::check_out_dir;
use crate::cmd::progress::Progress;
use dermis_engine::shading::material::PRESETS;
use dermis_engine::shading::{bake, preintegrated};
use dermis_measure::bake::{measure, threads};
use dermis_measure::{ground_truth, lut};

#[derive(clap::Args, Debug)]
pub struct LutArgs {
    /// Output directory (the shipped tables live in assets/sss).
    #[arg(long)]
    pub out: PathBuf,
    /// Only the kernel/oblique/slab tables (seconds), not the sphere LUTs (minutes).
    #[arg(long)]
    pub tables_only: bool,
    /// Only the A ↔ α' table (`albedo.table`: ~10 min on 2 shared cores).
    #[arg(long, conflicts_with = "tables_only")]
    pub albedo_only: bool,
    /// Everything but the A ↔ α' table (the spatial models' tables and the sphere LUTs: what
    /// a change to the slab or kernel bake re-makes).
    #[arg(long, conflicts_with_all = ["tables_only", "albedo_only"])]
    pub no_albedo: bool,
    /// Only the nondimensional grids every non-preset material's tables come from: `tables`
    /// (`optics.tables`: kernel, q(μ), δ(μ), slabs), `spheres` (`optics.lut`: the
    /// pre-integration sphere rows) or `all` (~2 h on 2 shared cores; deterministic).
    #[arg(long, value_parser = parse_grid, conflicts_with_all = ["tables_only", "albedo_only", "no_albedo"])]
    pub grid: Option<Grid>,
}

/// Which grid `dermis lut --grid` bakes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Grid {
    Tables,
    Spheres,
    All,
}

fn parse_grid(s: &str) -> Result<Grid, String> {
    match s {
        "tables" => Ok(Grid::Tables),
        "spheres" => Ok(Grid::Spheres),
        "all" => Ok(Grid::All),
        _ => Err(format!("unknown grid `{s}` (known: tables, spheres, all)")),
    }
}

/// Bakes the grids (`--grid`).
fn bake_grids(out: &std::path::Path, which: Grid, threads: usize) -> Result<(), String> {
    use dermis_engine::shading::grid::GRID_BUDGET;
    use dermis_engine::shading::sphere_grid;
    use dermis_measure::grid;
    let write = |name: &str, bytes: Vec<u8>, start: Instant, what: String| {
        let path = out.join(name);
        std::fs::write(&path, &bytes)
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        println!(
            "{} ({} bytes, {:.0} s wall; {what})",
            path.display(),
            bytes.len(),
            start.elapsed().as_secs_f64()
        );
        Ok::<(), String>(())
    };
    if which != Grid::Spheres {
        let start = Instant::now();
        let total = dermis_engine::shading::grid::S_COUNT * dermis_engine::shading::grid::ETA_COUNT;
        let mut progress = Progress::new("lut grid tables", total as u64);
        progress.begin("tables grid: one node (s, η) at a time");
        let g = grid::bake_tables(&GRID_BUDGET, threads, |d, n| {
            progress.step(&format!("node {d}/{n}"))
        });
        progress.finish();
        let what = format!("{} nodes (s × η)", g.nodes.len());
        write("optics.tables", g.to_bytes(), start, what)?;
    }
    if which != Grid::Tables {
        let start = Instant::now();
        let mut progress = Progress::new("lut grid spheres", sphere_grid::rows() as u64);
        progress.begin("sphere grid: one row (η, s, R̂) at a time");
        let g = grid::bake_spheres(&GRID_BUDGET, threads, |d, n| {
            progress.step(&format!("row {d}/{n}"))
        });
        progress.finish();
        let what = format!("{} rows (η × s × R̂)", sphere_grid::rows());
        write("optics.lut", g.to_bytes(), start, what)?;
    }
    Ok(())
}

/// Bakes the A ↔ α' table (`albedo.table`).
fn bake_albedo(out: &std::path::Path, threads: usize) -> Result<(), String> {
    use dermis_engine::shading::albedo::ETA_NODES;
    use dermis_measure::albedo::{bake_table, PHOTONS, SEED};
    let start = Instant::now();
    let mut progress = Progress::new("lut albedo", ETA_NODES as u64);
    progress.begin("A ↔ α' table (white Monte Carlo, one η row at a time)");
    let table = bake_table(PHOTONS, SEED, threads, |r| {
        progress.step(&format!("η row {r} done"))
    });
    progress.finish();
    let worst = table
        .multi
        .iter()
        .zip(&table.std_err)
        .flat_map(|(a, s)| a.iter().zip(s))
        .filter(|(a, _)| **a >= 0.05)
        .map(|(a, s)| s / a)
        .fold(0.0f32, f32::max);
    let path = out.join("albedo.table");
    let bytes = table.to_bytes();
    std::fs::write(&path, &bytes).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    println!(
        "{} ({} bytes, {:.0} s; {PHOTONS} photons per η row; largest relative SE where A_e ≥ 0.05: {:.3} %)",
        path.display(),
        bytes.len(),
        start.elapsed().as_secs_f64(),
        100.0 * worst
    );
    Ok(())
}

/// Bakes every preset at its own η and at the reference scenes' η (the tables are
/// deterministic: the same bytes for any thread count).
pub fn run(args: LutArgs) -> Result<(), String> {
    // Checked before minutes of Monte Carlo, not after.
    check_out_dir(&args.out)?;
    let threads = threads();
    if let Some(which) = args.grid {
        return bake_grids(&args.out, which, threads);
    }
    if !(args.tables_only || args.no_albedo) {
        bake_albedo(&args.out, threads)?;
    }
    if args.albedo_only {
        return Ok(());
    }
    let budget = bake::DEFAULT_BUDGET;
    let materials: Vec<_> = PRESETS
        .iter()
        .flat_map(|m| [m.clone(), ground_truth::acceptance_material(m)])
        .collect();
    let steps = if args.tables_only { 1 } else { 2 };
    eprintln!(
        "lut: {} materials into {} ({threads} threads; the sphere LUTs about a minute each on 2 cores)",
        materials.len(),
        args.out.display()
    );
    // Per material: the tables' Monte Carlo, then (unless --tables-only) the sphere LUT.
    let mut progress = Progress::new("lut", steps * materials.len() as u64);
    let write = |path: PathBuf, bytes: Vec<u8>, start: Instant, progress: &mut Progress| {
        std::fs::write(&path, bytes)
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        progress.suspend(|| {
            println!(
                "{} ({:.1} s)",
                path.display(),
                start.elapsed().as_secs_f64()
            )
        });
        Ok::<(), String>(())
    };
    for m in &materials {
        let start = Instant::now();
        progress.begin(&format!("{} η={}: tables (Monte Carlo)", m.name, m.eta));
        let tables = measure(m, budget, threads);
        let path = args.out.join(bake::file_name(m));
        write(path, tables.to_bytes(m, &budget), start, &mut progress)?;
        progress.step(&format!("{} η={}: tables written", m.name, m.eta));
        if !args.tables_only {
            let start = Instant::now();
            progress.begin(&format!("{} η={}: sphere LUT", m.name, m.eta));
            let lut = lut::bake_lut(&tables, m, &budget, threads);
            let path = args.out.join(preintegrated::file_name(m));
            write(path, lut.to_bytes(m, &budget), start, &mut progress)?;
            progress.step(&format!("{} η={}: LUT written", m.name, m.eta));
        }
    }
    progress.finish();
    Ok(())
}
