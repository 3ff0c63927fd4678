//! Spatial model `burley` (WGSL: `shaders/subsurface.wgsl`, shared by the screen-space
//! models): Christensen–Burley normalised diffusion, spread over the screen by the subsurface
//! pass.
//!
//! R(r) = A (e^{−r/d} + e^{−r/(3d)}) / (8π d r), which integrates to A over the plane, with the
//! cumulative power inside r, A (1 − ¼e^{−r/d} − ¾e^{−r/(3d)}), in closed form: the pass's
//! ring masses are its exact integrals. d = ℓ_d / s with ℓ_d = 1/σ_tr the diffuse mean free path
//! of each channel and s = 3.5 + 100 (A − 0.33)⁴, Christensen and Burley's fit for that
//! parametrisation (their "dmfp" fit; the searchlight fit s = 1.85 − A + 7|A − 0.8|³ with
//! ℓ = 1/σ'_t, used before, put the white coat's tail at ~1.6 mm where its diffusion length is
//! ~14 mm). A is the total diffuse
//! reflectance from the transport solution ([`transport`]), per entered power; the kernel is
//! per incident power (× F_t at normal incidence), oblique incidence by Fresnel alone
//! (q(μ) = F_t(μ)/F_t(1)), no translucency table: an analytic model with no Monte Carlo input.

use super::bake::{self, OBLIQUE_NODES};
use super::subsurface::{self, Kernel, Params};
use super::{fresnel, transport, Descriptor, Effects, Material};

/// Smallest r [mm] the profile is evaluated at (R ∝ 1/r).
pub const R_MIN_MM: f64 = 1e-4;

/// Christensen–Burley's scale for the diffuse-mean-free-path parametrisation.
pub fn scale(albedo: f64) -> f64 {
    3.5 + 100.0 * (albedo - 0.33).powi(4)
}

/// Total diffuse reflectance A of the semi-infinite medium per channel (per entered power),
/// from the discrete-ordinates transport solution in [`transport`].
pub fn surface_albedo(m: &Material) -> [f64; 3] {
    transport::albedo_rgb(m)
}

/// The profile on x = r/d: R·d² = A (e^{−x} + e^{−x/3})/(8π x).
pub fn rd_nd(x: f64, a: f64) -> f64 {
    a * ((-x).exp() + (-x / 3.0).exp()) / (8.0 * std::f64::consts::PI * x)
}

/// The profile's shape parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Profile {
    /// A per entered power.
    pub albedo: [f64; 3],
    /// d = ℓ_d / s [mm].
    pub d: [f64; 3],
    /// F_t(η, 1): power entering at normal incidence.
    pub entry: f64,
}

impl Profile {
    pub fn new(m: &Material) -> Self {
        let albedo = surface_albedo(m);
        let tr = m.sigma_tr();
        Self {
            albedo,
            d: std::array::from_fn(|c| 1.0 / (tr[c].max(1e-12) * scale(albedo[c]))),
            entry: fresnel::transmittance_shader(m.eta, 1.0),
        }
    }

    /// R(r) [mm⁻²] for channel `c`, per entered power.
    pub fn profile(&self, c: usize, r: f64) -> f64 {
        let k = 1.0 / self.d[c];
        k * k * rd_nd(k * r.max(R_MIN_MM), self.albedo[c])
    }

    /// Power per entered power leaving inside radius r (mm).
    pub fn cumulative(&self, c: usize, r: f64) -> f64 {
        let x = r / self.d[c];
        self.albedo[c] * (1.0 - 0.25 * (-x).exp() - 0.75 * (-x / 3.0).exp())
    }
}

pub fn params(m: &Material) -> Params {
    let p = Profile::new(m);
    Params {
        albedo: std::array::from_fn(|c| p.albedo[c] * p.entry),
        eta: m.eta,
        oblique: std::array::from_fn(|k| {
            let mu = bake::oblique_node(k);
            [fresnel::transmittance_shader(m.eta, mu) / p.entry.max(1e-12); 3]
        }),
        shift: [[0.0; 3]; OBLIQUE_NODES],
        slab: None,
        lift: [0.0; 3],
        entry_reach_mm: 0.0,
    }
}

/// The ring masses: exact integrals of the profile over the same rings as the measured
/// kernel's ([`bake::ring_edges`]).
pub fn kernel(m: &Material) -> Kernel {
    let p = Profile::new(m);
    let edges = bake::ring_edges(m);
    let mass: Vec<[f64; 3]> = edges
        .windows(2)
        .map(|w| std::array::from_fn(|c| (p.cumulative(c, w[1]) - p.cumulative(c, w[0])) * p.entry))
        .collect();
    Kernel::from_rings(&edges, &mass)
}

/// `burley`.
pub const BURLEY: Descriptor = Descriptor {
    name: "burley",
    label: "Burley diffusion",
    variant: None,
    effects: Effects {
        subsurface: true,
        screen_space: true,
        ..Effects::NONE
    },
    params: |m| params(m).pack(),
    params_from: None,
    kernel: Some(kernel),
    lut: None,
    total_reflectance: |m, _| surface_albedo(m),
    ..subsurface::SPATIAL
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::material::SKIN1;

    #[test]
    fn profile_integrates_to_the_albedo() {
        let p = Profile::new(&SKIN1);
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
