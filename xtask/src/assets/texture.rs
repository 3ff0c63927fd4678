//! The character's base-colour texture: painted in 3D (bind-pose positions) and baked into the
//! UV atlas by rasterising the mesh in texture space. One atlas serves every material (skin,
//! tank top, shorts, hair, eyes: `outfit`); each paints its own parts.

use super::mesh::Mesh;
use super::noise::fbm3;
use super::outfit::Mat;
use glam::{Vec2, Vec3};

pub const SIZE: u32 = 1024;

/// Atlas rectangles `[u0, v0, width, height]`; left and right limbs share theirs (the paint is
/// mirror-symmetric).
pub mod atlas {
    pub const TORSO: [f32; 4] = [0.0, 0.0, 0.5, 0.5];
    pub const HEAD: [f32; 4] = [0.5, 0.0, 0.5, 0.5];
    pub const LEG: [f32; 4] = [0.0, 0.5, 0.25, 0.5];
    pub const ARM: [f32; 4] = [0.25, 0.5, 0.125, 0.5];
    pub const NECK: [f32; 4] = [0.375, 0.5, 0.125, 0.125];
    pub const FOOT: [f32; 4] = [0.5, 0.5, 0.125, 0.125];
    pub const PALM: [f32; 4] = [0.625, 0.5, 0.125, 0.125];
    pub const FINGER: [f32; 4] = [0.75, 0.5, 0.125, 0.125];
    pub const EAR: [f32; 4] = [0.875, 0.5, 0.125, 0.125];
    pub const NOSE: [f32; 4] = [0.375, 0.625, 0.125, 0.125];
    pub const EYE: [f32; 4] = [0.5, 0.625, 0.125, 0.125];
}

fn in_rect(uv: Vec2, r: [f32; 4]) -> bool {
    uv.x >= r[0] && uv.x <= r[0] + r[2] && uv.y >= r[1] && uv.y <= r[1] + r[3]
}

const SKIN: Vec3 = Vec3::new(0.86, 0.67, 0.54);
const FLUSH: Vec3 = Vec3::new(0.82, 0.47, 0.43);
const LIPS: Vec3 = Vec3::new(0.70, 0.36, 0.35);
const HAIR: Vec3 = Vec3::new(0.17, 0.10, 0.07);
const SHIRT: Vec3 = Vec3::new(0.22, 0.46, 0.50);
const SHORTS: Vec3 = Vec3::new(0.16, 0.19, 0.30);

fn sq(x: f32) -> f32 {
    x * x
}

/// Soft ellipsoidal blob: 1 at `c`, 0 beyond radii `r`.
fn blob(p: Vec3, c: Vec3, r: Vec3) -> f32 {
    let t = (1.0 - ((p - c) / r).length()).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Colour at bind-pose position `p` with normal `n` on the part owning atlas rect `rect`, in a
/// triangle of material `mat`.
fn paint(p: Vec3, n: Vec3, rect: [f32; 4], mat: Mat) -> Vec3 {
    if rect == atlas::EYE {
        // The eyeball looks along +z: pupil, iris and sclera by the normal's angle.
        return if n.z > 0.985 {
            Vec3::splat(0.04)
        } else if n.z > 0.93 {
            Vec3::new(0.28, 0.19, 0.12)
        } else {
            Vec3::new(0.93, 0.91, 0.88)
        };
    }
    // Mirror-symmetric coordinates (limbs share atlas space between sides).
    let q = Vec3::new(p.x.abs(), p.y, p.z);
    let mottling = fbm3(q * 40.0, 3, 7) - 0.5;
    let broad = fbm3(q * 6.0, 2, 11) - 0.5;
    let mut c = SKIN * (1.0 + 0.10 * broad + 0.05 * mottling);
    // Warmer, redder areas: cheeks, nose tip, ears, knuckles, elbows, knees, fingertips, toes.
    let mut flush = 0.0f32;
    if rect == atlas::HEAD || rect == atlas::NOSE || rect == atlas::EAR {
        flush += 0.55
            * blob(
                q,
                Vec3::new(0.048, 1.592, 0.075),
                Vec3::new(0.03, 0.022, 0.03),
            );
        flush += 0.45
            * blob(
                q,
                Vec3::new(0.0, 1.598, 0.105),
                Vec3::new(0.018, 0.014, 0.02),
            );
    }
    if rect == atlas::EAR {
        flush += 0.35;
    }
    if rect == atlas::FINGER || rect == atlas::PALM {
        let wrist = super::skeleton::wrist_pos(1.0);
        let d = super::skeleton::arm_dir(1.0);
        let along = (q - wrist).dot(d);
        flush += 0.45 * (1.0 - ((along - 0.088).abs() / 0.02)).clamp(0.0, 1.0);
        flush += 0.35 * ((along - 0.13) / 0.03).clamp(0.0, 1.0);
    }
    if rect == atlas::ARM {
        flush += 0.3
            * blob(
                q,
                super::skeleton::elbow_pos(1.0) + Vec3::new(0.0, 0.0, -0.035),
                Vec3::splat(0.035),
            );
    }
    if rect == atlas::LEG {
        flush += 0.35
            * blob(
                q,
                super::skeleton::knee_pos(1.0) + Vec3::new(0.0, 0.0, 0.05),
                Vec3::new(0.05, 0.05, 0.03),
            );
    }
    if rect == atlas::FOOT {
        flush += 0.3 * ((q.z - 0.12) / 0.06).clamp(0.0, 1.0);
    }
    c = c.lerp(
        FLUSH,
        flush.clamp(0.0, 0.7) * (0.8 + 0.4 * (fbm3(q * 25.0, 2, 3) - 0.5)),
    );
    if rect == atlas::HEAD {
        // Lips.
        let lip = blob(
            q,
            Vec3::new(0.0, 1.556, 0.09),
            Vec3::new(0.024, 0.0085, 0.03),
        );
        c = c.lerp(LIPS, (lip * 2.5).min(1.0) * 0.85);
        if n.z > 0.2 {
            // Upper lid line and brow around the eyeball (a part of its own).
            let (ex, ey) = (0.032f32, 1.624f32);
            let r2 = sq((q.x - ex) / 0.0125) + sq((q.y - ey) / 0.0065);
            if (1.0..1.5).contains(&r2) && q.y > ey {
                c *= 0.55;
            }
            let bx = (q.x - ex) / 0.018;
            let by = q.y - (ey + 0.018 - 0.006 * bx * bx);
            if bx.abs() < 1.0 && by.abs() < 0.0025 {
                c = c.lerp(HAIR, 0.85);
            }
        }
        // Hair cap: hairline high at the forehead, low at the nape.
        let edge = super::outfit::hair_cover(p);
        if edge > 0.0 {
            let strands = fbm3(Vec3::new(q.x * 300.0, q.y * 60.0, q.z * 300.0), 2, 5);
            c = c.lerp(HAIR * (0.8 + 0.5 * strands), edge);
        }
    }
    let fabric = 0.9 + 0.2 * fbm3(q * 120.0, 2, 9);
    match mat {
        Mat::Shorts => c = SHORTS * fabric,
        Mat::TankTop => c = SHIRT * fabric,
        _ => {}
    }
    c.clamp(Vec3::ZERO, Vec3::ONE)
}

/// Bakes the atlas for `mesh` (bind pose), triangle `t` of material `mats[t]`, and returns
/// RGBA8 pixels (opaque).
pub fn bake(mesh: &Mesh, mats: &[Mat]) -> Vec<u8> {
    let size = SIZE as usize;
    let mut col = vec![Vec3::ZERO; size * size];
    let mut filled = vec![false; size * size];
    let rects = [
        atlas::TORSO,
        atlas::HEAD,
        atlas::LEG,
        atlas::ARM,
        atlas::NECK,
        atlas::FOOT,
        atlas::PALM,
        atlas::FINGER,
        atlas::EAR,
        atlas::NOSE,
        atlas::EYE,
    ];
    for (t, &mat) in mesh.indices.chunks(3).zip(mats) {
        let idx = [t[0] as usize, t[1] as usize, t[2] as usize];
        let uv = idx.map(|i| mesh.uvs[i] * SIZE as f32);
        let centre = (mesh.uvs[idx[0]] + mesh.uvs[idx[1]] + mesh.uvs[idx[2]]) / 3.0;
        let Some(rect) = rects.iter().copied().find(|r| in_rect(centre, *r)) else {
            continue;
        };
        let lo = uv[0].min(uv[1]).min(uv[2]).floor().max(Vec2::ZERO);
        let hi = uv[0]
            .max(uv[1])
            .max(uv[2])
            .ceil()
            .min(Vec2::splat(SIZE as f32 - 1.0));
        let area = (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]);
        if area.abs() < 1e-9 {
            continue;
        }
        for y in lo.y as usize..=hi.y as usize {
            for x in lo.x as usize..=hi.x as usize {
                let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let w0 = (uv[2] - uv[1]).perp_dot(p - uv[1]) / area;
                let w1 = (uv[0] - uv[2]).perp_dot(p - uv[2]) / area;
                let w2 = 1.0 - w0 - w1;
                let e = -0.02;
                if w0 < e || w1 < e || w2 < e || filled[y * size + x] {
                    continue;
                }
                let pos = mesh.positions[idx[0]] * w0
                    + mesh.positions[idx[1]] * w1
                    + mesh.positions[idx[2]] * w2;
                let nrm = (mesh.normals[idx[0]] * w0
                    + mesh.normals[idx[1]] * w1
                    + mesh.normals[idx[2]] * w2)
                    .normalize_or_zero();
                col[y * size + x] = paint(pos, nrm, rect, mat);
                filled[y * size + x] = true;
            }
        }
    }
    // Dilate into the gutters so bilinear filtering and mips never pick up the background.
    for _ in 0..8 {
        let prev = filled.clone();
        let prev_col = col.clone();
        for y in 0..size {
            for x in 0..size {
                if prev[y * size + x] {
                    continue;
                }
                let mut sum = Vec3::ZERO;
                let mut k = 0;
                for (dx, dy) in [(-1i32, 0i32), (1, 0), (0, -1), (0, 1)] {
                    let (nx, ny) = (x as i32 + dx, y as i32 + dy);
                    if nx >= 0
                        && ny >= 0
                        && (nx as usize) < size
                        && (ny as usize) < size
                        && prev[ny as usize * size + nx as usize]
                    {
                        sum += prev_col[ny as usize * size + nx as usize];
                        k += 1;
                    }
                }
                if k > 0 {
                    col[y * size + x] = sum / k as f32;
                    filled[y * size + x] = true;
                }
            }
        }
    }
    let mut out = Vec::with_capacity(size * size * 4);
    for (c, f) in col.iter().zip(&filled) {
        let c = if *f { *c } else { SKIN };
        out.extend_from_slice(&[
            (c.x * 255.0 + 0.5) as u8,
            (c.y * 255.0 + 0.5) as u8,
            (c.z * 255.0 + 0.5) as u8,
            255,
        ]);
    }
    out
}

/// Encodes RGBA8 pixels as a PNG (RGB, no metadata, deterministic).
pub fn encode_png(rgba: &[u8], w: u32, h: u32) -> Vec<u8> {
    let rgb: Vec<u8> = rgba.chunks(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    encode(&rgb, w, h, image::ExtendedColorType::Rgb8)
}

fn encode(pixels: &[u8], w: u32, h: u32, colour: image::ExtendedColorType) -> Vec<u8> {
    use image::ImageEncoder;
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new_with_quality(
        &mut out,
        image::codecs::png::CompressionType::Best,
        image::codecs::png::FilterType::Adaptive,
    )
    .write_image(pixels, w, h, colour)
    .expect("PNG encoding into memory cannot fail");
    out
}
