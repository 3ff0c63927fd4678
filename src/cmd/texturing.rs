//! `dermis texturing`: the albedo map through the subsurface medium, measured by the Monte
//! Carlo of the textured medium (`dermis_measure::texturing`, `mc::pigment`): the uniform
//! patch (each texel's albedo back) and the albedo step's exitance profiles for the three
//! texturings, written as the step reference (`albedo-step.json`).

use std::path::PathBuf;
use std::time::Instant;

use crate::cmd::args::{check_out_dir, parse_reference_photons, parse_seed};
use crate::cmd::progress::Progress;
use dermis_measure::mc::pigment::Texturing;
use dermis_measure::texturing::{self, StepLight, StepSet, PATCH_ALBEDO};

#[derive(clap::Args, Debug)]
pub struct TexturingArgs {
    /// Output directory; writes albedo-step.json there (the committed one: tools/reference).
    #[arg(long)]
    pub out: PathBuf,
    /// Photons per channel and profile, 1000..=1e9.
    #[arg(long, default_value_t = texturing::STEP_PHOTONS, value_parser = parse_reference_photons, allow_hyphen_values = true)]
    pub photons: u64,
    /// Seed of the Monte Carlo.
    #[arg(long, default_value_t = texturing::SEED, value_parser = parse_seed, allow_hyphen_values = true)]
    pub seed: u64,
    /// Only the uniform patch (photons/8 per channel and texturing; minutes), no step file.
    #[arg(long)]
    pub patch_only: bool,
}

pub fn run(args: TexturingArgs) -> Result<(), String> {
    check_out_dir(&args.out)?;
    let threads = dermis_measure::bake::threads();
    let start = Instant::now();
    let mut progress = Progress::new("texturing", 3 + 6);
    let patch_photons = (args.photons / 8).max(1000);
    let mut patches = Vec::new();
    for t in Texturing::ALL {
        progress.begin(&format!("patch, {}", t.name()));
        patches.push((t, texturing::patch(t, patch_photons, args.seed, threads)));
        progress.step(&format!("patch, {}", t.name()));
    }
    let set = if args.patch_only {
        None
    } else {
        Some(StepSet::generate(
            args.photons,
            args.seed,
            threads,
            |d, n| progress.set(3 + d as u64, 9, &format!("step profiles {d}/{n}")),
        ))
    };
    progress.finish();

    println!(
        "Uniform light on the patch (texels {} mm, centre {} mm; A₀ = {:.4}, η = {}): exitance per \
         unit irradiance over each texel's centre ({patch_photons} photons per channel):",
        texturing::PATCH_TEXEL_MM,
        texturing::PATCH_CENTRE_MM,
        texturing::base(),
        texturing::ETA
    );
    println!(
        "{:>10} {:>5}   {:>26}   {:>7}",
        "texturing", "A", "R, G, B (± SE)", "worst"
    );
    for (t, texels) in &patches {
        for (i, est) in texels.iter().enumerate() {
            let a = PATCH_ALBEDO[i];
            let worst = est
                .iter()
                .map(|e| (e.mean / a - 1.0).abs())
                .fold(0.0, f64::max);
            println!(
                "{:>10} {:>5.2}   {:.4} {:.4} {:.4} (±{:.4})   {:>6.2}%",
                t.name(),
                a,
                est[0].mean,
                est[1].mean,
                est[2].mean,
                est.iter().map(|e| e.std_err).fold(0.0, f64::max),
                100.0 * worst
            );
        }
    }
    let Some(set) = set else {
        println!("({:.0} s)", start.elapsed().as_secs_f64());
        return Ok(());
    };
    let path = texturing::step_file(&args.out);
    set.save(&path)?;
    println!(
        "\nThe step (A = {:.4} | {:.4} at x = 0; σ'_t {:?} mm⁻¹): exitance per strip, red / blue",
        texturing::dark(),
        texturing::base(),
        texturing::SIGMA_T
    );
    for light in texturing::STEP_LIGHTS {
        let unit = match light {
            StepLight::Uniform => "per unit irradiance",
            StepLight::Point { .. } => "mm⁻² per unit power, |y| < 0.5 mm",
        };
        println!("{light:?} ({unit}):");
        let edges = texturing::step_edges();
        print!("{:>10}", "x mm");
        let shown: Vec<usize> = (0..edges.len() - 1).step_by(3).collect();
        for &k in &shown {
            print!(" {:>19.2}", 0.5 * (edges[k] + edges[k + 1]));
        }
        println!();
        for t in Texturing::ALL {
            if let Some(e) = set.entry(t, light) {
                print!("{:>10}", t.name());
                for &k in &shown {
                    print!(" {:>9.3e}/{:>9.3e}", e.values[k][0], e.values[k][2]);
                }
                println!();
            }
        }
    }
    println!(
        "wrote {} ({:.0} s; {} photons per channel and profile)",
        path.display(),
        start.elapsed().as_secs_f64(),
        args.photons
    );
    Ok(())
}
