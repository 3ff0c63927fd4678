//! The mesh walker against the probes' Monte Carlo: a tessellated sphere under a distant
//! light against the sphere walker's bands, a box under a near point light against the flat
//! medium's exitance profile, energy bookkeeping, and determinism across thread counts.

use glam::DVec3;

use super::estimate::{run_batches_ordered, Acc};
use super::mesh::{uv_sphere, ClosedMesh, Hit};
use super::mesh_walk::{MeshTally, MeshWalker};
use super::rng::Rng;
use super::{point_light_profile, sphere, Medium, BATCH_SIZE};
use std::f64::consts::PI;

/// skin1's green channel at η = 1.3 (short walks: cheap).
fn green() -> Medium {
    Medium::new(0.17, 0.88, 0.0, 1.3)
}

/// An axis-aligned box [−a, a] × [−a, a] × [−d, 0] (mm) as 12 outward triangles.
fn slab_box(a: f64, d: f64) -> ClosedMesh {
    let p = |x: f64, y: f64, z: f64| DVec3::new(x * a, y * a, if z > 0.0 { 0.0 } else { -d });
    let v = vec![
        p(-1., -1., -1.),
        p(1., -1., -1.),
        p(1., 1., -1.),
        p(-1., 1., -1.),
        p(-1., -1., 1.),
        p(1., -1., 1.),
        p(1., 1., 1.),
        p(-1., 1., 1.),
    ];
    let quads = [
        [0, 3, 2, 1], // bottom (−z)
        [4, 5, 6, 7], // top (+z)
        [0, 1, 5, 4], // −y
        [2, 3, 7, 6], // +y
        [1, 2, 6, 5], // +x
        [3, 0, 4, 7], // −x
    ];
    let tris = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    let n = v.iter().map(|p| p.normalize()).collect();
    ClosedMesh::new(v, n, tris, 1.0).unwrap()
}

/// Runs `photons` photons of `walker` (deterministically, `threads` threads), binning each
/// exit with `bin` into `nbins` bins; returns the tally and the per-bin accumulators.
fn run(
    walker: &MeshWalker,
    photons: u64,
    threads: usize,
    nbins: usize,
    bin: impl Fn(DVec3, &Hit) -> Option<usize> + Sync,
) -> (MeshTally, Vec<Acc>) {
    let nb = photons.div_ceil(BATCH_SIZE) as usize;
    let mut tally = MeshTally::default();
    let mut bins = vec![Acc::default(); nbins];
    run_batches_ordered(
        nb,
        threads,
        |b| {
            let mut rng = Rng::new(7, b as u64);
            let mut t = MeshTally::default();
            let mut acc = vec![Acc::default(); nbins];
            for _ in 0..BATCH_SIZE {
                walker.photon(&mut rng, &mut t, &mut |e| {
                    if let Some(k) = bin(e.point, &e.hit) {
                        acc[k].add(e.weight);
                    }
                });
            }
            (t, acc)
        },
        |_, (t, acc)| {
            tally.merge(&t);
            for (a, b) in bins.iter_mut().zip(&acc) {
                a.merge(b);
            }
        },
    );
    (tally, bins)
}

#[test]
fn a_tessellated_sphere_under_a_distant_light_matches_the_sphere_walker() {
    let (r, dist) = (4.0, 4000.0);
    let (pos, nrm, tris) = uv_sphere(r, 64, 128);
    let mesh = ClosedMesh::new(pos, nrm, tris, 0.5).unwrap();
    let m = green();
    // The light on +z, far: the beam travels along −z as the sphere walker's does.
    let walker = MeshWalker::new(&mesh, &m, DVec3::new(0.0, 0.0, dist));
    let edges = [0.0, 30.0, 60.0, 80.0, 90.0, 100.0, 120.0, 180.0];
    let photons = 40_000;
    let (t, bins) = run(&walker, photons, 2, edges.len() - 1, |p, _| {
        let th = (p.z / p.length()).clamp(-1.0, 1.0).acos().to_degrees();
        edges.windows(2).position(|w| th >= w[0] && th < w[1])
    });
    let reference = sphere(&m, r, &edges, photons, 3, 2);
    // Per band: exitance per unit area per unit irradiance. A photon carries the cone's power
    // Ω (unit intensity); the irradiance at the sphere is 1/dist².
    let n = t.n;
    let scale = walker.cone_solid_angle() * dist * dist;
    for (k, w) in edges.windows(2).enumerate() {
        let area = 2.0 * PI * r * r * (w[0].to_radians().cos() - w[1].to_radians().cos());
        let e = bins[k].estimate(n).scaled(scale / area);
        let (want, se) = (reference.bands.values[k], reference.bands.std_err[k]);
        let z = (e.mean - want).abs() / (e.std_err.powi(2) + se.powi(2)).sqrt();
        println!(
            "band {w:?}: mesh {:.5} ± {:.5}, sphere {want:.5} ± {se:.5}, z {z:.2}",
            e.mean, e.std_err
        );
        assert!(
            z < 4.5,
            "band {w:?}: mesh {} vs sphere {want} (z {z:.1})",
            e.mean
        );
    }
    // Convex: nothing re-enters, nothing is lost.
    assert_eq!((t.reentered.s1, t.lost.s1), (0.0, 0.0));
}

#[test]
fn a_thick_box_under_a_near_point_light_matches_the_flat_medium() {
    let h = 2.0;
    let mesh = slab_box(30.0, 30.0);
    let m = green();
    let walker = MeshWalker::new(&mesh, &m, DVec3::new(0.0, 0.0, h));
    let edges = [0.0, 0.5, 1.0, 2.0, 3.0, 4.5, 6.0, 8.0];
    let photons = 60_000;
    let (t, bins) = run(&walker, photons, 2, edges.len() - 1, |p, hit| {
        // Top face exits only (normal +z), by distance from the light's foot.
        if mesh.normal(hit.tri).z < 0.5 {
            return None;
        }
        let rr = (p.x * p.x + p.y * p.y).sqrt();
        edges.windows(2).position(|w| rr >= w[0] && rr < w[1])
    });
    let reference = point_light_profile(&m, h, &edges, photons, 5, 2);
    // The walker's photons carry Ω = 4π (the light is inside the box's bounding sphere) per
    // unit intensity: per unit source power that is Ω/(4π) = 1.
    let scale = walker.cone_solid_angle() / (4.0 * PI);
    assert!((scale - 1.0).abs() < 1e-12);
    for (k, w) in edges.windows(2).enumerate() {
        let area = PI * (w[1] * w[1] - w[0] * w[0]);
        let e = bins[k].estimate(t.n).scaled(scale / area);
        let (want, se) = (reference.values[k], reference.std_err[k]);
        let z = (e.mean - want).abs() / (e.std_err.powi(2) + se.powi(2)).sqrt();
        println!(
            "annulus {w:?}: box {:.6} ± {:.6}, flat {want:.6} ± {se:.6}, z {z:.2}",
            e.mean, e.std_err
        );
        assert!(
            z < 4.5,
            "annulus {w:?}: box {} vs flat {want} (z {z:.1})",
            e.mean
        );
    }
}

#[test]
fn energy_is_conserved_and_results_do_not_depend_on_threads() {
    // A small box lit from above and the side: red's long walks leave through every face.
    let mesh = slab_box(10.0, 6.0);
    let m = Medium::new(0.032, 0.74, 0.0, 1.3); // skin1 red: long walks, many exits
    let walker = MeshWalker::new(&mesh, &m, DVec3::new(20.0, 5.0, 8.0));
    let photons = 3 * BATCH_SIZE;
    let bin = |p: DVec3, _: &Hit| Some(usize::from(p.z > -3.0));
    let (t1, b1) = run(&walker, photons, 1, 2, bin);
    let (t3, b3) = run(&walker, photons, 3, 2, bin);
    assert_eq!(b1, b3);
    assert_eq!(
        (t1.exits, t1.absorbed, t1.events),
        (t3.exits, t3.absorbed, t3.events)
    );
    let n = t1.n;
    let mean = |a: &Acc| a.estimate(n);
    let inc = mean(&t1.incident).mean;
    let books = mean(&t1.specular).mean
        + mean(&t1.escaped).mean
        + mean(&t1.absorbed).mean
        + mean(&t1.capped).mean
        + mean(&t1.lost).mean;
    let se = mean(&t1.absorbed).std_err + mean(&t1.escaped).std_err;
    println!("incident {inc:.5}, books {books:.5} ± {se:.5}");
    assert!(inc > 0.05, "the light misses the box ({inc})");
    assert!(
        (books - inc).abs() < 5.0 * se,
        "incident {inc} vs {books} ± {se}"
    );
    assert_eq!(t1.lost.s1, 0.0);
    // Exits are what escapes (nothing re-enters a convex box).
    assert_eq!(t1.exits.s1, t1.escaped.s1);
}

#[test]
fn light_inside_is_detected_and_the_grid_knows_inside_from_outside() {
    let mesh = slab_box(10.0, 6.0);
    assert!(mesh.contains(DVec3::new(1.0, 2.0, -3.0)));
    assert!(!mesh.contains(DVec3::new(1.0, 2.0, 3.0)));
    assert!(!mesh.contains(DVec3::new(50.0, 2.0, -3.0)));
    assert!((mesh.volume() - 20.0 * 20.0 * 6.0).abs() < 1e-9);
    // 3 mm from both faces: a safe distance of at least one voxel (1 mm) and never more than
    // the truth; at the surface every flight needs a query.
    let safe = mesh.safe_distance(DVec3::new(0.0, 0.0, -3.0)).unwrap();
    assert!((1.0..=3.0).contains(&safe), "{safe}");
    assert_eq!(mesh.safe_distance(DVec3::new(0.0, 0.0, -0.2)), Some(0.0));
    assert_eq!(mesh.safe_distance(DVec3::new(0.0, 0.0, 5.0)), None);
    let (out, surf, inside) = mesh.grid_fractions();
    assert!(out > 0.0 && surf > 0.0 && inside > 0.0);
}

#[test]
fn the_safe_distance_never_exceeds_the_distance_to_the_surface_and_follows_it() {
    // Convex meshes, where the distance from an inside point to the surface is the least of its
    // distances to the faces' planes: the box, and a coarse sphere whose large facets make the
    // voxels' L∞ bound loose.
    let (pos, nrm, tris) = uv_sphere(4.0, 12, 24);
    let planes: Vec<(DVec3, DVec3)> = tris
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| pos[i as usize]);
            (a, (b - a).cross(c - a).normalize())
        })
        .collect();
    let ball = ClosedMesh::new(pos, nrm, tris, 0.5).unwrap();
    let box_planes: Vec<(DVec3, DVec3)> = [
        (DVec3::new(10.0, 0.0, 0.0), DVec3::X),
        (DVec3::new(-10.0, 0.0, 0.0), -DVec3::X),
        (DVec3::new(0.0, 10.0, 0.0), DVec3::Y),
        (DVec3::new(0.0, -10.0, 0.0), -DVec3::Y),
        (DVec3::ZERO, DVec3::Z),
        (DVec3::new(0.0, 0.0, -6.0), -DVec3::Z),
    ]
    .into();
    let cube = slab_box(10.0, 6.0);
    let mut rng = Rng::new(3, 0);
    for (mesh, planes, lo, hi) in [
        (&ball, &planes, DVec3::splat(-4.0), DVec3::splat(4.0)),
        (
            &cube,
            &box_planes,
            DVec3::new(-10.0, -10.0, -6.0),
            DVec3::new(10.0, 10.0, 0.0),
        ),
    ] {
        let (mut n, mut deep, mut deep_safe) = (0, 0.0, 0.0);
        while n < 20_000 {
            let p = lo + (hi - lo) * DVec3::new(rng.uniform(), rng.uniform(), rng.uniform());
            let truth = planes
                .iter()
                .map(|(a, n)| n.dot(*a - p))
                .fold(f64::INFINITY, f64::min);
            if truth <= 0.0 {
                continue;
            }
            n += 1;
            let safe = mesh
                .safe_distance(p)
                .expect("an inside point is not outside");
            assert!(safe <= truth, "safe {safe} > distance {truth} at {p}");
            if truth > 1.0 {
                deep += truth;
                deep_safe += safe;
            }
        }
        // Deeper than a voxel or two, the bound is most of the distance.
        println!("safe / distance beyond 1 mm: {:.3}", deep_safe / deep);
        assert!(deep_safe > 0.6 * deep, "{deep_safe} of {deep}");
    }
}
