//! The photon walk's speed on each geometry: photons and events per second of the thread's
//! time on a CPU (`/proc/thread-self/schedstat`, so that other processes sharing the cores do
//! not count; wall time where it cannot be read), one thread, the median of `--rounds` rounds
//! (JSON with `--json`, else a table). Numbers, not assertions.
//!
//! `cargo run --release -p dermis-measure --example walk_speed -- [--photons N] [--rounds R]
//! [--only NAME] [--json]`: N photons per round and geometry (default 100 000; the head walks
//! N/4), R ≥ 1 rounds (default 3). Geometries: `flat` (skin1 red, semi-infinite, normal beam,
//! radial bins), `slab` (skin1 red, 1 mm, diffuse light), `sphere` (skin1 red, 5 mm radius,
//! bands), `pigment` (per-texel stripes, uniform light), `mesh-sphere` (a 64×128 tessellated
//! sphere, 10 mm, under a near point light), `head` (the scanned head, skin1 red, the face
//! truth's side light and entry roulette, exits counted but not projected), `head-build` (the
//! head's walkable mesh built: BVH and voxel grids; no photons).

use std::path::Path;
use std::time::Instant;

use dermis_engine::scene::face::{self, FaceLight};
use glam::DVec3;

use dermis_measure::face::truth::{
    FaceScene, ROULETTE_DISTANCE_MM, ROULETTE_SURVIVAL, ROULETTE_VOXEL_MM,
};
use dermis_measure::mc::mesh::{uv_sphere, ClosedMesh, DistanceField};
use dermis_measure::mc::mesh_walk::{EntryRoulette, MeshTally, MeshWalker};
use dermis_measure::mc::pigment::{self, Bins, Light, Stripes, Textured, Texturing};
use dermis_measure::mc::rng::Rng;
use dermis_measure::mc::{self, Detectors, Geometry, Medium, Source, BATCH_SIZE};

const NAMES: [&str; 7] = [
    "flat",
    "slab",
    "sphere",
    "pigment",
    "mesh-sphere",
    "head",
    "head-build",
];

struct Args {
    photons: u64,
    rounds: usize,
    only: Option<String>,
    json: bool,
}

fn parse() -> Result<Args, String> {
    let mut a = Args {
        photons: 100_000,
        rounds: 3,
        only: None,
        json: false,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let mut value = |what: &str| it.next().ok_or(format!("{flag}: missing {what}"));
        match flag.as_str() {
            "--photons" => {
                a.photons = value("a photon count")?
                    .parse()
                    .ok()
                    .filter(|n| (BATCH_SIZE..=1_000_000_000).contains(n))
                    .ok_or(format!("--photons: a count in {BATCH_SIZE}..=1e9"))?
            }
            "--rounds" => {
                a.rounds = value("a count")?
                    .parse()
                    .ok()
                    .filter(|n| (1..=100).contains(n))
                    .ok_or("--rounds: a count in 1..=100")?
            }
            "--only" => {
                let v = value("a geometry")?;
                if !NAMES.contains(&v.as_str()) {
                    return Err(format!("--only: one of {}", NAMES.join(", ")));
                }
                a.only = Some(v);
            }
            "--json" => a.json = true,
            _ => return Err(format!("{flag}: unknown argument")),
        }
    }
    Ok(a)
}

/// skin1's red channel at η = 1.4: the longest walks.
fn red() -> Medium {
    Medium::new(0.032, 0.74, 0.0, 1.4)
}

/// Runs `photons` photons of `walker` in batches (one thread); the walk's events.
fn mesh_run(walker: &MeshWalker, photons: u64) -> u64 {
    let mut tally = MeshTally::default();
    let mut exits = 0u64;
    for b in 0..photons.div_ceil(BATCH_SIZE) {
        let mut rng = Rng::new(1, b);
        for _ in 0..BATCH_SIZE {
            walker.photon(&mut rng, &mut tally, &mut |_| exits += 1);
        }
    }
    std::hint::black_box(exits);
    tally.events
}

/// Seconds this thread has run on a CPU (Linux's scheduler statistics), or `None`.
fn on_cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = s.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

/// A clock: on-CPU time where the system tells it, else wall time.
fn now(t0: Instant) -> f64 {
    on_cpu_seconds().unwrap_or_else(|| t0.elapsed().as_secs_f64())
}

fn main() {
    let args = match parse() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("walk_speed: {e}");
            std::process::exit(2);
        }
    };
    let n = args.photons;
    let edges: Vec<f64> = (0..=40).map(|k| 0.25 * k as f64).collect();
    let det = Detectors {
        edges: edges.clone(),
        ..Default::default()
    };
    let bands: Vec<f64> = (0..=18).map(|k| 10.0 * k as f64).collect();
    let tex = Textured {
        sigma_t: 0.772,
        eta: 1.4,
        base: 0.55,
        base_single: 0.95,
        map: Stripes {
            edges: vec![0.0, 1.0],
            albedo: vec![0.3, 0.55, 0.4],
            period: Some(3.0),
        },
        single: vec![0.85, 0.95, 0.9],
        texturing: Texturing::PerTexel,
    };
    let bins = Bins {
        edges: (0..=30).map(|k| 0.1 * k as f64).collect(),
        band: 1.0,
    };
    let (pos, nrm, tris) = uv_sphere(10.0, 64, 128);
    let ball = ClosedMesh::new(pos, nrm, tris, 1.0).expect("the tessellated sphere");
    let ball_walk = MeshWalker::new(&ball, &red(), DVec3::new(8.0, 3.0, 25.0));
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets");
    let scene = FaceScene::head(&assets);
    let head = match scene
        .as_ref()
        .map_err(|e| e.clone())
        .and_then(|s| s.closed_mesh())
    {
        Ok(m) => m,
        Err(e) => {
            eprintln!("walk_speed: the head: {e}");
            std::process::exit(1);
        }
    };
    // The face truth's side light [mm] and its entry roulette, by distance from what the face
    // camera sees (a 128 × 128 fan of rays from its eye over the head's bounding sphere).
    let side = FaceLight::Side.position().as_dvec3() * 1000.0;
    let cam = face::camera();
    let eye = cam.eye.as_dvec3() * 1000.0;
    let axis = (head.centre - eye).normalize();
    let (u, v) = axis.any_orthonormal_pair();
    let seen: Vec<DVec3> = (0..128 * 128)
        .filter_map(|i| {
            let (a, b) = ((i % 128) as f64 / 63.5 - 1.0, (i / 128) as f64 / 63.5 - 1.0);
            let to = head.centre + (u * a + v * b) * head.radius;
            let d = (to - eye).normalize();
            head.first_hit(eye, d, f64::INFINITY, None)
                .map(|h| eye + d * h.t)
        })
        .collect();
    let field = DistanceField::new(&seen, head.lo, head.hi, ROULETTE_VOXEL_MM, 32);
    let mut head_walk = MeshWalker::new(&head, &red(), side);
    head_walk.roulette = Some(EntryRoulette {
        field: &field,
        distance: ROULETTE_DISTANCE_MM,
        survival: ROULETTE_SURVIVAL,
    });

    let run = |name: &str| -> (u64, u64) {
        match name {
            "flat" => {
                let r = mc::simulate(
                    &red(),
                    Geometry::SemiInfinite,
                    Source::Normal,
                    &det,
                    n,
                    1,
                    1,
                );
                (r.photons, r.events)
            }
            "slab" => {
                let r = mc::simulate(
                    &red(),
                    Geometry::Slab { d: 1.0 },
                    Source::Diffuse,
                    &Detectors::default(),
                    n,
                    2,
                    1,
                );
                (r.photons, r.events)
            }
            "sphere" => {
                let r = mc::sphere(&red(), 5.0, &bands, n, 3, 1);
                (r.photons, r.events)
            }
            "pigment" => {
                let light = Light::Uniform {
                    x_min: 0.0,
                    x_max: 3.0,
                };
                let r = pigment::textured(&tex, light, &bins, n, 4, 1);
                (r.photons, r.events)
            }
            "mesh-sphere" => (n, mesh_run(&ball_walk, n)),
            "head" => (n / 4, mesh_run(&head_walk, n / 4)),
            _ => {
                let mesh = scene.as_ref().map(|s| s.closed_mesh());
                std::hint::black_box(mesh.is_ok());
                (0, 0)
            }
        }
    };
    let epoch = Instant::now();
    let clock = if on_cpu_seconds().is_some() {
        "on-CPU"
    } else {
        "wall"
    };
    let mut rows = Vec::new();
    for name in NAMES {
        if args.only.as_deref().is_some_and(|o| o != name) {
            continue;
        }
        let mut secs = Vec::new();
        let mut counts = (0, 0);
        for _ in 0..args.rounds {
            let start = now(epoch);
            counts = run(name);
            secs.push(now(epoch) - start);
        }
        secs.sort_by(f64::total_cmp);
        let median = secs[secs.len() / 2];
        rows.push((name, counts.0, counts.1, median, secs));
    }
    if args.json {
        let items: Vec<String> = rows
            .iter()
            .map(|(name, p, e, med, secs)| {
                format!(
                    "{{\"geometry\":\"{name}\",\"photons\":{p},\"events\":{e},\
                     \"clock\":\"{clock}\",\"median_s\":{med},\"photons_per_s\":{},\"events_per_s\":{},\"rounds_s\":{secs:?}}}",
                    *p as f64 / med,
                    *e as f64 / med
                )
            })
            .collect();
        println!("[{}]", items.join(","));
    } else {
        println!(
            "{:<12} {:>10} {:>12} {:>10} {:>12} {:>12}",
            "geometry",
            "photons",
            "events",
            format!("{clock} s"),
            "photons/s",
            "events/s"
        );
        for (name, p, e, med, _) in &rows {
            println!(
                "{name:<12} {p:>10} {e:>12} {med:>10.3} {:>12.0} {:>12.0}",
                *p as f64 / med,
                *e as f64 / med
            );
        }
    }
}
