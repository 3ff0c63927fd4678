//! The skin shading models of Lee, Kim & Chin (2014), one Rust module per WGSL file of the
//! same name in `shaders/`: each holds the model's parameters, the CPU-side precompute of
//! everything that does not vary per pixel, and an f64 reference of the per-pixel maths.
//!
//! [`ShadingModel`] is the one registry of models, used by the CLI, the UI, the renderer, the
//! composer and every JSON output. Adding a model is one Rust file here (declaring its
//! [`Descriptor`]), one WGSL file of the same name in `shaders/`, and its row below (with the
//! `pub mod` that declares the file).

pub mod albedo;
pub mod bake;
pub mod burley;
pub mod dipole;
pub mod edge_spread;
pub mod fresnel;
pub mod grid;
pub mod interp;
pub mod material;
pub mod oss;
pub mod pixel;
pub mod prediction;
pub mod preintegrated;
mod registry;
pub mod sphere_grid;
pub mod subsurface;
pub mod tabulated;
pub mod transport;
pub(crate) mod uniform;
pub mod units;
pub mod volume_optics;
pub mod ward;

pub use material::Material;
pub use preintegrated::Lut;
pub use registry::{Descriptor, Effects};
pub use uniform::{
    Const, Field, GpuType, Layout, ModelParams, SharedConst, Uniform, WgslType, MODEL_PARAM_ROWS,
};

registry::models! {
    default: Preintegrated;
    baseline: Ward;
    /// Ward anisotropic BRDF, standard half-vector form (Walter 2005).
    Ward => ward::WARD,
    /// Ward as printed in eq. 1 (φ_i / φ_o in the exponent).
    WardPrinted => ward::WARD_PRINTED,
    /// The paper's scaled Jensen dipole BSSRDF, standard form.
    Dipole => dipole::DIPOLE,
    /// The dipole as printed in eq. 3 (extra 1/σ'_t on the virtual source).
    DipolePrinted => dipole::DIPOLE_PRINTED,
    /// The authors' OSS colour model (eq. 5–6), as printed.
    Oss => oss::OSS,
    /// OSS with eq. 5's terms replaced by positive, bounded, dimensionally consistent forms.
    OssStable => oss::OSS_STABLE,
    /// Christensen–Burley normalised diffusion (transport-solved albedo, diffuse mean free
    /// path), spread in screen space.
    Burley => burley::BURLEY,
    /// The Monte Carlo-measured diffusion profile with oblique incidence and translucency,
    /// spread in screen space.
    Tabulated => tabulated::TABULATED,
    /// Pre-integrated skin: a LUT over (n·l, curvature) from the measured profile, one pass
    /// (the mobile tier, the most accurate model without a screen-space pass: the default).
    Preintegrated => preintegrated::PREINTEGRATED,
}
