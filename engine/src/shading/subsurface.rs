//! Shared by the spatial subsurface models, those whose descriptor starts from [`SPATIAL`]
//! (WGSL: `shaders/subsurface.wgsl`): their one uniform layout, the diffusion kernel the
//! screen-space pass spreads irradiance with, and the f64 twins of the per-pixel split.
//!
//! A spatial model's pixel receives the surface irradiance E = I cosθ/d² weighted by q(μ), the
//! diffuse reflectance at incidence μ relative to normal incidence; the screen-space pass
//! spreads it with the normal-incidence kernel (exitance per unit incident power, rings of
//! exact mass); the exitance M leaves with radiance M · F_t(η, n·v)/(π C(η)), C(η) =
//! ∫₀¹ F_t(η, μ) 2μ dμ, which integrates back to M over the hemisphere.

use glam::DVec3;

use super::bake::{OBLIQUE_NODES, SLAB_FIRST_MM, SLAB_NODES};
use super::pixel::Pixel;
use super::uniform::{f32x3, model_uniform, rgb, ModelParams, Uniform};
use super::{fresnel, units, Descriptor, Effects};
use crate::gpu_struct;

/// Rings the screen-space pass can take (`MAX_RINGS` in `sss_pass.wgsl`).
pub const MAX_RINGS: usize = 24;
/// Transmittances below this are packed as this (ln T stays finite: −69).
const SLAB_FLOOR: f64 = 1e-30;

/// Sample directions per ring (the pass's default quality).
pub const ANGLES: u32 = 8;
/// Relative pixel-size difference beyond which a neighbour is another surface.
pub const DEPTH_TOLERANCE: f32 = 0.1;
/// The smallest view cosine the exit factor F_t(η, n·v) is taken at (F_t(1.4, 0.25) = 0.76 of
/// 0.97 at normal view). A shaded pixel at a silhouette sees its surface at grazing over a
/// sub-pixel band, where the path-traced truth averages F_t over the pixel's footprint; the
/// shading normal (normal-mapped, interpolated) reaches n·v ≈ 0 there and took F_t → 0: a thin
/// dark outline along the nose and the eyelids in both spatial models, absent in `ward`
/// (which has no exit factor) and gone with this floor.
pub const EXIT_COSINE_MIN: f64 = 0.25;
/// The pre-integration LUT's curvature scale R0 (mm): the LUT's v axis is R0/(R0 + ρ).
pub const LUT_R0_MM: f64 = 10.0;

/// C(η) = ∫₀¹ F_t(η, μ) 2μ dμ: the fraction of a Lambertian outside radiance that enters,
/// i.e. (by reciprocity) the normalisation of the exit distribution F_t(θ_o)/(πC).
pub fn exit_normalisation(eta: f64) -> f64 {
    let n = 2000;
    (0..n)
        .map(|i| {
            let mu = (i as f64 + 0.5) / n as f64;
            fresnel::transmittance_shader(eta, mu) * 2.0 * mu / n as f64
        })
        .sum()
}

/// The radial kernel the screen-space pass applies: the exitance per unit incident power at
/// normal incidence, as power fractions over the inner disk and over rings.
#[derive(Clone, Debug, PartialEq)]
pub struct Kernel {
    /// Mass of the inner disk (taken at the pixel itself), per channel.
    pub centre: [f64; 3],
    /// Radius of the inner disk (mm).
    pub centre_radius: f64,
    /// (mass per channel, outer radius mm) of each ring; ring k starts where ring k − 1 ends.
    pub rings: Vec<([f64; 3], f64)>,
}

impl Kernel {
    /// From ring edges (mm, edges[0] = 0) and the power leaving through each ring.
    pub fn from_rings(edges: &[f64], mass: &[[f64; 3]]) -> Self {
        let centre = mass.first().copied().unwrap_or([0.0; 3]);
        let rings = edges
            .windows(2)
            .zip(mass)
            .skip(1)
            .map(|(w, m)| (*m, w[1]))
            .take(MAX_RINGS)
            .collect();
        Self {
            centre,
            centre_radius: edges.get(1).copied().unwrap_or(0.0),
            rings,
        }
    }

    /// Total power fraction (the diffuse reflectance at normal incidence).
    pub fn total(&self) -> [f64; 3] {
        std::array::from_fn(|c| self.centre[c] + self.rings.iter().map(|r| r.0[c]).sum::<f64>())
    }

    /// The uniform of `sss_pass.wgsl`: the counts, the background colour, the centre, then
    /// (mass, outer radius) per ring.
    pub fn pack(&self, angles: u32, background: [f32; 4]) -> KernelUniform {
        let mass = |m: [f64; 3]| m.map(|x| x as f32);
        let mut rings = [Ring::default(); MAX_RINGS];
        for (slot, (m, r)) in rings.iter_mut().zip(&self.rings) {
            *slot = Ring {
                mass: mass(*m),
                outer_mm: *r as f32,
            };
        }
        KernelUniform {
            ring_count: self.rings.len().min(MAX_RINGS) as u32,
            angles,
            depth_tolerance: DEPTH_TOLERANCE,
            _pad0: 0.0,
            background,
            centre_mass: mass(self.centre),
            centre_radius_mm: self.centre_radius as f32,
            rings,
        }
    }
}

gpu_struct! {
    /// What `sss_pass.wgsl` reads at `@group(1) @binding(0)`.
    pub struct KernelUniform {
        /// Rings used.
        pub ring_count: u32,
        /// Directions sampled per ring.
        pub angles: u32,
        /// How far a sample's pixel size may differ from the centre's (relative) and still
        /// count as the same surface.
        pub depth_tolerance: f32,
        pub _pad0: f32,
        /// The clear colour as displayed (where nothing was drawn).
        pub background: [f32; 4],
        /// Mass of the inner disk (taken at the pixel) …
        pub centre_mass: [f32; 3],
        /// … and its radius (mm).
        pub centre_radius_mm: f32,
        /// Ring k starts where ring k − 1 ends (ring 0 at the centre's radius).
        pub rings: [Ring; MAX_RINGS],
    }
}

gpu_struct! {
    /// One ring of the kernel as the subsurface pass reads it.
    #[derive(Default)]
    pub struct Ring {
        /// Its mass per channel.
        pub mass: [f32; 3],
        /// Its outer radius (mm).
        pub outer_mm: f32,
    }
}

model_uniform! {
    /// What `subsurface.wgsl` reads: the one uniform of the spatial models (those whose
    /// descriptor starts from [`SPATIAL`]).
    pub struct SubsurfaceUniform {
        /// Diffuse reflectance of the medium at normal incidence per incident power.
        pub albedo: [f32; 3],
        /// η.
        pub eta: f32,
        /// 1/(π C(η)).
        pub exit_norm: f32,
        /// 1/F_t(η, 1).
        pub inv_entry: f32,
        /// mm per metre of thickness.
        pub mm_per_m: f32,
        /// The pre-integration LUT's curvature scale R0 (mm).
        pub lut_r0_mm: f32,
        /// Height (mm) the light is lifted by (models that sample a LUT).
        pub lift: [f32; 3],
        /// 1 for models with translucency (read by the f64 twin).
        pub translucent: f32,
        /// The diffuse reflectance of the medium as the model renders it under uniform
        /// (diffuse) light on a flat surface, ∫ R(μ) 2μ dμ ([`uniform_albedo`]): what ambient
        /// light reflects with, and what a pigment's albedo is relative to.
        pub uniform_albedo: [f32; 3],
        /// How far (mm) past the terminator the shadow test looks toward the light, at least
        /// (models that sample a LUT; [`Params::entry_reach_mm`]).
        pub entry_reach_mm: f32,
        /// q(μ_k) = R(μ_k)/R(1), μ_k = (k/6)² (rgb).
        pub oblique: [[f32; 4]; OBLIQUE_NODES],
        /// ln of the diffuse transmittance of a slab SLAB_FIRST_MM · 2^k thick (rgb).
        pub slab: [[f32; 4]; SLAB_NODES],
        /// δ(μ_k) (mm) (rgb).
        pub shift: [[f32; 4]; OBLIQUE_NODES],
    }
}

/// What `subsurface.wgsl` reads, in f64 ([`SubsurfaceUniform`] packed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// Diffuse reflectance at normal incidence per unit incident power.
    pub albedo: [f64; 3],
    pub eta: f64,
    /// q(μ_k) = R(μ_k)/R(1), μ_k = (k/6)².
    pub oblique: [[f64; 3]; OBLIQUE_NODES],
    /// Forward shift δ(μ_k) (mm) of obliquely entering light; zeros: none.
    pub shift: [[f64; 3]; OBLIQUE_NODES],
    /// Diffuse transmittance of slabs SLAB_FIRST_MM · 2^k thick; `None`: no translucency.
    pub slab: Option<[[f64; 3]; SLAB_NODES]>,
    /// Height (mm) the light is lifted by (models that sample a LUT), per channel.
    pub lift: [f64; 3],
    /// How far (mm) past the terminator the shadow test looks toward the light, at least
    /// (models that sample a LUT: twice the kernel's longest median radius; 0 for the others).
    pub entry_reach_mm: f64,
}

impl Params {
    pub fn uniform(&self) -> SubsurfaceUniform {
        let row = |v: [f64; 3]| [v[0] as f32, v[1] as f32, v[2] as f32, 0.0];
        let slab = self.slab.unwrap_or([[0.0; 3]; SLAB_NODES]);
        SubsurfaceUniform {
            albedo: f32x3(self.albedo),
            eta: self.eta as f32,
            exit_norm: (1.0 / (std::f64::consts::PI * exit_normalisation(self.eta))) as f32,
            inv_entry: (1.0 / fresnel::transmittance_shader(self.eta, 1.0).max(1e-12)) as f32,
            mm_per_m: units::MM_PER_M as f32,
            lut_r0_mm: LUT_R0_MM as f32,
            lift: f32x3(self.lift),
            translucent: f32::from(u8::from(self.slab.is_some())),
            uniform_albedo: [0.0; 3],
            entry_reach_mm: self.entry_reach_mm as f32,
            oblique: self.oblique.map(row),
            slab: slab.map(|t| row(t.map(|v| v.max(SLAB_FLOOR).ln()))),
            shift: self.shift.map(row),
        }
    }

    /// The packed uniform, with the medium's reflectance under uniform light as these
    /// parameters render it ([`uniform_albedo`]).
    pub fn pack(&self) -> ModelParams {
        let mut u = self.uniform();
        let r = uniform_albedo(&ModelParams::from_uniform(&u));
        u.uniform_albedo = [r.x as f32, r.y as f32, r.z as f32];
        ModelParams::from_uniform(&u)
    }
}

/// The packed uniform as the shader reads it, in f64.
struct Packed {
    albedo: DVec3,
    uniform_albedo: DVec3,
    eta: f64,
    exit_norm: f64,
    translucent: bool,
    inv_entry: f64,
    mm_per_m: f64,
    oblique: [DVec3; OBLIQUE_NODES],
    slab: [DVec3; SLAB_NODES],
    shift: [DVec3; OBLIQUE_NODES],
}

fn unpack(p: &ModelParams) -> Packed {
    fn rgb_table<const N: usize>(t: &[[f32; 4]; N]) -> [DVec3; N] {
        t.map(|r| rgb([r[0], r[1], r[2]]))
    }
    let u: &SubsurfaceUniform = p.uniform();
    Packed {
        albedo: rgb(u.albedo),
        uniform_albedo: rgb(u.uniform_albedo),
        eta: u.eta.into(),
        exit_norm: u.exit_norm.into(),
        translucent: u.translucent > 0.5,
        inv_entry: u.inv_entry.into(),
        mm_per_m: u.mm_per_m.into(),
        oblique: rgb_table(&u.oblique),
        slab: rgb_table(&u.slab),
        shift: rgb_table(&u.shift),
    }
}

/// Linear interpolation in √μ in a table over μ_k = (k/6)².
fn table(t: &[DVec3; OBLIQUE_NODES], mu: f64) -> DVec3 {
    let x = mu.clamp(0.0, 1.0).sqrt() * (OBLIQUE_NODES - 1) as f64;
    let i = (x as usize).min(OBLIQUE_NODES - 2);
    let f = x - i as f64;
    t[i].lerp(t[i + 1], f)
}

/// f64 twin of `sss_oblique`.
fn oblique(p: &Packed, mu: f64) -> DVec3 {
    table(&p.oblique, mu)
}

/// f64 twin of `sss_oblique` on the packed uniform.
pub fn oblique_packed(pm: &ModelParams, mu: f64) -> DVec3 {
    oblique(&unpack(pm), mu)
}

/// f64 twin of `sss_spread`: the irradiance each channel spreads, taken where the light that
/// leaves here entered, δ_c(μ) mm back toward the light along the surface, with the area
/// ratio ((ρ − δ)/ρ)(1 − dδ/dρ) of that outward shift.
fn spread(p: &Packed, px: &Pixel) -> DVec3 {
    let n = px.n;
    let nl = n.dot(px.l);
    let along = px.l - n * nl;
    let len = along.length();
    let dir = if len > 1e-9 {
        along / len.max(1e-12)
    } else {
        DVec3::ZERO
    };
    let dist = px.light_dist();
    let rho = len * dist * p.mm_per_m;
    let to_light = px.l * dist;
    let delta = table(&p.shift, nl.max(0.0)).min(DVec3::splat(rho));
    let q = nl.clamp(0.0, 1.0).sqrt();
    let i = ((q * (OBLIQUE_NODES - 1) as f64) as usize).min(OBLIQUE_NODES - 2);
    let slope = (p.shift[i + 1] - p.shift[i]) * (OBLIQUE_NODES - 1) as f64 / (2.0 * q.max(1e-3));
    let ddelta = -slope * nl.max(0.0) * len / (dist * p.mm_per_m);
    DVec3::from_array(std::array::from_fn(|c| {
        let d = to_light - dir * (delta[c] / p.mm_per_m);
        let r = d.length().max(1e-3);
        // On a curved surface the entry point's normal turns toward the light by δ/ρ_c (at
        // most 1 rad).
        let tilt = (delta[c] / (px.curvature_radius_m * p.mm_per_m).max(1e-3)).min(1.0);
        let tilted = (n + dir * tilt).normalize();
        let mu = (tilted.dot(d) / r).max(0.0);
        let area = if rho > 1e-6 {
            (rho - delta[c]) / rho
        } else {
            1.0
        } * (1.0 - ddelta[c]).max(0.0);
        px.light[c] / (r * r) * mu * table(&p.oblique, mu)[c] * area
    }))
}

/// f64 twin of `sss_slab` (the packed table holds ln T).
pub fn slab_packed(pm: &ModelParams, t_mm: f64) -> DVec3 {
    slab_transmittance(&unpack(pm).slab, t_mm)
}

/// The diffuse transmittance through `t_mm` from a table of ln T at the slab nodes
/// SLAB_FIRST_MM · 2^k: ln T linear in the thickness between nodes (deep in a medium light
/// decays exponentially with depth), and past the thickest node at the last interval's slope.
pub fn slab_transmittance(ln_t: &[DVec3; SLAB_NODES], t_mm: f64) -> DVec3 {
    let exp = |v: DVec3| DVec3::new(v.x.exp(), v.y.exp(), v.z.exp());
    let x = (t_mm.max(SLAB_FIRST_MM) / SLAB_FIRST_MM).log2();
    let last_node = (SLAB_NODES - 1) as f64;
    if x >= last_node {
        let width = SLAB_FIRST_MM * 2f64.powf(last_node - 1.0);
        let slope = (ln_t[SLAB_NODES - 1] - ln_t[SLAB_NODES - 2]) / width;
        let t_last = SLAB_FIRST_MM * 2f64.powf(last_node);
        return exp(ln_t[SLAB_NODES - 1] + slope * (t_mm - t_last));
    }
    let i = (x as usize).min(SLAB_NODES - 2);
    let f = (t_mm / (SLAB_FIRST_MM * 2f64.powi(i as i32)) - 1.0).clamp(0.0, 1.0);
    exp(ln_t[i].lerp(ln_t[i + 1], f))
}

/// f64 twin of `sss_back_path_mm`: how far light from behind (`back` = −n·l) travels through
/// the material to `px`, the chord through the sphere of its curvature or the slab's path
/// t/|n·l|, whichever is shorter.
fn back_path_mm(p: &Packed, px: &Pixel, back: f64) -> f64 {
    let chord = 2.0 * px.curvature_radius_m * p.mm_per_m * back;
    chord.min(px.thickness() * p.mm_per_m / back.max(1e-3))
}

/// f64 twin of `sss_split`: (local radiance, irradiance to spread, exit factor).
pub fn split(pm: &ModelParams, px: &Pixel) -> (DVec3, DVec3, f64) {
    let p = unpack(pm);
    let exit =
        fresnel::transmittance_shader(p.eta, px.n.dot(px.v).max(EXIT_COSINE_MIN)) * p.exit_norm;
    let e = px.irradiance();
    let spread = spread(&p, px);
    let translucency = if p.translucent {
        let back = (-px.n.dot(px.l)).max(0.0);
        let entry = fresnel::transmittance_shader(p.eta, back) * p.inv_entry;
        e * back * entry * slab_packed(pm, back_path_mm(&p, px, back))
    } else {
        DVec3::ZERO
    };
    let local = exit * (std::f64::consts::PI * px.ambient * p.uniform_albedo + translucency);
    (local, spread, exit)
}

/// The diffuse reflectance of the medium as the spatial models render it on a flat surface
/// under uniform (diffuse, cosine-weighted) light: ∫ R(μ) 2μ dμ, R(μ) the exitance per unit
/// incident power of a distant light at incidence cosine μ, from the f64 twin of the shader
/// ([`local`]; the exitance from the radiance toward the normal). A pigment's albedo A is
/// relative to it: the shaders scale what leaves a texel by T² = A / this, so uniform light
/// returns A exactly (pre- and post-scatter: T on the way in, T on the way out).
pub fn uniform_albedo(pm: &ModelParams) -> DVec3 {
    let p = unpack(pm);
    let normal_exit = fresnel::transmittance_shader(p.eta, 1.0) * p.exit_norm;
    if normal_exit <= 0.0 {
        return DVec3::ZERO;
    }
    // μ = x², 2μ dμ = 4x³ dx; R(μ) = M(μ)/μ for a unit normal irradiance.
    const STEPS: usize = 256;
    let mut sum = DVec3::ZERO;
    for k in 0..STEPS {
        let x = (k as f64 + 0.5) / STEPS as f64;
        let mu = x * x;
        let mut px = Pixel::new(DVec3::new((1.0 - mu * mu).sqrt(), 0.0, mu), DVec3::Z);
        px.ambient = DVec3::ZERO;
        // Thick (no translucency), the light far (no lift) with unit normal irradiance.
        px.thickness_m = 1.0;
        px.light_dist_m = 1e3;
        px.light = DVec3::splat(1e6);
        let exitance = local(pm, &px) / normal_exit;
        sum += exitance * (4.0 * x / STEPS as f64);
    }
    sum
}

/// f64 twin of `sss_local`: the pixel under uniform irradiance.
pub fn local(pm: &ModelParams, px: &Pixel) -> DVec3 {
    let p = unpack(pm);
    let (local, spread, exit) = split(pm, px);
    local + exit * p.albedo * spread
}

/// What the spatial models' descriptors share (their uniform, the per-pixel part and its
/// probed oblique table, and for the screen-space ones their whole WGSL module,
/// `subsurface.wgsl`); each fills in the rest (`..subsurface::SPATIAL`).
pub const SPATIAL: Descriptor = Descriptor {
    name: "",
    label: "",
    module: "subsurface",
    wgsl: include_str!("../../../shaders/subsurface.wgsl"),
    variant: None,
    effects: Effects::NONE,
    uniform: SubsurfaceUniform::LAYOUT,
    params: |_| ModelParams([[0.0; 4]; super::MODEL_PARAM_ROWS]),
    params_from: None,
    kernel: None,
    lut: None,
    shade: local,
    probe: |p, _, x| oblique_packed(p, x / (1.0 + x)),
    probe_wgsl: "sss_oblique(x / (1.0 + x))",
    total_reflectance: |_, _| [0.0; 3],
    consts: &[],
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exit_normalisation_is_one_without_a_boundary_and_below_one_with() {
        assert!((exit_normalisation(1.0) - 1.0).abs() < 1e-6);
        let c = exit_normalisation(1.4);
        // 1 − C is the external diffuse reflectance of η = 1.4 (≈ 0.09).
        assert!(c > 0.88 && c < 0.94, "{c}");
    }

    #[test]
    fn light_from_behind_crosses_a_curved_parts_chord_and_a_flat_parts_slab() {
        use crate::shading::{material::SKIN1, ShadingModel};
        // A model whose whole shader is this module's, with translucency (by its effects).
        let model = ShadingModel::ALL
            .into_iter()
            .find(|m| m.effects().screen_space && m.effects().translucency)
            .expect("a translucent screen-space model");
        let pm = model.params(&SKIN1);
        // What stays at a pixel lit from behind at −n·l = `back` (no ambient): translucency.
        let through = |thickness_m: f64, radius_m: f64, back: f64| {
            let l = DVec3::new((1.0 - back * back).sqrt(), 0.0, -back);
            let mut px = Pixel::new(l, DVec3::Z);
            px.ambient = DVec3::ZERO;
            px.thickness_m = thickness_m;
            px.curvature_radius_m = radius_m;
            split(&pm, &px).0
        };
        // A 4 mm ball at −n·l = 0.3: the light crosses its chord, 2ρ|n·l| = 1.2 mm, however
        // thick the part is along its normal beyond that.
        let ball = through(0.004, 0.002, 0.3);
        assert!(ball.x > 0.0 && ball.y > 0.0, "{ball}");
        assert_eq!(ball, through(0.04, 0.002, 0.3));
        // A flat part 5 cm thick turned from the light at −n·l = 0.1: the light would cross
        // t/|n·l| = 50 cm of it, so nothing comes through. (Taken as a chord, t·|n·l| = 5 mm,
        // a jaw turned from the light glowed.)
        let flat = through(0.05, units::FLAT_RADIUS_M, 0.1);
        assert!(flat.max_element() < 1e-6 * ball.x, "{flat} against {ball}");
        // A thin flat part (an ear, 3 mm) lit straight from behind comes through in every
        // channel, and less as it thickens (past the first millimetres, where less light is
        // scattered than goes straight through).
        let ear = through(0.003, units::FLAT_RADIUS_M, 1.0);
        let thicker = through(0.006, units::FLAT_RADIUS_M, 1.0);
        for c in 0..3 {
            assert!(
                ear[c] > thicker[c] && thicker[c] > 0.0,
                "ch{c}: {ear} {thicker}"
            );
        }
    }

    #[test]
    fn ring_kernel_keeps_the_total_and_samples_inside_each_ring() {
        let edges = [0.0, 0.1, 0.5, 2.0];
        let mass = [[0.1, 0.2, 0.3], [0.2, 0.1, 0.0], [0.05, 0.05, 0.05]];
        let k = Kernel::from_rings(&edges, &mass);
        let t = k.total();
        assert!((t[0] - 0.35).abs() < 1e-12 && (t[2] - 0.35).abs() < 1e-12);
        for (w, (_, r)) in edges.windows(2).skip(1).zip(&k.rings) {
            assert_eq!(*r, w[1]);
        }
        let u = k.pack(8, [0.0; 4]);
        assert_eq!(u.ring_count, 2);
        let ring = |mass: [f32; 3], outer_mm| Ring { mass, outer_mm };
        assert_eq!(u.rings[1], ring([0.05; 3], 2.0));
        assert_eq!(u.rings[2], ring([0.0; 3], 0.0));
    }
}
