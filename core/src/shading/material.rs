//! Optical material presets (σ in mm⁻¹).

/// A homogeneous scattering material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    pub name: &'static str,
    /// Absorption coefficient σ_a per RGB channel [mm⁻¹].
    pub sigma_a: [f64; 3],
    /// Reduced scattering coefficient σ'_s per RGB channel [mm⁻¹].
    pub sigma_s_prime: [f64; 3],
    /// Relative index of refraction η.
    pub eta: f64,
    /// Henyey–Greenstein anisotropy g (0: σ'_s already reduced, isotropic).
    pub g: f64,
    /// Whether the character's base-colour texture tints the models that use one
    /// (skin: yes; the paper's white-coat material is shown untextured).
    pub textured: bool,
}

/// Skin, Jensen et al. 2001 (skin1).
pub const SKIN1: Material = Material {
    name: "skin1",
    sigma_a: [0.032, 0.17, 0.48],
    sigma_s_prime: [0.74, 0.88, 1.01],
    eta: 1.3,
    g: 0.0,
    textured: true,
};

/// The paper's white-coated material (§4.1, Fig. 1), fitted by Levenberg–Marquardt.
pub const WHITE_COAT: Material = Material {
    name: "white-coat",
    sigma_a: [0.000905, 0.001083, 0.002038],
    sigma_s_prime: [1.94, 1.94, 1.874],
    eta: 1.0936,
    g: 0.0,
    textured: false,
};

/// Every preset, in menu order.
pub const PRESETS: &[Material] = &[SKIN1, WHITE_COAT];

impl Material {
    /// Looks a preset up by name.
    pub fn preset(name: &str) -> Option<Material> {
        PRESETS.iter().copied().find(|m| m.name == name)
    }

    /// σ'_t = σ_a + σ'_s per channel.
    pub fn sigma_t_prime(&self) -> [f64; 3] {
        std::array::from_fn(|c| self.sigma_a[c] + self.sigma_s_prime[c])
    }

    /// Reduced albedo α' = σ'_s / σ'_t per channel.
    pub fn albedo(&self) -> [f64; 3] {
        let t = self.sigma_t_prime();
        std::array::from_fn(|c| {
            if t[c] > 0.0 {
                self.sigma_s_prime[c] / t[c]
            } else {
                0.0
            }
        })
    }

    /// 1 − α' computed without cancellation, as σ_a / σ'_t.
    pub fn one_minus_albedo(&self) -> [f64; 3] {
        let t = self.sigma_t_prime();
        std::array::from_fn(|c| {
            if t[c] > 0.0 {
                self.sigma_a[c] / t[c]
            } else {
                1.0
            }
        })
    }

    /// Effective transport coefficient σ_tr = √(3 σ_a σ'_t) [mm⁻¹].
    pub fn sigma_tr(&self) -> [f64; 3] {
        let t = self.sigma_t_prime();
        std::array::from_fn(|c| (3.0 * self.sigma_a[c] * t[c]).sqrt())
    }
}
