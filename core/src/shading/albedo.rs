//! Multi-scatter albedo A ↔ reduced single-scattering albedo α' = σ'_s / σ'_t.
//!
//! A is the medium's total diffuse reflectance under uniform (diffuse) light, boundary
//! included, specular excluded; η the relative index of refraction; g the Henyey–Greenstein
//! anisotropy.
//!
//! **Stand-in.** These are the analytic relation of the `KHR_materials_volume_scatter` draft
//! (KhronosGroup/glTF, `extensions/2.0/Khronos/KHR_materials_volume_scatter/README.md`,
//! "Multi-Scatter Albedo", after Kulla & Conty 2017):
//! ρ_ss = 1 − (4.09712 + 4.20863 A − √(9.59217 + 41.6808 A + 17.7126 A²))²,
//! which ignores η and g (it is taken here as α', equal to σ_s/σ_t at g = 0), and its exact
//! inverse. The table measured with the project's Monte Carlo replaces this file at merge.

/// The reduced single-scattering albedo α' of a medium whose multi-scatter albedo is `multi`
/// (clamped to [0, 1]; the result is in [0, 1]).
pub fn single_scatter_albedo(multi: f64, _eta: f64, _g: f64) -> f64 {
    let a = if multi.is_nan() {
        0.0
    } else {
        multi.clamp(0.0, 1.0)
    };
    let k = 4.09712 + 4.20863 * a - (9.59217 + 41.6808 * a + 17.7126 * a * a).sqrt();
    (1.0 - k * k).clamp(0.0, 1.0)
}

/// The multi-scatter albedo A of a medium whose reduced single-scattering albedo is `single`
/// (clamped to [0, 1]; the result is in [0, 1]): the draft's relation solved for A. With
/// k = √(1 − α') and u = 4.09712 − k, squaring k = u + 4.20863 A − √(…) gives
/// a A² + b A + c = 0 with a = 4.20863² − 17.7126 (≈ −3·10⁻⁵), b = 2·4.20863 u − 41.6808,
/// c = u² − 9.59217; the root taken is the one that tends to −c/b as a → 0.
pub fn multi_scatter_albedo(single: f64, _eta: f64, _g: f64) -> f64 {
    let s = if single.is_nan() {
        0.0
    } else {
        single.clamp(0.0, 1.0)
    };
    let u = 4.09712 - (1.0 - s).sqrt();
    let a = 4.20863 * 4.20863 - 17.7126;
    let b = 2.0 * 4.20863 * u - 41.6808;
    let c = u * u - 9.59217;
    let disc = (b * b - 4.0 * a * c).max(0.0).sqrt();
    let q = -0.5 * (b + b.signum() * disc);
    let root = if q != 0.0 { c / q } else { 0.0 };
    root.clamp(0.0, 1.0)
}
