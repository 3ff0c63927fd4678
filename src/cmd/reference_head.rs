//! `dermis reference --scene head`: the face truth — the project's Monte Carlo on the scanned
//! head under a point light, as linear radiance and its standard error in the face scenes'
//! camera (`dermis_measure::face::truth`); the three named lights make the cache
//! (`tools/reference/face/`, read by `bench face` and the tests).

use std::path::Path;

use dermis_engine::asset::head;
use dermis_engine::scene::face::{self, FaceLight};
use dermis_measure::face::score::{Reference, BLOCK, MAX_REL_SE};
use dermis_measure::face::truth::{self, FaceScene, Truth, TruthRun};
use dermis_measure::face::truth_cache;

use super::args::check_out_dir;
use super::progress::Progress;
use super::reference::ReferenceArgs;

/// Default photons per channel and light.
pub const DEFAULT_PHOTONS: u64 = 8_000_000;

/// The lights asked for: (name, position [m]).
fn lights(args: &ReferenceArgs) -> Result<Vec<(String, glam::Vec3)>, String> {
    match (&args.light, args.face_light.as_deref()) {
        (Some(_), Some(_)) => Err("give --light or --face-light, not both".into()),
        (Some(p), None) => Ok(vec![("light".into(), *p)]),
        (None, None | Some("all")) => Ok(FaceLight::ALL
            .iter()
            .map(|l| (l.name().to_string(), l.position()))
            .collect()),
        (None, Some(name)) => {
            let l = FaceLight::parse(name).map_err(|e| format!("--face-light: {e} or all"))?;
            Ok(vec![(l.name().into(), l.position())])
        }
    }
}

pub fn run(args: &ReferenceArgs) -> Result<(), String> {
    // The face scenes' medium is skin1 (what `bench face` scores); any other is a truth of
    // its own (its cache refuses the face scenes' material, and theirs refuses it).
    let medium = match args.medium.material.as_deref() {
        Some("all") if !args.medium.is_custom() => crate::cmd::material_args::MaterialArgs {
            material: None,
            ..args.medium.clone()
        },
        _ => args.medium.clone(),
    };
    let material = medium.resolve("skin1", crate::cmd::args::parse_material)?;
    let lights = lights(args)?;
    check_out_dir(&args.out)?;
    let scene = FaceScene {
        material,
        ..FaceScene::head(&crate::paths::assets_dir())?
    };
    // The light must be outside the head: checked for every light before any photon runs.
    let mesh = scene.closed_mesh()?;
    for (name, p) in &lights {
        if mesh.contains(p.as_dvec3() * 1000.0) {
            return Err(format!(
                "--light {name} at {:?} m is inside the head",
                p.to_array()
            ));
        }
    }
    let run = TruthRun {
        photons: args.photons.unwrap_or(DEFAULT_PHOTONS),
        seed: args.seed,
        threads: args
            .threads
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())),
    };
    for (name, position) in &lights {
        let mut progress = Progress::new(&format!("reference head {name}"), 1);
        let truth = truth::compute(
            &scene,
            &mesh,
            name,
            *position,
            face::LIGHT_INTENSITY,
            &run,
            &mut |d, t| progress.set(d, t, "photons"),
        )?;
        progress.finish();
        truth_cache::save(&args.out, &truth)?;
        summary(&args.out, &truth)?;
    }
    println!("{}", head::ATTRIBUTION);
    Ok(())
}

/// Percentile `q` (0..1) of ascending `v`.
fn percentile(v: &[f64], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v[((v.len() - 1) as f64 * q).round() as usize]
}

fn summary(dir: &Path, t: &Truth) -> Result<(), String> {
    let r = &t.record;
    let reference = Reference::from_truth(&t.radiance, &t.std_err, &t.alpha, BLOCK)?;
    let rel = reference.relative_errors();
    let cpu: f64 = r.cpu_seconds.iter().sum();
    let wall: f64 = r.wall_seconds.iter().sum();
    let photons: u64 = r.photons_per_channel.iter().sum();
    println!(
        "{}: {} {}x{} light at {:.3?} m: {:?} photons (R, G, B; seed {}), {:.0} s wall, \
         {:.0} s CPU on {} threads: {:.0} photons/s per CPU-second",
        dir.display(),
        r.name,
        t.radiance.width,
        t.radiance.height,
        r.position,
        r.photons_per_channel,
        r.seed,
        wall,
        cpu,
        r.threads,
        photons as f64 / cpu.max(1e-9)
    );
    let e = &r.energy;
    for (c, name) in ["R", "G", "B"].iter().enumerate() {
        let k = |v: [f64; 2]| v[0];
        let inc = k(e[c].incident);
        let balance =
            k(e[c].specular) + k(e[c].escaped) + k(e[c].absorbed) + k(e[c].capped) + k(e[c].lost);
        println!(
            "  {name}: hit {:.4} of the cone; per incident: specular {:.4}, exits {:.4} \
             (re-entered {:.4}), escaped {:.4}, absorbed {:.4}, capped {:.1e}, lost {:.1e}, \
             culled at entry {:.4}; balance {:.5}; {:.1} events/photon",
            inc,
            k(e[c].specular) / inc,
            k(e[c].exits) / inc,
            k(e[c].reentered) / inc,
            k(e[c].escaped) / inc,
            k(e[c].absorbed) / inc,
            k(e[c].capped) / inc,
            k(e[c].lost) / inc,
            k(e[c].culled) / inc,
            balance / inc,
            r.events[c] as f64 / r.photons_per_channel[c] as f64
        );
    }
    println!(
        "  {BLOCK}x{BLOCK} blocks scored (relative SE ≤ {MAX_REL_SE}): {} block channels; \
         relative SE median {:.4}, 95th percentile {:.4}",
        reference.scored(),
        percentile(&rel, 0.5),
        percentile(&rel, 0.95)
    );
    Ok(())
}
