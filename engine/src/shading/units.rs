//! Units and the models' scale factors, in one place.
//!
//! * glTF positions and distances are in **metres**.
//! * Optical coefficients (σ_a, σ'_s, σ_tr) are in **mm⁻¹**; lengths that meet them are
//!   converted to millimetres first: `mm = m × MM_PER_M`.
//! * Each model turns scene distances into its own inputs with one documented factor below,
//!   chosen so the character at game scale (light 2–4 m away) looks like lit skin.

/// Millimetres per metre.
pub const MM_PER_M: f64 = 1000.0;

/// Dipole ("scaled BSSRDF", §3.2): r [mm] = light distance [m] × `MM_PER_M` × this.
/// The paper replaces the entry–exit distance by the scaled distance to the light; with
/// 1e-3 a light 3 m away gives r = 3 mm, where skin1's profile is strongly red-shifted.
pub const DIPOLE_R_SCALE: f64 = 1.0e-3;

/// Dipole: the area [mm²] over which R_d(r) [mm⁻²] is integrated into a reflectance-like
/// factor, i.e. radiance = I · F_t · F_t · R_d(r) · area / π. Chosen so skin1 under the
/// default light has a luminance comparable to Ward's.
pub const DIPOLE_AREA_MM2: f64 = 16.0;

/// OSS (eq. 5): the depth d [mm] = vertex thickness [m] × `MM_PER_M` × this. Limbs 0.07–0.11 m
/// thick map to 0.9–1.3 mm, where eq. 5's colour is skin-red; the printed polynomial turns
/// negative beyond ~1.4 mm (blue) to ~2.9 mm (red) for skin1, so the torso (0.25 m → 3 mm)
/// shows the printed model's defect (dark), which OSS's stable form fixes.
pub const OSS_DEPTH_SCALE: f64 = 1.2e-2;

/// OSS translucency term 20·ρ_ts/d^2.5 (eq. 6): d is the light distance in metres, clamped
/// below at this value so the term stays bounded (d^-2.5 ≤ 0.1^-2.5 ≈ 316).
pub const OSS_LIGHT_D_MIN_M: f64 = 0.1;

/// Smallest light distance any model sees [m] (the light never sits inside the skin).
pub const LIGHT_D_MIN_M: f64 = 1.0e-3;

/// The radius of curvature [m] a surface has where it is flat or unknown.
pub const FLAT_RADIUS_M: f64 = 1.0e6;
