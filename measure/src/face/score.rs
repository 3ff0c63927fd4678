//! The image-space score of a rendered face against the face truth (`truth.rs`).
//!
//! Both the truth and the model are averaged over blocks of [`BLOCK`]² pixels, and only blocks
//! the head covers entirely are scored (silhouettes, where a box filter and MSAA differ, are
//! left out). The truth carries its standard error per pixel (from its photon batches); a
//! block's is the root sum of its pixels' squares over [`BLOCK`]⁴ (pixels are independent but
//! for the rare photon that leaves twice). A block's channel is scored where the truth's
//! relative standard error is at most [`MAX_REL_SE`]: a model equal to the truth then scores at
//! most about 0.8 × 0.02 by the truth's noise. The score is the mean over those of
//! |ln(model/truth)|, each capped at [`CAP`] (a black image scores the cap, a doubled one
//! ln 2).

use dermis_engine::render::pfm::FloatImage;

/// Pixels per side of a scored block.
pub const BLOCK: u32 = 4;
/// Largest relative standard error of the truth at which a block's channel is scored.
pub const MAX_REL_SE: f32 = 0.02;
/// The looser bar of the second score and of the diagnosis: it reaches the dimmer blocks (the
/// terminator, the eye sockets, the back light's rim) at a noise floor of about 0.8 × 0.03.
pub const WIDE_REL_SE: f32 = 0.05;
/// The most one block's channel can add (a zero or negative model value).
pub const CAP: f64 = 10.0;

/// A cached reference ready for scoring.
#[derive(Clone, Debug)]
pub struct Reference {
    /// The truth at full resolution.
    pub full: FloatImage,
    /// Its block means.
    pub mean: FloatImage,
    /// Standard error of `mean` per block and channel.
    pub noise: Vec<[f32; 3]>,
    /// Scored block channels.
    pub mask: Vec<[bool; 3]>,
    /// Blocks the head covers wholly.
    covered: Vec<bool>,
    block: u32,
}

/// One model's score on one scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Score {
    /// Mean |ln(model/reference)| over the scored block channels.
    pub mean_abs_ln: f64,
    /// |ln(Σ model / Σ reference)| over the same block channels.
    pub integrated: f64,
    /// Scored block channels.
    pub count: usize,
}

/// Means over `block`² pixels (a partial last row or column of blocks is dropped).
pub fn block_means(img: &FloatImage, block: u32) -> FloatImage {
    let (bw, bh) = (img.width / block, img.height / block);
    let mut out = vec![[0f32; 3]; (bw * bh) as usize];
    for by in 0..bh {
        for bx in 0..bw {
            let mut sum = [0f64; 3];
            for y in by * block..(by + 1) * block {
                for x in bx * block..(bx + 1) * block {
                    let p = img.pixels[(y * img.width + x) as usize];
                    for c in 0..3 {
                        sum[c] += p[c] as f64;
                    }
                }
            }
            let n = (block * block) as f64;
            out[(by * bw + bx) as usize] = sum.map(|s| (s / n) as f32);
        }
    }
    FloatImage {
        width: bw,
        height: bh,
        pixels: out,
    }
}

impl Reference {
    /// From the truth's radiance, its standard error per pixel and the head's coverage (alpha,
    /// 0..1), in blocks of `block`² pixels.
    pub fn from_truth(
        mean: &FloatImage,
        std_err: &FloatImage,
        alpha: &[f32],
        block: u32,
    ) -> Result<Self, String> {
        let (w, h) = (mean.width, mean.height);
        if (std_err.width, std_err.height) != (w, h) || alpha.len() != (w * h) as usize {
            return Err("the truth, its standard error and the coverage differ in size".into());
        }
        if block == 0 || w < block || h < block {
            return Err(format!("block {block} does not fit a {w}x{h} image"));
        }
        let cov = FloatImage::new(w, h, alpha.iter().map(|&v| [v; 3]).collect())?;
        let var = FloatImage::new(
            w,
            h,
            std_err.pixels.iter().map(|p| p.map(|s| s * s)).collect(),
        )?;
        let (bm, bv, bc) = (
            block_means(mean, block),
            block_means(&var, block),
            block_means(&cov, block),
        );
        let n = (block * block) as f32;
        let noise: Vec<[f32; 3]> = bv
            .pixels
            .iter()
            .map(|v| v.map(|v| (v / n).sqrt()))
            .collect();
        let covered = bc.pixels.iter().map(|c| c[0] >= 0.999).collect();
        Ok(Self {
            full: mean.clone(),
            mean: bm,
            noise,
            mask: Vec::new(),
            covered,
            block,
        }
        .with_max_rel_se(MAX_REL_SE))
    }

    /// The same truth scored where its relative standard error is at most `limit`.
    pub fn with_max_rel_se(mut self, limit: f32) -> Self {
        self.mask = self
            .mean
            .pixels
            .iter()
            .zip(&self.noise)
            .zip(&self.covered)
            .map(|((m, s), c)| std::array::from_fn(|k| *c && m[k] > 0.0 && s[k] <= limit * m[k]))
            .collect();
        self
    }

    /// Relative standard errors of the scored block channels, ascending.
    pub fn relative_errors(&self) -> Vec<f64> {
        let mut v: Vec<f64> = self
            .mean
            .pixels
            .iter()
            .zip(&self.noise)
            .zip(&self.mask)
            .flat_map(|((m, s), k)| {
                (0..3)
                    .filter(|&c| k[c])
                    .map(|c| (s[c] / m[c]) as f64)
                    .collect::<Vec<_>>()
            })
            .collect();
        v.sort_by(f64::total_cmp);
        v
    }

    /// Scored block channels.
    pub fn scored(&self) -> usize {
        self.mask.iter().flatten().filter(|k| **k).count()
    }

    /// Mean relative standard error over the scored block channels.
    pub fn relative_noise(&self) -> f64 {
        let (mut sum, mut n) = (0.0, 0usize);
        for ((m, s), k) in self.mean.pixels.iter().zip(&self.noise).zip(&self.mask) {
            for c in 0..3 {
                if k[c] {
                    sum += (s[c] / m[c]) as f64;
                    n += 1;
                }
            }
        }
        sum / n.max(1) as f64
    }

    /// Scores `model` (linear radiance, the reference's size and units).
    pub fn score(&self, model: &FloatImage) -> Result<Score, String> {
        if (model.width, model.height) != (self.full.width, self.full.height) {
            return Err(format!(
                "model image {}x{} is not the reference's {}x{}",
                model.width, model.height, self.full.width, self.full.height
            ));
        }
        let blocks = block_means(model, self.block);
        let (mut sum, mut n) = (0.0f64, 0usize);
        let (mut total_m, mut total_r) = (0.0f64, 0.0f64);
        for ((p, r), k) in blocks.pixels.iter().zip(&self.mean.pixels).zip(&self.mask) {
            for c in 0..3 {
                if !k[c] {
                    continue;
                }
                let (m, r) = (p[c] as f64, r[c] as f64);
                let e = if m > 0.0 && m.is_finite() {
                    (m / r).ln().abs().min(CAP)
                } else {
                    CAP
                };
                sum += e;
                n += 1;
                total_m += if m.is_finite() { m.max(0.0) } else { 0.0 };
                total_r += r;
            }
        }
        if n == 0 {
            return Err("the reference has no block above its noise".into());
        }
        let integrated = if total_m > 0.0 {
            (total_m / total_r).ln().abs().min(CAP)
        } else {
            CAP
        };
        Ok(Score {
            mean_abs_ln: sum / n as f64,
            integrated,
            count: n,
        })
    }
}

/// The tone mapping the pair is compared with perceptually: exposure, Narkowicz's ACES fit
/// (the game's `tonemap`), sRGB encode; 8-bit RGB, rows top to bottom.
pub fn tone_map(image: &FloatImage, exposure: f32) -> Vec<u8> {
    let aces = |x: f32| {
        let c = (x * exposure).max(0.0);
        ((c * (2.51 * c + 0.03)) / (c * (2.43 * c + 0.59) + 0.14)).clamp(0.0, 1.0)
    };
    let srgb = |c: f32| {
        if c <= 0.0031308 {
            c * 12.92
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        }
    };
    image
        .pixels
        .iter()
        .flat_map(|p| p.map(|c| (srgb(aces(c)) * 255.0 + 0.5) as u8))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A smooth reference, a gradient, with a 1 % relative standard error per pixel.
    fn reference() -> (Reference, FloatImage) {
        let (w, h) = (16u32, 12u32);
        let mean: Vec<[f32; 3]> = (0..w * h)
            .map(|i| {
                let v = 0.1 + (i % w) as f32 * 0.01;
                [v, 0.5 * v, 0.2 * v]
            })
            .collect();
        let se = mean.iter().map(|p| p.map(|c| 0.01 * c)).collect();
        let a = FloatImage::new(w, h, mean).unwrap();
        let s = FloatImage::new(w, h, se).unwrap();
        let alpha = vec![1.0; (w * h) as usize];
        let r = Reference::from_truth(&a, &s, &alpha, 1).unwrap();
        (r, a)
    }

    #[test]
    fn black_scores_the_cap_doubled_scores_ln2_itself_zero() {
        let (r, mean) = reference();
        assert!(
            (r.relative_noise() - 0.01).abs() < 1e-4,
            "{}",
            r.relative_noise()
        );
        assert_eq!(r.scored(), 3 * 16 * 12);
        let own = r.score(&mean).unwrap();
        assert!(own.mean_abs_ln < 1e-9 && own.count > 0);
        let doubled = FloatImage {
            pixels: mean.pixels.iter().map(|p| p.map(|c| 2.0 * c)).collect(),
            ..mean.clone()
        };
        let s = r.score(&doubled).unwrap();
        assert!((s.mean_abs_ln - 2f64.ln()).abs() < 1e-6, "{s:?}");
        assert!((s.integrated - 2f64.ln()).abs() < 1e-6);
        let black = FloatImage {
            pixels: vec![[0.0; 3]; mean.pixels.len()],
            ..mean.clone()
        };
        let s = r.score(&black).unwrap();
        assert_eq!((s.mean_abs_ln, s.integrated), (CAP, CAP));
    }

    #[test]
    fn partly_covered_blocks_and_noisy_blocks_are_left_out() {
        let (w, h) = (8u32, 8u32);
        // Red: 1 ± 0.02 per pixel, 0.01 per 2×2 block: scored; green: 1 ± 0.06 per pixel,
        // 0.03 per block: too noisy; blue: 0.
        let a = FloatImage::new(w, h, vec![[1.0, 1.0, 0.0]; 64]).unwrap();
        let s = FloatImage::new(w, h, vec![[0.02, 0.06, 0.01]; 64]).unwrap();
        // Covered on the left 3 columns: 2×2 blocks, only the first block column is whole.
        let alpha: Vec<f32> = (0..64).map(|i| if i % 8 < 3 { 1.0 } else { 0.0 }).collect();
        let r = Reference::from_truth(&a, &s, &alpha, 2).unwrap();
        assert_eq!((r.mean.width, r.mean.height), (4, 4));
        for (i, k) in r.mask.iter().enumerate() {
            assert!(!k[1] && !k[2]);
            assert_eq!(k[0], i % 4 == 0, "{i}");
            assert!((r.noise[i][0] - 0.01).abs() < 1e-6);
        }
        // A model scored against it: black is the cap, the reference itself 0.
        let black = FloatImage::new(w, h, vec![[0.0; 3]; 64]).unwrap();
        assert_eq!(r.score(&black).unwrap().mean_abs_ln, CAP);
        assert_eq!(r.score(&r.full).unwrap().mean_abs_ln, 0.0);
        assert!(r.score(&r.mean).is_err());
    }
}
