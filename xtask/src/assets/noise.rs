//! Seeded, integer-hash value noise (deterministic on every platform).

use glam::Vec3;

fn hash(x: i32, y: i32, z: i32, seed: u32) -> f32 {
    let mut h = seed
        .wrapping_mul(0x9E37_79B9)
        .wrapping_add((x as u32).wrapping_mul(0x85EB_CA6B))
        .wrapping_add((y as u32).wrapping_mul(0xC2B2_AE35))
        .wrapping_add((z as u32).wrapping_mul(0x27D4_EB2F));
    h ^= h >> 15;
    h = h.wrapping_mul(0x2C1B_3C6D);
    h ^= h >> 12;
    h = h.wrapping_mul(0x297A_2D39);
    h ^= h >> 15;
    (h & 0x00FF_FFFF) as f32 / 0x00FF_FFFF as f32
}

/// Smoothly interpolated value noise in [0, 1] at `p` (one cell per unit).
pub fn value3(p: Vec3, seed: u32) -> f32 {
    let f = p.floor();
    let (ix, iy, iz) = (f.x as i32, f.y as i32, f.z as i32);
    let t = p - f;
    let s = t * t * (Vec3::splat(3.0) - 2.0 * t);
    let mut c = [0.0f32; 8];
    for (k, v) in c.iter_mut().enumerate() {
        let (dx, dy, dz) = ((k & 1) as i32, ((k >> 1) & 1) as i32, ((k >> 2) & 1) as i32);
        *v = hash(ix + dx, iy + dy, iz + dz, seed);
    }
    let l = |a: f32, b: f32, t: f32| a + (b - a) * t;
    let x00 = l(c[0], c[1], s.x);
    let x10 = l(c[2], c[3], s.x);
    let x01 = l(c[4], c[5], s.x);
    let x11 = l(c[6], c[7], s.x);
    l(l(x00, x10, s.y), l(x01, x11, s.y), s.z)
}

/// Fractal sum of `octaves` value-noise layers, roughly in [0, 1].
pub fn fbm3(p: Vec3, octaves: u32, seed: u32) -> f32 {
    let mut sum = 0.0;
    let mut amp = 0.5;
    let mut freq = 1.0;
    let mut norm = 0.0;
    for o in 0..octaves {
        sum += amp * value3(p * freq, seed.wrapping_add(o * 101));
        norm += amp;
        amp *= 0.5;
        freq *= 2.03;
    }
    sum / norm
}

/// 2D convenience wrapper.
pub fn fbm2(x: f32, y: f32, octaves: u32, seed: u32) -> f32 {
    fbm3(Vec3::new(x, y, 0.37), octaves, seed)
}
