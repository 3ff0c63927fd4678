//! `cargo xtask ui-atlas [--out DIR] [--check]`: generates the UI skin atlas — a 9-slice
//! panel, a button (normal and pressed), a white texel block for solid fills and dermis' own
//! bitmap font (see `font.rs`) — as `atlas.png` (256×256 RGBA, straight alpha) and
//! `atlas.json` (rects and glyph metrics) in `assets/ui/`. The output is deterministic
//! (fixed inputs, IEEE-exact float operations only, fixed PNG settings, sorted JSON keys);
//! `--check` regenerates in memory and fails if the files on disk differ.

mod font;

use std::path::PathBuf;

pub const SIZE: u32 = 256;
/// Font cell in the atlas: 16 columns × 6 rows of 16×24 texels from the origin.
const CELL_W: u32 = 16;
const CELL_H: u32 = 24;
const CELL_COLS: u32 = 16;
/// Each font pixel is drawn as a 2×2 texel block, the ink starting 3 texels into the cell.
const PIXEL: u32 = 2;
const PAD: u32 = 3;
/// Pen advance (5 columns × 2 texels + 2 texels spacing).
const ADVANCE: u32 = 12;
/// Skin sprites: 48×48 with a 16-texel 9-slice border, in a row below the font.
const SPRITE: u32 = 48;
const SPRITE_Y: u32 = 160;
const BORDER: u32 = 16;
const WHITE: [u32; 4] = [3 * SPRITE + 4, SPRITE_Y + 4, 8, 8];

// The layout fits the atlas and nothing overlaps (checked at compile time).
const _: () = {
    let glyph_rows = ((font::LAST - font::FIRST) as u32 + CELL_COLS) / CELL_COLS;
    assert!(glyph_rows * CELL_H <= SPRITE_Y);
    assert!(WHITE[0] + WHITE[2] <= SIZE && 3 * SPRITE <= WHITE[0]);
    assert!(SPRITE_Y + SPRITE <= SIZE);
    assert!(PAD + font::COLS as u32 * PIXEL < CELL_W && PAD + font::ROWS as u32 * PIXEL < CELL_H);
};

struct Image {
    rgba: Vec<u8>,
}

impl Image {
    fn new() -> Self {
        Self {
            rgba: vec![0; (SIZE * SIZE * 4) as usize],
        }
    }
    fn set(&mut self, x: u32, y: u32, c: [u8; 4]) {
        let i = ((y * SIZE + x) * 4) as usize;
        self.rgba[i..i + 4].copy_from_slice(&c);
    }
    fn alpha(&self, x: u32, y: u32) -> u8 {
        self.rgba[((y * SIZE + x) * 4 + 3) as usize]
    }
}

/// Glyph ink as a boolean grid in texels (cell-local).
fn draw_glyph(img: &mut Image, c: u8, cx: u32, cy: u32) {
    let rows = font::glyph(c).expect("printable ASCII");
    let ink = |x: i32, y: i32| -> bool {
        if x < PAD as i32 || y < PAD as i32 {
            return false;
        }
        let (gx, gy) = (
            ((x - PAD as i32) / PIXEL as i32) as usize,
            ((y - PAD as i32) / PIXEL as i32) as usize,
        );
        gx < font::COLS && gy < font::ROWS && rows[gy] & (1 << (font::COLS - 1 - gx)) != 0
    };
    for y in 0..CELL_H as i32 {
        for x in 0..CELL_W as i32 {
            let texel = if ink(x, y) {
                [255, 255, 255, 255]
            } else if (-1..=1).any(|dy| (-1..=1).any(|dx| ink(x + dx, y + dy))) {
                // A one-texel dark outline keeps text readable over the 3D scene.
                [0, 0, 0, 255]
            } else {
                [0, 0, 0, 0]
            };
            img.set(cx + x as u32, cy + y as u32, texel);
        }
    }
}

fn mix(a: [f32; 4], b: [f32; 4], t: f32) -> [f32; 4] {
    [0, 1, 2, 3].map(|i| a[i] + (b[i] - a[i]) * t)
}

/// A rounded-rectangle sprite: vertical fill gradient, a 2-texel border, anti-aliased edge.
fn draw_sprite(img: &mut Image, x0: u32, top: [f32; 4], bottom: [f32; 4], border: [f32; 4]) {
    let half = SPRITE as f32 / 2.0;
    let (b, r) = (half - 1.0, 10.0f32);
    for y in 0..SPRITE {
        for x in 0..SPRITE {
            let (px, py) = (x as f32 + 0.5 - half, y as f32 + 0.5 - half);
            let (qx, qy) = (px.abs() - (b - r), py.abs() - (b - r));
            let outside = (qx.max(0.0) * qx.max(0.0) + qy.max(0.0) * qy.max(0.0)).sqrt();
            let d = outside + qx.max(qy).min(0.0) - r;
            let coverage = (0.5 - d).clamp(0.0, 1.0);
            let fill = mix(top, bottom, (y as f32 + 0.5) / SPRITE as f32);
            let c = mix(fill, border, (d + 2.5).clamp(0.0, 1.0));
            let q = |v: f32| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
            img.set(
                x0 + x,
                SPRITE_Y + y,
                [q(c[0]), q(c[1]), q(c[2]), q(c[3] * coverage)],
            );
        }
    }
}

fn rgb(r: u8, g: u8, b: u8, a: u8) -> [f32; 4] {
    [
        r as f32 / 255.0,
        g as f32 / 255.0,
        b as f32 / 255.0,
        a as f32 / 255.0,
    ]
}

/// The atlas pixels and its JSON description.
pub fn generate() -> (Vec<u8>, String) {
    let mut img = Image::new();
    let mut glyphs = Vec::new();
    for c in font::FIRST..=font::LAST {
        let i = (c - font::FIRST) as u32;
        let (cx, cy) = ((i % CELL_COLS) * CELL_W, (i / CELL_COLS) * CELL_H);
        draw_glyph(&mut img, c, cx, cy);
        glyphs.push(serde_json::json!({
            "char": c,
            "rect": [cx, cy, CELL_W, CELL_H],
            "offset": [-(PAD as i32), 0],
            "advance": ADVANCE,
        }));
    }
    let panel = [0, SPRITE_Y, SPRITE, SPRITE];
    let button = [SPRITE, SPRITE_Y, SPRITE, SPRITE];
    let pressed = [2 * SPRITE, SPRITE_Y, SPRITE, SPRITE];
    draw_sprite(
        &mut img,
        panel[0],
        rgb(30, 34, 48, 225),
        rgb(18, 20, 30, 225),
        rgb(170, 185, 215, 255),
    );
    draw_sprite(
        &mut img,
        button[0],
        rgb(86, 140, 220, 255),
        rgb(44, 84, 160, 255),
        rgb(210, 228, 255, 255),
    );
    draw_sprite(
        &mut img,
        pressed[0],
        rgb(34, 62, 120, 255),
        rgb(44, 80, 150, 255),
        rgb(150, 170, 210, 255),
    );
    for y in WHITE[1]..WHITE[1] + WHITE[3] {
        for x in WHITE[0]..WHITE[0] + WHITE[2] {
            img.set(x, y, [255; 4]);
        }
    }
    debug_assert_eq!(img.alpha(WHITE[0], WHITE[1]), 255);
    let sprite = |rect: [u32; 4]| serde_json::json!({ "rect": rect, "border": BORDER });
    let json = serde_json::json!({
        "format": "dermis-ui-atlas 1",
        "width": SIZE,
        "height": SIZE,
        "white": WHITE,
        "sprites": { "panel": sprite(panel), "button": sprite(button), "button_pressed": sprite(pressed) },
        "font": {
            "line_height": CELL_H,
            "baseline": PAD + 7 * PIXEL,
            "glyphs": glyphs,
        },
    });
    let mut text = serde_json::to_string_pretty(&json).expect("json");
    text.push('\n');
    (img.rgba, text)
}

fn encode_png(rgba: &[u8]) -> Result<Vec<u8>, String> {
    use image::ImageEncoder;
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new_with_quality(
        &mut out,
        image::codecs::png::CompressionType::Best,
        image::codecs::png::FilterType::Adaptive,
    )
    .write_image(rgba, SIZE, SIZE, image::ExtendedColorType::Rgba8)
    .map_err(|e| format!("png: {e}"))?;
    Ok(out)
}

pub fn run(args: &[String]) -> Result<(), String> {
    let mut out = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../assets/ui");
    let mut check = false;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--out" => out = PathBuf::from(it.next().ok_or("--out needs a directory")?),
            "--check" => check = true,
            other => {
                return Err(format!(
                    "ui-atlas: unknown argument `{other}` (usage: ui-atlas [--out DIR] [--check])"
                ))
            }
        }
    }
    let (rgba, json) = generate();
    let png = encode_png(&rgba)?;
    let files = [("atlas.png", png), ("atlas.json", json.into_bytes())];
    if check {
        for (name, bytes) in &files {
            let path = out.join(name);
            let disk = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            if &disk != bytes {
                return Err(format!(
                    "{} is stale: run `cargo xtask ui-atlas`",
                    path.display()
                ));
            }
        }
        println!("ui-atlas: {} up to date", out.display());
        return Ok(());
    }
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    for (name, bytes) in &files {
        let path = out.join(name);
        std::fs::write(&path, bytes).map_err(|e| format!("{}: {e}", path.display()))?;
        println!("wrote {} ({} bytes)", path.display(), bytes.len());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deterministic() {
        let (a, ja) = generate();
        let (b, jb) = generate();
        assert!(a == b && ja == jb);
        assert_eq!(encode_png(&a).unwrap(), encode_png(&b).unwrap());
    }
}
