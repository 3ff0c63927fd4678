//! A fourth model: the Christensen–Burley normalised diffusion profile (2015) in the paper's
//! "scaled" set-up (WGSL: `shaders/burley.wgsl`).
//!
//! R(r) = A · k · (e^{−k r} + e^{−k r/3}) / (8π r), k = s/ℓ, which integrates to exactly A over
//! the plane. ℓ = 1/σ'_t is the mean free path and s = 1.85 − A + 7|A − 0.8|³ is Christensen
//! and Burley's fit of the scale for a normally incident beam ("searchlight"), published
//! against Monte Carlo with about 5 % error in the profile. The surface albedo A comes from a
//! transport solution of the semi-infinite medium with the same σ_a, σ'_s, g, η
//! ([`surface_albedo`]) — never from the Monte Carlo reference — so the total diffuse
//! reflectance is right even where diffusion theory (the dipole) is not, at low albedo.
//! Shading is as for the dipole: radiance = I · F_t(ω_i) F_t(ω_o) · R(r) · area / π, with r
//! the scaled light distance and a grey texture; per pixel it costs two exponentials and no
//! square roots.

use super::conformance::{rows, Pixel};
use super::{fresnel, registry::ModelParams, transport, units, Material};
use glam::DVec3;

/// Smallest r [mm] the profile is evaluated at (R ∝ 1/r).
pub const R_MIN_MM: f64 = 1e-4;

/// Christensen–Burley's scale for normal incidence.
pub fn scale(albedo: f64) -> f64 {
    1.85 - albedo + 7.0 * (albedo - 0.8).abs().powi(3)
}

/// Total diffuse reflectance A of the semi-infinite medium per channel (per entered power),
/// from the discrete-ordinates transport solution in [`transport`].
pub fn surface_albedo(m: &Material) -> [f64; 3] {
    transport::albedo_rgb(m)
}

/// f64 twin of `burley_rd_nd` (`shaders/burley_nd.wgsl`): R/k² at x = k r, A (e^{−x} + e^{−x/3})/(8π x).
pub fn rd_nd(x: f64, a: f64) -> f64 {
    a * ((-x).exp() + (-x / 3.0).exp()) / (8.0 * std::f64::consts::PI * x)
}

/// f64 reference of `burley.wgsl`'s `burley_profile(r)` [mm⁻²] from the packed uniform.
pub fn profile_packed(p: &ModelParams, r_mm: f64) -> DVec3 {
    let k = rows(p);
    let r = r_mm.max(k[2][1]);
    DVec3::from_array(std::array::from_fn(|c| {
        k[1][c] * k[1][c] * rd_nd(k[1][c] * r, k[0][c])
    }))
}

/// f64 reference of `burley.wgsl`'s `shade` for the packed uniform and one pixel.
pub fn shade(p: &ModelParams, px: &Pixel) -> DVec3 {
    let k = rows(p);
    let r = px.light_dist().max(k[2][2]) * k[1][3];
    let eta = k[0][3];
    let ft = fresnel::transmittance_shader(eta, px.n.dot(px.l))
        * fresnel::transmittance_shader(eta, px.n.dot(px.v));
    let direct = px.light * profile_packed(p, r) * (ft / std::f64::consts::PI * k[2][0]);
    px.ambient * DVec3::new(k[0][0], k[0][1], k[0][2]) + direct
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    pub albedo: [f64; 3],
    /// k = s/ℓ [mm⁻¹].
    pub k: [f64; 3],
    pub eta: f64,
}

impl Params {
    pub fn new(m: &Material) -> Self {
        let albedo = surface_albedo(m);
        let t = m.sigma_t_prime();
        Self {
            albedo,
            k: std::array::from_fn(|c| scale(albedo[c]) * t[c]),
            eta: m.eta,
        }
    }

    /// f64 reference of R(r) [mm⁻²] for channel `c`.
    pub fn profile(&self, c: usize, r: f64) -> f64 {
        let r = r.max(R_MIN_MM);
        let k = self.k[c];
        self.albedo[c] * k * ((-k * r).exp() + (-k * r / 3.0).exp())
            / (8.0 * std::f64::consts::PI * r)
    }

    pub fn pack(&self) -> ModelParams {
        let row = |v: [f64; 3], w: f64| [v[0] as f32, v[1] as f32, v[2] as f32, w as f32];
        ModelParams::from_rows(&[
            row(self.albedo, self.eta),
            row(self.k, units::MM_PER_M * units::DIPOLE_R_SCALE),
            [
                units::DIPOLE_AREA_MM2 as f32,
                R_MIN_MM as f32,
                units::LIGHT_D_MIN_M as f32,
                0.0,
            ],
        ])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::material::SKIN1;

    #[test]
    fn profile_integrates_to_the_albedo() {
        let p = Params::new(&SKIN1);
        for c in 0..3 {
            // ∫ 2πr R dr with the substitution r = e^u.
            let (mut sum, n) = (0.0, 40_000);
            let (u0, u1) = ((1e-7f64).ln(), (1e4f64).ln());
            for i in 0..n {
                let u = u0 + (u1 - u0) * (i as f64 + 0.5) / n as f64;
                let r = u.exp();
                sum += 2.0 * std::f64::consts::PI * r * p.profile(c, r) * r * (u1 - u0) / n as f64;
            }
            assert!(
                (sum / p.albedo[c] - 1.0).abs() < 1e-3,
                "channel {c}: {sum} vs {}",
                p.albedo[c]
            );
        }
    }
}
