//! `bench face`'s diagnosis of the face scores: for every model and light the signed integrated
//! bias per channel, ln(Σ model / Σ truth) over the scored blocks; for the spatial models (the
//! affordable tier and the screen-space ones: [`mapped`]) a per-block image of
//! ln(model/truth) over the blocks where the truth's relative SE ≤ `score::WIDE_REL_SE`
//! (`face-<light>-<model>-lnerr.png`: red too bright, blue too dark, ±0.5 full
//! scale; grey not scored) and the signed mean error per region of the head (eye sockets, nose,
//! lips, the ear, the neck, the rest).

use std::fmt::Write as _;
use std::path::Path;

use dermis_engine::render::pfm::FloatImage;
use dermis_engine::shading::ShadingModel;
use dermis_measure::face::regions::{ln_error_png, region_errors, RegionError};
use dermis_measure::face::score::{block_means, Reference, BLOCK};
use serde_json::{json, Value};

/// Whether `m`'s errors are mapped and split by region: the spatial models, those whose
/// descriptor carries a diffusion kernel or a LUT.
pub fn mapped(m: ShadingModel) -> bool {
    let d = m.descriptor();
    d.kernel.is_some() || d.lut.is_some()
}
/// Full scale of the ln-error images.
const RANGE: f64 = 0.5;

/// One model under one light: its signed integrated ln ratio per channel and, when mapped, its
/// regions.
type Row = (ShadingModel, String, [f64; 3], Option<Vec<RegionError>>);

#[derive(Default)]
pub struct Diagnosis {
    rows: Vec<Row>,
    pub json: Vec<Value>,
}

impl Diagnosis {
    /// Adds `image` (model `shading` under `light`) against `reference`.
    pub fn add(
        &mut self,
        out: &Path,
        shading: ShadingModel,
        light: &str,
        reference: &Reference,
        image: &FloatImage,
        regions: &[Option<usize>],
    ) -> Result<(), String> {
        let blocks = block_means(image, BLOCK);
        let bias: [f64; 3] = std::array::from_fn(|c| {
            let (mut m, mut t) = (0f64, 0f64);
            for ((p, r), k) in blocks
                .pixels
                .iter()
                .zip(&reference.mean.pixels)
                .zip(&reference.mask)
            {
                if k[c] {
                    m += p[c].max(0.0) as f64;
                    t += r[c] as f64;
                }
            }
            if t > 0.0 {
                (m.max(1e-30) / t).ln()
            } else {
                f64::NAN
            }
        });
        let mapped = mapped(shading).then(|| region_errors(reference, image, regions, BLOCK));
        if mapped.is_some() {
            let (w, h, rgb) = ln_error_png(reference, image, BLOCK, None, RANGE, 8);
            let path = out.join(format!("face-{light}-{}-lnerr.png", shading.name()));
            image::save_buffer(&path, &rgb, w, h, image::ExtendedColorType::Rgb8)
                .map_err(|e| format!("{}: {e}", path.display()))?;
        }
        self.json.push(json!({
            "model": shading.name(), "light": light, "integrated_signed_ln_rgb": bias,
            "regions": mapped.as_ref().map(|r| r.iter().map(|(name, n, e)| json!({
                "region": name, "block_channels": n, "mean_signed_ln_rgb": e,
            })).collect::<Vec<_>>()),
        }));
        self.rows.push((shading, light.to_string(), bias, mapped));
        Ok(())
    }

    /// The diagnosis as Markdown: the bias table, then each mapped model's regions per light.
    pub fn markdown(&self) -> String {
        let mut md = String::from(
            "Signed integrated bias ln(Σ model / Σ truth) over the scored blocks, R / G / B \
             (positive: too bright):\n\n| model | light | R | G | B |\n|---|---|---|---|---|\n",
        );
        for (m, light, b, _) in &self.rows {
            let _ = writeln!(
                md,
                "| {m} | {light} | {:+.3} | {:+.3} | {:+.3} |",
                b[0], b[1], b[2]
            );
        }
        md += "\nMean signed ln(model/truth) per region (scored block channels), R / G / B:\n\n\
               | model | light | region | R | G | B |\n|---|---|---|---|---|---|\n";
        for (m, light, _, regions) in &self.rows {
            for (name, n, e) in regions.iter().flatten() {
                let cell =
                    |c: usize| e[c].map_or("–".to_string(), |v| format!("{v:+.3} ({})", n[c]));
                let _ = writeln!(
                    md,
                    "| {m} | {light} | {name} | {} | {} | {} |",
                    cell(0),
                    cell(1),
                    cell(2)
                );
            }
        }
        md
    }
}
