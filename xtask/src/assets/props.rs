//! Static props for the runner game: rounded-box meshes with small procedural textures.

use super::mesh::Mesh;
use super::noise::{fbm2, value3};
use super::shapes::rounded_box;
use super::texture::encode_png;
use glam::{Vec2, Vec3};

pub struct Prop {
    pub name: &'static str,
    pub mesh: Mesh,
    pub png: Vec<u8>,
    pub roughness: f32,
}

const TEX: u32 = 256;

/// Renders a `TEX`-square texture from `f(u, v) -> sRGB`.
fn texture(f: impl Fn(f32, f32) -> Vec3) -> Vec<u8> {
    let mut rgba = Vec::with_capacity((TEX * TEX * 4) as usize);
    for y in 0..TEX {
        for x in 0..TEX {
            let c = f((x as f32 + 0.5) / TEX as f32, (y as f32 + 0.5) / TEX as f32)
                .clamp(Vec3::ZERO, Vec3::ONE);
            rgba.extend_from_slice(&[
                (c.x * 255.0 + 0.5) as u8,
                (c.y * 255.0 + 0.5) as u8,
                (c.z * 255.0 + 0.5) as u8,
                255,
            ]);
        }
    }
    encode_png(&rgba, TEX, TEX)
}

/// Tileable fbm (wraps at integer periods by sampling on a torus-like lattice).
fn tile_noise(u: f32, v: f32, cells: f32, seed: u32) -> f32 {
    // Blend four offset copies so the pattern repeats seamlessly at u, v = 0/1.
    let n = |a: f32, b: f32| fbm2(a * cells, b * cells, 3, seed);
    let (a, b) = (u.fract(), v.fract());
    let x0 = n(a, b) * (1.0 - a) + n(a - 1.0, b) * a;
    let x1 = n(a, b - 1.0) * (1.0 - a) + n(a - 1.0, b - 1.0) * a;
    x0 * (1.0 - b) + x1 * b
}

fn wood(u: f32, v: f32, base: Vec3, seed: u32) -> Vec3 {
    let grain = tile_noise(u * 0.25, v * 4.0, 4.0, seed);
    let rings = (grain * 18.0).fract();
    let streak = 0.85 + 0.15 * (rings * rings) + 0.1 * (tile_noise(u, v, 16.0, seed + 1) - 0.5);
    base * streak
}

fn boxes(parts: &[(Vec3, Vec3, f32)], uv_per_m: f32) -> Mesh {
    let mut m = Mesh::default();
    for (i, &(c, h, r)) in parts.iter().enumerate() {
        // Offset each box's UVs so identical parts do not show identical grain.
        let off = Vec2::new(0.37 * i as f32, 0.61 * i as f32).fract() + Vec2::splat(0.5);
        m.append(&rounded_box(c, h, r, 3, uv_per_m, off));
    }
    m
}

fn floor_tile() -> Prop {
    // 4 m x 4 m, 0.1 m thick, walking surface at y = 0; the texture spans the tile once.
    let mesh = boxes(
        &[(Vec3::new(0.0, -0.05, 0.0), Vec3::new(2.0, 0.05, 2.0), 0.015)],
        0.25,
    );
    let png = texture(|u, v| {
        let (gu, gv) = ((u * 4.0).fract(), (v * 4.0).fract());
        let grout = gu.min(1.0 - gu).min(gv.min(1.0 - gv)) < 0.012;
        let cell = value3(Vec3::new((u * 4.0).floor(), (v * 4.0).floor(), 3.0), 21);
        let base = Vec3::new(0.56, 0.55, 0.52) * (0.92 + 0.12 * cell);
        let speck = tile_noise(u, v, 40.0, 4) - 0.5;
        if grout {
            Vec3::splat(0.30)
        } else {
            base * (1.0 + 0.18 * speck)
        }
    });
    Prop {
        name: "floor_tile",
        mesh,
        png,
        roughness: 0.85,
    }
}

fn wall() -> Prop {
    // 4 m long (X), 2.5 m high, 0.2 m thick, standing on y = 0; one texture repeat per 2 m.
    let mesh = boxes(
        &[(Vec3::new(0.0, 1.25, 0.0), Vec3::new(2.0, 1.25, 0.1), 0.02)],
        0.5,
    );
    let png = texture(|u, v| {
        // Running-bond bricks: 8 courses x 4 bricks per repeat.
        let row = (v * 8.0).floor();
        let shift = if row as i32 % 2 == 0 { 0.0 } else { 0.5 };
        let bu = (u * 4.0 + shift).fract();
        let bv = (v * 8.0).fract();
        let mortar = bu < 0.04 || bv < 0.08;
        let id = value3(Vec3::new((u * 4.0 + shift).floor(), row, 1.0), 33);
        let n = tile_noise(u, v, 24.0, 8) - 0.5;
        if mortar {
            Vec3::new(0.72, 0.70, 0.66) * (1.0 + 0.1 * n)
        } else {
            Vec3::new(0.62, 0.30, 0.22) * (0.85 + 0.25 * id) * (1.0 + 0.2 * n)
        }
    });
    Prop {
        name: "wall",
        mesh,
        png,
        roughness: 0.9,
    }
}

fn table() -> Prop {
    let mut parts = vec![(Vec3::new(0.0, 0.73, 0.0), Vec3::new(0.6, 0.02, 0.35), 0.012)];
    for (x, z) in [(-0.54, -0.29), (0.54, -0.29), (-0.54, 0.29), (0.54, 0.29)] {
        parts.push((
            Vec3::new(x, 0.355, z),
            Vec3::new(0.025, 0.355, 0.025),
            0.008,
        ));
    }
    let png = texture(|u, v| wood(u, v, Vec3::new(0.55, 0.36, 0.20), 40));
    Prop {
        name: "table",
        mesh: boxes(&parts, 1.0),
        png,
        roughness: 0.6,
    }
}

fn chair() -> Prop {
    let mut parts = vec![(Vec3::new(0.0, 0.45, 0.0), Vec3::new(0.22, 0.02, 0.22), 0.01)];
    for (x, z) in [(-0.19, -0.19), (0.19, -0.19), (-0.19, 0.19), (0.19, 0.19)] {
        parts.push((
            Vec3::new(x, 0.215, z),
            Vec3::new(0.018, 0.215, 0.018),
            0.006,
        ));
    }
    // Back posts and back rest (behind the seat, -Z; the chair faces +Z).
    for x in [-0.19, 0.19] {
        parts.push((
            Vec3::new(x, 0.68, -0.19),
            Vec3::new(0.018, 0.21, 0.018),
            0.006,
        ));
    }
    parts.push((
        Vec3::new(0.0, 0.76, -0.19),
        Vec3::new(0.2, 0.1, 0.015),
        0.008,
    ));
    let png = texture(|u, v| wood(u, v, Vec3::new(0.45, 0.28, 0.16), 50));
    Prop {
        name: "chair",
        mesh: boxes(&parts, 1.0),
        png,
        roughness: 0.6,
    }
}

fn obstacle() -> Prop {
    // A 1 m wooden crate; each face maps the whole texture once.
    let mesh = boxes(&[(Vec3::new(0.0, 0.5, 0.0), Vec3::splat(0.5), 0.025)], 1.0);
    let png = texture(|u, v| {
        let (a, b) = ((u - 0.5).abs(), (v - 0.5).abs());
        let (uu, vv) = (u, v);
        let frame = a > 0.41 || b > 0.41;
        let brace = (uu - vv).abs() < 0.07;
        let plank_gap = ((v * 5.0).fract() - 0.5).abs() > 0.47;
        let w = wood(u * 2.0, v * 0.5, Vec3::new(0.62, 0.45, 0.26), 60);
        if frame || brace {
            w * 0.8
        } else if plank_gap {
            w * 0.45
        } else {
            w
        }
    });
    Prop {
        name: "obstacle",
        mesh,
        png,
        roughness: 0.7,
    }
}

pub fn props() -> Vec<Prop> {
    vec![floor_tile(), wall(), table(), chair(), obstacle()]
}
