//! Where on the head a face score's error sits: named regions of the head (boxes in its own
//! frame, metres: +x toward the ear the face camera sees, +y up, the face toward +z), each
//! scored block assigned to the region holding the point the camera sees at the block's
//! centre, and the signed error per region and channel.

use glam::DVec3;

use super::score::{block_means, Reference};
use super::truth::FaceScene;
use dermis_engine::render::pfm::FloatImage;

/// A named box on the head [m].
#[derive(Clone, Copy, Debug)]
pub struct Region {
    pub name: &'static str,
    pub lo: [f64; 3],
    pub hi: [f64; 3],
}

/// The regions the diagnosis reports (the first that holds a point wins).
pub const REGIONS: [Region; 6] = [
    Region {
        name: "nose",
        lo: [-0.018, 0.030, 0.080],
        hi: [0.018, 0.075, 0.120],
    },
    Region {
        name: "eye sockets",
        lo: [-0.055, 0.050, 0.050],
        hi: [0.055, 0.082, 0.110],
    },
    Region {
        name: "lips",
        lo: [-0.030, 0.000, 0.070],
        hi: [0.030, 0.030, 0.120],
    },
    Region {
        name: "right ear",
        lo: [0.060, 0.025, -0.030],
        hi: [0.110, 0.100, 0.020],
    },
    Region {
        name: "neck",
        lo: [-0.090, -0.160, -0.110],
        hi: [0.090, -0.035, 0.080],
    },
    Region {
        name: "rest of the head",
        lo: [-1.0, -1.0, -1.0],
        hi: [1.0, 1.0, 1.0],
    },
];

/// The region of each block (`block`² pixels) whose centre ray meets the head, else `None`.
pub fn block_regions(scene: &FaceScene, block: u32) -> Result<Vec<Option<usize>>, String> {
    let mesh = scene.closed_mesh()?;
    let cam = &scene.camera;
    let (w, h) = (scene.width, scene.height);
    let view_proj = dermis_engine::camera::look_at(
        cam.eye,
        cam.target,
        cam.fov_y_deg.to_radians(),
        w as f32 / h as f32,
    )
    .as_dmat4();
    let inverse = view_proj.inverse();
    let eye = cam.eye.as_dvec3();
    let (bw, bh) = (w / block, h / block);
    Ok((0..bw * bh)
        .map(|i| {
            let x = ((i % bw) * block) as f64 + 0.5 * block as f64;
            let y = ((i / bw) * block) as f64 + 0.5 * block as f64;
            let ndc =
                glam::DVec4::new(2.0 * x / w as f64 - 1.0, 1.0 - 2.0 * y / h as f64, 0.5, 1.0);
            let p = inverse * ndc;
            let d = (p.truncate() / p.w - eye).normalize();
            let hit = mesh.first_hit(eye * 1000.0, d, f64::INFINITY, None)?;
            let q: DVec3 = eye + d * (hit.t / 1000.0);
            REGIONS
                .iter()
                .position(|r| (0..3).all(|k| q[k] >= r.lo[k] && q[k] <= r.hi[k]))
        })
        .collect())
}

/// Per region: scored block channels and the mean signed ln(model/truth) per channel
/// (`None` where a channel has no scored block there).
pub type RegionError = (&'static str, [usize; 3], [Option<f64>; 3]);

/// The signed error of `model` against `reference` per region of `regions`.
pub fn region_errors(
    reference: &Reference,
    model: &FloatImage,
    regions: &[Option<usize>],
    block: u32,
) -> Vec<RegionError> {
    let blocks = block_means(model, block);
    REGIONS
        .iter()
        .enumerate()
        .map(|(k, r)| {
            let mut n = [0usize; 3];
            let mut sum = [0f64; 3];
            for (i, reg) in regions.iter().enumerate() {
                if *reg != Some(k) {
                    continue;
                }
                for c in 0..3 {
                    if reference.mask[i][c] {
                        let (m, t) = (
                            blocks.pixels[i][c] as f64,
                            reference.mean.pixels[i][c] as f64,
                        );
                        sum[c] += (m.max(1e-30) / t)
                            .ln()
                            .clamp(-super::score::CAP, super::score::CAP);
                        n[c] += 1;
                    }
                }
            }
            (
                r.name,
                n,
                std::array::from_fn(|c| (n[c] > 0).then(|| sum[c] / n[c] as f64)),
            )
        })
        .collect()
}

/// A per-block image of ln(model/truth) on a diverging scale (±`range`: blue too dark, red too
/// bright, white right), grey where the block is not scored, black off the head; 8-bit RGB,
/// `scale` pixels per block. `channel`: which channel, or the mean of the scored ones (None).
pub fn ln_error_png(
    reference: &Reference,
    model: &FloatImage,
    block: u32,
    channel: Option<usize>,
    range: f64,
    scale: u32,
) -> (u32, u32, Vec<u8>) {
    let blocks = block_means(model, block);
    let (bw, bh) = (blocks.width, blocks.height);
    let colour = |i: usize| -> [u8; 3] {
        let cs: Vec<usize> = match channel {
            Some(c) => vec![c],
            None => (0..3).collect(),
        };
        let vals: Vec<f64> = cs
            .iter()
            .filter(|&&c| reference.mask[i][c])
            .map(|&c| {
                let (m, t) = (
                    blocks.pixels[i][c] as f64,
                    reference.mean.pixels[i][c] as f64,
                );
                (m.max(1e-30) / t).ln()
            })
            .collect();
        if vals.is_empty() {
            return if reference.mean.pixels[i].iter().any(|v| *v > 0.0) {
                [96, 96, 96]
            } else {
                [0, 0, 0]
            };
        }
        let e = (vals.iter().sum::<f64>() / vals.len() as f64 / range).clamp(-1.0, 1.0);
        let fade = |x: f64| (255.0 * (1.0 - x.abs())) as u8;
        if e >= 0.0 {
            [255, fade(e), fade(e)]
        } else {
            [fade(e), fade(e), 255]
        }
    };
    let (w, h) = (bw * scale, bh * scale);
    let mut out = Vec::with_capacity((w * h * 3) as usize);
    for y in 0..h {
        for x in 0..w {
            out.extend_from_slice(&colour(((y / scale) * bw + x / scale) as usize));
        }
    }
    (w, h, out)
}
