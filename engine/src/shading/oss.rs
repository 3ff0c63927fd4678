//! The authors' subsurface colour model, OSS (§3.3, eq. 5–6; WGSL: `shaders/oss.wgsl`).
//!
//! f_d = (1 − F_dr,t) (σ'_s P(g) {d − σ_a d² + σ_a² d³/3} + F_dr,b (1 − σ_a d − σ'_s P(g) d²))
//! is a cubic in the depth d [mm] whose coefficients depend only on the material, so they are
//! precomputed here and the shader evaluates f_d = c0 + c1 d + c2 d² + c3 d³ (Horner).
//! Colour (eq. 6): f_d (ρ_d cosθ E + 20 ρ_ts I / d_L^2.5) + ρ_d L cosθ · Ward lobe (ρ_s), d_L the
//! light distance [m], E = I/d_L² the irradiance: the translucency term is read as its own
//! d_L^-2.5 fall-off of the light's intensity I (eq. 6 multiplies it by neither E nor 1/d²). Skin: ρ_d = 1, ρ_s = 0.2, ρ_ts = 0.01. F_dr,t = F_dr,b = F_dr(η)
//! (a layer in air on both sides). The printed eq. 6 writes θ_n in the lobe; the angle between
//! the normal and itself is 0, so the lobe's θ is read as θ_h (Walter's form).
//! As printed, f_d turns negative for thick layers (skin1: beyond ~1.4 mm in blue); the
//! shader clamps the final radiance at 0.
//!
//! `oss-stable` replaces eq. 5's two terms by forms that agree with the printed top term to
//! first order in d and stay positive and bounded for every d ≥ 0:
//! * top: 1 − exp(−σ'_s P L(d)) with L(d) = (1 − e^{−2σ_a d})/(2σ_a) = ∫₀^d e^{−2σ_a x} dx
//!   (the printed ∫₀^d (1 − σ_a x)² dx is its second-order expansion); evaluated as
//!   d·E(2σ_a d) with E(x) = (1 − e^{−x})/x computed without cancellation;
//! * bottom: F_dr,b · exp(−(σ_a + σ'_s P) d), the dimensionally consistent attenuation of the
//!   light reflected at the bottom boundary (the printed 1 − σ_a d − σ'_s P d² mixes a length
//!   into a dimensionless sum and goes negative).
//!
//! So 0 ≤ f_d ≤ (1 − F_dr)(1 + F_dr) < 1.

use super::pixel::Pixel;
use super::uniform::{f32x3, model_uniform, rgb, ModelParams, Uniform};
use super::{fresnel, units, ward, Descriptor, Effects, Material};
use glam::DVec3;

model_uniform! {
    /// What `oss.wgsl` reads (`#import OssUniform`, generated from this declaration).
    pub struct OssUniform {
        /// f_d = c0 + c1 d + c2 d² + c3 d³ per channel (printed form).
        pub c0: [f32; 3],
        /// mm of depth per metre of thickness.
        pub depth_mm_per_m: f32,
        pub c1: [f32; 3],
        pub _pad0: f32,
        pub c2: [f32; 3],
        pub _pad1: f32,
        pub c3: [f32; 3],
        pub _pad2: f32,
        /// ρ_d.
        pub rho_d: f32,
        /// ρ_ts.
        pub rho_ts: f32,
        /// Minimum light distance (m) in d^-2.5.
        pub light_d_min_m: f32,
        /// 1 when the texture tints the colour.
        pub textured: f32,
        /// The Ward lobe ([`ward::Lobe`]).
        pub rho_s: f32,
        pub alpha_x: f32,
        pub alpha_y: f32,
        pub _pad3: f32,
        /// σ_a (mm⁻¹), stable form only.
        pub sigma_a: [f32; 3],
        /// F_dr(η), stable form only.
        pub fdr: f32,
        /// σ'_s P (mm⁻¹), stable form only.
        pub sp: [f32; 3],
        pub _pad4: f32,
    }
}

/// ρ_d, ρ_s, ρ_ts for skin (§3.3).
pub const RHO_D: f64 = 1.0;
pub const RHO_S: f64 = 0.2;
pub const RHO_TS: f64 = 0.01;

/// P(g): the fraction of Henyey–Greenstein scattering into the backward hemisphere,
/// (1 − g)/(2g) · ((1 + g)/√(1 + g²) − 1), evaluated without cancellation near g = 0.
pub fn backward_fraction(g: f64) -> f64 {
    // (1+g)/s − 1 = 2g / (s (1 + g + s)) because (1+g)² − s² = 2g, so the 1/g cancels exactly:
    // P(g) = (1 − g) / (s (1 + g + s)), s = √(1 + g²); P(0) = 1/2.
    let s = (1.0 + g * g).sqrt();
    (1.0 - g) / (s * (1.0 + g + s))
}

/// E(x) = (1 − e^{−x})/x, with E(0) = 1, without cancellation for small x.
pub fn one_minus_exp_over_x(x: f64) -> f64 {
    if x.abs() < 1e-4 {
        1.0 - x * (0.5 - x / 6.0)
    } else {
        -(-x).exp_m1() / x
    }
}

/// f64 twin of `oss_fd_stable_nd` (`shaders/oss_nd.wgsl`) on the optical depths a = σ_a d and
/// sp = σ'_s P(g) d, f = F_dr: (1 − f)(1 − e^{−sp E(2a)} + f e^{−(a + sp)}), in [0, 1 − f²].
pub fn f_d_stable_nd(a: f64, sp: f64, f: f64) -> f64 {
    let y = sp * one_minus_exp_over_x(2.0 * a);
    let top = -(-y).exp_m1();
    let bottom = f * (-(a + sp)).exp();
    (1.0 - f) * (top + bottom)
}

/// f64 reference of `oss.wgsl`'s `oss_colour(d)` (d in mm) from the packed uniform.
pub fn colour_packed(p: &ModelParams, stable: bool, d: f64) -> DVec3 {
    let u: &OssUniform = p.uniform();
    if stable {
        let (a, sp) = (rgb(u.sigma_a), rgb(u.sp));
        DVec3::from_array(std::array::from_fn(|c| {
            f_d_stable_nd(a[c] * d, sp[c] * d, u.fdr.into())
        }))
    } else {
        let [c0, c1, c2, c3] = [u.c0, u.c1, u.c2, u.c3].map(rgb);
        c0 + d * (c1 + d * (c2 + d * c3))
    }
}

/// f64 reference of `oss.wgsl`'s `shade` for the packed uniform and one pixel. The light
/// distance in the translucency term 20 ρ_ts / d^2.5 is clamped below at
/// [`units::OSS_LIGHT_D_MIN_M`] (packed as `light_d_min_m`), so the term is ≤ 20 ρ_ts · 316.
pub fn shade(p: &ModelParams, stable: bool, px: &Pixel) -> DVec3 {
    let u: &OssUniform = p.uniform();
    let fd = colour_packed(p, stable, px.thickness() * f64::from(u.depth_mm_per_m));
    let tex = if u.textured > 0.5 {
        px.albedo
    } else {
        DVec3::ONE
    };
    let nl = px.n.dot(px.l).max(0.0);
    let dl = px.light_dist().max(u.light_d_min_m.into());
    let (rho_d, rho_ts) = (f64::from(u.rho_d), f64::from(u.rho_ts));
    let translucency = 20.0 * rho_ts / dl.powf(2.5) * px.light;
    let e0 = px.irradiance();
    let diffuse = fd * tex * (rho_d * nl * e0 + translucency) / std::f64::consts::PI;
    let lobe = ward::Lobe {
        rho_s: u.rho_s.into(),
        alpha_x: u.alpha_x.into(),
        alpha_y: u.alpha_y.into(),
    };
    let specular = e0 * nl * ward::lobe_specular(px, &lobe, false);
    let ambient = px.ambient * fd * tex * rho_d;
    (ambient + diffuse + specular).max(DVec3::ZERO)
}

/// What `oss.wgsl` reads, in f64 ([`OssUniform`] packed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// f_d = c[0] + c[1] d + c[2] d² + c[3] d³ per channel.
    pub coeffs: [[f64; 3]; 4],
    /// σ_a per channel (stable form).
    pub sigma_a: [f64; 3],
    /// σ'_s P(0) = σ'_s/2 per channel (stable form; the printed form's σ'_s P(g) applies g
    /// twice).
    pub sp: [f64; 3],
    /// F_dr(η) (top and bottom).
    pub fdr: f64,
    pub textured: bool,
}

impl Params {
    pub fn new(m: &Material) -> Self {
        let f = fresnel::diffuse_reflectance(m.eta);
        let (ft, fb) = (f, f);
        let p = backward_fraction(m.g);
        // As printed, eq. 5 multiplies σ'_s by P(g); σ'_s = σ_s (1 − g) is already the reduced
        // (similarity-scaled, isotropic-equivalent) coefficient, so the stable form takes the
        // isotropic backward fraction P(0) = 1/2 instead of applying g a second time.
        let sp_printed: [f64; 3] = std::array::from_fn(|c| m.sigma_s_prime[c] * p);
        let sp: [f64; 3] = std::array::from_fn(|c| m.sigma_s_prime[c] * backward_fraction(0.0));
        let a = m.sigma_a;
        let k = 1.0 - ft;
        let coeffs = [
            [k * fb; 3],
            std::array::from_fn(|c| k * (sp_printed[c] - fb * a[c])),
            std::array::from_fn(|c| k * (-sp_printed[c] * a[c] - fb * sp_printed[c])),
            std::array::from_fn(|c| k * sp_printed[c] * a[c] * a[c] / 3.0),
        ];
        Self {
            coeffs,
            sigma_a: m.sigma_a,
            sp,
            fdr: f,
            textured: m.textured,
        }
    }

    /// f64 reference of the stable f_d(d) for channel `c`, d in mm.
    pub fn f_d_stable(&self, c: usize, d: f64) -> f64 {
        f_d_stable_nd(self.sigma_a[c] * d, self.sp[c] * d, self.fdr)
    }

    /// f64 reference of f_d(d) for channel `c`, d in mm, exactly as eq. 5 prints it.
    pub fn f_d(&self, c: usize, d: f64) -> f64 {
        let k = &self.coeffs;
        k[0][c] + d * (k[1][c] + d * (k[2][c] + d * k[3][c]))
    }

    pub fn uniform(&self) -> OssUniform {
        let lobe = ward::Lobe {
            rho_s: RHO_S,
            ..ward::Lobe::SKIN
        };
        let [c0, c1, c2, c3] = self.coeffs.map(f32x3);
        OssUniform {
            c0,
            depth_mm_per_m: (units::MM_PER_M * units::OSS_DEPTH_SCALE) as f32,
            c1,
            c2,
            c3,
            rho_d: RHO_D as f32,
            rho_ts: RHO_TS as f32,
            light_d_min_m: units::OSS_LIGHT_D_MIN_M as f32,
            textured: self.textured as u8 as f32,
            rho_s: lobe.rho_s as f32,
            alpha_x: lobe.alpha_x as f32,
            alpha_y: lobe.alpha_y as f32,
            sigma_a: f32x3(self.sigma_a),
            fdr: self.fdr as f32,
            sp: f32x3(self.sp),
            ..bytemuck::Zeroable::zeroed()
        }
    }

    pub fn pack(&self) -> ModelParams {
        ModelParams::from_uniform(&self.uniform())
    }
}

/// `oss`: eq. 5–6 as printed.
pub const OSS: Descriptor = Descriptor {
    name: "oss",
    label: "OSS",
    module: "oss",
    wgsl: include_str!("../../../shaders/oss.wgsl"),
    variant: None,
    effects: Effects {
        subsurface: true,
        translucency: true,
        ..Effects::NONE
    },
    uniform: OssUniform::LAYOUT,
    params: |m| Params::new(m).pack(),
    params_from: None,
    kernel: None,
    lut: None,
    shade: |p, px| shade(p, false, px),
    probe: |p, _, x| colour_packed(p, false, x),
    probe_wgsl: "oss_colour(x)",
    total_reflectance: |m, slab| super::prediction::oss(m, slab, false),
    consts: &[],
};

/// `oss-stable`: eq. 5's terms positive and bounded.
pub const OSS_STABLE: Descriptor = Descriptor {
    name: "oss-stable",
    label: "OSS (stable)",
    variant: Some("OSS_STABLE"),
    shade: |p, px| shade(p, true, px),
    probe: |p, _, x| colour_packed(p, true, x),
    total_reflectance: |m, slab| super::prediction::oss(m, slab, true),
    ..OSS
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::material::{Material, SKIN1};

    #[test]
    fn cubic_matches_eq5() {
        let m = Material { eta: 1.4, ..SKIN1 };
        let p = Params::new(&m);
        let f = fresnel::diffuse_reflectance(1.4);
        for d in [0.0, 0.3, 1.0, 2.5] {
            for c in 0..3 {
                let (a, s) = (m.sigma_a[c], m.sigma_s_prime[c] * 0.5);
                let top = s * (d - a * d * d + a * a * d * d * d / 3.0);
                let bottom = f * (1.0 - a * d - s * d * d);
                let want = (1.0 - f) * (top + bottom);
                assert!((p.f_d(c, d) - want).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn printed_f_d_goes_negative_in_blue_first() {
        // The observation: skin1 at η = 1.4 turns negative from ~1.4 mm in blue.
        let p = Params::new(&Material { eta: 1.4, ..SKIN1 });
        let zero = |c| {
            (1..4000)
                .map(|i| i as f64 * 1e-3)
                .find(|&d| p.f_d(c, d) < 0.0)
                .unwrap()
        };
        let (r, g, b) = (zero(0), zero(1), zero(2));
        assert!(b < g && g < r, "{r} {g} {b}");
        assert!((b - 1.4).abs() < 0.15 && (g - 2.0).abs() < 0.15 && (r - 2.7).abs() < 0.2);
    }

    #[test]
    fn stable_form_is_positive_bounded_and_first_order_exact() {
        let p = Params::new(&Material { eta: 1.4, ..SKIN1 });
        let bound = (1.0 - p.fdr) * (1.0 + p.fdr);
        for i in 0..=2000 {
            let d = 1e-9 * 10f64.powf(i as f64 * 11.0 / 2000.0); // 1e-9 .. 100 mm
            for c in 0..3 {
                let v = p.f_d_stable(c, d);
                assert!(v.is_finite() && v > 0.0 && v <= bound, "d={d} c={c} {v}");
            }
        }
        // Same value and same top-term slope as eq. 5 at d → 0.
        let d = 1e-6;
        for c in 0..3 {
            assert!((p.f_d_stable(c, 0.0) - p.f_d(c, 0.0)).abs() < 1e-15);
            let top_slope = (1.0 - p.fdr) * p.sp[c];
            let stable_slope = (p.f_d_stable(c, d) - p.f_d_stable(c, 0.0)) / d;
            let bottom_slope = -(1.0 - p.fdr) * p.fdr * (p.sigma_a[c] + p.sp[c]);
            assert!((stable_slope - (top_slope + bottom_slope)).abs() < 1e-5);
        }
    }

    #[test]
    fn e_of_x_is_smooth_across_the_series_switch() {
        // Either side of the switch at 1e-4 (E' ≈ −1/2, so the two agree to ~1e-12).
        let (a, b) = (
            one_minus_exp_over_x(1e-4 - 1e-12),
            one_minus_exp_over_x(1e-4 + 1e-12),
        );
        assert!((a - b).abs() < 1e-11, "{a} vs {b}");
        assert_eq!(one_minus_exp_over_x(0.0), 1.0);
    }

    #[test]
    fn backward_fraction_is_half_at_zero_and_continuous() {
        assert_eq!(backward_fraction(0.0), 0.5);
        let naive = |g: f64| (1.0 - g) / (2.0 * g) * ((1.0 + g) / (1.0 + g * g).sqrt() - 1.0);
        assert!((backward_fraction(0.3) - naive(0.3)).abs() < 1e-12);
        assert!((backward_fraction(1e-9) - 0.5).abs() < 1e-8);
        assert!(backward_fraction(0.9) < 0.1);
    }
}
