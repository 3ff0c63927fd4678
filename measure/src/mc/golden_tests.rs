//! The Monte Carlo's results pinned bit for bit: every public entry point that walks photons,
//! with small photon counts and fixed seeds, hashed (FNV-1a over the f64 bit patterns and
//! counters of everything it returns) and compared with the hashes the code gave when they
//! were recorded. A change of the walk that moves any bit — an operation reordered, a random
//! number drawn in another order — fails here; a deliberate change of the ground truth
//! re-records these hashes and re-bakes `assets/sss` and `tools/reference/face` with it.
//!
//! The scenes reach every branch of the walk: both faces of a slab, total internal reflection,
//! η = 1, g ≠ 0, the event cap, Russian roulette, the shadow-edge strips, the cone detector,
//! the sphere's bands, the pigment's three texturings under both lights (one map periodic),
//! and the mesh walk with re-entry (two boxes, one overlapping the other: its layers), its
//! entry roulette, and the face truth on the scanned head.

use std::path::Path;

use glam::{DVec3, Vec3};

use super::albedo::multi_scatter_curve;
use super::estimate::Acc;
use super::mesh::{uv_sphere, ClosedMesh, DistanceField};
use super::mesh_walk::{EntryRoulette, MeshTally, MeshWalker};
use super::pigment::{self, Bins, Light, Stripes, Textured, Texturing};
use super::rng::Rng;
use super::*;

/// FNV-1a, 64 bits, fed 64-bit words (their little-endian bytes).
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    fn word(&mut self, w: u64) {
        for b in w.to_le_bytes() {
            self.0 ^= b as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
}

/// What a result hashes: its counters and the bit patterns of its f64s, in field order.
trait Golden {
    fn feed(&self, h: &mut Fnv);
}

impl Golden for f64 {
    fn feed(&self, h: &mut Fnv) {
        h.word(self.to_bits());
    }
}
impl Golden for u64 {
    fn feed(&self, h: &mut Fnv) {
        h.word(*self);
    }
}
impl Golden for f32 {
    fn feed(&self, h: &mut Fnv) {
        h.word(self.to_bits() as u64);
    }
}
impl<T: Golden> Golden for [T] {
    fn feed(&self, h: &mut Fnv) {
        h.word(self.len() as u64);
        self.iter().for_each(|x| x.feed(h));
    }
}
impl<T: Golden, const N: usize> Golden for [T; N] {
    fn feed(&self, h: &mut Fnv) {
        self.iter().for_each(|x| x.feed(h));
    }
}
impl<T: Golden> Golden for Vec<T> {
    fn feed(&self, h: &mut Fnv) {
        self.as_slice().feed(h);
    }
}
impl Golden for Estimate {
    fn feed(&self, h: &mut Fnv) {
        [self.mean, self.std_err].feed(h);
    }
}
impl Golden for Acc {
    fn feed(&self, h: &mut Fnv) {
        [self.s1, self.s2].feed(h);
    }
}
impl Golden for Profile {
    fn feed(&self, h: &mut Fnv) {
        for v in [&self.edges, &self.r_mid, &self.values, &self.std_err] {
            v.feed(h);
        }
    }
}
impl Golden for Results {
    fn feed(&self, h: &mut Fnv) {
        [self.photons, self.events].feed(h);
        [
            self.specular,
            self.reflectance,
            self.transmittance,
            self.unscattered,
            self.absorbed,
            self.capped,
            self.cone,
        ]
        .feed(h);
        self.reflectance_profile.feed(h);
        self.transmittance_profile.feed(h);
        self.irradiance_profile.feed(h);
    }
}
impl Golden for SlabEstimate {
    fn feed(&self, h: &mut Fnv) {
        [self.r, self.t, self.absorbed, self.capped].feed(h);
        self.specular.feed(h);
    }
}
impl Golden for EdgeResults {
    fn feed(&self, h: &mut Fnv) {
        [self.photons, self.events].feed(h);
        [self.specular, self.reflectance, self.absorbed, self.capped].feed(h);
        self.strips.feed(h);
    }
}
impl Golden for SphereResults {
    fn feed(&self, h: &mut Fnv) {
        [self.photons, self.events].feed(h);
        [
            self.specular,
            self.entered,
            self.exitance,
            self.absorbed,
            self.capped,
        ]
        .feed(h);
        self.bands.feed(h);
    }
}
impl Golden for pigment::TexturedResults {
    fn feed(&self, h: &mut Fnv) {
        [self.photons, self.events].feed(h);
        self.strips.feed(h);
        self.capped.feed(h);
    }
}
impl Golden for albedo::AlbedoCurve {
    fn feed(&self, h: &mut Fnv) {
        self.eta.feed(h);
        self.albedos.feed(h);
        self.multi.feed(h);
        [self.photons, self.events].feed(h);
        self.capped.feed(h);
    }
}
impl Golden for MeshTally {
    fn feed(&self, h: &mut Fnv) {
        [self.n, self.events].feed(h);
        [
            self.incident,
            self.specular,
            self.entered,
            self.exits,
            self.reentered,
            self.escaped,
            self.absorbed,
            self.capped,
            self.lost,
            self.culled,
        ]
        .feed(h);
    }
}

fn hash(x: &impl Golden) -> u64 {
    let mut h = Fnv::new();
    x.feed(&mut h);
    h.0
}

/// Compares every (name, hash) with the recorded table, printing them all (the table to paste
/// when the ground truth is changed on purpose) before failing on any difference.
fn check(got: &[(&str, u64)], want: &[(&str, u64)]) {
    for (name, h) in got {
        println!("    (\"{name}\", 0x{h:016x}),");
    }
    let names = |t: &[(&str, u64)]| t.iter().map(|p| p.0.to_string()).collect::<Vec<_>>();
    assert_eq!(names(got), names(want), "the cases differ from the table");
    let moved: Vec<&str> = got
        .iter()
        .zip(want)
        .filter(|(g, w)| g.1 != w.1)
        .map(|(g, _)| g.0)
        .collect();
    assert!(moved.is_empty(), "results moved: {moved:?}");
}

/// skin1's channels at η = 1.4 (red: long walks; blue: short) and a forward-scattering one.
fn red() -> Medium {
    Medium::new(0.032, 0.74, 0.0, 1.4)
}
fn blue() -> Medium {
    Medium::new(0.48, 1.01, 0.0, 1.4)
}
fn forward() -> Medium {
    Medium::new(0.05, 0.9, 0.8, 1.33)
}

const N: u64 = 6000; // one full batch and a partial one

#[test]
fn the_flat_walks_are_bit_identical_to_the_recorded_ones() {
    let edges: Vec<f64> = (0..=12).map(|k| 0.25 * k as f64).collect();
    let det = Detectors {
        edges: edges.clone(),
        cone_mu: 0.8,
        max_events: MAX_EVENTS,
    };
    let capped = Detectors {
        max_events: 12,
        ..det.clone()
    };
    let matched = Medium::new(0.1, 1.0, 0.0, 1.0);
    let slab2 = Geometry::Slab { d: 2.0 };
    let got = [
        (
            "normal semi-infinite",
            hash(&simulate(
                &red(),
                Geometry::SemiInfinite,
                Source::Normal,
                &det,
                N,
                1,
                2,
            )),
        ),
        (
            "diffuse slab, g",
            hash(&simulate(&forward(), slab2, Source::Diffuse, &det, N, 2, 2)),
        ),
        (
            "cone slab",
            hash(&simulate(
                &blue(),
                Geometry::Slab { d: 0.7 },
                Source::Cone { mu_min: 0.5 },
                &det,
                N,
                3,
                1,
            )),
        ),
        (
            "point light slab",
            hash(&point_light(&red(), slab2, 1.5, &edges, N, 4, 2)),
        ),
        (
            "collimated, capped",
            hash(&simulate(
                &red(),
                Geometry::SemiInfinite,
                Source::Collimated { mu: 0.4 },
                &capped,
                N,
                5,
                2,
            )),
        ),
        (
            "index-matched slab",
            hash(&simulate(&matched, slab2, Source::Normal, &det, N, 6, 2)),
        ),
        (
            "total reflectance",
            hash(&total_reflectance(&blue(), N, 7, 2)),
        ),
        (
            "total diffuse reflectance",
            hash(&total_reflectance_diffuse(&forward(), N, 8, 2)),
        ),
        ("slab", hash(&slab(&red(), 1.0, N, 9, 2))),
        (
            "radial profile",
            hash(&radial_profile(&blue(), &edges, N, 10, 2)),
        ),
        (
            "slab radial profiles",
            hash(&{
                let (r, t) = slab_radial_profiles(&red(), 1.5, &edges, N, 11, 2);
                [r, t]
            }),
        ),
        (
            "point light profile",
            hash(&point_light_profile(&red(), 0.8, &edges, N, 12, 2)),
        ),
        (
            "oblique reflectance",
            hash(&oblique_reflectance(&forward(), 0.3, N, 13, 2)),
        ),
        (
            "shadow edge",
            hash(&shadow_edge(
                &red(),
                0.6,
                &[-3.0, -1.0, -0.2, 0.0, 0.3, 1.0, 4.0],
                N,
                14,
                2,
            )),
        ),
        (
            "shadow edge, capped",
            hash(&shadow_edge_with(
                &blue(),
                1.0,
                &[-1.0, 0.0, 1.0],
                9,
                N,
                15,
                2,
            )),
        ),
        (
            "slab diffuse transmittance",
            hash(&slab_diffuse_transmittance(&forward(), 1.2, N, 16, 2)),
        ),
        (
            "white albedo curve",
            hash(&multi_scatter_curve(1.4, &[0.2, 0.9, 0.999], N, 17, 2)),
        ),
    ];
    check(&got, FLAT);
}

#[test]
fn the_sphere_and_pigment_walks_are_bit_identical_to_the_recorded_ones() {
    let bands = [0.0, 20.0, 45.0, 80.0, 90.0, 100.0, 150.0, 180.0];
    let stripes = |period| Stripes {
        edges: vec![-0.5, 0.0, 1.0],
        albedo: vec![0.2, 0.45, 0.3, 0.6],
        period,
    };
    let periodic = Stripes {
        edges: vec![0.4, 1.1, 1.5],
        ..stripes(Some(2.0))
    };
    let textured = |map: Stripes, texturing| Textured {
        sigma_t: 1.05,
        eta: 1.4,
        base: 0.45,
        base_single: 0.93,
        map,
        single: vec![0.8, 0.93, 0.88, 0.97],
        texturing,
    };
    let bins = Bins {
        edges: (0..=10).map(|k| -2.0 + 0.4 * k as f64).collect(),
        band: 0.5,
    };
    let uniform = Light::Uniform {
        x_min: -6.0,
        x_max: 6.0,
    };
    let mut got = vec![
        ("sphere", hash(&sphere(&red(), 3.0, &bands, N, 21, 2))),
        (
            "sphere, g, capped",
            hash(&sphere_with(&forward(), 1.5, &bands, 15, N, 22, 2)),
        ),
    ];
    let names = [
        ["pre-post uniform", "pre-post point", "pre-post periodic"],
        ["post-only uniform", "post-only point", "post-only periodic"],
        ["per-texel uniform", "per-texel point", "per-texel periodic"],
    ];
    for (t, names) in Texturing::ALL.into_iter().zip(names) {
        let m = textured(stripes(None), t);
        let point = Light::Point { h: 1.2 };
        got.push((
            names[0],
            hash(&pigment::textured(&m, uniform, &bins, N, 23, 2)),
        ));
        got.push((
            names[1],
            hash(&pigment::textured(&m, point, &bins, N, 24, 2)),
        ));
        let p = textured(periodic.clone(), t);
        got.push((
            names[2],
            hash(&pigment::textured(&p, uniform, &bins, N, 25, 2)),
        ));
    }
    check(&got, SPHERE_PIGMENT);
}

/// An axis-aligned box [lo, hi] as 12 outward triangles appended to (positions, triangles).
fn add_box(lo: DVec3, hi: DVec3, pos: &mut Vec<DVec3>, tris: &mut Vec<[u32; 3]>) {
    let base = pos.len() as u32;
    for k in 0..8 {
        let pick = |bit: u32, a: f64, b: f64| if k & bit == 0 { a } else { b };
        pos.push(DVec3::new(
            pick(1, lo.x, hi.x),
            pick(2, lo.y, hi.y),
            pick(4, lo.z, hi.z),
        ));
    }
    // Quads by corner bits (x = 1, y = 2, z = 4), counter-clockwise seen from outside.
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [1, 3, 7, 5],
        [0, 4, 6, 2],
    ];
    for q in quads {
        let q = q.map(|i| base + i);
        tris.push([q[0], q[1], q[2]]);
        tris.push([q[0], q[2], q[3]]);
    }
}

/// Runs `batches` batches of 4096 photons of `walker` (seed `seed`), binning every exit into
/// 8 bins by its triangle and its shading normal's side; the tally and the bins.
fn mesh_run(walker: &MeshWalker, batches: u64, seed: u64) -> (MeshTally, Vec<Acc>) {
    let mut tally = MeshTally::default();
    let mut bins = vec![Acc::default(); 8];
    for b in 0..batches {
        let mut rng = Rng::new(seed, b);
        for _ in 0..BATCH_SIZE {
            walker.photon(&mut rng, &mut tally, &mut |e| {
                let n = walker.mesh.shading_normal(&e.hit);
                let k = (e.hit.tri as usize % 4) * 2 + usize::from(n.z > e.point.x * 0.01);
                bins[k].add(e.weight * (1.0 + e.hit.b1 - 0.5 * e.hit.b2));
            });
        }
    }
    (tally, bins)
}

#[test]
fn the_mesh_walks_are_bit_identical_to_the_recorded_ones() {
    // A tessellated sphere under a near light.
    let (pos, nrm, tris) = uv_sphere(4.0, 12, 24);
    let ball = ClosedMesh::new(pos, nrm, tris, 0.5).unwrap();
    let sphere_walk = MeshWalker::new(&ball, &blue(), DVec3::new(3.0, -2.0, 12.0));
    // Two boxes overlapping (the second's corner inside the first: two layers there) and a
    // third apart: light leaving one meets another and re-enters.
    let (mut pos, mut tris) = (Vec::new(), Vec::new());
    add_box(
        DVec3::new(-5.0, -5.0, -4.0),
        DVec3::new(5.0, 5.0, 0.0),
        &mut pos,
        &mut tris,
    );
    add_box(
        DVec3::new(3.0, 3.0, -2.0),
        DVec3::new(9.0, 9.0, 3.0),
        &mut pos,
        &mut tris,
    );
    add_box(
        DVec3::new(-9.0, -4.0, -4.0),
        DVec3::new(-6.0, 4.0, 2.0),
        &mut pos,
        &mut tris,
    );
    let nrm = pos.iter().map(|p| p.normalize()).collect();
    let boxes = ClosedMesh::new(pos, nrm, tris, 0.7).unwrap();
    let light = DVec3::new(-2.0, 1.0, 10.0);
    let mut box_walk = MeshWalker::new(&boxes, &red(), light);
    let (t_boxes, b_boxes) = mesh_run(&box_walk, 2, 31);
    assert!(t_boxes.reentered.s1 > 0.0, "nothing re-entered");
    // The entry roulette, by distance from the first box's top face, and a small event cap.
    let seen: Vec<DVec3> = (0..100)
        .map(|k| DVec3::new((k % 10) as f64 - 4.5, (k / 10) as f64 - 4.5, 0.0))
        .collect();
    let field = DistanceField::new(&seen, boxes.lo, boxes.hi, 1.0, 32);
    box_walk.roulette = Some(EntryRoulette {
        field: &field,
        distance: 3.0,
        survival: 0.2,
    });
    box_walk.max_events = 40;
    let (t_roulette, b_roulette) = mesh_run(&box_walk, 2, 32);
    assert!(t_roulette.culled.s1 > 0.0 && t_roulette.capped.s1 > 0.0);
    let got = [
        (
            "mesh sphere",
            hash(&{
                let (t, b) = mesh_run(&sphere_walk, 2, 30);
                (t, b)
            }),
        ),
        ("mesh boxes", hash(&(t_boxes, b_boxes))),
        ("mesh boxes, roulette", hash(&(t_roulette, b_roulette))),
    ];
    check(&got, MESH);
}

impl Golden for (MeshTally, Vec<Acc>) {
    fn feed(&self, h: &mut Fnv) {
        self.0.feed(h);
        self.1.feed(h);
    }
}

#[test]
fn the_face_truth_is_bit_identical_to_the_recorded_one() {
    use crate::face::truth::{self, FaceScene, TruthRun};
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets");
    let scene = FaceScene::head(&assets).unwrap();
    let mesh = scene.closed_mesh().unwrap();
    let run = TruthRun {
        photons: 4096,
        seed: 11,
        threads: 2,
    };
    let light = Vec3::new(0.3, 0.1, 0.5);
    let t = truth::compute(&scene, &mesh, "golden", light, 1.0, &run, &mut |_, _| {}).unwrap();
    let mut h = Fnv::new();
    for p in t.radiance.pixels.iter().chain(&t.std_err.pixels) {
        p.feed(&mut h);
    }
    t.alpha.iter().for_each(|a| a.feed(&mut h));
    t.record.events.feed(&mut h);
    for e in &t.record.energy {
        [
            e.incident,
            e.specular,
            e.entered,
            e.exits,
            e.reentered,
            e.escaped,
            e.absorbed,
            e.capped,
            e.lost,
            e.culled,
        ]
        .feed(&mut h);
    }
    check(&[("face truth", h.0)], FACE);
}

// The recorded hashes (from the walks as they were when this test was written).
const FLAT: &[(&str, u64)] = &[
    ("normal semi-infinite", 0x26fa3e90570eddb7),
    ("diffuse slab, g", 0x4a5b32988330e156),
    ("cone slab", 0xd062e619aaf5085e),
    ("point light slab", 0x2d9a59d07cda7f45),
    ("collimated, capped", 0xfd2c88f44d1e0023),
    ("index-matched slab", 0x7ee11b972dff6a5b),
    ("total reflectance", 0xaef9f62e5deabf50),
    ("total diffuse reflectance", 0xaa4629da90f4c76b),
    ("slab", 0x695d4bbee180289b),
    ("radial profile", 0x89ea54917d543514),
    ("slab radial profiles", 0x82127486e0d74daa),
    ("point light profile", 0xd932b92606331cef),
    ("oblique reflectance", 0x1b6b50398f9daff6),
    ("shadow edge", 0x0782f421d9d5433b),
    ("shadow edge, capped", 0x4ab7ca3649b4a8be),
    ("slab diffuse transmittance", 0x453f713ea7aa7326),
    ("white albedo curve", 0xc869a80515d32db3),
];
const SPHERE_PIGMENT: &[(&str, u64)] = &[
    ("sphere", 0x5495e7ca86bc88c8),
    ("sphere, g, capped", 0x84d74261929f7836),
    ("pre-post uniform", 0x1c66bde87fe5fe60),
    ("pre-post point", 0xb84794a822162087),
    ("pre-post periodic", 0xaf376a76760ed544),
    ("post-only uniform", 0x3cfaf566f808071b),
    ("post-only point", 0x629047a8d13fe8c5),
    ("post-only periodic", 0x24adcacd528b8eea),
    ("per-texel uniform", 0xb64abc926b9523f8),
    ("per-texel point", 0x9ebdf885f3649471),
    ("per-texel periodic", 0x7f76d94b834c5637),
];
const MESH: &[(&str, u64)] = &[
    ("mesh sphere", 0x83d3c7d50bb0f930),
    ("mesh boxes", 0xf44bfac717f414ac),
    ("mesh boxes, roulette", 0x8e73d32f868f3f01),
];
const FACE: &[(&str, u64)] = &[("face truth", 0x323fc9346d68783f)];
