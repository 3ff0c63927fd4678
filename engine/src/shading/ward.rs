//! Ward anisotropic BRDF (paper eq. 1; WGSL: `shaders/ward.wgsl` + `shaders/ward_lobe.wgsl`).
//!
//! Standard form (Walter 2005, "Notes on the Ward BRDF"):
//! f = ρ_d/π + ρ_s / (4π α_x α_y √(cosθ_i cosθ_o)) · exp(−tan²θ_h (cos²φ_h/α_x² + sin²φ_h/α_y²)),
//! evaluated without angles as exp(−((h·t/α_x)² + (h·b/α_y)²) / (h·n)²).
//! The paper prints φ_i and φ_o in the exponent; that variant is `ward-printed`.
//! As in §4.1 the diffuse colour ρ_d is the dipole's total diffuse reflectance R_d(α')
//! (Jensen's "BRDF approximation" of the BSSRDF) times the texture.

use super::{
    dipole,
    pixel::Pixel,
    uniform::{f32x3, model_uniform, rgb, ModelParams, Uniform},
    Descriptor, Effects, Material,
};
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
    pub const SKIN: Lobe = Lobe {
        rho_s: 0.06,
        alpha_x: 0.30,
        alpha_y: 0.36,
    };
}

/// The paper's three sliders (§3.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sliders {
    pub diffuse: f64,
    pub ambient: f64,
    pub specular: f64,
}

impl Sliders {
    pub const DEFAULT: Sliders = Sliders {
        diffuse: 1.0,
        ambient: 1.0,
        specular: 1.0,
    };
}

model_uniform! {
    /// What `ward.wgsl` reads (`#import WardUniform`, generated from this declaration).
    pub struct WardUniform {
        /// R_d(α') (the diffuse colour before the texture).
        pub rho_d: [f32; 3],
        /// 1 when the texture tints the diffuse colour.
        pub textured: f32,
        /// The specular lobe ([`Lobe`]).
        pub rho_s: f32,
        pub alpha_x: f32,
        pub alpha_y: f32,
        /// The paper's sliders (§3.1): diffuse, ambient, specular.
        pub slider_diffuse: f32,
        pub slider_ambient: f32,
        pub slider_specular: f32,
        pub _pad0: f32,
        pub _pad1: f32,
    }
}

impl WardUniform {
    /// The lobe as the shader sees it.
    pub fn lobe(&self) -> Lobe {
        Lobe {
            rho_s: self.rho_s.into(),
            alpha_x: self.alpha_x.into(),
            alpha_y: self.alpha_y.into(),
        }
    }
}

/// What `ward.wgsl` reads, in f64 ([`WardUniform`] packed).
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

    pub fn uniform(&self) -> WardUniform {
        let (l, s) = (self.lobe, self.sliders);
        WardUniform {
            rho_d: f32x3(self.rho_d),
            textured: self.textured as u8 as f32,
            rho_s: l.rho_s as f32,
            alpha_x: l.alpha_x as f32,
            alpha_y: l.alpha_y as f32,
            slider_diffuse: s.diffuse as f32,
            slider_ambient: s.ambient as f32,
            slider_specular: s.specular as f32,
            ..bytemuck::Zeroable::zeroed()
        }
    }

    pub fn pack(&self) -> ModelParams {
        ModelParams::from_uniform(&self.uniform())
    }
}

/// The shading frame: normal, tangent, bitangent (orthonormal).
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    pub n: DVec3,
    pub t: DVec3,
    pub b: DVec3,
}

/// Smallest roughness the lobe is evaluated with (`WARD_ALPHA_MIN` in `ward_nd.wgsl`): keeps
/// α_x α_y from underflowing, which would turn ρ_s/(4π α_x α_y …) · exp(−∞) into ∞ · 0.
pub const ALPHA_MIN: f64 = 1e-3;

/// Smallest cosθ_i cosθ_o under the lobe's square root (bounded at grazing angles).
pub const COS_PRODUCT_MIN: f64 = 1e-6;

/// f64 twin of `ward_lobe_nd` (`shaders/ward_nd.wgsl`): Walter's form on the cosines
/// `nl` = n·l, `nv` = n·v and the components (`ht`, `hb`, `hn`) of h = l + v (unnormalised)
/// in the frame (t, b, n), with the same guards: zero for nl ≤ 0, nv ≤ 0 or hn ≤ 1e-6
/// (θ_h → 90°, l = −v); √ of max(nl nv, [`COS_PRODUCT_MIN`]); α ≥ [`ALPHA_MIN`]. No azimuth is
/// formed, so h ∥ n (φ_h undefined) is an ordinary point (exponent 0).
#[allow(clippy::too_many_arguments)]
pub fn lobe_nd(nl: f64, nv: f64, ht: f64, hb: f64, hn: f64, rho_s: f64, ax: f64, ay: f64) -> f64 {
    if nl <= 0.0 || nv <= 0.0 || hn <= 1e-6 {
        return 0.0;
    }
    let (ax, ay) = (ax.max(ALPHA_MIN), ay.max(ALPHA_MIN));
    let (x, y) = (ht / ax, hb / ay);
    let e = -(x * x + y * y) / (hn * hn);
    rho_s / (4.0 * std::f64::consts::PI * ax * ay * (nl * nv).max(COS_PRODUCT_MIN).sqrt()) * e.exp()
}

/// f64 reference of the specular lobe (standard form), `l` and `v` unit vectors: exactly what
/// `ward_specular` computes without `WARD_PRINTED`.
pub fn specular(frame: &Frame, l: DVec3, v: DVec3, lobe: &Lobe) -> f64 {
    let h = l + v;
    lobe_nd(
        frame.n.dot(l),
        frame.n.dot(v),
        h.dot(frame.t),
        h.dot(frame.b),
        h.dot(frame.n),
        lobe.rho_s,
        lobe.alpha_x,
        lobe.alpha_y,
    )
}

/// f64 reference of the lobe as printed in eq. 1: tan²θ_h (cos²φ_i/α_x² + sin²φ_o/α_y²), with
/// the guards of `ward_specular` under `WARD_PRINTED` (no α clamp: that is part of the defect).
pub fn specular_printed(frame: &Frame, l: DVec3, v: DVec3, lobe: &Lobe) -> f64 {
    let (nl, nv) = (frame.n.dot(l), frame.n.dot(v));
    if nl <= 0.0 || nv <= 0.0 {
        return 0.0;
    }
    if (l + v).dot(frame.n) <= 1e-6 {
        return 0.0;
    }
    let h = (l + v).normalize();
    let cos_h = h.dot(frame.n);
    let tan2_h = (1.0 - cos_h * cos_h).max(0.0) / (cos_h * cos_h);
    let cos2_phi = |w: DVec3| {
        let (x, y) = (w.dot(frame.t), w.dot(frame.b));
        let r2 = x * x + y * y;
        if r2 > 1e-12 {
            x * x / r2
        } else {
            1.0
        }
    };
    let cos2_phi_i = cos2_phi(l);
    let sin2_phi_o = 1.0 - cos2_phi(v);
    let exponent = -tan2_h
        * (cos2_phi_i / (lobe.alpha_x * lobe.alpha_x) + sin2_phi_o / (lobe.alpha_y * lobe.alpha_y));
    lobe.rho_s
        / (4.0
            * std::f64::consts::PI
            * lobe.alpha_x
            * lobe.alpha_y
            * (nl * nv).max(COS_PRODUCT_MIN).sqrt())
        * exponent.exp()
}

/// f64 reference of `ward.wgsl`'s `shade` for the packed uniform `p` (read back to f64, so
/// the comparison sees only the shader's arithmetic) and one pixel.
pub fn shade(p: &ModelParams, printed: bool, px: &Pixel) -> DVec3 {
    let u: &WardUniform = p.uniform();
    let tex = if u.textured > 0.5 {
        px.albedo
    } else {
        DVec3::ONE
    };
    let kd = rgb(u.rho_d) * tex;
    let slider = |v: f32| f64::from(v);
    let ambient = px.ambient * kd * slider(u.slider_ambient);
    let nl = px.n.dot(px.l);
    if nl <= 0.0 {
        return ambient;
    }
    let spec = lobe_specular(px, &u.lobe(), printed);
    ambient
        + px.irradiance()
            * nl
            * (kd * slider(u.slider_diffuse) / std::f64::consts::PI
                + DVec3::splat(spec * slider(u.slider_specular)))
}

/// f64 reference of the probed `ward_specular` for the packed uniform `p` (grey).
pub fn probe(p: &ModelParams, printed: bool, px: &Pixel) -> DVec3 {
    let u: &WardUniform = p.uniform();
    DVec3::splat(lobe_specular(px, &u.lobe(), printed))
}

/// `ward_specular(s, …)` for a pixel, either variant.
pub fn lobe_specular(px: &Pixel, lobe: &Lobe, printed: bool) -> f64 {
    let frame = Frame {
        n: px.n,
        t: px.t,
        b: px.b,
    };
    if printed {
        specular_printed(&frame, px.l, px.v, lobe)
    } else {
        specular(&frame, px.l, px.v, lobe)
    }
}

const WGSL: &str = include_str!("../../../shaders/ward.wgsl");

/// Ward is a BRDF: none of the effects a pass or a table serves.
const EFFECTS: Effects = Effects::NONE;

/// The probed sub-function in WGSL: the specular lobe.
const PROBE_WGSL: &str = "vec3<f32>(ward_specular(s, model.rho_s, model.alpha_x, model.alpha_y))";

/// `ward`: the standard half-vector form.
pub const WARD: Descriptor = Descriptor {
    name: "ward",
    label: "Ward BRDF",
    module: "ward",
    wgsl: WGSL,
    variant: None,
    effects: EFFECTS,
    uniform: WardUniform::LAYOUT,
    params: |m| Params::new(m, &Lobe::SKIN).pack(),
    params_from: None,
    kernel: None,
    lut: None,
    shade: |p, px| shade(p, false, px),
    probe: |p, px, _| probe(p, false, px),
    probe_wgsl: PROBE_WGSL,
    total_reflectance: |m, _| dipole::total_reflectance(m),
    consts: &[],
};

/// `ward-printed`: eq. 1 as printed.
pub const WARD_PRINTED: Descriptor = Descriptor {
    name: "ward-printed",
    label: "Ward BRDF (as printed)",
    variant: Some("WARD_PRINTED"),
    shade: |p, px| shade(p, true, px),
    probe: |p, px, _| probe(p, true, px),
    ..WARD
};

#[cfg(test)]
mod tests {
    use super::*;

    fn frame() -> Frame {
        Frame {
            n: DVec3::Z,
            t: DVec3::X,
            b: DVec3::Y,
        }
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
