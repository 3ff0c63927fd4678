//! Ward anisotropic BRDF (paper eq. 1; WGSL: `shaders/ward.wgsl` + `shaders/ward_lobe.wgsl`).
//!
//! Standard form (Walter 2005, "Notes on the Ward BRDF"):
//! f = ρ_d/π + ρ_s / (4π α_x α_y √(cosθ_i cosθ_o)) · exp(−tan²θ_h (cos²φ_h/α_x² + sin²φ_h/α_y²)),
//! evaluated without angles as exp(−((h·t/α_x)² + (h·b/α_y)²) / (h·n)²).
//! The paper prints φ_i and φ_o in the exponent; that variant is `ward-printed`.
//! As in §4.1 the diffuse colour ρ_d is the dipole's total diffuse reflectance R_d(α')
//! (Jensen's "BRDF approximation" of the BSSRDF) times the texture.

use super::{dipole, registry::ModelParams, Material};
use glam::DVec3;

/// Specular lobe parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lobe {
    /// Specular reflectance ρ_s.
    pub rho_s: f64,
    /// Roughness along the tangent and the bitangent.
    pub alpha_x: f64,
    pub alpha_y: f64,
}

impl Lobe {
    /// Defaults for skin: a weak, broad, slightly anisotropic lobe (Ward fits of measured skin
    /// put ρ_s at a few percent and α around 0.3).
    pub const SKIN: Lobe = Lobe { rho_s: 0.06, alpha_x: 0.30, alpha_y: 0.36 };
}

/// The paper's three sliders (§3.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sliders {
    pub diffuse: f64,
    pub ambient: f64,
    pub specular: f64,
}

impl Sliders {
    pub const DEFAULT: Sliders = Sliders { diffuse: 1.0, ambient: 1.0, specular: 1.0 };
}

/// What `ward.wgsl` reads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    pub rho_d: [f64; 3],
    pub textured: bool,
    pub lobe: Lobe,
    pub sliders: Sliders,
}

impl Params {
    pub fn new(material: &Material, lobe: &Lobe) -> Self {
        Self {
            rho_d: dipole::total_reflectance(material),
            textured: material.textured,
            lobe: *lobe,
            sliders: Sliders::DEFAULT,
        }
    }

    pub fn pack(&self) -> ModelParams {
        let d = self.rho_d;
        let (l, s) = (self.lobe, self.sliders);
        ModelParams::from_rows(&[
            [d[0] as f32, d[1] as f32, d[2] as f32, self.textured as u8 as f32],
            [l.rho_s as f32, l.alpha_x as f32, l.alpha_y as f32, 0.0],
            [s.diffuse as f32, s.ambient as f32, s.specular as f32, 0.0],
        ])
    }
}

/// The shading frame: normal, tangent, bitangent (orthonormal).
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    pub n: DVec3,
    pub t: DVec3,
    pub b: DVec3,
}

/// f64 reference of the specular lobe (standard form), `l` and `v` unit vectors.
pub fn specular(frame: &Frame, l: DVec3, v: DVec3, lobe: &Lobe) -> f64 {
    let (nl, nv) = (frame.n.dot(l), frame.n.dot(v));
    if nl <= 0.0 || nv <= 0.0 {
        return 0.0;
    }
    let h = l + v;
    let hn = h.dot(frame.n);
    if hn <= 0.0 {
        return 0.0;
    }
    let ht = h.dot(frame.t) / lobe.alpha_x;
    let hb = h.dot(frame.b) / lobe.alpha_y;
    let exponent = -(ht * ht + hb * hb) / (hn * hn);
    lobe.rho_s / (4.0 * std::f64::consts::PI * lobe.alpha_x * lobe.alpha_y * (nl * nv).sqrt())
        * exponent.exp()
}

/// f64 reference of the lobe as printed in eq. 1: tan²θ_h (cos²φ_i/α_x² + sin²φ_o/α_y²).
pub fn specular_printed(frame: &Frame, l: DVec3, v: DVec3, lobe: &Lobe) -> f64 {
    let (nl, nv) = (frame.n.dot(l), frame.n.dot(v));
    if nl <= 0.0 || nv <= 0.0 {
        return 0.0;
    }
    let h = (l + v).normalize();
    let cos_h = h.dot(frame.n);
    if cos_h <= 0.0 {
        return 0.0;
    }
    let tan2_h = (1.0 - cos_h * cos_h).max(0.0) / (cos_h * cos_h);
    let cos2_phi = |w: DVec3| {
        let (x, y) = (w.dot(frame.t), w.dot(frame.b));
        let r2 = x * x + y * y;
        if r2 > 0.0 {
            x * x / r2
        } else {
            1.0
        }
    };
    let cos2_phi_i = cos2_phi(l);
    let sin2_phi_o = 1.0 - cos2_phi(v);
    let exponent = -tan2_h
        * (cos2_phi_i / (lobe.alpha_x * lobe.alpha_x) + sin2_phi_o / (lobe.alpha_y * lobe.alpha_y));
    lobe.rho_s / (4.0 * std::f64::consts::PI * lobe.alpha_x * lobe.alpha_y * (nl * nv).sqrt())
        * exponent.exp()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame() -> Frame {
        Frame { n: DVec3::Z, t: DVec3::X, b: DVec3::Y }
    }

    #[test]
    fn standard_form_is_reciprocal() {
        let l = DVec3::new(0.3, 0.5, 0.8).normalize();
        let v = DVec3::new(-0.6, 0.1, 0.7).normalize();
        let a = specular(&frame(), l, v, &Lobe::SKIN);
        let b = specular(&frame(), v, l, &Lobe::SKIN);
        assert!((a - b).abs() <= 1e-12 * a.abs().max(1.0), "{a} vs {b}");
    }

    #[test]
    fn printed_form_is_not_reciprocal() {
        let l = DVec3::new(0.3, 0.5, 0.8).normalize();
        let v = DVec3::new(-0.6, 0.1, 0.7).normalize();
        let a = specular_printed(&frame(), l, v, &Lobe::SKIN);
        let b = specular_printed(&frame(), v, l, &Lobe::SKIN);
        assert!((a - b).abs() > 1e-6 * a, "{a} vs {b}");
    }
}
