//! The GPU conformance suite. What the harness ([`harness`], which runs **the
//! WGSL functions the renderer uses** in a compute shader on the real driver) is compared
//! with: the f64 references beside each model (`ward::shade`, `dipole::shade`, `oss::shade`,
//! `subsurface::local` and their sub-functions and nondimensional kernels), per model and per
//! [`NdFunction`], and the tolerances. Pure f64: no GPU here.
//!
//! References are evaluated on the inputs *as the GPU sees them* (rounded to f32, or to f16
//! for the f16 kernel) and on the packed f32 uniform read back to f64, so a difference is the
//! shader's arithmetic only.
//!
//! # Tolerances (|gpu − f64| ≤ abs + rel·|f64|, per channel)
//! * [`F32_SHADE`]: rel 2e-5, abs 1e-30. WGSL does not fix the accuracy of `exp`/`pow`
//!   (Vulkan: 3 + 2|x| ULP for exp, pow via exp2/log2), compilers may contract a·b + c into
//!   FMA (lavapipe's LLVM does), and the models evaluate exponentials of arguments up to ~80
//!   before they underflow: a relative error of the argument δ becomes |x|·δ in the result
//!   (80 × 6e-8 ≈ 5e-6), on top of a few ULP per operation over ~30 operations. The absolute
//!   floor covers results in f32's denormal range (flushed to 0 by some drivers).
//! * [`F32_ND`]: the same, for the nondimensional kernels.
//! * [`F16_ND`]: rel 3e-2, abs 2e-4 (about 60 ULP of f16's 2⁻¹¹ ≈ 4.9e-4 unit roundoff, and
//!   |x|·2⁻¹¹ for exp at |x| ≤ 30 ≈ 1.5 %; absolute: results below f16's normal range 6.1e-5).
//!   Only inside f16's range, see [`NdFunction::f16_domain`].

use glam::DVec3;

use dermis_engine::shading::pixel::Pixel;
use dermis_engine::shading::{dipole, fresnel, oss, ward, ModelParams, ShadingModel};

pub mod harness;

/// Whether the compute harness can check `model`: models that sample a LUT texture are
/// checked by rendering instead (`tests/render/subsurface_render.rs`), since texture filtering's
/// sub-texel precision is the implementation's choice (Vulkan requires 4 bits), far coarser
/// than the harness's f32 tolerance.
pub fn harness_checks(model: ShadingModel) -> bool {
    !model.effects().lut
}

/// f64 reference of `model`'s `shade` for the packed uniform `p` (models with
/// [`harness_checks`]; the others get their flat-ground limit without the LUT).
pub fn reference_shade(model: ShadingModel, p: &ModelParams, px: &Pixel) -> DVec3 {
    (model.descriptor().shade)(p, px)
}

/// f64 reference of `model`'s probed sub-function: the Ward lobe (`ward_specular`, grey),
/// `dipole_profile(x)`, `oss_colour(x)` (x in mm) or the spatial models' `sss_oblique(x/(1+x))`.
pub fn reference_probe(model: ShadingModel, p: &ModelParams, px: &Pixel, x: f64) -> DVec3 {
    (model.descriptor().probe)(p, px, x)
}

/// Floating-point precision of a kernel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Precision {
    F32,
    F16,
}

/// A per-pixel function on nondimensional inputs, as the renderer imports it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NdFunction {
    /// `ward_lobe_nd(nl, nv, ht, hb, hn, ρ_s, α_x, α_y)`.
    WardLobe,
    /// `fresnel_transmittance(η, cosθ)`.
    Fresnel,
    /// `dipole_rd_nd(ρ = σ'_t r, s = σ_tr ℓ, z_v/ℓ, α')` (channel x).
    DipoleRd,
    /// `oss_fd_stable_nd(σ_a d, σ'_s P d, F_dr)` (channel x).
    OssFdStable,
}

impl NdFunction {
    pub const ALL: [NdFunction; 4] = [
        Self::WardLobe,
        Self::Fresnel,
        Self::DipoleRd,
        Self::OssFdStable,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Self::WardLobe => "ward_lobe_nd",
            Self::Fresnel => "fresnel_transmittance",
            Self::DipoleRd => "dipole_rd_nd",
            Self::OssFdStable => "oss_fd_stable_nd",
        }
    }

    /// The composer module holding the function.
    pub fn module(self) -> &'static str {
        match self {
            Self::WardLobe => "ward_nd",
            Self::Fresnel => "fresnel",
            Self::DipoleRd => "dipole_nd",
            Self::OssFdStable => "oss_nd",
        }
    }

    /// f64 reference on the inputs (a.x, a.y, a.z, a.w, b.x, b.y, b.z, b.w).
    pub fn reference(self, x: &[f64; 8]) -> f64 {
        match self {
            Self::WardLobe => ward::lobe_nd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7]),
            Self::Fresnel => fresnel::transmittance_shader(x[0], x[1]),
            Self::DipoleRd => dipole::rd_nd(x[0], x[1], x[2], x[3]),
            Self::OssFdStable => oss::f_d_stable_nd(x[0], x[1], x[2]),
        }
    }

    /// Whether inputs `x` lie in the domain the f16 kernel is specified on: every input and
    /// intermediate inside f16's normal range (≤ 65504, ≥ 6.1e-5 where it divides).
    /// * ward: α ≥ 0.1 (ρ_s/(4π α_x α_y √1e-6) and (h·t/α)²/h_n² stay < 65504), h_n ≥ 0.05;
    /// * fresnel: η ∈ [1, 3], cosθ ≥ 0.01 (q = η² − 1 + cos² ≥ 1e-4, f16-normal);
    /// * dipole: ρ ≤ 30 (d³ ≤ 3e4), s ≤ 30 (s·d ≤ 900 only feeds exp, which underflows to 0);
    /// * oss: σ_a d, σ'_s P d ≤ 1e4.
    pub fn f16_domain(self, x: &[f64; 8]) -> bool {
        match self {
            Self::WardLobe => x[6] >= 0.1 && x[7] >= 0.1 && x[4] >= 0.05,
            Self::Fresnel => (1.0..=3.0).contains(&x[0]) && x[1] >= 0.01,
            Self::DipoleRd => x[0] <= 30.0 && x[1] <= 30.0,
            Self::OssFdStable => x[0] <= 1e4 && x[1] <= 1e4,
        }
    }
}

/// Rounds to the nearest f16 value (ties to even), returned as f64; ±∞ beyond 65504.
pub fn round_f16(x: f64) -> f64 {
    if !x.is_finite() || x == 0.0 {
        return x;
    }
    let a = x.abs();
    if a >= 65520.0 {
        return f64::INFINITY.copysign(x);
    }
    let exp = (((a.to_bits() >> 52) & 0x7ff) as i32 - 1023).max(-14);
    let ulp = 2f64.powi(exp - 10);
    ((a / ulp).round_ties_even() * ulp).copysign(x)
}

/// An absolute + relative tolerance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    pub abs: f64,
    pub rel: f64,
}

impl Tolerance {
    pub const fn new(abs: f64, rel: f64) -> Self {
        Self { abs, rel }
    }

    /// Whether `got` is within tolerance of `want` (both finite, or both the same infinity).
    pub fn accepts(&self, got: f64, want: f64) -> bool {
        if !got.is_finite() || !want.is_finite() {
            return got == want;
        }
        (got - want).abs() <= self.abs + self.rel * want.abs()
    }
}

/// f32 shade kernel vs f64 (see the module docs for why).
/// The absolute floor is far below any displayable radiance: it only matters where a result
/// is a near-cancellation of O(1) terms (the printed OSS cubic at its root, ~1.4–2.7 mm),
/// whose relative error no precision bounds.
pub const F32_SHADE: Tolerance = Tolerance::new(1e-9, 2e-5);
/// f32 nondimensional kernels vs f64.
pub const F32_ND: Tolerance = Tolerance::new(1e-30, 2e-5);
/// f16 nondimensional kernels vs f64, inside [`NdFunction::f16_domain`].
pub const F16_ND: Tolerance = Tolerance::new(2e-4, 3e-2);

/// f32 Fresnel transmittance within |q| < 1e-6 of the critical angle (η < 1,
/// q = η² − 1 + cos²θ → 0): F_t ≈ (2√q/c)(1 + 1/η²) has an infinite condition number there;
/// rounding η² and c² leaves q uncertain by ~2⁻²³, i.e. √q by ~3.5e-4 and F_t by ≲ 3e-3
/// (observed on lavapipe: 2.2e-4). An absolute bound is the honest statement.
pub const F32_CRITICAL_ANGLE: Tolerance = Tolerance::new(3e-3, 2e-5);

/// Whether Fresnel inputs (η, cosθ) lie within |q| < 1e-6 of the critical angle.
pub fn near_critical_angle(eta: f64, cos_i: f64) -> bool {
    eta < 1.0 && ((eta - 1.0) * (eta + 1.0) + cos_i * cos_i).abs() < 1e-6
}

/// Relative error with a floor: |got − want| / max(|want|, floor).
pub fn rel_error(got: f64, want: f64, floor: f64) -> f64 {
    if got == want {
        return 0.0;
    }
    (got - want).abs() / want.abs().max(floor)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn f16_rounding() {
        assert_eq!(round_f16(1.0), 1.0);
        assert_eq!(round_f16(1.0 + 1.0 / 4096.0), 1.0); // half an ulp below: ties to even
        assert_eq!(round_f16(1.0 + 3.0 / 2048.0), 1.0 + 2.0 / 1024.0);
        assert_eq!(round_f16(65504.0), 65504.0);
        assert_eq!(round_f16(1e6), f64::INFINITY);
        assert_eq!(round_f16(1e-8), 0.0);
        assert_eq!(round_f16(2f64.powi(-24)), 2f64.powi(-24));
    }
}
