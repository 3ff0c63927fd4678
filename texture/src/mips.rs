//! The mip chain the renderer samples and `cargo xtask assets` encodes: 2×2 box filters,
//! in linear light for sRGB data.

/// Level 0 and every smaller level down to 1×1, each a 2×2 box filter of the one above (in
/// linear light when `srgb`, alpha linear): the chain the renderer samples, and what
/// `cargo xtask assets` encodes.
pub fn mip_chain(rgba: &[u8], width: u32, height: u32, srgb: bool) -> Vec<Vec<u8>> {
    let mut levels = vec![rgba.to_vec()];
    let (mut w, mut h) = (width, height);
    for _ in 1..crate::full_chain(width, height) {
        let next = downsample(levels.last().map_or(&[][..], Vec::as_slice), w, h, srgb);
        levels.push(next);
        w = (w / 2).max(1);
        h = (h / 2).max(1);
    }
    levels
}

/// 2×2 box filter (edge texels repeat for odd sizes), in linear light when `srgb`.
fn downsample(src: &[u8], w: u32, h: u32, srgb: bool) -> Vec<u8> {
    let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
    let mut out = vec![0u8; (nw * nh * 4) as usize];
    let t = tables();
    let at = |x: u32, y: u32| ((y.min(h - 1) * w + x.min(w - 1)) * 4) as usize;
    for y in 0..nh {
        for x in 0..nw {
            let (x2, y2) = (x * 2, y * 2);
            let quad = [
                at(x2, y2),
                at(x2 + 1, y2),
                at(x2, y2 + 1),
                at(x2 + 1, y2 + 1),
            ];
            let texel = ((y * nw + x) * 4) as usize;
            for c in 0..4 {
                let linear = srgb && c < 3;
                let decode = &t.decode[usize::from(linear)];
                let sum: f32 = quad.iter().map(|&i| decode[src[i + c] as usize]).sum();
                let avg = sum * 0.25;
                out[texel + c] = if linear {
                    t.encode(avg)
                } else {
                    (avg * 255.0 + 0.5).clamp(0.0, 255.0) as u8
                };
            }
        }
    }
    out
}

/// Each byte's value (plain and sRGB-decoded), and the linear values where the sRGB-encoded
/// byte steps up: what a mip level costs is table lookups, not `powf` per texel.
struct Tables {
    decode: [[f32; 256]; 2],
    /// `steps[k]`: the least linear value encoded to byte `k + 1` (the sRGB curve's midpoint
    /// between `k` and `k + 1`, decoded).
    steps: [f32; 255],
}

impl Tables {
    /// The sRGB byte of a linear value in [0, 1]: the steps at or below it.
    fn encode(&self, linear: f32) -> u8 {
        self.steps.partition_point(|&s| s <= linear) as u8
    }
}

fn tables() -> &'static Tables {
    static TABLES: std::sync::OnceLock<Tables> = std::sync::OnceLock::new();
    TABLES.get_or_init(|| {
        let unit = |b: usize| b as f32 / 255.0;
        Tables {
            decode: [
                std::array::from_fn(unit),
                std::array::from_fn(|b| srgb_to_linear(unit(b))),
            ],
            steps: std::array::from_fn(|k| srgb_to_linear((k as f32 + 0.5) / 255.0)),
        }
    })
}

fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// The sRGB curve itself (what [`Tables::encode`] is checked against).
#[cfg(test)]
fn linear_to_srgb(v: f32) -> f32 {
    if v <= 0.0031308 {
        v * 12.92
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mip_chain_length() {
        assert_eq!(crate::full_chain(1, 1), 1);
        assert_eq!(crate::full_chain(512, 512), 10);
        assert_eq!(crate::full_chain(640, 3), 10);
    }

    #[test]
    fn the_encode_table_rounds_as_the_srgb_curve_does() {
        let t = tables();
        let mut off = 0;
        let n = 200_000;
        for i in 0..=n {
            let v = i as f32 / n as f32;
            let exact = (linear_to_srgb(v) * 255.0 + 0.5).clamp(0.0, 255.0) as u8;
            let got = t.encode(v);
            assert!(exact.abs_diff(got) <= 1, "{v}: {exact} vs {got}");
            off += usize::from(exact != got);
        }
        // Only where float rounding lands exactly on a step.
        assert!(off <= 2, "{off} of {n} values off by one");
        assert_eq!((t.encode(0.0), t.encode(1.0)), (0, 255));
    }

    #[test]
    fn srgb_downsample_averages_in_linear_light() {
        // Black and white average to 50 % linear, which is sRGB 188, not 128.
        let src = [0, 0, 0, 255, 255, 255, 255, 255];
        let out = downsample(&src, 2, 1, true);
        assert!((out[0] as i32 - 188).abs() <= 1, "{}", out[0]);
        let lin = downsample(&src, 2, 1, false);
        assert!((lin[0] as i32 - 128).abs() <= 1);
    }
}
