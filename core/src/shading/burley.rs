//! A fourth model: transport-exact albedo with a Christensen–Burley normalised-diffusion
//! wrap (WGSL: `shaders/burley.wgsl`).
//!
//! R(r) = A · k · (e^{−k r} + e^{−k r/3}) / (8π r), k = s/ℓ, which integrates to exactly A over
//! the plane. ℓ = 1/σ'_t is the mean free path and s = 1.85 − A + 7|A − 0.8|³ is Christensen
//! and Burley's fit of the scale for a normally incident beam ("searchlight"), published
//! against Monte Carlo with about 5 % error in the profile. The surface albedo A comes from a
//! transport solution of the semi-infinite medium with the same σ_a, σ'_s, g, η
//! ([`surface_albedo`]) — never from the Monte Carlo reference — so the total diffuse
//! reflectance is right even where diffusion theory (the dipole) is not, at low albedo.
//!
//! Shading: on a locally flat surface the exitance under irradiance E is F_t(θ_i)·A·E, since
//! the profile integrates to A. On a curved surface light diffuses a distance ~1/k, which
//! wraps it around the terminator: w = 1/(k ρ) per channel (ρ the radius of curvature from
//! screen-space derivatives, red wraps most), with the energy-normalised wrap
//! (n·l + w)/(1 + w)² — a closed-form stand-in for Penner's pre-integrated ring integral.
//! radiance = E·F_t(η, max(n·l, 0.25))·A·wrap/π + ambient·A, grey texture, no specular lobe.
//! Unlike the paper's scaled dipole it is in physical units, so on flat ground it converges
//! to the transport solution. Per pixel: one division and a Fresnel term, no exponentials.

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

/// Wrap strength (1: the full w = 1/(kρ)).
pub const WRAP: f64 = 1.0;

/// f64 reference of `burley.wgsl`'s `shade` for the packed uniform and one pixel whose
/// curvature radius is `curvature_m` (the conformance harness leaves it 0: maximal wrap).
pub fn shade_curved(p: &ModelParams, px: &Pixel, curvature_m: f64) -> DVec3 {
    let k = rows(p);
    let eta = k[0][3];
    let nl = px.n.dot(px.l);
    let rho_mm = curvature_m * 1000.0;
    let e = px.light / (px.light_dist() * px.light_dist());
    let ft = fresnel::transmittance_shader(eta, nl.max(0.25));
    let albedo = DVec3::new(k[0][0], k[0][1], k[0][2]);
    let wrapped = DVec3::from_array(std::array::from_fn(|c| {
        let w = (1.0 / (k[1][c] * rho_mm).max(1e-6)).min(1.0) * k[2][3];
        (nl + w).max(0.0) / ((1.0 + w) * (1.0 + w))
    }));
    px.ambient * albedo + e / std::f64::consts::PI * ft * albedo * wrapped
}

/// f64 reference of `shade` as the conformance harness calls it (curvature radius 0).
pub fn shade(p: &ModelParams, px: &Pixel) -> DVec3 {
    shade_curved(p, px, 0.0)
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
                0.0,
                R_MIN_MM as f32,
                units::LIGHT_D_MIN_M as f32,
                WRAP as f32,
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
