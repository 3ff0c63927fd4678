//! `dermis profile`: the radial exitance profile M(r) of a flat medium under a point light,
//! rendered through the real renderer (`dermis_measure::scenes`) for one or more shading models.
//!
//! The scene is the reference's `point_light` scene: a flat semi-infinite medium lit by an
//! isotropic point light of unit power at height H; the output is M(r) averaged over annuli,
//! in mm⁻² per unit source power (the Monte Carlo's units, `tools/reference/*.json`).

use dermis_engine::render::Gpu;
use dermis_engine::shading::{Material, ShadingModel};
use dermis_measure::ground_truth::{self, Scene};
use dermis_measure::scenes::SceneRenderer;
use serde_json::{json, Map, Value};

use crate::cmd::args::MAX_RADIUS_MM;
use crate::cmd::args::{parse_edge_mm, parse_light_height_mm, parse_material, parse_model};
use crate::cmd::material_args::MaterialArgs;
use crate::cmd::progress::Progress;
/// Annuli of the default edges.
const DEFAULT_BINS: usize = 24;

#[derive(clap::Args, Debug)]
pub struct ProfileArgs {
    /// Shading model(s), comma-separated (default: every model).
    #[arg(long, value_delimiter = ',', value_parser = parse_model, conflicts_with = "all")]
    pub shading: Vec<ShadingModel>,
    /// Every shading model (the default when --shading is not given).
    #[arg(long)]
    pub all: bool,
    /// The medium (default skin1): a name, coefficients, albedo and mean free path, or a
    /// file's skin material.
    #[command(flatten)]
    pub medium: MaterialArgs,
    /// Height of the point light above the surface (mm), 0.01..=1000.
    #[arg(long, value_parser = parse_light_height_mm, allow_hyphen_values = true)]
    pub light_height_mm: f64,
    /// Annulus edges (mm), comma-separated, ascending, ≥ 0 (default: 24 annuli out to 4H + 20).
    #[arg(long, value_delimiter = ',', value_parser = parse_edge_mm, allow_hyphen_values = true)]
    pub edges_mm: Option<Vec<f64>>,
    /// Print JSON: {"edges_mm": [...], "models": {"<name>": {"exitance": [[r, g, b], ...]}}}.
    #[arg(long)]
    pub json: bool,
}

/// The checked request.
#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    pub models: Vec<ShadingModel>,
    pub material: Material,
    pub h_mm: f64,
    pub edges: Vec<f64>,
}

/// Checks the arguments the value parsers cannot (the edges as a list; no GPU work); the
/// message names what is wrong.
pub fn validate(args: &ProfileArgs) -> Result<Request, String> {
    let h = args.light_height_mm;
    let material = args.medium.resolve("skin1", parse_material)?;
    let edges = match &args.edges_mm {
        Some(e) => {
            check_edges(e)?;
            e.clone()
        }
        None => default_edges(h),
    };
    let models = if args.shading.is_empty() {
        ShadingModel::ALL.to_vec()
    } else {
        let mut m: Vec<ShadingModel> = Vec::new();
        for &x in &args.shading {
            if !m.contains(&x) {
                m.push(x);
            }
        }
        m
    };
    Ok(Request {
        models,
        material,
        h_mm: h,
        edges,
    })
}

fn check_edges(e: &[f64]) -> Result<(), String> {
    let list = || {
        e.iter()
            .map(|x| x.to_string())
            .collect::<Vec<_>>()
            .join(",")
    };
    if e.len() < 2 {
        return Err(format!(
            "--edges-mm `{}`: needs at least 2 edges (one annulus)",
            list()
        ));
    }
    if e.iter().any(|x| !x.is_finite()) {
        return Err(format!(
            "--edges-mm `{}`: every edge must be finite",
            list()
        ));
    }
    if e[0] < 0.0 {
        return Err(format!("--edges-mm `{}`: radii must be ≥ 0", list()));
    }
    if e.windows(2).any(|w| w[0] >= w[1]) {
        return Err(format!(
            "--edges-mm `{}`: edges must be strictly increasing",
            list()
        ));
    }
    if e[e.len() - 1] > MAX_RADIUS_MM {
        return Err(format!(
            "--edges-mm `{}`: the last edge exceeds {MAX_RADIUS_MM} mm",
            list()
        ));
    }
    Ok(())
}

/// [`DEFAULT_BINS`] annuli from 0 to 4H + 20 mm, sinh-spaced: the first H/4 wide (but at least
/// two of the probe's pixels, so every annulus holds pixel centres), widening outward.
pub fn default_edges(h_mm: f64) -> Vec<f64> {
    let r_max = 4.0 * h_mm + 20.0;
    // The probe's view reaches 1.1 r_max + 2 mm from the centre over its pixels.
    let pixel = 2.0 * (1.1 * r_max + 2.0) / dermis_measure::scenes::PIXELS as f64;
    let first = (0.25 * h_mm).max(2.0 * pixel);
    ground_truth::sinh_spaced(r_max, DEFAULT_BINS, first)
        .into_iter()
        .map(ground_truth::round_edge)
        .collect()
}

/// A model's profile: the exitance per annulus.
pub type Profile = (ShadingModel, Vec<[f64; 3]>);

/// Renders the profile of every requested model, a step of `progress` each.
pub fn render(gpu: &Gpu, req: &Request, progress: &mut Progress) -> Result<Vec<Profile>, String> {
    let mut probe = SceneRenderer::new(gpu);
    let scene = Scene::PointLight { h_mm: req.h_mm };
    req.models
        .iter()
        .enumerate()
        .map(|(i, &m)| {
            // The first render sets the material up, measuring its tables when it has none.
            if i == 0 {
                progress.begin(&format!("{} (first: the material's tables)", m.name()));
            } else {
                progress.begin(m.name());
            }
            let profile = probe
                .render(gpu, m, &req.material, &scene, &req.edges)
                .map(|e| (m, e))
                .map_err(|e| format!("{}: {e}", m.name()));
            progress.step(m.name());
            profile
        })
        .collect()
}

/// The JSON report.
pub fn to_json(edges: &[f64], profiles: &[Profile]) -> Value {
    let mut models = Map::new();
    for (m, e) in profiles {
        models.insert(m.name().into(), json!({ "exitance": e }));
    }
    json!({ "edges_mm": edges, "models": models })
}

/// The human table: one block per model, a row per annulus.
pub fn table(req: &Request, profiles: &[Profile]) -> String {
    let m = &req.material;
    let mut s = format!(
        "flat medium, {} (η = {}, g = {}), point light of unit power at h = {} mm\n\
         M(r) averaged over each annulus, mm⁻² per unit source power\n",
        m.name, m.eta, m.g, req.h_mm
    );
    for (model, e) in profiles {
        s += &format!(
            "\n{}\n  {:>17}  {:>11} {:>11} {:>11}\n",
            model.name(),
            "r [mm]",
            "R",
            "G",
            "B"
        );
        for (w, v) in req.edges.windows(2).zip(e) {
            s += &format!(
                "  {:>8.3}–{:<8.3}  {:>11.4e} {:>11.4e} {:>11.4e}\n",
                w[0], w[1], v[0], v[1], v[2]
            );
        }
    }
    s
}

pub fn run(args: ProfileArgs) -> Result<(), String> {
    let req = validate(&args)?;
    // Steps: the GPU, then one per model.
    let mut progress = Progress::new("profile", 1 + req.models.len() as u64);
    progress.begin("GPU device");
    let gpu = Gpu::headless().map_err(|e| e.to_string())?;
    progress.step("GPU device");
    let profiles = render(&gpu, &req, &mut progress)?;
    progress.finish();
    if args.json {
        println!(
            "{}",
            serde_json::to_string(&to_json(&req.edges, &profiles)).map_err(|e| e.to_string())?
        );
    } else {
        print!("{}", table(&req, &profiles));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_edges_are_valid_and_reach_4h_plus_20() {
        for h in [0.01, 0.5, 2.0, 5.0, 20.0, 1000.0] {
            let e = default_edges(h);
            assert_eq!(e.len(), DEFAULT_BINS + 1);
            check_edges(&e).unwrap();
            assert!(Scene::PointLight { h_mm: h }.validate(&e).is_ok());
            let last = e[DEFAULT_BINS];
            assert!(
                (last - (4.0 * h + 20.0)).abs() <= 0.01 * last,
                "{h}: {last}"
            );
        }
        // h = 5: the first annulus is h/4 wide.
        let e = default_edges(5.0);
        assert!((e[1] - 1.25).abs() < 0.01, "{e:?}");
    }

    #[test]
    fn bad_edges() {
        assert!(check_edges(&[1.0]).is_err());
        assert!(check_edges(&[0.0, f64::NAN]).is_err());
        assert!(check_edges(&[-1.0, 1.0]).is_err());
        assert!(check_edges(&[0.0, 2.0, 1.0]).is_err());
        assert!(check_edges(&[0.0, 1.0, 1.0]).is_err());
        assert!(check_edges(&[0.0, 1.0, 2.0]).is_ok());
    }
}
