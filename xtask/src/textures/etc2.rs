//! An ETC2 encoder (the RGB8 and RGBA8 formats): colour in ETC2's ETC1-compatible
//! individual and differential modes, alpha as an EAC block. Integer arithmetic only, so the
//! same image gives the same bytes on every machine. (No pure-Rust ETC2 encoder is on
//! crates.io; the C++ ones would add a C++ build to every workspace build.)
//!
//! Per 4×4 block and orientation (two 2×4 or two 4×2 halves), each half's base colour starts
//! at its mean, quantised to 4 bits (individual mode) or 5 bits with a 3-bit signed delta
//! (differential mode, only where the delta fits: an overflow would be read as ETC2's T, H or
//! planar mode), then moved along the grey axis by up to ±2 steps; for each candidate the
//! intensity table with the least weighted squared error wins. Alpha: the EAC base, multiplier
//! and table minimising the squared error over a search around the block's mid value.

/// ETC1/ETC2 intensity modifier tables (codeword 0..7): the small and the large step.
const INTENSITY: [[i32; 2]; 8] = [
    [2, 8],
    [5, 17],
    [9, 29],
    [13, 42],
    [18, 60],
    [24, 80],
    [33, 106],
    [47, 183],
];

/// EAC modifier tables (table index 0..15), pixel index 0..7.
const EAC: [[i32; 8]; 16] = [
    [-3, -6, -9, -15, 2, 5, 8, 14],
    [-3, -7, -10, -13, 2, 6, 9, 12],
    [-2, -5, -8, -13, 1, 4, 7, 12],
    [-2, -4, -6, -13, 1, 3, 5, 12],
    [-3, -6, -8, -12, 2, 5, 7, 11],
    [-3, -7, -9, -11, 2, 6, 8, 10],
    [-4, -7, -8, -11, 3, 6, 7, 10],
    [-3, -5, -8, -11, 2, 4, 7, 10],
    [-2, -6, -8, -10, 1, 5, 7, 9],
    [-2, -5, -8, -10, 1, 4, 7, 9],
    [-2, -4, -8, -10, 1, 3, 7, 9],
    [-2, -5, -7, -10, 1, 4, 6, 9],
    [-3, -4, -7, -10, 2, 3, 6, 9],
    [-1, -2, -3, -10, 0, 1, 2, 9],
    [-4, -6, -8, -9, 3, 5, 7, 8],
    [-3, -5, -7, -9, 2, 4, 6, 8],
];

/// The modifier of pixel index `i` (msb·2 + lsb) in intensity table `t`.
fn modifier(t: usize, i: usize) -> i32 {
    let [a, b] = INTENSITY[t];
    [a, b, -a, -b][i]
}

/// Per-channel error weights: luma-like for colour, even for data (normal maps).
#[derive(Clone, Copy)]
pub struct Weights(pub [i32; 3]);

impl Weights {
    pub const COLOUR: Weights = Weights([3, 6, 1]);
    pub const DATA: Weights = Weights([1, 1, 1]);
}

/// The 8 pixels (index x + 4y) of half `half` of a block in orientation `flip`.
fn half_pixels(flip: bool, half: usize) -> [usize; 8] {
    std::array::from_fn(|k| {
        let (x, y) = if flip {
            (k % 4, half * 2 + k / 4)
        } else {
            (half * 2 + k / 4, k % 4)
        };
        x + 4 * y
    })
}

struct HalfFit {
    err: i64,
    table: usize,
    /// Pixel index (0..3) of each of the half's 8 pixels.
    indices: [usize; 8],
}

/// The best table and indices for a half with base colour `base` (8-bit per channel).
fn fit_half(px: &[[u8; 4]; 16], pixels: &[usize; 8], base: [i32; 3], w: Weights) -> HalfFit {
    let mut best = HalfFit {
        err: i64::MAX,
        table: 0,
        indices: [0; 8],
    };
    for t in 0..8 {
        let mut err = 0i64;
        let mut indices = [0; 8];
        for (k, &p) in pixels.iter().enumerate() {
            let mut pixel_best = i64::MAX;
            for i in 0..4 {
                let m = modifier(t, i);
                let e: i64 = (0..3)
                    .map(|c| {
                        let d = (base[c] + m).clamp(0, 255) - i32::from(px[p][c]);
                        i64::from(w.0[c] * d * d)
                    })
                    .sum();
                if e < pixel_best {
                    pixel_best = e;
                    indices[k] = i;
                }
            }
            err += pixel_best;
            if err >= best.err {
                break;
            }
        }
        if err < best.err {
            best = HalfFit {
                err,
                table: t,
                indices,
            };
        }
    }
    best
}

fn mean(px: &[[u8; 4]; 16], pixels: &[usize; 8]) -> [i32; 3] {
    std::array::from_fn(|c| pixels.iter().map(|&p| i32::from(px[p][c])).sum::<i32>())
}

/// `sum / 8` (an 8-pixel sum) quantised to `bits`, rounded to nearest.
fn quantise(sum: i32, bits: u32) -> i32 {
    let max = (1 << bits) - 1;
    ((sum * max + 8 * 255 / 2) / (8 * 255)).clamp(0, max)
}

fn expand(v: i32, bits: u32) -> i32 {
    match bits {
        4 => (v << 4) | v,
        _ => (v << 3) | (v >> 2),
    }
}

struct Candidate {
    err: i64,
    bytes: [u8; 8],
}

/// The best base for one half among its mean and ±1, ±2 grey steps, quantised to `bits`.
fn best_base(
    px: &[[u8; 4]; 16],
    pixels: &[usize; 8],
    q: [i32; 3],
    bits: u32,
    w: Weights,
    allowed: &dyn Fn([i32; 3]) -> bool,
) -> Option<([i32; 3], HalfFit)> {
    let max = (1 << bits) - 1;
    let mut best: Option<([i32; 3], HalfFit)> = None;
    for step in [0, -1, 1, -2, 2] {
        let cand = q.map(|v| (v + step).clamp(0, max));
        if !allowed(cand) {
            continue;
        }
        let base = cand.map(|v| expand(v, bits));
        let fit = fit_half(px, pixels, base, w);
        if best.as_ref().is_none_or(|(_, b)| fit.err < b.err) {
            best = Some((cand, fit));
        }
    }
    best
}

fn pack(
    colour: [u8; 3],
    fits: [&HalfFit; 2],
    diff: bool,
    flip: bool,
    halves: [[usize; 8]; 2],
) -> [u8; 8] {
    let mut out = [0u8; 8];
    out[..3].copy_from_slice(&colour);
    out[3] = (fits[0].table as u8) << 5
        | (fits[1].table as u8) << 2
        | u8::from(diff) << 1
        | u8::from(flip);
    let (mut msb, mut lsb) = (0u16, 0u16);
    for (fit, pixels) in fits.iter().zip(halves) {
        for (k, &p) in pixels.iter().enumerate() {
            let (x, y) = (p % 4, p / 4);
            let bit = x * 4 + y;
            msb |= ((fit.indices[k] >> 1) as u16) << bit;
            lsb |= ((fit.indices[k] & 1) as u16) << bit;
        }
    }
    out[4..6].copy_from_slice(&msb.to_be_bytes());
    out[6..8].copy_from_slice(&lsb.to_be_bytes());
    out
}

/// One 8-byte ETC2 RGB block of 16 pixels (x + 4y).
pub fn encode_rgb_block(px: &[[u8; 4]; 16], w: Weights) -> [u8; 8] {
    let mut best: Option<Candidate> = None;
    let mut keep = |c: Candidate| {
        if best.as_ref().is_none_or(|b| c.err < b.err) {
            best = Some(c);
        }
    };
    for flip in [false, true] {
        let halves = [half_pixels(flip, 0), half_pixels(flip, 1)];
        let sums = halves.map(|h| mean(px, &h));
        // Individual: two 4-bit colours.
        let any = |_: [i32; 3]| true;
        let fits: [Option<_>; 2] = std::array::from_fn(|k| {
            let q = sums[k].map(|s| quantise(s, 4));
            best_base(px, &halves[k], q, 4, w, &any)
        });
        if let [Some((c0, f0)), Some((c1, f1))] = &fits {
            let colour = std::array::from_fn(|c| ((c0[c] << 4) | c1[c]) as u8);
            keep(Candidate {
                err: f0.err + f1.err,
                bytes: pack(colour, [f0, f1], false, flip, halves),
            });
        }
        // Differential: a 5-bit colour and a delta in -4..=3 for the second half.
        let q0 = sums[0].map(|s| quantise(s, 5));
        if let Some((c0, f0)) = best_base(px, &halves[0], q0, 5, w, &any) {
            let q1 = sums[1].map(|s| quantise(s, 5));
            let fits_delta = |c1: [i32; 3]| (0..3).all(|c| (-4..=3).contains(&(c1[c] - c0[c])));
            let q1 = std::array::from_fn(|c| q1[c].clamp(c0[c] - 4, c0[c] + 3));
            if let Some((c1, f1)) = best_base(px, &halves[1], q1, 5, w, &fits_delta) {
                let colour = std::array::from_fn(|c| ((c0[c] << 3) | ((c1[c] - c0[c]) & 7)) as u8);
                keep(Candidate {
                    err: f0.err + f1.err,
                    bytes: pack(colour, [&f0, &f1], true, flip, halves),
                });
            }
        }
    }
    best.map_or([0; 8], |b| b.bytes)
}

/// One 8-byte EAC block of the 16 pixels' alpha (x + 4y).
pub fn encode_alpha_block(px: &[[u8; 4]; 16]) -> [u8; 8] {
    let alpha: [i32; 16] = std::array::from_fn(|i| i32::from(px[i][3]));
    let (lo, hi) = (
        *alpha.iter().min().unwrap_or(&0),
        *alpha.iter().max().unwrap_or(&0),
    );
    // (error, base, multiplier, table, indices)
    let mut best = (i64::MAX, lo, 1, 13, [4usize; 16]);
    if lo == hi {
        // Table 13 has a zero modifier (index 4): exact.
        best = (0, lo, 1, 13, [4; 16]);
    } else {
        let mid = (lo + hi) / 2;
        for base in (mid - 16..=mid + 16).step_by(2).map(|b| b.clamp(0, 255)) {
            for mult in 1..16 {
                for (t, table) in EAC.iter().enumerate() {
                    let mut err = 0i64;
                    let mut idx = [0usize; 16];
                    for (p, &a) in alpha.iter().enumerate() {
                        let mut pe = i64::MAX;
                        for (i, m) in table.iter().enumerate() {
                            let d = i64::from((base + m * mult).clamp(0, 255) - a);
                            if d * d < pe {
                                pe = d * d;
                                idx[p] = i;
                            }
                        }
                        err += pe;
                        if err >= best.0 {
                            break;
                        }
                    }
                    if err < best.0 {
                        best = (err, base, mult, t, idx);
                    }
                }
            }
        }
    }
    let (_, base, mult, table, idx) = best;
    let mut bits: u64 = 0;
    for x in 0..4 {
        for y in 0..4 {
            bits = (bits << 3) | idx[x + 4 * y] as u64;
        }
    }
    let mut out = [0u8; 8];
    out[0] = base as u8;
    out[1] = ((mult as u8) << 4) | table as u8;
    out[2..].copy_from_slice(&bits.to_be_bytes()[2..]);
    out
}

/// The 16 pixels of block (bx, by) of an RGBA8 image (edges repeat).
pub fn block(rgba: &[u8], w: u32, h: u32, bx: u32, by: u32) -> [[u8; 4]; 16] {
    std::array::from_fn(|i| {
        let x = (bx * 4 + (i % 4) as u32).min(w - 1);
        let y = (by * 4 + (i / 4) as u32).min(h - 1);
        let o = ((y * w + x) * 4) as usize;
        [rgba[o], rgba[o + 1], rgba[o + 2], rgba[o + 3]]
    })
}

/// An RGBA8 level as ETC2 RGB8 (`alpha`: RGBA8, the EAC alpha block first in each block).
pub fn encode(rgba: &[u8], w: u32, h: u32, alpha: bool, weights: Weights) -> Vec<u8> {
    let mut out = Vec::new();
    for by in 0..h.div_ceil(4) {
        for bx in 0..w.div_ceil(4) {
            let px = block(rgba, w, h, bx, by);
            if alpha {
                out.extend_from_slice(&encode_alpha_block(&px));
            }
            out.extend_from_slice(&encode_rgb_block(&px, weights));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A test image: gradients, a hard edge and a hashed texture, alpha a binary mask.
    fn image(w: u32, h: u32) -> Vec<u8> {
        let mut out = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let n = (x.wrapping_mul(73_856_093) ^ y.wrapping_mul(19_349_663)) % 23;
                let edge = if x > w / 2 { 180 } else { 40 };
                out.extend_from_slice(&[
                    (x * 255 / w) as u8,
                    (edge + n) as u8,
                    (y * 255 / h) as u8,
                    if (x / 5 + y / 7) % 2 == 0 { 255 } else { 0 },
                ]);
            }
        }
        out
    }

    fn psnr(a: &[u8], b: &[u8], channels: std::ops::Range<usize>) -> f64 {
        let (mut se, mut n) = (0f64, 0f64);
        for (pa, pb) in a.chunks_exact(4).zip(b.chunks_exact(4)) {
            for c in channels.clone() {
                let d = f64::from(pa[c]) - f64::from(pb[c]);
                se += d * d;
                n += 1.0;
            }
        }
        10.0 * (255.0 * 255.0 / (se / n).max(1e-9)).log10()
    }

    /// The blocks decode (with an independent decoder) to the image about as closely as BC1
    /// (texpresso's cluster fit, the desktop's encoder) does at the same 4 bits a texel; alpha
    /// exactly for a binary mask.
    #[test]
    fn blocks_decode_close_to_the_image() {
        let (w, h) = (64, 32);
        let img = image(w, h);
        for alpha in [false, true] {
            let blocks = encode(&img, w, h, alpha, Weights::COLOUR);
            let mut texels = vec![0u32; (w * h) as usize];
            let decode = match alpha {
                true => texture2ddecoder::decode_etc2_rgba8,
                false => texture2ddecoder::decode_etc2_rgb,
            };
            decode(&blocks, w as usize, h as usize, &mut texels).unwrap();
            let rgba: Vec<u8> = texels
                .iter()
                .flat_map(|t| {
                    let [b, g, r, a] = t.to_le_bytes();
                    [r, g, b, a]
                })
                .collect();
            let p = psnr(&img, &rgba, 0..3);
            let f = texpresso::Format::Bc1;
            let mut bc1 = vec![0; f.compressed_size(w as usize, h as usize)];
            f.compress(&img, w as usize, h as usize, Default::default(), &mut bc1);
            let mut back = vec![0; img.len()];
            f.decompress(&bc1, w as usize, h as usize, &mut back);
            let bc1 = psnr(&img, &back, 0..3);
            assert!(
                p > 25.0 && p > bc1 - 1.5,
                "colour PSNR {p:.1} dB (BC1 {bc1:.1})"
            );
            if alpha {
                assert_eq!(
                    psnr(&img, &rgba, 3..4),
                    10.0 * (255f64 * 255.0 / 1e-9).log10()
                );
            }
        }
    }

    #[test]
    fn a_flat_block_is_exact() {
        let px = [[200, 100, 50, 255]; 16];
        let bytes = encode_rgb_block(&px, Weights::COLOUR);
        let mut out = [0u32; 16];
        texture2ddecoder::decode_etc2_rgb_block(&bytes, &mut out);
        for t in out {
            let [b, g, r, _] = t.to_le_bytes();
            assert!(r.abs_diff(200) <= 4 && g.abs_diff(100) <= 4 && b.abs_diff(50) <= 4);
        }
    }
}
