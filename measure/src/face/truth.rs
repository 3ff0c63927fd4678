//! The face truth: the project's own Monte Carlo ([`crate::mc::mesh_walk`]) on the scanned
//! head, as linear radiance in the face scenes' camera — what `dermis reference --scene head`
//! computes and `tools/reference/face/` caches.
//!
//! **Scene.** The welded head ([`WeldedMesh`], closed) in metres, walked in millimetres (σ in
//! mm⁻¹: the material's, one grey medium per channel as the probes walk them); a white point
//! light of `intensity` W/sr, no ambient; the face scenes' camera ([`face::camera`]) and
//! image size. The boundary is the triangles themselves (geometric normals) with a smooth
//! Fresnel dielectric; the specular reflection at entry is excluded (as the probes exclude
//! it, and the shading models render subsurface light only); light that leaves and meets the
//! head again re-enters through Fresnel (interreflection is part of the truth).
//!
//! **Exitance → radiance.** Each exit is scored where it leaves: seen from the camera (a ray
//! from the eye reaches it before anything else, its facet faces the eye), it adds to the pixel
//! it projects into the radiance M·F_t(η, n·v)/(π C(η)) of the exitance it carries — the
//! measurement scenes' conversion (`shading::subsurface`), n the interpolated vertex normal —
//! times the projection's Jacobian (pixels per unit area, F_p² cos θ / (d² cos³ α)), so a pixel
//! holds the mean radiance over its footprint: a box filter, as the renderer's MSAA resolve.
//!
//! **Noise.** Photons run in batches of [`BATCH_SIZE`] (one RNG stream per batch and channel);
//! each pixel's standard error is the spread of its batch means. Results do not depend on the
//! thread count.

use std::path::Path;
use std::time::Instant;

use glam::{DMat4, DVec3, DVec4, Vec3};
use serde::{Deserialize, Serialize};

use super::export::{WeldedMesh, REFERENCE_PIXELS};
use crate::mc::estimate::{run_batches_ordered, Acc};
use crate::mc::mesh::{ClosedMesh, DistanceField};
use crate::mc::mesh_walk::{EntryRoulette, Exit, MeshTally, MeshWalker};
use crate::mc::rng::Rng;
use crate::mc::{Medium, BATCH_SIZE};
use dermis_engine::asset::head;
use dermis_engine::render::pfm::FloatImage;
use dermis_engine::scene::face::{self, Camera};
use dermis_engine::shading::{fresnel, material::SKIN1, subsurface, Material};

/// What the truth computes, in words: part of every cache's hash, so a change of method
/// invalidates the cache as a change of scene does.
pub const METHOD: &str = "dermis mesh Monte Carlo v1: geometric-normal smooth dielectric, \
specular at entry excluded, re-entry, exits projected with F_t(eta, n.v)/(pi C), box pixels";
/// Side of the safe-distance grid's voxels [mm].
pub const VOXEL_MM: f64 = 1.0;
/// Sub-pixel rays per side for the head's coverage (alpha).
pub const ALPHA_SAMPLES: u32 = 8;
/// Millimetres per metre.
const MM: f64 = 1000.0;
/// Photons per channel relative to `--photons` (red's): green and blue exit less and their
/// blocks are noisier, their walks shorter; these shares make the three channels' noise about
/// equal on the front-lit face.
pub const CHANNEL_SHARE: [f64; 3] = [1.0, 1.5, 2.5];
/// The entry roulette (`mesh_walk::EntryRoulette`): voxel side [mm] of the distance field to
/// the camera's visible surface, the distance [mm] beyond which an entering photon is
/// rouletted (≈ 6.5 of red's diffusion lengths), and its survival probability.
pub const ROULETTE_VOXEL_MM: f64 = 2.0;
pub const ROULETTE_DISTANCE_MM: f64 = 24.0;
pub const ROULETTE_SURVIVAL: f64 = 0.05;

/// FNV-1a, 64 bits: the scene hash the cache records (no hashing dependency); the engine's
/// (the texture encodings' source hash).
pub use dermis_engine::asset::compressed::fnv1a64;

/// The face scene the truth is computed for: the head, its material, the camera and image size.
#[derive(Clone, Debug)]
pub struct FaceScene {
    pub mesh: WeldedMesh,
    pub material: Material,
    pub camera: Camera,
    pub width: u32,
    pub height: u32,
}

impl FaceScene {
    /// The face scenes as the engine has them now: the head from `assets`, skin1, the face
    /// camera, [`REFERENCE_PIXELS`]².
    pub fn head(assets: &Path) -> Result<Self, String> {
        let maps = head::Maps {
            albedo: false,
            normal: false,
        };
        let model = head::load_with(assets, maps).map_err(|e| e.to_string())?;
        let mesh = WeldedMesh::from_model(&model)?;
        let (open, multi) = mesh.open_and_nonmanifold_edges();
        if open + multi > 0 {
            return Err(format!(
                "{}: not closed after welding ({open} open, {multi} non-manifold edges)",
                model.source
            ));
        }
        Ok(Self {
            mesh,
            material: SKIN1,
            camera: face::camera(),
            width: REFERENCE_PIXELS,
            height: REFERENCE_PIXELS,
        })
    }

    /// FNV-1a of everything the truth under a light at `light` [m] of `intensity` [W/sr]
    /// depends on: the mesh (its PLY bytes), the material's optics, the camera, the image size,
    /// the light and [`METHOD`].
    pub fn hash(&self, light: Vec3, intensity: f32) -> String {
        let m = &self.material;
        let c = &self.camera;
        let text = format!(
            "{METHOD}\nsigma_a {:?} sigma_s' {:?} g {} eta {}\ncamera {:?} {:?} {}\n\
             size {}x{}\nlight {:?} {}\n",
            m.sigma_a,
            m.sigma_s_prime,
            m.g,
            m.eta,
            c.eye.to_array(),
            c.target.to_array(),
            c.fov_y_deg,
            self.width,
            self.height,
            light.to_array(),
            intensity
        );
        let mut bytes = self.mesh.to_ply();
        bytes.extend_from_slice(text.as_bytes());
        format!("{:016x}", fnv1a64(&bytes))
    }

    /// The walkable mesh, in millimetres.
    pub fn closed_mesh(&self) -> Result<ClosedMesh, String> {
        ClosedMesh::new(
            self.mesh
                .positions
                .iter()
                .map(|p| p.as_dvec3() * MM)
                .collect(),
            self.mesh.normals.iter().map(|n| n.as_dvec3()).collect(),
            self.mesh.triangles.clone(),
            VOXEL_MM,
        )
    }
}

/// The camera as the renderer projects (its view-projection, f64) with what the Jacobian needs.
struct Projector {
    view_proj: DMat4,
    inverse: DMat4,
    /// Eye [m].
    eye: DVec3,
    forward: DVec3,
    /// Focal length in pixels.
    focal_px: f64,
    width: u32,
    height: u32,
}

impl Projector {
    fn new(camera: &Camera, width: u32, height: u32) -> Self {
        let view_proj = dermis_engine::camera::look_at(
            camera.eye,
            camera.target,
            camera.fov_y_deg.to_radians(),
            width as f32 / height as f32,
        )
        .as_dmat4();
        let half = (camera.fov_y_deg as f64).to_radians() * 0.5;
        Self {
            view_proj,
            inverse: view_proj.inverse(),
            eye: camera.eye.as_dvec3(),
            forward: (camera.target - camera.eye).as_dvec3().normalize(),
            focal_px: 0.5 * height as f64 / half.tan(),
            width,
            height,
        }
    }

    /// Pixel coordinates (x right, y down; the pixel (i, j) spans [i, i+1) × [j, j+1)).
    fn project(&self, p: DVec3) -> Option<(f64, f64)> {
        let c = self.view_proj * DVec4::from((p, 1.0));
        if c.w <= 0.0 {
            return None;
        }
        let (x, y) = (c.x / c.w, c.y / c.w);
        Some((
            (x + 1.0) * 0.5 * self.width as f64,
            (1.0 - y) * 0.5 * self.height as f64,
        ))
    }

    /// Unit direction from the eye through pixel coordinates (x, y).
    fn ray(&self, x: f64, y: f64) -> DVec3 {
        let ndc = DVec4::new(
            2.0 * x / self.width as f64 - 1.0,
            1.0 - 2.0 * y / self.height as f64,
            0.5,
            1.0,
        );
        let w = self.inverse * ndc;
        (w.truncate() / w.w - self.eye).normalize()
    }
}

/// How a truth is computed: photons per channel (rounded up to whole batches), seed, threads.
#[derive(Clone, Copy, Debug)]
pub struct TruthRun {
    pub photons: u64,
    pub seed: u64,
    pub threads: usize,
}

/// One channel's bookkeeping, per unit power sent toward the head (mean, standard error).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Energy {
    pub incident: [f64; 2],
    pub specular: [f64; 2],
    pub entered: [f64; 2],
    pub exits: [f64; 2],
    pub reentered: [f64; 2],
    pub escaped: [f64; 2],
    pub absorbed: [f64; 2],
    pub capped: [f64; 2],
    pub lost: [f64; 2],
    pub culled: [f64; 2],
}

impl Energy {
    fn from_tally(t: &MeshTally) -> Self {
        let e = |a: &Acc| {
            let e = a.estimate(t.n);
            [e.mean, e.std_err]
        };
        Self {
            incident: e(&t.incident),
            specular: e(&t.specular),
            entered: e(&t.entered),
            exits: e(&t.exits),
            reentered: e(&t.reentered),
            escaped: e(&t.escaped),
            absorbed: e(&t.absorbed),
            capped: e(&t.capped),
            lost: e(&t.lost),
            culled: e(&t.culled),
        }
    }
}

/// What one light's truth records besides its images.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LightRecord {
    pub name: String,
    /// [m], the head's frame.
    pub position: [f32; 3],
    /// [W/sr].
    pub intensity: f32,
    /// [`FaceScene::hash`] of the scene and this light.
    pub scene_fnv1a64: String,
    /// Photons per channel (R, G, B), whole batches.
    pub photons_per_channel: [u64; 3],
    pub seed: u64,
    pub threads: usize,
    /// Solid angle of the source cone (the power per photon per unit intensity).
    pub cone_sr: f64,
    /// Per channel: process CPU seconds, wall seconds, scattering/boundary events.
    pub cpu_seconds: [f64; 3],
    pub wall_seconds: [f64; 3],
    pub events: [u64; 3],
    pub energy: [Energy; 3],
}

/// A computed truth: radiance and its standard error per pixel, the head's coverage, and how
/// it was made.
#[derive(Clone, Debug)]
pub struct Truth {
    pub radiance: FloatImage,
    pub std_err: FloatImage,
    pub alpha: Vec<f32>,
    pub record: LightRecord,
}

/// The head's coverage of each pixel from [`ALPHA_SAMPLES`]² rays per pixel, and the points
/// those rays see [mm].
fn coverage(mesh: &ClosedMesh, cam: &Projector) -> (Vec<f32>, Vec<DVec3>) {
    let n = ALPHA_SAMPLES;
    let eye = cam.eye * MM;
    let mut seen = Vec::new();
    let alpha = (0..cam.width * cam.height)
        .map(|i| {
            let (px, py) = ((i % cam.width) as f64, (i / cam.width) as f64);
            let mut hits = 0;
            for s in 0..n * n {
                let x = px + ((s % n) as f64 + 0.5) / n as f64;
                let y = py + ((s / n) as f64 + 0.5) / n as f64;
                let d = cam.ray(x, y);
                if let Some(h) = mesh.first_hit(eye, d, f64::INFINITY, None) {
                    hits += 1;
                    seen.push(eye + d * h.t);
                }
            }
            hits as f32 / (n * n) as f32
        })
        .collect();
    (alpha, seen)
}

/// Process CPU time [s] (user + system, `/proc/self/stat`; 0 where it cannot be read).
pub fn cpu_seconds() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return 0.0;
    };
    // Fields after the command name's closing parenthesis; utime and stime are the 12th and
    // 13th of those, in clock ticks of 1/100 s (USER_HZ, fixed by the kernel's ABI).
    let rest = stat.rsplit_once(')').map_or("", |r| r.1);
    let f: Vec<f64> = rest
        .split_whitespace()
        .skip(11)
        .take(2)
        .filter_map(|v| v.parse().ok())
        .collect();
    f.iter().sum::<f64>() / 100.0
}

/// Computes the truth of `scene` (its walkable `mesh`: [`FaceScene::closed_mesh`]) under a
/// point light at `light` [m] of `intensity` W/sr. `progress(done, total)` counts photons over
/// the three channels.
pub fn compute(
    scene: &FaceScene,
    mesh: &ClosedMesh,
    name: &str,
    light: Vec3,
    intensity: f32,
    run: &TruthRun,
    progress: &mut (dyn FnMut(u64, u64) + Send),
) -> Result<Truth, String> {
    if !(light.is_finite() && intensity > 0.0 && intensity.is_finite()) {
        return Err("the light's position and intensity must be finite, intensity > 0".into());
    }
    if run.photons == 0 {
        return Err("no photons".into());
    }
    let light_mm = light.as_dvec3() * MM;
    if mesh.contains(light_mm) {
        return Err(format!(
            "the light at {:?} m is inside the head",
            light.to_array()
        ));
    }
    let (w, h) = (scene.width, scene.height);
    let cam = Projector::new(&scene.camera, w, h);
    let (alpha, seen) = coverage(mesh, &cam);
    let field = DistanceField::new(&seen, mesh.lo, mesh.hi, ROULETTE_VOXEL_MM, 32);
    let roulette = EntryRoulette {
        field: &field,
        distance: ROULETTE_DISTANCE_MM,
        survival: ROULETTE_SURVIVAL,
    };
    let nbatches: [usize; 3] = CHANNEL_SHARE.map(|k| {
        ((run.photons as f64 * k).ceil() as u64)
            .div_ceil(BATCH_SIZE)
            .max(2) as usize
    });
    let total: u64 = nbatches.iter().map(|&n| n as u64 * BATCH_SIZE).sum();
    let mut done0 = 0;
    let m = &scene.material;
    let c_exit = subsurface::exit_normalisation(m.eta);
    let npix = (w * h) as usize;
    let mut mean = vec![[0f32; 3]; npix];
    let mut se = vec![[0f32; 3]; npix];
    let mut record = LightRecord {
        name: name.into(),
        position: light.to_array(),
        intensity,
        scene_fnv1a64: scene.hash(light, intensity),
        photons_per_channel: nbatches.map(|n| n as u64 * BATCH_SIZE),
        seed: run.seed,
        threads: run.threads,
        cone_sr: 0.0,
        cpu_seconds: [0.0; 3],
        wall_seconds: [0.0; 3],
        events: [0; 3],
        energy: Default::default(),
    };
    for ch in 0..3 {
        let medium = Medium::new(m.sigma_a[ch], m.sigma_s_prime[ch], m.g, m.eta);
        let mut walker = MeshWalker::new(mesh, &medium, light_mm);
        walker.roulette = Some(roulette);
        let nbatches = nbatches[ch];
        record.cone_sr = walker.cone_solid_angle();
        // Power per photon [W]: the cone's share of the light.
        let w0 = intensity as f64 * walker.cone_solid_angle();
        let score_exit = |e: &Exit, image: &mut [f64]| {
            let x = e.point / MM;
            let to_eye = cam.eye - x;
            let d = to_eye.length();
            let v = to_eye / d;
            let cos_geo = mesh.normal(e.hit.tri).dot(v);
            let nv = mesh.shading_normal(&e.hit).dot(v);
            if cos_geo <= 0.0 || nv <= 0.0 {
                return;
            }
            let Some((px, py)) = cam.project(x) else {
                return;
            };
            if !(px >= 0.0 && py >= 0.0 && px < w as f64 && py < h as f64) {
                return;
            }
            let d_mm = d * MM;
            if mesh.occluded(cam.eye * MM, -v, d_mm - 1e-3, Some(e.hit.tri)) {
                return;
            }
            let cos_a = (-v).dot(cam.forward);
            let jacobian = cam.focal_px * cam.focal_px * cos_geo / (d * d * cos_a.powi(3));
            let radiance =
                fresnel::transmittance_shader(m.eta, nv) / (std::f64::consts::PI * c_exit);
            image[py as usize * w as usize + px as usize] += w0 * e.weight * radiance * jacobian;
        };
        let run_batch = |b: usize| {
            let mut rng = Rng::new(run.seed, ((ch as u64) << 48) | b as u64);
            let mut tally = MeshTally::default();
            let mut image = vec![0f64; npix];
            for _ in 0..BATCH_SIZE {
                walker.photon(&mut rng, &mut tally, &mut |e| score_exit(e, &mut image));
            }
            let pixels: Vec<(u32, f64)> = image
                .iter()
                .enumerate()
                .filter(|(_, v)| **v != 0.0)
                .map(|(i, v)| (i as u32, *v))
                .collect();
            (tally, pixels)
        };
        let mut sum = vec![0f64; npix];
        let mut sum2 = vec![0f64; npix];
        let mut tally = MeshTally::default();
        let (cpu0, t0) = (cpu_seconds(), Instant::now());
        run_batches_ordered(nbatches, run.threads, run_batch, |b, (t, pixels)| {
            tally.merge(&t);
            for (i, v) in pixels {
                sum[i as usize] += v;
                sum2[i as usize] += v * v;
            }
            progress(done0 + (b as u64 + 1) * BATCH_SIZE, total);
        });
        done0 += nbatches as u64 * BATCH_SIZE;
        record.cpu_seconds[ch] = cpu_seconds() - cpu0;
        record.wall_seconds[ch] = t0.elapsed().as_secs_f64();
        record.events[ch] = tally.events;
        record.energy[ch] = Energy::from_tally(&tally);
        // Batch means m_b = S_b/n: the mean and the standard error of the mean over batches.
        let (nb, n) = (nbatches as f64, BATCH_SIZE as f64);
        for i in 0..npix {
            let mu = sum[i] / (nb * n);
            let var = ((sum2[i] / (n * n) - nb * mu * mu) / (nb - 1.0)).max(0.0);
            mean[i][ch] = mu as f32;
            se[i][ch] = (var / nb).sqrt() as f32;
        }
    }
    Ok(Truth {
        radiance: FloatImage::new(w, h, mean)?,
        std_err: FloatImage::new(w, h, se)?,
        alpha,
        record,
    })
}
