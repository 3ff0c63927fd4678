//! `dermis lut`: bakes the pre-integrated skin LUTs the core ships
//! (`assets/sss/<material>-eta<η>.lut`, see `dermis_core::shading::preintegrated`).

use std::path::PathBuf;
use std::time::Instant;

use crate::cmd::args::check_out_dir;
use crate::cmd::progress::Progress;
use dermis_core::reference;
use dermis_core::shading::bake;
use dermis_core::shading::material::PRESETS;
use dermis_core::shading::preintegrated;

#[derive(clap::Args, Debug)]
pub struct LutArgs {
    /// Output directory (the shipped tables live in assets/sss).
    #[arg(long)]
    pub out: PathBuf,
}

/// Bakes every preset at its own η and at the reference scenes' η (the tables are
/// deterministic: the same bytes for any thread count).
pub fn run(args: LutArgs) -> Result<(), String> {
    // Checked before minutes of Monte Carlo, not after.
    check_out_dir(&args.out)?;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let budget = bake::DEFAULT_BUDGET;
    let materials: Vec<_> = PRESETS
        .iter()
        .flat_map(|m| [*m, reference::acceptance_material(m)])
        .collect();
    eprintln!(
        "lut: {} tables into {} ({threads} threads; about a minute each on 2 cores)",
        materials.len(),
        args.out.display()
    );
    // Two steps per table: the Monte Carlo measurement, then the LUT integration.
    let mut progress = Progress::new("lut", 2 * materials.len() as u64);
    for m in &materials {
        let path = args.out.join(preintegrated::file_name(m));
        let start = Instant::now();
        progress.begin(&format!("{} η={}: Monte Carlo", m.name, m.eta));
        let measured = bake::measure(m, budget, threads);
        progress.step(&format!("{} η={}: LUT", m.name, m.eta));
        let lut = preintegrated::bake_lut(&measured, m, &budget, threads);
        std::fs::write(&path, lut.to_bytes(m, &budget))
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        progress.step(&format!("{} η={}: written", m.name, m.eta));
        progress.suspend(|| {
            println!(
                "{} ({:.0} s)",
                path.display(),
                start.elapsed().as_secs_f64()
            )
        });
    }
    progress.finish();
    Ok(())
}
