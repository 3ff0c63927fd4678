//! The paper's "scaled BSSRDF" (§3.2, eq. 2–4; WGSL: `shaders/dipole.wgsl`): Jensen 2001's
//! dipole diffusion profile R_d(r) with Fresnel transmittance at entry and exit,
//! S_d = (1/π) F_t(η, ω_i) R_d(r) F_t(η, ω_o), where r is the scaled distance from the
//! shaded point to the light (see [`super::units::DIPOLE_R_SCALE`]).
//!
//! Standard form: R_d(r) = α'/(4π) [ z_r (σ_tr d_r + 1) e^{−σ_tr d_r} / d_r³
//!                                  + z_v (σ_tr d_v + 1) e^{−σ_tr d_v} / d_v³ ],
//! z_r = 1/σ'_t, z_v = z_r + 4AD = z_r (1 + 4A/3), d = √(z² + r²).
//! Eq. 3 as printed divides the virtual-source term by an extra σ'_t (wrong units): that is
//! the `dipole-printed` variant.

use super::pixel::Pixel;
use super::uniform::{f32x3, model_uniform, rgb, ModelParams, Uniform};
use super::{fresnel, units, Descriptor, Effects, Material};
use glam::DVec3;

model_uniform! {
    /// What `dipole.wgsl` reads (`#import DipoleUniform`, generated from this declaration).
    pub struct DipoleUniform {
        /// σ_tr (mm⁻¹).
        pub sigma_tr: [f32; 3],
        /// η.
        pub eta: f32,
        /// z_r (mm).
        pub z_r: [f32; 3],
        /// mm of r per metre of light distance.
        pub r_mm_per_m: f32,
        /// z_v (mm).
        pub z_v: [f32; 3],
        /// Area (mm²) turning R_d into a reflectance.
        pub area_mm2: f32,
        /// α'.
        pub albedo: [f32; 3],
        /// Minimum light distance (m).
        pub light_d_min_m: f32,
        /// Total diffuse reflectance R_d (ambient term).
        pub total: [f32; 3],
        pub _pad0: f32,
        /// σ'_t = 1/ℓ (mm⁻¹).
        pub sigma_t_prime: [f32; 3],
        pub _pad1: f32,
        /// σ_tr ℓ = √(3σ_a/σ'_t) (standard form's nondimensional input).
        pub s_nd: [f32; 3],
        /// z_v/ℓ = 1 + 4A/3 (standard form's nondimensional input).
        pub zv_nd: f32,
    }
}

/// What `dipole.wgsl` reads, in f64 ([`DipoleUniform`] packed): everything that does not
/// vary per pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    pub sigma_tr: [f64; 3],
    pub z_r: [f64; 3],
    pub z_v: [f64; 3],
    pub albedo: [f64; 3],
    pub sigma_t_prime: [f64; 3],
    pub total: [f64; 3],
    pub eta: f64,
    /// σ_tr ℓ = √(3 (1 − α')) with 1 − α' = σ_a/σ'_t (nondimensional form).
    pub s_nd: [f64; 3],
    /// z_v / ℓ = 1 + 4A/3 (nondimensional form).
    pub zv_nd: f64,
}

impl Params {
    pub fn new(m: &Material) -> Self {
        let a = fresnel::boundary_a(m.eta);
        let t = m.sigma_t_prime();
        let z_r: [f64; 3] = std::array::from_fn(|c| 1.0 / t[c].max(1e-12));
        Self {
            sigma_tr: m.sigma_tr(),
            z_r,
            z_v: std::array::from_fn(|c| z_r[c] * (1.0 + 4.0 * a / 3.0)),
            albedo: m.albedo(),
            sigma_t_prime: t,
            total: total_reflectance(m),
            eta: m.eta,
            s_nd: m.one_minus_albedo().map(|x| (3.0 * x).sqrt()),
            zv_nd: 1.0 + 4.0 * a / 3.0,
        }
    }

    pub fn uniform(&self) -> DipoleUniform {
        DipoleUniform {
            sigma_tr: f32x3(self.sigma_tr),
            eta: self.eta as f32,
            z_r: f32x3(self.z_r),
            r_mm_per_m: (units::MM_PER_M * units::DIPOLE_R_SCALE) as f32,
            z_v: f32x3(self.z_v),
            area_mm2: units::DIPOLE_AREA_MM2 as f32,
            albedo: f32x3(self.albedo),
            light_d_min_m: units::LIGHT_D_MIN_M as f32,
            total: f32x3(self.total),
            sigma_t_prime: f32x3(self.sigma_t_prime),
            s_nd: f32x3(self.s_nd),
            zv_nd: self.zv_nd as f32,
            ..bytemuck::Zeroable::zeroed()
        }
    }

    pub fn pack(&self) -> ModelParams {
        ModelParams::from_uniform(&self.uniform())
    }

    /// f64 reference of R_d(r) [mm⁻²] for channel `c`, r in mm (standard form).
    pub fn profile(&self, c: usize, r: f64) -> f64 {
        let (s, zr, zv) = (self.sigma_tr[c], self.z_r[c], self.z_v[c]);
        let dr = (zr * zr + r * r).sqrt();
        let dv = (zv * zv + r * r).sqrt();
        let real = zr * (s * dr + 1.0) * (-s * dr).exp() / (dr * dr * dr);
        let virt = zv * (s * dv + 1.0) * (-s * dv).exp() / (dv * dv * dv);
        self.albedo[c] / (4.0 * std::f64::consts::PI) * (real + virt)
    }

    /// f64 reference of R_d(r) as printed in eq. 3.
    pub fn profile_printed(&self, c: usize, r: f64) -> f64 {
        let (s, zr, zv, t) = (
            self.sigma_tr[c],
            self.z_r[c],
            self.z_v[c],
            self.sigma_t_prime[c],
        );
        let dr = (zr * zr + r * r).sqrt();
        let dv = (zv * zv + r * r).sqrt();
        let real = (s * dr + 1.0) * (-s * dr).exp() / (t * dr * dr * dr);
        let virt = zv * (s * dv + 1.0) * (-s * dv).exp() / (t * dv * dv * dv);
        self.albedo[c] / (4.0 * std::f64::consts::PI) * (real + virt)
    }
}

/// f64 twin of `dipole_rd_nd` (`shaders/dipole_nd.wgsl`): R_d ℓ² at ρ = r/ℓ (ℓ = 1/σ'_t),
/// s = σ_tr ℓ = √(3(1 − α')), zv = z_v/ℓ = 1 + 4A/3. Finite for every ρ ≥ 0, s ≥ 0.
pub fn rd_nd(rho: f64, s: f64, zv: f64, albedo: f64) -> f64 {
    let rho2 = rho * rho;
    let dr = (1.0 + rho2).sqrt();
    let dv = (zv * zv + rho2).sqrt();
    let src = (s * dr + 1.0) * (-s * dr).exp() / (dr * dr * dr);
    let virt = zv * (s * dv + 1.0) * (-s * dv).exp() / (dv * dv * dv);
    albedo / (4.0 * std::f64::consts::PI) * (src + virt)
}

/// f64 reference of `dipole.wgsl`'s `dipole_profile(r)` [mm⁻²] from the packed uniform.
pub fn profile_packed(p: &ModelParams, printed: bool, r: f64) -> DVec3 {
    let u: &DipoleUniform = p.uniform();
    let albedo = rgb(u.albedo);
    if printed {
        let (s, zr, zv, t) = (
            rgb(u.sigma_tr),
            rgb(u.z_r),
            rgb(u.z_v),
            rgb(u.sigma_t_prime),
        );
        let dr = (zr * zr + DVec3::splat(r * r)).map(f64::sqrt);
        let dv = (zv * zv + DVec3::splat(r * r)).map(f64::sqrt);
        let real = (s * dr + 1.0) * (-s * dr).map(f64::exp) / (t * dr * dr * dr);
        let virt = zv * (s * dv + 1.0) * (-s * dv).map(f64::exp) / (t * dv * dv * dv);
        albedo / (4.0 * std::f64::consts::PI) * (real + virt)
    } else {
        let (t, s) = (rgb(u.sigma_t_prime), rgb(u.s_nd));
        DVec3::from_array(std::array::from_fn(|c| {
            t[c] * t[c] * rd_nd(t[c] * r, s[c], u.zv_nd.into(), albedo[c])
        }))
    }
}

/// f64 reference of `dipole.wgsl`'s `shade` for the packed uniform and one pixel.
pub fn shade(p: &ModelParams, printed: bool, px: &Pixel) -> DVec3 {
    let u: &DipoleUniform = p.uniform();
    let r = px.light_dist().max(u.light_d_min_m.into()) * f64::from(u.r_mm_per_m);
    let eta = u.eta.into();
    let ft = fresnel::transmittance_shader(eta, px.n.dot(px.l))
        * fresnel::transmittance_shader(eta, px.n.dot(px.v));
    let area = f64::from(u.area_mm2);
    let direct = px.light * profile_packed(p, printed, r) * (ft / std::f64::consts::PI * area);
    px.ambient * rgb(u.total) + direct
}

/// Total diffuse reflectance of the dipole (Jensen 2001, eq. for R_d):
/// R_d = (α'/2)(1 + e^{−(4/3)A√(3(1−α'))}) e^{−√(3(1−α'))}, with 1 − α' = σ_a/σ'_t.
pub fn total_reflectance(m: &Material) -> [f64; 3] {
    let a = fresnel::boundary_a(m.eta);
    let albedo = m.albedo();
    let one_minus = m.one_minus_albedo();
    std::array::from_fn(|c| {
        let s = (3.0 * one_minus[c]).sqrt();
        0.5 * albedo[c] * (1.0 + (-(4.0 / 3.0) * a * s).exp()) * (-s).exp()
    })
}

/// `dipole`: the standard form.
pub const DIPOLE: Descriptor = Descriptor {
    name: "dipole",
    label: "Scaled BSSRDF",
    module: "dipole",
    wgsl: include_str!("../../../shaders/dipole.wgsl"),
    variant: None,
    effects: Effects {
        subsurface: true,
        ..Effects::NONE
    },
    uniform: DipoleUniform::LAYOUT,
    params: |m| Params::new(m).pack(),
    params_from: None,
    kernel: None,
    lut: None,
    shade: |p, px| shade(p, false, px),
    probe: |p, _, x| profile_packed(p, false, x),
    probe_wgsl: "dipole_profile(x)",
    total_reflectance: |m, _| total_reflectance(m),
    consts: &[],
};

/// `dipole-printed`: eq. 3 as printed.
pub const DIPOLE_PRINTED: Descriptor = Descriptor {
    name: "dipole-printed",
    label: "Scaled BSSRDF (as printed)",
    variant: Some("DIPOLE_PRINTED"),
    shade: |p, px| shade(p, true, px),
    probe: |p, _, x| profile_packed(p, true, x),
    total_reflectance: |m, _| super::prediction::dipole_printed(m),
    ..DIPOLE
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::material::SKIN1;

    #[test]
    fn skin1_total_reflectance_is_red() {
        let r = total_reflectance(&SKIN1);
        assert!(r[0] > r[1] && r[1] > r[2], "{r:?}");
        assert!((r[0] - 0.4356).abs() < 2e-3, "{r:?}");
    }

    #[test]
    fn printed_virtual_term_differs_by_sigma_t() {
        let p = Params::new(&SKIN1);
        let (a, b) = (p.profile(1, 1.0), p.profile_printed(1, 1.0));
        assert!((a - b).abs() > 1e-3 * a);
    }
}
