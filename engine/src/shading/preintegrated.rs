//! Mobile tier `preintegrated` (WGSL: `shaders/preintegrated.wgsl`): pre-integrated skin
//! (Penner & Borshukov, GPU Pro 2, 2011), the sphere response measured rather than integrated.
//!
//! The LUT holds, per channel, log2 of the exitance of a homogeneous sphere of radius ρ under a
//! directional light of unit irradiance, at the points whose normal makes cos θ = n·l with the
//! light: exactly what pre-integration assumes the local geometry is. Penner integrates the
//! flat medium's diffusion profile over the sphere's surface (by chord distance); measured
//! against the path-traced spheres that scores 0.35–0.53 mean |ln| (the dark side 2–5× too
//! bright for R ≥ 20 mm, 2–4× too dark for R = 5 mm: a ball confines the light a half-space
//! lets go, and light near the terminator escapes before it gets far). The rows here are the
//! project's Monte Carlo sphere walker itself (`dermis_measure::mc::sphere_with`), the
//! transport of the reference scenes, baked offline because it takes minutes: for the presets
//! per material ([`SHIPPED`]), for every other material over a nondimensional grid
//! ([`super::sphere_grid`], `assets/sss/optics.lut`) the rows are interpolated from.
//! Axes: u = (n·l + 1)/2, v = R0/(R0 + ρ) (v = 0: flat).
//!
//! A point light's irradiance is blurred on flat ground by lifting the light by s, the height
//! of a Poisson kernel s/(2π(s² + r²)^{3/2}) standing in for the material's ([`lift`]): Poisson
//! kernels compose by adding heights, and a point light at height h lights the plane with the
//! Poisson kernel of height h, so the blurred irradiance is that of the light at h + s. Each
//! channel reads the rows at its own lifted cosine (the entry Fresnel factor and the oblique
//! response at the incidence its lifted light has). The lift fades with the distance from the
//! light's foot ([`LIFT_REACH`]): the material's kernel has no Poisson tail, and far out the
//! irradiance is the light's own.

use std::sync::{Arc, Mutex, OnceLock};

use super::bake::{self, Bake, Budget};
use super::subsurface::{self, Params, LUT_R0_MM};
use super::uniform::{Const, SharedConst};
use super::{Descriptor, Effects, Material};

/// LUT size: n·l × curvature …
pub const LUT_U: usize = 64;
pub const LUT_V: usize = 32;
/// … plus two rows that turn per-pixel maths into fetches: row [`LUT_V`] holds the exit factor
/// F_t(η, u)/(πC) (r) and the entry factor F_t(η, u)/F_t(η, 1) (g) over u = cos θ ∈ [0, 1];
/// row `LUT_V + 1` the diffuse transmittance T of a backlit slab (rgb) over
/// u = log2(t/0.25 mm)/[`SLAB_SPAN`] (0.25–128 mm), dense enough for linear filtering.
pub const LUT_ROWS: usize = LUT_V + 2;
/// The texture the renderer uploads has one more row, made at load from the material's
/// kernel rather than shipped: the edge-spread function (log2, rgb) over the signed distance
/// to a shadow edge ([`edge_spread`](super::edge_spread)), read with the penumbra map.
pub const PENUMBRA_ROW: usize = LUT_ROWS;
pub const TEXTURE_ROWS: usize = LUT_ROWS + 1;
/// Doublings of thickness the slab row spans from 0.25 mm.
pub const SLAB_SPAN: f64 = 9.0;

/// Per-channel log2 of the exitance per unit irradiance, row-major over v then u, RGBA (A = 1),
/// then the two factor rows (linear; see [`LUT_ROWS`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Lut {
    pub texels: Vec<[f32; 4]>,
}

impl Lut {
    /// The texture's size in texels (width, height): the sphere rows, the factor rows and
    /// the penumbra row.
    pub const SIZE: (u32, u32) = (LUT_U as u32, TEXTURE_ROWS as u32);

    /// The value at texel (i, j) for channel c.
    pub fn at(&self, i: usize, j: usize, c: usize) -> f32 {
        self.texels[j * LUT_U + i][c]
    }
}

/// Curvature radius (mm) of LUT row j (texel centre).
pub fn row_radius_mm(j: usize) -> f64 {
    let v = (j as f64 + 0.5) / LUT_V as f64;
    LUT_R0_MM * (1.0 - v) / v
}

/// The shipped LUTs: baked offline at [`bake::DEFAULT_BUDGET`] by `dermis lut --out
/// assets/sss` for the presets at their own η and at the reference scenes' η = 1.4 (the
/// sphere rows take 0.5–2 minutes of Monte Carlo per material, too long for a load). Each
/// file records the material and budget it was baked for; one that does not match is ignored.
pub const SHIPPED: &[&[u8]] = &[
    include_bytes!("../../../assets/sss/skin1-eta1.3.lut"),
    include_bytes!("../../../assets/sss/skin1-eta1.4.lut"),
    include_bytes!("../../../assets/sss/white-coat-eta1.0936.lut"),
    include_bytes!("../../../assets/sss/white-coat-eta1.4.lut"),
];

/// File name of the shipped LUT of `m`.
pub fn file_name(m: &Material) -> String {
    format!("{}-eta{}.lut", m.name, m.eta)
}

const MAGIC: &[u8; 8] = b"DERMLUT2";

/// What a LUT was baked from: [`bake::baked_from`] and the LUT's size.
fn header(m: &Material, budget: &Budget) -> Vec<f64> {
    let mut h = bake::baked_from(m, budget);
    h.extend([LUT_U as f64, LUT_ROWS as f64]);
    h
}

impl Lut {
    /// Little-endian: magic, the [`header`] (f64), the texels (f32 RGBA).
    pub fn to_bytes(&self, m: &Material, budget: &Budget) -> Vec<u8> {
        let mut out = MAGIC.to_vec();
        for v in header(m, budget) {
            out.extend(v.to_le_bytes());
        }
        for t in &self.texels {
            for v in t {
                out.extend(v.to_le_bytes());
            }
        }
        out
    }

    /// The LUT in `bytes` if it was baked for `m` at `budget`.
    pub fn from_bytes(bytes: &[u8], m: &Material, budget: &Budget) -> Option<Lut> {
        let h = header(m, budget);
        let body = bytes.strip_prefix(MAGIC.as_slice())?;
        let (head, texels) = body.split_at_checked(8 * h.len())?;
        let matches = head
            .chunks_exact(8)
            .zip(&h)
            .all(|(b, v)| b == v.to_le_bytes());
        if !matches || texels.len() != 16 * LUT_U * LUT_ROWS {
            return None;
        }
        let f = |b: &[u8]| f32::from_le_bytes(b.try_into().unwrap_or([0; 4]));
        let texels = texels
            .chunks_exact(16)
            .map(|t| std::array::from_fn(|k| f(&t[4 * k..4 * k + 4])))
            .collect();
        Some(Lut { texels })
    }
}

type Cache = Mutex<Vec<(Material, Arc<Lut>)>>;
static CACHE: Cache = Mutex::new(Vec::new());

/// Bakes one material's LUT directly by the Monte Carlo (installed by the measurement crate,
/// `dermis_measure::bake::install`, only where a command or a test asks for a direct bake;
/// the sphere rows take minutes).
pub type LutBaker = fn(&Material, &Bake) -> Lut;
static BAKER: OnceLock<LutBaker> = OnceLock::new();

/// Installs the direct LUT baker (the first installation wins).
pub fn install_baker(baker: LutBaker) {
    let _ = BAKER.set(baker);
}

/// The shipped LUT baked for `m`, if any.
pub fn shipped(m: &Material) -> Option<Lut> {
    SHIPPED
        .iter()
        .find_map(|b| Lut::from_bytes(b, m, &bake::DEFAULT_BUDGET))
}

/// The LUT of `m` from its sphere rows `rows` (log2 M per texel and channel, the first
/// [`LUT_V`] rows) and tables `b`: the rows, then the two factor rows ([`LUT_ROWS`]).
pub fn lut_from(rows: &[[f64; 3]], b: &Bake, m: &Material) -> Lut {
    let mut texels = vec![[0.0f32; 4]; LUT_U * LUT_ROWS];
    let p = params_from(b, m).pack();
    let exit_norm = 1.0 / (std::f64::consts::PI * subsurface::exit_normalisation(m.eta));
    let entry = super::fresnel::transmittance_shader(m.eta, 1.0).max(1e-12);
    for i in 0..LUT_U {
        let u = i as f64 / (LUT_U - 1) as f64;
        let ft = super::fresnel::transmittance_shader(m.eta, u);
        texels[LUT_V * LUT_U + i] = [(ft * exit_norm) as f32, (ft / entry) as f32, 0.0, 1.0];
        let t = bake::SLAB_FIRST_MM * 2f64.powf(u * SLAB_SPAN);
        let slab = subsurface::slab_packed(&p, t);
        texels[(LUT_V + 1) * LUT_U + i] = [slab.x as f32, slab.y as f32, slab.z as f32, 1.0];
    }
    for (t, v) in texels.iter_mut().zip(rows.iter().take(LUT_V * LUT_U)) {
        *t = [v[0] as f32, v[1] as f32, v[2] as f32, 1.0];
    }
    Lut { texels }
}

/// `m`'s LUT (without the penumbra row) from the shipped grids: the sphere rows interpolated
/// by [`super::sphere_grid`] (dark rows if a grid is unreadable, which a test rules out), the
/// factor rows from `m`'s tables.
pub fn from_grid(m: &Material) -> Lut {
    let b = bake::for_material(m);
    let rows = match (super::sphere_grid::shipped(), super::grid::shipped()) {
        (Some(spheres), Some(tables)) => spheres.rows(m, tables),
        _ => vec![[-40.0; 3]; LUT_V * LUT_U],
    };
    lut_from(&rows, &b, m)
}

/// The LUT texture for `m`, cached for the process: the shipped LUT baked for exactly these
/// optics, else the installed direct [`LutBaker`]'s (only where a command asked for a direct
/// bake; logged: the sphere rows take minutes), else the rows interpolated from the shipped
/// grid ([`from_grid`]: milliseconds, no Monte Carlo); then the penumbra row
/// ([`PENUMBRA_ROW`]), made from `m`'s kernel.
pub fn lut(m: &Material) -> Arc<Lut> {
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, l)) = cache.iter().find(|(k, _)| k == m) {
        return l.clone();
    }
    let mut texture = match (shipped(m), BAKER.get()) {
        (Some(l), _) => l,
        (None, Some(baker)) => {
            log::info!(
                "preintegrated: baking the sphere LUT of {} (η {}) directly (Monte Carlo)",
                m.name,
                m.eta
            );
            baker(m, &bake::for_material(m))
        }
        (None, None) => from_grid(m),
    };
    texture
        .texels
        .extend(super::edge_spread::lut_row(&bake::for_material(m), LUT_U));
    let l = Arc::new(texture);
    cache.push((m.clone(), l.clone()));
    l
}

/// Per channel, the height s (mm) the light is lifted by: half the kernel's median radius
/// (the Poisson height whose blur of a light 1–10 mm up matches the kernel's at the light's
/// foot: 0.43–0.56 of the median for skin and white coat) plus [`SHIFT_LIFT`] × the forward
/// shift averaged over incidence, ∫₀¹ δ(μ) dμ: a point light's light enters obliquely
/// everywhere but at its foot and leaves pushed outward, so its exitance spreads further than
/// the normal-incidence kernel's.
pub fn lift(b: &Bake) -> [f64; 3] {
    std::array::from_fn(|c| 0.5 * b.median_radius(c) + SHIFT_LIFT * mean_shift(b, c))
}

/// The lift per mm of mean forward shift: fitted to the Monte Carlo point-light profiles of
/// skin1 and white coat at h = 1–20 mm (the worst error is flat within 0.01 for 0.5–0.8).
pub const SHIFT_LIFT: f64 = 0.7;

/// ∫₀¹ δ(μ) dμ (mm) of channel `c` (midpoint rule over the interpolated table).
pub fn mean_shift(b: &Bake, c: usize) -> f64 {
    const N: usize = 256;
    (0..N)
        .map(|k| b.shift_at(c, (k as f64 + 0.5) / N as f64))
        .sum::<f64>()
        / N as f64
}

/// How far (mm) toward the light past the terminator the shadow test looks for where light
/// entered, at least (`wrap_visibility`): twice the kernel's longest median radius, where
/// most of the light that reaches a point entered. (A rim the ball of its curvature makes
/// thinner than it is — an ear's — tested inside itself, at its own far face.)
pub fn entry_reach_mm(b: &Bake) -> f64 {
    2.0 * (0..3).map(|c| b.median_radius(c)).fold(0.0, f64::max)
}

pub fn params(m: &Material) -> Params {
    params_from(&bake::for_material(m), m)
}

/// The uniform for `m` from the tables `b`.
pub fn params_from(b: &Bake, m: &Material) -> Params {
    Params {
        albedo: b.reflectance(),
        eta: m.eta,
        oblique: b.oblique,
        shift: [[0.0; 3]; super::bake::OBLIQUE_NODES],
        slab: Some(b.slab),
        lift: lift(b),
        entry_reach_mm: entry_reach_mm(b),
    }
}

/// How far from a point light's foot, in lifts, the lift fades to half: s/(1 + (r/(k s))²)
/// (beyond the kernel's reach the irradiance is the light's own; fitted with [`SHIFT_LIFT`]
/// to the same profiles, the worst error flat within 0.01 for k = 30–60).
pub const LIFT_REACH: f64 = 40.0;

/// The LUT's layout as its shader reads it (`preintegrated.wgsl`, through `consts`).
const SHADER_CONSTS: &[SharedConst] = &[
    SharedConst {
        name: "LIFT_REACH",
        value: Const::F32(LIFT_REACH as f32),
        doc: "lifts from a point light's foot at which its lift is halved (LIFT_REACH)",
    },
    SharedConst {
        name: "LUT_U",
        value: Const::F32(LUT_U as f32),
        doc: "texels per row of the LUT (LUT_U)",
    },
    SharedConst {
        name: "LUT_CURVATURE_ROWS",
        value: Const::F32(LUT_V as f32),
        doc: "the LUT's sphere rows over curvature (LUT_V)",
    },
    SharedConst {
        name: "LUT_TEXTURE_ROWS",
        value: Const::F32(TEXTURE_ROWS as f32),
        doc: "rows of the LUT texture (TEXTURE_ROWS)",
    },
    SharedConst {
        name: "LUT_PENUMBRA_ROW",
        value: Const::F32(PENUMBRA_ROW as f32),
        doc: "the LUT's edge-spread row (PENUMBRA_ROW)",
    },
    SharedConst {
        name: "LUT_SLAB_SPAN",
        value: Const::F32(SLAB_SPAN as f32),
        doc: "doublings of thickness the LUT's slab row spans (SLAB_SPAN)",
    },
];

/// `preintegrated`.
pub const PREINTEGRATED: Descriptor = Descriptor {
    name: "preintegrated",
    label: "Pre-integrated",
    module: "preintegrated",
    wgsl: include_str!("../../../shaders/preintegrated.wgsl"),
    variant: None,
    effects: Effects {
        subsurface: true,
        translucency: true,
        lut: true,
        penumbra: true,
        ..Effects::NONE
    },
    params: |m| params(m).pack(),
    params_from: Some(|b, m| params_from(b, m).pack()),
    kernel: None,
    lut: Some(lut),
    total_reflectance: |m, _| super::prediction::measured(m),
    consts: SHADER_CONSTS,
    ..subsurface::SPATIAL
};
