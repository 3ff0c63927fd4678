//! One pixel's shading inputs in f64, as the renderer's `make_surface` produces them: what
//! each model's f64 reference (`ward::shade`, `dipole::shade`, `oss::shade`,
//! `subsurface::local`) evaluates, and what the GPU conformance harness
//! (`dermis_measure::conformance`) feeds the renderer's WGSL.

use glam::DVec3;

use super::units;

/// One pixel's shading inputs, as `make_surface` produces them (world-space unit vectors).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pixel {
    pub n: DVec3,
    pub t: DVec3,
    pub b: DVec3,
    pub l: DVec3,
    pub v: DVec3,
    /// Distance to the light [m] (the shader sees at least 1 mm).
    pub light_dist_m: f64,
    /// Light intensity × colour.
    pub light: DVec3,
    /// Base colour.
    pub albedo: DVec3,
    /// Thickness through the point [m] (the shader sees at least 0).
    pub thickness_m: f64,
    /// Ambient radiance (the Frame uniform's `ambient`).
    pub ambient: DVec3,
    /// Radius of curvature of the surface [m] (`make_surface`, and so the conformance
    /// harness: flat, [`units::FLAT_RADIUS_M`]).
    pub curvature_radius_m: f64,
}

impl Pixel {
    /// A pixel in the frame n = z, t = x, b = y with the given light and view directions.
    pub fn new(l: DVec3, v: DVec3) -> Self {
        Self {
            n: DVec3::Z,
            t: DVec3::X,
            b: DVec3::Y,
            l,
            v,
            light_dist_m: 3.0,
            light: DVec3::splat(10.0),
            albedo: DVec3::new(0.8, 0.6, 0.5),
            thickness_m: 0.1,
            ambient: DVec3::new(0.05, 0.04, 0.03),
            curvature_radius_m: units::FLAT_RADIUS_M,
        }
    }

    /// The light distance the shader uses [m].
    pub fn light_dist(&self) -> f64 {
        self.light_dist_m.max(units::LIGHT_D_MIN_M)
    }

    /// The thickness the shader uses [m].
    pub fn thickness(&self) -> f64 {
        self.thickness_m.max(0.0)
    }

    /// `irradiance(s)`: light / distance².
    pub fn irradiance(&self) -> DVec3 {
        let d = self.light_dist();
        self.light / (d * d)
    }

    /// This pixel with every input rounded to f32, as the GPU receives it.
    pub fn to_f32(&self) -> Self {
        let v = |x: DVec3| x.as_vec3().as_dvec3();
        let s = |x: f64| x as f32 as f64;
        Self {
            n: v(self.n),
            t: v(self.t),
            b: v(self.b),
            l: v(self.l),
            v: v(self.v),
            light_dist_m: s(self.light_dist_m),
            light: v(self.light),
            albedo: v(self.albedo),
            thickness_m: s(self.thickness_m),
            ambient: v(self.ambient),
            curvature_radius_m: s(self.curvature_radius_m),
        }
    }
}
