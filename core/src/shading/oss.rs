//! The authors' subsurface colour model, OSS (§3.3, eq. 5–6; WGSL: `shaders/oss.wgsl`).
//!
//! f_d = (1 − F_dr,t) (σ'_s P(g) {d − σ_a d² + σ_a² d³/3} + F_dr,b (1 − σ_a d − σ'_s P(g) d²))
//! is a cubic in the depth d [mm] whose coefficients depend only on the material, so they are
//! precomputed here and the shader evaluates f_d = c0 + c1 d + c2 d² + c3 d³ (Horner).
//! Colour (eq. 6): f_d (ρ_d cosθ + 20 ρ_ts / d_L^2.5) + ρ_d L cosθ · Ward lobe (ρ_s), d_L the
//! light distance [m]. Skin: ρ_d = 1, ρ_s = 0.2, ρ_ts = 0.01. F_dr,t = F_dr,b = F_dr(η)
//! (a layer in air on both sides). The printed eq. 6 writes θ_n in the lobe; the angle between
//! the normal and itself is 0, so the lobe's θ is read as θ_h (Walter's form).
//! As printed, f_d turns negative for thick layers (skin1: beyond ~1.4 mm in blue); the
//! shader clamps the final radiance at 0.

use super::{fresnel, registry::ModelParams, units, ward, Material};

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

/// What `oss.wgsl` reads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// f_d = c[0] + c[1] d + c[2] d² + c[3] d³ per channel.
    pub coeffs: [[f64; 3]; 4],
    pub textured: bool,
}

impl Params {
    pub fn new(m: &Material) -> Self {
        let f = fresnel::diffuse_reflectance(m.eta);
        let (ft, fb) = (f, f);
        let p = backward_fraction(m.g);
        let mut coeffs = [[0.0; 3]; 4];
        for c in 0..3 {
            let (a, sp) = (m.sigma_a[c], m.sigma_s_prime[c] * p);
            let k = 1.0 - ft;
            coeffs[0][c] = k * fb;
            coeffs[1][c] = k * (sp - fb * a);
            coeffs[2][c] = k * (-sp * a - fb * sp);
            coeffs[3][c] = k * sp * a * a / 3.0;
        }
        Self { coeffs, textured: m.textured }
    }

    /// f64 reference of f_d(d) for channel `c`, d in mm, exactly as eq. 5 prints it.
    pub fn f_d(&self, c: usize, d: f64) -> f64 {
        let k = &self.coeffs;
        k[0][c] + d * (k[1][c] + d * (k[2][c] + d * k[3][c]))
    }

    pub fn pack(&self) -> ModelParams {
        let row = |v: [f64; 3], w: f64| [v[0] as f32, v[1] as f32, v[2] as f32, w as f32];
        let lobe = ward::Lobe { rho_s: RHO_S, ..ward::Lobe::SKIN };
        ModelParams::from_rows(&[
            row(self.coeffs[0], units::MM_PER_M * units::OSS_DEPTH_SCALE),
            row(self.coeffs[1], 0.0),
            row(self.coeffs[2], 0.0),
            row(self.coeffs[3], 0.0),
            [RHO_D as f32, RHO_TS as f32, units::OSS_LIGHT_D_MIN_M as f32, self.textured as u8 as f32],
            [lobe.rho_s as f32, lobe.alpha_x as f32, lobe.alpha_y as f32, 0.0],
        ])
    }
}

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
        let zero = |c| (1..4000).map(|i| i as f64 * 1e-3).find(|&d| p.f_d(c, d) < 0.0).unwrap();
        let (r, g, b) = (zero(0), zero(1), zero(2));
        assert!(b < g && g < r, "{r} {g} {b}");
        assert!((b - 1.4).abs() < 0.15 && (g - 2.0).abs() < 0.15 && (r - 2.7).abs() < 0.2);
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
