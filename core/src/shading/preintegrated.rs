//! Mobile tier `preintegrated` (WGSL: `shaders/preintegrated.wgsl`): pre-integrated skin
//! (Penner & Borshukov, GPU Pro 2, 2011) from the material's measured kernel ([`bake`]).
//!
//! The LUT holds, per channel, the exitance of a sphere of radius ρ under a directional light
//! of unit irradiance at the point whose normal makes cos θ = n·l with the light, spreading
//! the irradiance max(cos θ_Q, 0)·q(cos θ_Q)·(kernel total) over the sphere's surface with the
//! kernel at chord distance. On a sphere the area between chord distances r and r + dr is
//! exactly 2πr dr (Archimedes), so with chord r and azimuth φ around the point the integral
//! is ∫ r dr dφ K(r) E(Q): no Jacobian. Where the sphere is smaller than the kernel, the
//! kernel is renormalised to the part that fits (energy stays on the sphere), as Penner's
//! ring integral does. Axes: u = (n·l + 1)/2, v = R0/(R0 + ρ) (v = 0: flat).
//!
//! A point light's irradiance is blurred on flat ground by lifting the light by s, the height
//! of the Poisson kernel s/(2π(s² + r²)^{3/2}) with the kernel's median radius (√3 s): Poisson
//! kernels compose by adding heights, and a point light at height h lights the plane with the
//! Poisson kernel of height h, so the blurred irradiance is that of the light at h + s.

use std::sync::{Arc, Mutex};

use super::bake::{self, Bake, SLAB_FIRST_MM};
use super::subsurface::{self, Params, LUT_R0_MM};
use super::{fresnel, Material};

/// LUT size: n·l × curvature …
pub const LUT_U: usize = 64;
pub const LUT_V: usize = 32;
/// … plus two rows that turn per-pixel maths into fetches: row [`LUT_V`] holds the exit factor
/// F_t(η, u)/(πC) (r) and the entry factor F_t(η, u)/F_t(η, 1) (g) over u = cos θ ∈ [0, 1];
/// row `LUT_V + 1` the diffuse transmittance T of a backlit slab (rgb) over
/// u = log2(t/0.25 mm)/[`SLAB_SPAN`] (0.25–128 mm), dense enough for linear filtering.
pub const LUT_ROWS: usize = LUT_V + 2;
/// Doublings of thickness the slab row spans from 0.25 mm.
pub const SLAB_SPAN: f64 = 9.0;

/// Per-channel exitance per unit irradiance, row-major over v then u, RGBA (A = 1), then the
/// two factor rows (see [`LUT_ROWS`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Lut {
    pub texels: Vec<[f32; 4]>,
}

impl Lut {
    /// The value at texel (i, j) for channel c.
    pub fn at(&self, i: usize, j: usize, c: usize) -> f32 {
        self.texels[j * LUT_U + i][c]
    }
}

/// Curvature radius (mm) of LUT row j (texel centre).
pub fn row_radius_mm(j: usize) -> f64 {
    let v = (j as f64 + 0.5) / LUT_V as f64;
    LUT_R0_MM * (1.0 - v) / v
}

/// Exitance per unit beam irradiance at the point with n·l = `mu` on a sphere of radius `rho`
/// mm, per channel (see the module docs).
pub fn sphere_response(b: &Bake, mu: f64, rho: f64) -> [f64; 3] {
    const PHI: usize = 48;
    const GAUSS: [(f64, f64); 3] = [
        (0.112_701_665_379_258_3, 5.0 / 18.0),
        (0.5, 8.0 / 18.0),
        (0.887_298_334_620_741_7, 5.0 / 18.0),
    ];
    let total = b.reflectance();
    let sin_t = (1.0 - mu * mu).max(0.0).sqrt();
    let r_max = 2.0 * rho;
    let (mut num, mut den) = ([0.0f64; 3], [0.0f64; 3]);
    for (k, w) in b.edges.windows(2).enumerate() {
        let (a, e) = (w[0], w[1].min(r_max));
        if a >= e {
            break;
        }
        let area = std::f64::consts::PI * (w[1] * w[1] - w[0] * w[0]);
        let density: [f64; 3] = std::array::from_fn(|c| b.mass[k][c] / area);
        for (x, wx) in GAUSS {
            let r = a + (e - a) * x;
            let weight = wx * (e - a) * r * std::f64::consts::TAU / PHI as f64;
            // Angle ψ between the point and Q as seen from the centre: cos ψ = 1 − r²/(2ρ²).
            let cos_psi = 1.0 - r * r / (2.0 * rho * rho);
            let sin_psi = (1.0 - cos_psi * cos_psi).max(0.0).sqrt();
            let mut irr = [0.0f64; 3];
            for p in 0..PHI {
                let phi = (p as f64 + 0.5) * std::f64::consts::TAU / PHI as f64;
                let cos_q = mu * cos_psi + sin_t * sin_psi * phi.cos();
                if cos_q > 0.0 {
                    for (c, v) in irr.iter_mut().enumerate() {
                        *v += cos_q * b.oblique_at(c, cos_q);
                    }
                }
            }
            for c in 0..3 {
                num[c] += weight * density[c] * irr[c];
                den[c] += weight * density[c] * PHI as f64;
            }
        }
    }
    std::array::from_fn(|c| {
        if den[c] > 0.0 {
            total[c] * num[c] / den[c]
        } else {
            total[c] * mu.max(0.0) * b.oblique_at(c, mu.max(0.0))
        }
    })
}

/// Bakes the LUT for the tables `b` of material `m`.
pub fn bake_lut(b: &Bake, m: &Material) -> Lut {
    let mut texels = vec![[0.0f32; 4]; LUT_U * LUT_ROWS];
    let p = params_from(b, m).pack();
    let exit_norm = 1.0 / (std::f64::consts::PI * subsurface::exit_normalisation(m.eta));
    let entry = fresnel::transmittance_shader(m.eta, 1.0).max(1e-12);
    for i in 0..LUT_U {
        let u = i as f64 / (LUT_U - 1) as f64;
        let ft = fresnel::transmittance_shader(m.eta, u);
        texels[LUT_V * LUT_U + i] = [(ft * exit_norm) as f32, (ft / entry) as f32, 0.0, 1.0];
        let t = SLAB_FIRST_MM * 2f64.powf(u * SLAB_SPAN);
        let slab = subsurface::slab_packed(&p, t);
        texels[(LUT_V + 1) * LUT_U + i] = [slab.x as f32, slab.y as f32, slab.z as f32, 1.0];
    }
    for j in 0..LUT_V {
        let rho = row_radius_mm(j);
        for i in 0..LUT_U {
            let mu = 2.0 * (i as f64 + 0.5) / LUT_U as f64 - 1.0;
            let m = sphere_response(b, mu, rho);
            texels[j * LUT_U + i] = [m[0] as f32, m[1] as f32, m[2] as f32, 1.0];
        }
    }
    Lut { texels }
}

type Cache = Mutex<Vec<(Material, Arc<Lut>)>>;
static CACHE: Cache = Mutex::new(Vec::new());

/// The LUT for `m`, baked on first use and cached for the process.
pub fn lut(m: &Material) -> Arc<Lut> {
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, l)) = cache.iter().find(|(k, _)| k == m) {
        return l.clone();
    }
    let l = Arc::new(bake_lut(&bake::for_material(m), m));
    cache.push((*m, l.clone()));
    l
}

/// Height s (mm) of the Poisson kernel with the kernel's median radius, per channel.
pub fn lift(b: &Bake) -> [f64; 3] {
    std::array::from_fn(|c| b.median_radius(c) / 3f64.sqrt())
}

pub fn params(m: &Material) -> Params {
    params_from(&bake::for_material(m), m)
}

/// The uniform for `m` from the tables `b`.
pub fn params_from(b: &Bake, m: &Material) -> Params {
    Params {
        albedo: b.reflectance(),
        eta: m.eta,
        oblique: b.oblique,
        shift: [[0.0; 3]; super::bake::OBLIQUE_NODES],
        slab: Some(b.slab),
        lift: lift(b),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::bake::{measure, Budget};
    use crate::shading::material::SKIN1;

    fn small_bake() -> Bake {
        let budget = Budget {
            kernel: 2_000,
            oblique: 500,
            slab: 500,
            kernel_events: 1_000_000,
            events: 200_000,
            max_events: 100_000,
            min_photons: 100,
        };
        measure(&SKIN1, budget, 2)
    }

    #[test]
    fn flat_ground_is_the_local_response_and_the_lut_is_deterministic() {
        let b = small_bake();
        for mu in [0.2, 0.5, 0.9] {
            let m = sphere_response(&b, mu, 1e7);
            let t = b.reflectance();
            for c in 0..3 {
                let want = t[c] * mu * b.oblique_at(c, mu);
                assert!(
                    (m[c] / want - 1.0).abs() < 1e-3,
                    "μ {mu} c {c}: {} vs {want}",
                    m[c]
                );
            }
        }
        assert_eq!(bake_lut(&b, &SKIN1), bake_lut(&small_bake(), &SKIN1));
    }

    #[test]
    fn small_spheres_wrap_light_past_the_terminator() {
        let b = small_bake();
        // Just past the terminator a 5 mm sphere still glows red; flat ground does not.
        let curved = sphere_response(&b, -0.1, 5.0);
        let flat = sphere_response(&b, -0.1, 1e7);
        assert!(curved[0] > 0.0 && flat[0] == 0.0);
        assert!(
            curved[0] > curved[2],
            "red wraps further than blue: {curved:?}"
        );
    }
}
