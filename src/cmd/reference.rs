//! `dermis reference`: generates the path-traced reference data set
//! (`tools/reference/<material>.json`, see `dermis_measure::ground_truth`), or with
//! `--scene head` the face truth (`reference_head.rs`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::cmd::args::{
    check_out_dir, parse_reference_photons, parse_seed, parse_threads, parse_vec3,
};
use crate::cmd::material_args::MaterialArgs;
use crate::cmd::progress::Progress;
use dermis_engine::shading::material::{Material, SKIN1, WHITE_COAT};
use dermis_measure::ground_truth::{self, ReferenceSet};

#[derive(clap::Args, Debug)]
pub struct ReferenceArgs {
    /// Output directory; writes <material>.json there (`--scene head`: <light>.pfm,
    /// <light>-se.pfm, alpha.pfm and truth.json; tools/reference/face is the cache).
    #[arg(long)]
    pub out: PathBuf,
    /// probes (the measurement scenes) | head (the scanned head in the face scenes' camera).
    #[arg(long, default_value = "probes", value_parser = ["probes", "head"])]
    pub scene: String,
    /// `--scene head`: a point light at X,Y,Z [m, the head's frame] (written as `light`).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub light: Option<glam::Vec3>,
    /// `--scene head`: the face scenes' light(s): front | side | back | all (default: all,
    /// unless --light).
    #[arg(long, value_parser = ["front", "side", "back", "all"])]
    pub face_light: Option<String>,
    /// Photons per channel and scene, 1000..=1e9 (default: per material, see
    /// tools/reference/README.md; `--scene head`: 8e6 for red, ×1.5 green, ×2.5 blue, per light).
    #[arg(long, value_parser = parse_reference_photons, allow_hyphen_values = true)]
    pub photons: Option<u64>,
    /// The medium (probes): a name — skin1 | white-coat | skin-dark | skin-pale | marble |
    /// all (the default) —, coefficients, albedo and mean free path, or a file's skin material
    /// (written as <its name>.json; `custom` for numbers).
    #[command(flatten)]
    pub medium: MaterialArgs,
    /// Seed of the Monte Carlo.
    #[arg(long, default_value_t = 1, value_parser = parse_seed, allow_hyphen_values = true)]
    pub seed: u64,
    /// Worker threads, 1..=1024 (default: all cores; the results do not depend on it).
    #[arg(long, value_parser = parse_threads, allow_hyphen_values = true)]
    pub threads: Option<usize>,
}

/// Default photons per channel and scene: enough for ≲ 1–2 % relative standard error over
/// the bins that carry the light, within a few minutes per material on two cores. A material
/// with a channel whose albedo is near 1 (α' > 0.999: the white coat, marble) walks ~20× longer
/// per photon and gets 400,000; the others 2,000,000.
pub fn default_photons(material: &Material) -> u64 {
    if material.albedo().iter().any(|a| *a > 0.999) {
        400_000
    } else {
        2_000_000
    }
}

/// Every material with a reference set: the presets as the acceptance case, then the test
/// materials that are not a preset.
fn all_materials() -> Vec<Material> {
    [SKIN1, WHITE_COAT]
        .iter()
        .map(ground_truth::acceptance_material)
        .chain(ground_truth::test_materials())
        .collect()
}

/// A material with a reference set by name (not `all`).
pub fn named(name: &str) -> Result<Material, String> {
    let all = all_materials();
    let known: Vec<&str> = all.iter().map(|m| &*m.name).collect();
    all.iter().find(|m| m.name == name).cloned().ok_or_else(|| {
        format!(
            "unknown material `{name}` (known: {}, all)",
            known.join(", ")
        )
    })
}

/// The materials `medium` asks for: every one with a reference set (`all`, the default),
/// or the one it names or describes.
fn materials(medium: &MaterialArgs) -> Result<Vec<Material>, String> {
    let all = medium.material.as_deref().unwrap_or("all") == "all" && !medium.is_custom();
    if all && (medium.eta.is_some() || medium.g.is_some()) {
        return Err("--eta and --g need one material (a name, or a medium's numbers)".into());
    }
    match all {
        true => Ok(all_materials()),
        false => Ok(vec![medium.resolve("all", named)?]),
    }
}

pub fn run(args: ReferenceArgs) -> Result<(), String> {
    if args.scene == "head" {
        return super::reference_head::run(&args);
    }
    if args.light.is_some() || args.face_light.is_some() {
        return Err("--light and --face-light need --scene head".into());
    }
    let mats = materials(&args.medium)?;
    let threads = args
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    for m in &mats {
        for (scene, edges) in ground_truth::standard_scenes(m) {
            scene
                .validate(&edges)
                .map_err(|e| format!("{}: {e}", m.name))?;
        }
    }
    check_out_dir(&args.out)?;

    for m in &mats {
        let photons = args.photons.unwrap_or_else(|| default_photons(m));
        let scenes = ground_truth::standard_scenes(m);
        eprintln!(
            "{}: {} scenes × 3 channels, {photons} photons each, seed {}, {threads} threads",
            m.name,
            scenes.len(),
            args.seed
        );
        let start = Instant::now();
        let set = with_progress(&m.name, |progress| {
            ReferenceSet::generate(m, &scenes, photons, args.seed, threads, progress)
        });
        let secs = start.elapsed().as_secs_f64();
        let path = ground_truth::file_for(&args.out, &m.name);
        set.save(&path)?;
        print_summary(&set, secs, &path);
    }
    Ok(())
}

/// Runs `work` with a [`Progress`] display of its simulations.
fn with_progress<T>(name: &str, work: impl FnOnce(&mut dyn FnMut(usize, usize)) -> T) -> T {
    let mut progress = Progress::new(name, 1);
    let out = work(&mut |d, t| progress.set(d as u64, t as u64, "simulations"));
    progress.finish();
    out
}

fn print_summary(set: &ReferenceSet, secs: f64, path: &Path) {
    println!(
        "{} (η = {}, g = {}): {} in {:.0} s",
        set.material,
        set.eta,
        set.g,
        path.display(),
        secs
    );
    println!(
        "  {:<22} {:>5} {:>9}   {:>14} {:>14}",
        "scene", "bins", "photons", "max rel SE ≥1%", "max rel SE all"
    );
    for e in &set.entries {
        let (bright, all) = max_rel_se(e);
        println!(
            "  {:<22} {:>5} {:>9}   {:>13.2}% {:>13.2}%",
            e.scene.label(),
            e.values.len(),
            e.photons,
            100.0 * bright,
            100.0 * all
        );
    }
    println!(
        "  (relative SE over the bins above the metric's noise floor of {} SE: those holding \
         ≥ 1 % of the channel's peak, and all of them)",
        ground_truth::metric::NOISE_FLOOR
    );
}

/// Largest relative standard error over the bins (and channels) whose value is at least 1 %
/// of that channel's peak in the entry, and over every bin above the metric's noise floor.
pub fn max_rel_se(e: &ground_truth::Entry) -> (f64, f64) {
    let (mut bright, mut all): (f64, f64) = (0.0, 0.0);
    for c in 0..3 {
        let peak = e.values.iter().map(|v| v[c]).fold(0.0, f64::max);
        for (v, s) in e.values.iter().zip(&e.std_err) {
            if v[c] > 0.0 && v[c] > ground_truth::metric::NOISE_FLOOR * s[c] {
                let rel = s[c] / v[c];
                all = all.max(rel);
                if v[c] >= 0.01 * peak {
                    bright = bright.max(rel);
                }
            }
        }
    }
    (bright, all)
}
