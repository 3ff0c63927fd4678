//! A glTF skin material's volume extensions ↔ the engine's optics ([`Material`]).
//!
//! * `KHR_materials_volume`: attenuation distance d [m] and colour c give the extinction
//!   coefficient σ_t = −ln(c) / d per channel (the `KHR_materials_volume_scatter` draft,
//!   "Attenuation": with that extension σ_t counts scattering as well as absorption).
//! * `KHR_materials_volume_scatter`: the multi-scatter albedo A per channel and the
//!   Henyey–Greenstein anisotropy g; the reduced single-scattering albedo
//!   α' = σ'_s / σ'_t comes from A by [`albedo::single_scatter_albedo`].
//! * `KHR_materials_ior`: η.
//!
//! σ_t is the *unreduced* extinction σ_a + σ_s with σ_s = σ'_s / (1 − g), so
//! σ'_t = σ_a + σ'_s = σ_t / (1 − α' + α' / (1 − g)), σ'_s = α' σ'_t, σ_a = (1 − α') σ'_t.
//! glTF lengths are metres, the engine's coefficients mm⁻¹ ([`MM_PER_M`]).

use super::albedo::{multi_scatter_albedo, single_scatter_albedo};
use super::material::{Material, Origin, DEFAULT_SKIN};
use super::units::MM_PER_M;

/// The extinction coefficients the engine's skin models are built for [mm⁻¹]: a mean free
/// path from 1 µm to 1 m. A file outside this range keeps its albedo, η and g and takes the
/// default skin's σ'_t.
pub const SIGMA_T_RANGE: (f64, f64) = (1e-3, 1e3);

/// A skin material's optics as its glTF extensions declare them (already range-checked by
/// the loader: d > 0, c and A in [0, 1], g in (−1, 1), η ≥ 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VolumeOptics {
    /// `KHR_materials_volume.attenuationDistance` [m] (+∞: no attenuation).
    pub attenuation_distance_m: f64,
    /// `KHR_materials_volume.attenuationColor`.
    pub attenuation_color: [f64; 3],
    /// `KHR_materials_volume_scatter.multiscatterColor`: the multi-scatter albedo A.
    pub multiscatter: [f64; 3],
    /// `KHR_materials_volume_scatter.scatterAnisotropy`: g.
    pub anisotropy: f64,
    /// `KHR_materials_ior.ior`: η.
    pub ior: f64,
}

impl VolumeOptics {
    /// σ_t = −ln(c) / d per channel [mm⁻¹] (0 where c = 1 or d = ∞, ∞ where c = 0).
    pub fn sigma_t(&self) -> [f64; 3] {
        let d_mm = self.attenuation_distance_m * MM_PER_M;
        self.attenuation_color.map(|c| {
            let s = -c.ln() / d_mm;
            if s == 0.0 {
                0.0 // -0.0 and the like
            } else {
                s
            }
        })
    }

    /// The engine's material named `name` ([`Self::optics`]); optics within `PRESET_MATCH`
    /// of a preset take the preset's exact values (so its shipped tables serve them).
    pub fn to_material(&self, name: &str) -> (Material, Option<String>) {
        let (m, note) = self.optics(name);
        match m.matching_preset() {
            Some(p) => {
                let snapped = Material {
                    name: m.name,
                    origin: Origin::Extensions {
                        preset: p.preset_name(),
                    },
                    textured: true,
                    ..p.clone()
                };
                (snapped, note)
            }
            None => (m, note),
        }
    }

    /// The optics these values map to, as computed, and a note when the attenuation had to be
    /// replaced (σ_t outside [`SIGMA_T_RANGE`] in some channel: the default skin's σ'_t is
    /// used with the file's albedo, η and g).
    pub fn optics(&self, name: &str) -> (Material, Option<String>) {
        let g = self.anisotropy;
        let alpha = self
            .multiscatter
            .map(|a| single_scatter_albedo(a, self.ior, g));
        let sigma_t = self.sigma_t();
        let (lo, hi) = SIGMA_T_RANGE;
        let usable = sigma_t.iter().all(|s| (lo..=hi).contains(s));
        let (t_prime, note) = if usable {
            let t: [f64; 3] =
                std::array::from_fn(|c| sigma_t[c] / (1.0 - alpha[c] + alpha[c] / (1.0 - g)));
            (t, None)
        } else {
            let note = format!(
                "attenuation gives σ_t = [{:.3e}, {:.3e}, {:.3e}] mm⁻¹, outside [{lo}, {hi}]; \
                 {}'s σ'_t is used with the file's albedo",
                sigma_t[0], sigma_t[1], sigma_t[2], DEFAULT_SKIN.name
            );
            (DEFAULT_SKIN.sigma_t_prime(), Some(note))
        };
        let m = Material {
            name: name.to_owned().into(),
            origin: Origin::Extensions { preset: None },
            sigma_a: std::array::from_fn(|c| (1.0 - alpha[c]) * t_prime[c]),
            sigma_s_prime: std::array::from_fn(|c| alpha[c] * t_prime[c]),
            eta: self.ior,
            g,
            textured: true,
        };
        (m, note)
    }

    /// The extension values that declare `m`, with attenuation distance `d_m` [m] (any
    /// positive distance; the colour follows: c = exp(−σ_t d)).
    pub fn from_material(m: &Material, d_m: f64) -> VolumeOptics {
        let alpha = m.albedo();
        let d_mm = d_m * MM_PER_M;
        VolumeOptics {
            attenuation_distance_m: d_m,
            attenuation_color: std::array::from_fn(|c| {
                let sigma_t = m.sigma_a[c] + m.sigma_s_prime[c] / (1.0 - m.g);
                (-sigma_t * d_mm).exp()
            }),
            multiscatter: alpha.map(|a| multi_scatter_albedo(a, m.eta, m.g)),
            anisotropy: m.g,
            ior: m.eta,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::material::{SKIN1, WHITE_COAT};

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    #[test]
    fn albedo_relation_round_trips() {
        // The measured relation (`albedo`): one monotone map both ways below what a white
        // medium reflects, C(η); A at or above it is white.
        let white = crate::shading::subsurface::exit_normalisation(1.4);
        for i in 0..100 {
            let a = white * i as f64 / 100.0;
            let s = single_scatter_albedo(a, 1.4, 0.0);
            assert!((0.0..=1.0).contains(&s));
            assert!(
                (multi_scatter_albedo(s, 1.4, 0.0) - a).abs() < 1e-6,
                "A = {a}"
            );
        }
        assert_eq!(single_scatter_albedo(white, 1.4, 0.0), 1.0);
        // A = 0 is a pure absorber, A = 1 does not absorb, and a medium reflects much less
        // than its single-scattering albedo.
        assert!(single_scatter_albedo(0.0, 1.3, 0.0) < 1e-4);
        assert!(single_scatter_albedo(1.0, 1.3, 0.0) > 0.9999);
        assert!(single_scatter_albedo(0.5, 1.3, 0.0) > 0.9);
    }

    #[test]
    fn presets_round_trip_through_the_extensions() {
        for p in [&SKIN1, &WHITE_COAT] {
            for d in [0.0005, 0.001, 0.01] {
                let ext = VolumeOptics::from_material(p, d);
                let (m, note) = ext.to_material("Skin");
                assert!(note.is_none());
                assert_eq!(m.name, "Skin");
                assert_eq!(
                    m.origin,
                    Origin::Extensions {
                        preset: p.preset_name()
                    }
                );
                assert!(m.same_optics(p), "{m:?}");
            }
        }
    }

    #[test]
    fn values_reach_the_optics() {
        // σ_t = −ln(0.5)/1 mm, A = 0.5 → α' from the measured relation.
        let ext = VolumeOptics {
            attenuation_distance_m: 0.001,
            attenuation_color: [0.5, 0.25, 0.125],
            multiscatter: [0.5, 0.5, 0.5],
            anisotropy: 0.0,
            ior: 1.4,
        };
        let (m, note) = ext.to_material("Wax");
        assert!(note.is_none());
        assert_eq!(m.origin, Origin::Extensions { preset: None });
        let alpha = single_scatter_albedo(0.5, 1.4, 0.0);
        let ln2 = std::f64::consts::LN_2;
        for (c, k) in [1.0, 2.0, 3.0].into_iter().enumerate() {
            let sigma_t = k * ln2;
            assert!(rel(m.sigma_t_prime()[c], sigma_t) < 1e-12);
            assert!(rel(m.sigma_s_prime[c], alpha * sigma_t) < 1e-12);
            assert!(rel(m.sigma_a[c], (1.0 - alpha) * sigma_t) < 1e-12);
        }
        assert_eq!(m.eta, 1.4);
        // Forward scattering: σ_t counts σ_s = σ'_s/(1 − g), so σ'_t shrinks.
        let fwd = VolumeOptics {
            anisotropy: 0.8,
            ..ext
        };
        let (f, _) = fwd.to_material("Wax");
        assert_eq!(f.g, 0.8);
        assert!((f.albedo()[0] - alpha).abs() < 1e-12);
        let sigma_t = f.sigma_a[0] + f.sigma_s_prime[0] / (1.0 - 0.8);
        assert!(rel(sigma_t, ln2) < 1e-12);
    }

    #[test]
    fn unusable_attenuation_takes_the_default_extinction() {
        let ext = VolumeOptics {
            attenuation_distance_m: f64::INFINITY,
            attenuation_color: [1.0; 3],
            multiscatter: [0.8, 0.5, 0.3],
            anisotropy: 0.0,
            ior: 1.3,
        };
        let (m, note) = ext.to_material("Skin");
        assert!(note.unwrap().contains("outside"));
        for c in 0..3 {
            assert!(rel(m.sigma_t_prime()[c], SKIN1.sigma_t_prime()[c]) < 1e-12);
            let a = single_scatter_albedo(ext.multiscatter[c], 1.3, 0.0);
            assert!((m.albedo()[c] - a).abs() < 1e-12);
        }
    }
}
