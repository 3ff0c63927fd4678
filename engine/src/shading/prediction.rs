//! Each model's own prediction of the total diffuse reflectance of a semi-infinite medium and
//! of a slab (per unit power entering the medium, specular reflection excluded — Jensen's R_d
//! convention), for comparison with the Monte Carlo reference (`dermis sss`).
//!
//! What a model can say about a slab follows from its formula: the Ward BRDF, the dipole and
//! Burley's profile describe a semi-infinite medium, so their slab prediction is their
//! semi-infinite one; OSS is a layer model, f_d(d). For the semi-infinite medium OSS is
//! evaluated at [`OSS_SEMI_INFINITE_MM`] (its printed form has no finite limit).

use super::{bake, dipole, fresnel, oss, Material, ShadingModel};

/// Depth at which OSS stands in for a semi-infinite medium (mm).
pub const OSS_SEMI_INFINITE_MM: f64 = 100.0;

/// Total diffuse reflectance predicted by `model` for `material`, for a slab of `slab_mm`
/// millimetres or (None) a semi-infinite medium (the model's row of the registry table).
pub fn total_reflectance(
    model: ShadingModel,
    material: &Material,
    slab_mm: Option<f64>,
) -> [f64; 3] {
    (model.descriptor().total_reflectance)(material, slab_mm)
}

/// The printed dipole's profile integrated numerically (it has no closed form).
pub fn dipole_printed(material: &Material) -> [f64; 3] {
    let p = dipole::Params::new(material);
    std::array::from_fn(|c| integrate_radial(|r| p.profile_printed(c, r)))
}

/// OSS's layer reflectance f_d(d), at [`OSS_SEMI_INFINITE_MM`] for a semi-infinite medium.
pub fn oss(material: &Material, slab_mm: Option<f64>, stable: bool) -> [f64; 3] {
    let p = oss::Params::new(material);
    let d = slab_mm.unwrap_or(OSS_SEMI_INFINITE_MM);
    std::array::from_fn(|c| {
        if stable {
            p.f_d_stable(c, d)
        } else {
            p.f_d(c, d)
        }
    })
}

/// The measured kernel's total, per entered power; a slab's reflectance is not in the
/// tables (their translucency is the light through it).
pub fn measured(material: &Material) -> [f64; 3] {
    let t = bake::for_material(material).reflectance();
    let entry = fresnel::transmittance_shader(material.eta, 1.0);
    t.map(|r| r / entry)
}

/// ∫₀^∞ 2πr f(r) dr by the substitution r = e^u (profiles span many decades).
pub fn integrate_radial(f: impl Fn(f64) -> f64) -> f64 {
    let (u0, u1, n) = ((1e-8f64).ln(), (1e5f64).ln(), 20_000);
    let du = (u1 - u0) / n as f64;
    (0..n)
        .map(|i| {
            let r = (u0 + (i as f64 + 0.5) * du).exp();
            2.0 * std::f64::consts::PI * r * r * f(r) * du
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::material::SKIN1;

    #[test]
    fn the_standard_dipole_integrates_to_its_closed_form() {
        let p = dipole::Params::new(&SKIN1);
        let closed = dipole::total_reflectance(&SKIN1);
        for (c, closed) in closed.iter().enumerate() {
            let num = integrate_radial(|r| p.profile(c, r));
            assert!((num / closed - 1.0).abs() < 1e-4, "{num} vs {closed}");
        }
    }

    #[test]
    fn the_printed_dipole_does_not() {
        let printed = total_reflectance(ShadingModel::DipolePrinted, &SKIN1, None);
        let standard = dipole::total_reflectance(&SKIN1);
        assert!((printed[2] / standard[2] - 1.0).abs() > 0.01);
    }
}
