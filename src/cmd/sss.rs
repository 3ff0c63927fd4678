//! `dermis sss`: every model's total diffuse reflectance next to the Monte Carlo reference.

use dermis_engine::shading::{prediction, Material, ShadingModel};
use dermis_measure::mc::{self, Medium};
use serde_json::{json, Map, Value};

use crate::cmd::args::{parse_material, parse_seed, parse_sss_photons};
use crate::cmd::material_args::MaterialArgs;
use crate::cmd::progress::Progress;

#[derive(clap::Args, Debug)]
pub struct SssArgs {
    /// The medium (default skin1): a name, coefficients, albedo and mean free path, or a
    /// file's skin material (the Monte Carlo walks σ_s = σ'_s/(1−g) with the real phase).
    #[command(flatten)]
    pub medium: MaterialArgs,
    /// Photons per channel and geometry, 1000..=1e8.
    #[arg(long, default_value_t = 100_000, value_parser = parse_sss_photons, allow_hyphen_values = true)]
    pub photons: u64,
    /// Seed of the Monte Carlo.
    #[arg(long, default_value_t = 1, value_parser = parse_seed, allow_hyphen_values = true)]
    pub seed: u64,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// Slab thicknesses (mm).
pub const SLABS: [f64; 4] = [0.5, 1.0, 2.0, 5.0];

/// Monte Carlo reference: value and standard error per channel, per entered power.
pub struct Reference {
    pub semi_infinite: ([f64; 3], [f64; 3]),
    pub slabs: Vec<(f64, [f64; 3], [f64; 3])>,
}

/// Monte Carlo runs of [`reference`]: three channels, semi-infinite and every slab.
pub const RUNS: usize = 3 * (1 + SLABS.len());

/// The Monte Carlo reference, a step of `progress` per run.
pub fn reference(
    material: &Material,
    photons: u64,
    seed: u64,
    progress: &mut Progress,
) -> Reference {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let medium = |c: usize| Medium {
        sigma_a: material.sigma_a[c],
        sigma_s_prime: material.sigma_s_prime[c],
        g: material.g,
        eta: material.eta,
    };
    let specular = mc::fresnel::fresnel(1.0, material.eta).0;
    let entered = 1.0 / (1.0 - specular);
    let mut semi = ([0.0; 3], [0.0; 3]);
    for c in 0..3 {
        progress.begin("Monte Carlo: semi-infinite");
        let e = mc::total_reflectance(&medium(c), photons, seed + c as u64, threads);
        progress.step("Monte Carlo: semi-infinite");
        semi.0[c] = e.mean * entered;
        semi.1[c] = e.std_err * entered;
    }
    let slabs = SLABS
        .iter()
        .map(|&d| {
            let mut v = ([0.0; 3], [0.0; 3]);
            for c in 0..3 {
                progress.begin(&format!("Monte Carlo: slab {d} mm"));
                let s = mc::slab(&medium(c), d, photons, seed + 10 + c as u64, threads);
                progress.step(&format!("Monte Carlo: slab {d} mm"));
                v.0[c] = s.r.mean * entered;
                v.1[c] = s.r.std_err * entered;
            }
            (d, v.0, v.1)
        })
        .collect();
    Reference {
        semi_infinite: semi,
        slabs,
    }
}

fn rel(model: [f64; 3], reference: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|c| model[c] / reference[c] - 1.0)
}

pub fn run(args: SssArgs) -> Result<(), String> {
    let material = args.medium.resolve("skin1", parse_material)?;
    // Steps: the Monte Carlo runs, then the models' predictions (the spatial models measure
    // their tables for a material met for the first time).
    let mut progress = Progress::new("sss", (RUNS + 1) as u64);
    let reference = reference(&material, args.photons, args.seed, &mut progress);
    progress.begin("model predictions");
    for model in ShadingModel::ALL {
        prediction::total_reflectance(model, &material, None);
    }
    progress.step("model predictions");
    progress.finish();
    let mut ref_slab = Map::new();
    let mut ref_slab_se = Map::new();
    for (d, v, se) in &reference.slabs {
        ref_slab.insert(d.to_string(), json!(v));
        ref_slab_se.insert(d.to_string(), json!(se));
    }
    let mut models = Map::new();
    for model in ShadingModel::ALL {
        let semi = prediction::total_reflectance(model, &material, None);
        let mut slab = Map::new();
        let mut slab_err = Map::new();
        for (d, v, _) in &reference.slabs {
            let p = prediction::total_reflectance(model, &material, Some(*d));
            slab.insert(d.to_string(), json!(p));
            slab_err.insert(d.to_string(), json!(rel(p, *v)));
        }
        models.insert(
            model.name().into(),
            json!({
                "semi_infinite": semi,
                "slab": slab,
                "relative_error": {"semi_infinite": rel(semi, reference.semi_infinite.0), "slab": slab_err},
            }),
        );
    }
    let report = json!({
        "material": material.name,
        "sigma_a": material.sigma_a,
        "sigma_s_prime": material.sigma_s_prime,
        "eta": material.eta,
        "g": material.g,
        "photons": args.photons,
        "convention": "diffuse reflectance per unit power entering the medium (Jensen's R_d), normal incidence, specular excluded",
        "reference": {
            "semi_infinite": reference.semi_infinite.0,
            "semi_infinite_std_err": reference.semi_infinite.1,
            "slab": Value::Object(ref_slab),
            "slab_std_err": Value::Object(ref_slab_se),
        },
        "models": Value::Object(models),
    });
    if args.json {
        return crate::cmd::stats::print_json(&report);
    }
    println!(
        "{} (σ_a {:?}, σ'_s {:?} mm⁻¹) η={} g={} — total diffuse reflectance (R, G, B), \
         relative error vs Monte Carlo ({} photons)",
        material.name,
        material.sigma_a,
        material.sigma_s_prime,
        material.eta,
        material.g,
        args.photons
    );
    let (r, se) = reference.semi_infinite;
    let max_se = |se: &[f64; 3]| se[0].max(se[1]).max(se[2]);
    println!(
        "semi-infinite: MC {:.4} {:.4} {:.4} (±{:.4})",
        r[0],
        r[1],
        r[2],
        max_se(&se)
    );
    print_models(&material, None, r);
    for (d, v, se) in &reference.slabs {
        println!(
            "slab {d} mm: MC {:.4} {:.4} {:.4} (±{:.4})",
            v[0],
            v[1],
            v[2],
            max_se(se)
        );
        print_models(&material, Some(*d), *v);
    }
    Ok(())
}

/// One line per model: its prediction and its relative error against `reference`.
fn print_models(material: &Material, slab: Option<f64>, reference: [f64; 3]) {
    for model in ShadingModel::ALL {
        let p = prediction::total_reflectance(model, material, slab);
        let e = rel(p, reference);
        println!(
            "  {:<14} {:.4} {:.4} {:.4}   {:+6.1} % {:+6.1} % {:+6.1} %",
            model.name(),
            p[0],
            p[1],
            p[2],
            e[0] * 100.0,
            e[1] * 100.0,
            e[2] * 100.0
        );
    }
}
