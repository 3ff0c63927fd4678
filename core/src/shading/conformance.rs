//! GPU conformance harness: runs **the WGSL functions the renderer uses** in a compute shader
//! on the real driver (lavapipe in CI) and compares them with the f64 references beside each
//! model (`ward::shade`, `dipole::shade`, `oss::shade`, `subsurface::local` and their
//! sub-functions and nondimensional kernels).
//!
//! # What runs
//! * **Shade kernel** (`shaders/conformance_shade.wgsl`), f32: appended, with a per-model
//!   `conformance_probe`, to `compose("shading_model", &model.defs())` — the alias and flags of
//!   the renderer's character pipeline for that model, so the model's `shade(s: Surface)` and
//!   its sub-function (`ward_specular`, `dipole_profile`, `oss_colour`, `sss_oblique`) are
//!   the renderer's text. The Frame uniform is at `@group(0) @binding(0)` and
//!   [`ModelParams`] at `@group(1) @binding(0)`, as in the renderer; inputs and outputs are
//!   storage buffers at group 2.
//! * **Nondimensional kernel** (`shaders/conformance_nd.wgsl`): one [`NdFunction`] (`ward_nd`,
//!   `fresnel`, `dipole_nd`, `oss_nd` — modules the renderer imports) composed in
//!   f32, or with flag `REAL_F16` after `enable f16;` ([`Precision::F16`], only where the
//!   device has `SHADER_F16`), which makes the same text compute in half precision.
//!
//! References are evaluated on the inputs *as the GPU sees them* (rounded to f32, or to f16
//! for the f16 kernel) and on the packed f32 uniform read back to f64, so a difference is the
//! shader's arithmetic only.
//!
//! # Tolerances (|gpu − f64| ≤ abs + rel·|f64|, per channel)
//! * [`F32_SHADE`]: rel 2e-5, abs 1e-30. WGSL does not fix the accuracy of `exp`/`pow`
//!   (Vulkan: 3 + 2|x| ULP for exp, pow via exp2/log2), compilers may contract a·b + c into
//!   FMA (lavapipe's LLVM does), and the models evaluate exponentials of arguments up to ~80
//!   before they underflow: a relative error of the argument δ becomes |x|·δ in the result
//!   (80 × 6e-8 ≈ 5e-6), on top of a few ULP per operation over ~30 operations. The absolute
//!   floor covers results in f32's denormal range (flushed to 0 by some drivers).
//! * [`F32_ND`]: the same, for the nondimensional kernels.
//! * [`F16_ND`]: rel 3e-2, abs 2e-4 (about 60 ULP of f16's 2⁻¹¹ ≈ 4.9e-4 unit roundoff, and
//!   |x|·2⁻¹¹ for exp at |x| ≤ 30 ≈ 1.5 %; absolute: results below f16's normal range 6.1e-5).
//!   Only inside f16's range, see [`NdFunction::f16_domain`].

use std::collections::HashMap;

use glam::DVec3;
use wgpu::util::DeviceExt;

use super::{dipole, fresnel, oss, subsurface, ward, ModelParams, ShadingModel, MODEL_PARAM_ROWS};
use crate::render::Gpu;
use crate::shader::{compose, ShaderDefs};

/// The f32 shade kernel (not a composer module: appended after composition).
pub const SHADE_KERNEL: &str = include_str!("../../../shaders/conformance_shade.wgsl");
/// The nondimensional kernel (not a composer module: appended after composition).
pub const ND_KERNEL: &str = include_str!("../../../shaders/conformance_nd.wgsl");

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
        }
    }

    /// The light distance the shader uses [m].
    pub fn light_dist(&self) -> f64 {
        self.light_dist_m.max(super::units::LIGHT_D_MIN_M)
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
        }
    }
}

/// The packed uniform as f64 rows.
pub fn rows(p: &ModelParams) -> [[f64; 4]; MODEL_PARAM_ROWS] {
    p.0.map(|r| r.map(f64::from))
}

/// Whether the compute harness can check `model`: models that sample a LUT texture are
/// checked by rendering instead (`tests/subsurface_render.rs`), since texture filtering's
/// sub-texel precision is the implementation's choice (Vulkan requires 4 bits), far coarser
/// than the harness's f32 tolerance.
pub fn harness_checks(model: ShadingModel) -> bool {
    !model.effects().lut
}

/// f64 reference of `model`'s `shade` for the packed uniform `p` (models with
/// [`harness_checks`]; the others get their flat-ground limit without the LUT).
pub fn reference_shade(model: ShadingModel, p: &ModelParams, px: &Pixel) -> DVec3 {
    match model {
        ShadingModel::Ward => ward::shade(p, false, px),
        ShadingModel::WardPrinted => ward::shade(p, true, px),
        ShadingModel::Dipole => dipole::shade(p, false, px),
        ShadingModel::DipolePrinted => dipole::shade(p, true, px),
        ShadingModel::Oss => oss::shade(p, false, px),
        ShadingModel::OssStable => oss::shade(p, true, px),
        ShadingModel::Burley | ShadingModel::Tabulated | ShadingModel::Preintegrated => {
            subsurface::local(p, px)
        }
    }
}

/// f64 reference of `model`'s probed sub-function: the Ward lobe (`ward_specular`, grey),
/// `dipole_profile(x)`, `oss_colour(x)` (x in mm) or the spatial models' `sss_oblique(x/(1+x))`.
pub fn reference_probe(model: ShadingModel, p: &ModelParams, px: &Pixel, x: f64) -> DVec3 {
    let k = rows(p);
    match model {
        ShadingModel::Ward | ShadingModel::WardPrinted => {
            let lobe = ward::Lobe {
                rho_s: k[1][0],
                alpha_x: k[1][1],
                alpha_y: k[1][2],
            };
            DVec3::splat(ward::lobe_specular(
                px,
                &lobe,
                model == ShadingModel::WardPrinted,
            ))
        }
        ShadingModel::Dipole => dipole::profile_packed(p, false, x),
        ShadingModel::DipolePrinted => dipole::profile_packed(p, true, x),
        ShadingModel::Oss => oss::colour_packed(p, false, x),
        ShadingModel::OssStable => oss::colour_packed(p, true, x),
        ShadingModel::Burley | ShadingModel::Tabulated | ShadingModel::Preintegrated => {
            subsurface::oblique_packed(p, x / (1.0 + x))
        }
    }
}

/// The per-model probe appended to the shade kernel.
fn shade_probe(model: ShadingModel) -> &'static str {
    match model {
        ShadingModel::Ward | ShadingModel::WardPrinted => {
            "fn conformance_probe(s: Surface, x: f32) -> vec3<f32> {\n    \
             return vec3<f32>(ward_specular(s, model.lobe.x, model.lobe.y, model.lobe.z));\n}\n"
        }
        ShadingModel::Dipole | ShadingModel::DipolePrinted => {
            "fn conformance_probe(s: Surface, x: f32) -> vec3<f32> {\n    return dipole_profile(x);\n}\n"
        }
        ShadingModel::Oss | ShadingModel::OssStable => {
            "fn conformance_probe(s: Surface, x: f32) -> vec3<f32> {\n    return oss_colour(x);\n}\n"
        }
        ShadingModel::Burley | ShadingModel::Tabulated | ShadingModel::Preintegrated => {
            "fn conformance_probe(s: Surface, x: f32) -> vec3<f32> {\n    return sss_oblique(x / (1.0 + x));\n}\n"
        }
    }
}

/// The WGSL the shade harness compiles for `model`.
pub fn shade_source(model: ShadingModel) -> String {
    let composed = compose("shading_model", &model.defs()).expect("built-in shaders compose");
    format!("{composed}{}{SHADE_KERNEL}", shade_probe(model))
}

/// Floating-point precision of a kernel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Precision {
    F32,
    F16,
}

/// A per-pixel function on nondimensional inputs, as the renderer imports it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NdFunction {
    /// `ward_lobe_nd(nl, nv, ht, hb, hn, ρ_s, α_x, α_y)`.
    WardLobe,
    /// `fresnel_transmittance(η, cosθ)`.
    Fresnel,
    /// `dipole_rd_nd(ρ = σ'_t r, s = σ_tr ℓ, z_v/ℓ, α')` (channel x).
    DipoleRd,
    /// `oss_fd_stable_nd(σ_a d, σ'_s P d, F_dr)` (channel x).
    OssFdStable,
}

impl NdFunction {
    pub const ALL: [NdFunction; 4] = [
        Self::WardLobe,
        Self::Fresnel,
        Self::DipoleRd,
        Self::OssFdStable,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Self::WardLobe => "ward_lobe_nd",
            Self::Fresnel => "fresnel_transmittance",
            Self::DipoleRd => "dipole_rd_nd",
            Self::OssFdStable => "oss_fd_stable_nd",
        }
    }

    /// The composer module holding the function.
    pub fn module(self) -> &'static str {
        match self {
            Self::WardLobe => "ward_nd",
            Self::Fresnel => "fresnel",
            Self::DipoleRd => "dipole_nd",
            Self::OssFdStable => "oss_nd",
        }
    }

    fn probe(self) -> &'static str {
        match self {
            Self::WardLobe => {
                "let p = vec4<real>(a);\n    let q = vec4<real>(b);\n    \
                 return vec4<f32>(f32(ward_lobe_nd(p.x, p.y, p.z, p.w, q.x, q.y, q.z, q.w)), 0.0, 0.0, 0.0);"
            }
            Self::Fresnel => {
                "return vec4<f32>(f32(fresnel_transmittance(real(a.x), real(a.y))), 0.0, 0.0, 0.0);"
            }
            Self::DipoleRd => {
                "let r = dipole_rd_nd(vec3<real>(real(a.x)), vec3<real>(real(a.y)), real(a.z), vec3<real>(real(a.w)));\n    \
                 return vec4<f32>(f32(r.x), 0.0, 0.0, 0.0);"
            }
            Self::OssFdStable => {
                "let r = oss_fd_stable_nd(vec3<real>(real(a.x)), vec3<real>(real(a.y)), real(a.z));\n    \
                 return vec4<f32>(f32(r.x), 0.0, 0.0, 0.0);"
            }
        }
    }

    /// f64 reference on the inputs (a.x, a.y, a.z, a.w, b.x, b.y, b.z, b.w).
    pub fn reference(self, x: &[f64; 8]) -> f64 {
        match self {
            Self::WardLobe => ward::lobe_nd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7]),
            Self::Fresnel => fresnel::transmittance_shader(x[0], x[1]),
            Self::DipoleRd => dipole::rd_nd(x[0], x[1], x[2], x[3]),
            Self::OssFdStable => oss::f_d_stable_nd(x[0], x[1], x[2]),
        }
    }

    /// Whether inputs `x` lie in the domain the f16 kernel is specified on: every input and
    /// intermediate inside f16's normal range (≤ 65504, ≥ 6.1e-5 where it divides).
    /// * ward: α ≥ 0.1 (ρ_s/(4π α_x α_y √1e-6) and (h·t/α)²/h_n² stay < 65504), h_n ≥ 0.05;
    /// * fresnel: η ∈ [1, 3], cosθ ≥ 0.01 (q = η² − 1 + cos² ≥ 1e-4, f16-normal);
    /// * dipole: ρ ≤ 30 (d³ ≤ 3e4), s ≤ 30 (s·d ≤ 900 only feeds exp, which underflows to 0);
    /// * oss: σ_a d, σ'_s P d ≤ 1e4.
    pub fn f16_domain(self, x: &[f64; 8]) -> bool {
        match self {
            Self::WardLobe => x[6] >= 0.1 && x[7] >= 0.1 && x[4] >= 0.05,
            Self::Fresnel => (1.0..=3.0).contains(&x[0]) && x[1] >= 0.01,
            Self::DipoleRd => x[0] <= 30.0 && x[1] <= 30.0,
            Self::OssFdStable => x[0] <= 1e4 && x[1] <= 1e4,
        }
    }
}

/// The WGSL the nondimensional harness compiles for `f` at `precision`.
pub fn nd_source(f: NdFunction, precision: Precision) -> String {
    let defs = ShaderDefs::new();
    let (enable, defs) = match precision {
        Precision::F32 => ("", defs),
        Precision::F16 => ("enable f16;\n", defs.flag("REAL_F16")),
    };
    let composed = compose(f.module(), &defs).expect("built-in shaders compose");
    format!(
        "{enable}{composed}// ---- conformance probe ----\nfn nd_probe(a: vec4<f32>, b: vec4<f32>) -> vec4<f32> {{\n    {}\n}}\n{ND_KERNEL}",
        f.probe()
    )
}

/// Rounds to the nearest f16 value (ties to even), returned as f64; ±∞ beyond 65504.
pub fn round_f16(x: f64) -> f64 {
    if !x.is_finite() || x == 0.0 {
        return x;
    }
    let a = x.abs();
    if a >= 65520.0 {
        return f64::INFINITY.copysign(x);
    }
    let exp = (((a.to_bits() >> 52) & 0x7ff) as i32 - 1023).max(-14);
    let ulp = 2f64.powi(exp - 10);
    ((a / ulp).round_ties_even() * ulp).copysign(x)
}

/// An absolute + relative tolerance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    pub abs: f64,
    pub rel: f64,
}

impl Tolerance {
    /// Whether `got` is within tolerance of `want` (both finite, or both the same infinity).
    pub fn accepts(&self, got: f64, want: f64) -> bool {
        if !got.is_finite() || !want.is_finite() {
            return got == want;
        }
        (got - want).abs() <= self.abs + self.rel * want.abs()
    }
}

/// f32 shade kernel vs f64 (see the module docs for why).
/// The absolute floor is far below any displayable radiance: it only matters where a result
/// is a near-cancellation of O(1) terms (the printed OSS cubic at its root, ~1.4–2.7 mm),
/// whose relative error no precision bounds.
pub const F32_SHADE: Tolerance = Tolerance {
    abs: 1e-9,
    rel: 2e-5,
};
/// f32 nondimensional kernels vs f64.
pub const F32_ND: Tolerance = Tolerance {
    abs: 1e-30,
    rel: 2e-5,
};
/// f16 nondimensional kernels vs f64, inside [`NdFunction::f16_domain`].
pub const F16_ND: Tolerance = Tolerance {
    abs: 2e-4,
    rel: 3e-2,
};

/// f32 Fresnel transmittance within |q| < 1e-6 of the critical angle (η < 1,
/// q = η² − 1 + cos²θ → 0): F_t ≈ (2√q/c)(1 + 1/η²) has an infinite condition number there;
/// rounding η² and c² leaves q uncertain by ~2⁻²³, i.e. √q by ~3.5e-4 and F_t by ≲ 3e-3
/// (observed on lavapipe: 2.2e-4). An absolute bound is the honest statement.
pub const F32_CRITICAL_ANGLE: Tolerance = Tolerance {
    abs: 3e-3,
    rel: 2e-5,
};

/// Whether Fresnel inputs (η, cosθ) lie within |q| < 1e-6 of the critical angle.
pub fn near_critical_angle(eta: f64, cos_i: f64) -> bool {
    eta < 1.0 && ((eta - 1.0) * (eta + 1.0) + cos_i * cos_i).abs() < 1e-6
}

/// Relative error with a floor: |got − want| / max(|want|, floor).
pub fn rel_error(got: f64, want: f64, floor: f64) -> f64 {
    if got == want {
        return 0.0;
    }
    (got - want).abs() / want.abs().max(floor)
}

/// One input of the shade kernel: which uniform (index into the `params` slice), the pixel,
/// and the probe's argument x [mm].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Item {
    pub params: usize,
    pub pixel: Pixel,
    pub probe: f64,
}

/// Output of the shade kernel for one item: `shade(s)` and the probe.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadeOut {
    pub shade: [f32; 3],
    pub probe: [f32; 3],
}

/// The compute harness on one device.
pub struct Harness<'g> {
    gpu: &'g Gpu,
    frame_layout: wgpu::BindGroupLayout,
    model_layout: wgpu::BindGroupLayout,
    io_layout: wgpu::BindGroupLayout,
    shade_pipelines: HashMap<ShadingModel, wgpu::ComputePipeline>,
    nd_pipelines: HashMap<(NdFunction, Precision), wgpu::ComputePipeline>,
}

fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// Size of the Frame uniform (`common.wgsl`): a mat4 and six vec4s (the light clip plane,
/// last, stays 0: no clipping).
const FRAME_FLOATS: usize = 40;
/// Bytes of one `ConformanceInput`.
const INPUT_BYTES: u64 = 128;
/// Bytes of one shade output (two vec4).
const OUTPUT_BYTES: u64 = 32;

impl<'g> Harness<'g> {
    pub fn new(gpu: &'g Gpu) -> Self {
        let device = &gpu.device;
        let make = |label, entries: &[wgpu::BindGroupLayoutEntry]| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries,
            })
        };
        Self {
            gpu,
            frame_layout: make("conformance frame", &[uniform_entry(0)]),
            model_layout: make("conformance model", &[uniform_entry(0)]),
            io_layout: make(
                "conformance io",
                &[storage_entry(0, true), storage_entry(1, false)],
            ),
            shade_pipelines: HashMap::new(),
            nd_pipelines: HashMap::new(),
        }
    }

    /// Whether the device can run [`Precision::F16`] kernels.
    pub fn has_f16(&self) -> bool {
        self.gpu
            .device
            .features()
            .contains(wgpu::Features::SHADER_F16)
    }

    fn pipeline(
        &self,
        label: &str,
        source: String,
        layouts: &[&wgpu::BindGroupLayout],
        entry: &str,
    ) -> wgpu::ComputePipeline {
        let device = &self.gpu.device;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let layouts: Vec<Option<&wgpu::BindGroupLayout>> =
            layouts.iter().map(|l| Some(*l)).collect();
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: &layouts,
            immediate_size: 0,
        });
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(label),
            layout: Some(&layout),
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        })
    }

    fn read_back(&self, buffer: &wgpu::Buffer, size: u64) -> Vec<f32> {
        let device = &self.gpu.device;
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("conformance readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
        self.gpu.queue.submit([encoder.finish()]);
        let slice = staging.slice(..);
        slice.map_async(wgpu::MapMode::Read, |_| {});
        self.gpu.wait();
        let out = {
            let data = slice
                .get_mapped_range()
                .expect("readback buffer was mapped above");
            bytemuck::cast_slice::<u8, f32>(&data).to_vec()
        };
        staging.unmap();
        out
    }

    /// Runs `model`'s `shade` and probe over `items`, each with uniform `params[item.params]`,
    /// the Frame uniform's ambient set to `ambient`. Returns one output per item, in order.
    pub fn shade(
        &mut self,
        model: ShadingModel,
        params: &[ModelParams],
        items: &[Item],
        ambient: DVec3,
    ) -> Vec<ShadeOut> {
        if !self.shade_pipelines.contains_key(&model) {
            let layouts = [&self.frame_layout, &self.model_layout, &self.io_layout];
            let p = self.pipeline(
                &format!("conformance {model}"),
                shade_source(model),
                &layouts,
                "conformance_shade",
            );
            self.shade_pipelines.insert(model, p);
        }
        let device = &self.gpu.device;
        // Group items by uniform; each group starts at an offset aligned for storage bindings.
        let align = device.limits().min_storage_buffer_offset_alignment as u64;
        let chunk = (align.div_ceil(OUTPUT_BYTES)).max(1) as usize;
        assert!(
            align <= 1024
                && (chunk as u64 * INPUT_BYTES).is_multiple_of(align)
                && (chunk as u64 * OUTPUT_BYTES).is_multiple_of(align)
        );
        let mut order: Vec<usize> = (0..items.len()).collect();
        order.sort_by_key(|&i| items[i].params);
        let mut inputs: Vec<f32> = Vec::new();
        let mut slots = vec![0usize; items.len()];
        let mut groups: Vec<(usize, usize, usize)> = Vec::new(); // (params, first slot, count)
        let mut k = 0;
        while k < order.len() {
            let p = items[order[k]].params;
            assert!(p < params.len(), "item uses params {p} of {}", params.len());
            let first = inputs.len() / 32;
            let mut count = 0;
            while k < order.len() && items[order[k]].params == p {
                let it = &items[order[k]];
                slots[order[k]] = first + count;
                let px = &it.pixel;
                let v4 = |v: DVec3, w: f64| [v.x as f32, v.y as f32, v.z as f32, w as f32];
                for row in [
                    v4(px.n, 0.0),
                    v4(px.t, 0.0),
                    v4(px.b, 0.0),
                    v4(px.l, 0.0),
                    v4(px.v, 0.0),
                    v4(px.light, px.light_dist_m),
                    v4(px.albedo, px.thickness_m),
                    [it.probe as f32, 0.0, 0.0, 0.0],
                ] {
                    inputs.extend_from_slice(&row);
                }
                count += 1;
                k += 1;
            }
            groups.push((p, first, count));
            let padded = (first + count).div_ceil(chunk) * chunk;
            inputs.resize(padded * 32, 0.0);
        }
        let slots_total = (inputs.len() / 32).max(1);
        inputs.resize(slots_total * 32, 0.0);
        let input_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("conformance inputs"),
            contents: bytemuck::cast_slice(&inputs),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let out_size = slots_total as u64 * OUTPUT_BYTES;
        let output_buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("conformance outputs"),
            size: out_size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let mut frame = [0.0f32; FRAME_FLOATS];
        for i in 0..4 {
            frame[i * 5] = 1.0; // identity view_proj
        }
        // view_proj 0..16, camera_pos, light_pos, light_color, ambient 28..32, output.
        frame[28..32].copy_from_slice(&[ambient.x as f32, ambient.y as f32, ambient.z as f32, 0.0]);
        let frame_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("conformance frame"),
            contents: bytemuck::cast_slice(&frame),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let params_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("conformance params"),
            contents: bytemuck::cast_slice(params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let frame_bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("conformance frame"),
            layout: &self.frame_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: frame_buf.as_entire_binding(),
            }],
        });
        let pipeline = &self.shade_pipelines[&model];
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("conformance"),
                timestamp_writes: None,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &frame_bg, &[]);
            for &(p, first, count) in &groups {
                let model_bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("conformance model"),
                    layout: &self.model_layout,
                    entries: &[wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer: &params_buf,
                            offset: p as u64 * ModelParams::SIZE,
                            size: wgpu::BufferSize::new(ModelParams::SIZE),
                        }),
                    }],
                });
                let io_bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("conformance io"),
                    layout: &self.io_layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                                buffer: &input_buf,
                                offset: first as u64 * INPUT_BYTES,
                                size: wgpu::BufferSize::new(count as u64 * INPUT_BYTES),
                            }),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                                buffer: &output_buf,
                                offset: first as u64 * OUTPUT_BYTES,
                                size: wgpu::BufferSize::new(count as u64 * OUTPUT_BYTES),
                            }),
                        },
                    ],
                });
                pass.set_bind_group(1, &model_bg, &[]);
                pass.set_bind_group(2, &io_bg, &[]);
                pass.dispatch_workgroups((count as u32).div_ceil(64), 1, 1);
            }
        }
        self.gpu.queue.submit([encoder.finish()]);
        let out = self.read_back(&output_buf, out_size);
        slots
            .iter()
            .map(|&s| ShadeOut {
                shade: [out[s * 8], out[s * 8 + 1], out[s * 8 + 2]],
                probe: [out[s * 8 + 4], out[s * 8 + 5], out[s * 8 + 6]],
            })
            .collect()
    }

    /// Runs nondimensional function `f` at `precision` over `inputs`; returns output.x per item.
    /// Panics for [`Precision::F16`] on a device without `SHADER_F16`.
    pub fn nd(&mut self, f: NdFunction, precision: Precision, inputs: &[[f32; 8]]) -> Vec<f32> {
        assert!(
            precision == Precision::F32 || self.has_f16(),
            "the device has no SHADER_F16"
        );
        if inputs.is_empty() {
            return Vec::new();
        }
        if !self.nd_pipelines.contains_key(&(f, precision)) {
            let layouts = [&self.io_layout];
            let label = format!("conformance {} {precision:?}", f.name());
            let p = self.pipeline(&label, nd_source(f, precision), &layouts, "conformance_nd");
            self.nd_pipelines.insert((f, precision), p);
        }
        let device = &self.gpu.device;
        let input_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("conformance nd inputs"),
            contents: bytemuck::cast_slice(inputs),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let out_size = inputs.len() as u64 * 16;
        let output_buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("conformance nd outputs"),
            size: out_size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("conformance nd io"),
            layout: &self.io_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: input_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: output_buf.as_entire_binding(),
                },
            ],
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("conformance nd"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.nd_pipelines[&(f, precision)]);
            pass.set_bind_group(0, &bg, &[]);
            pass.dispatch_workgroups((inputs.len() as u32).div_ceil(64), 1, 1);
        }
        self.gpu.queue.submit([encoder.finish()]);
        let out = self.read_back(&output_buf, out_size);
        out.chunks_exact(4).map(|c| c[0]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn f16_rounding() {
        assert_eq!(round_f16(1.0), 1.0);
        assert_eq!(round_f16(1.0 + 1.0 / 4096.0), 1.0); // half an ulp below: ties to even
        assert_eq!(round_f16(1.0 + 3.0 / 2048.0), 1.0 + 2.0 / 1024.0);
        assert_eq!(round_f16(65504.0), 65504.0);
        assert_eq!(round_f16(1e6), f64::INFINITY);
        assert_eq!(round_f16(1e-8), 0.0);
        assert_eq!(round_f16(2f64.powi(-24)), 2f64.powi(-24));
    }

    #[test]
    fn every_model_and_function_composes_and_validates_with_naga() {
        let mut sources: Vec<(String, String)> = ShadingModel::ALL
            .iter()
            .map(|m| (m.name().to_string(), shade_source(*m)))
            .collect();
        for f in NdFunction::ALL {
            for p in [Precision::F32, Precision::F16] {
                sources.push((format!("{} {p:?}", f.name()), nd_source(f, p)));
            }
        }
        for (label, src) in sources {
            let module = naga::front::wgsl::parse_str(&src)
                .unwrap_or_else(|e| panic!("{label}: {}", e.emit_to_string(&src)));
            naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::all(),
            )
            .validate(&module)
            .unwrap_or_else(|e| panic!("{label}: {}", e.emit_to_string(&src)));
        }
    }
}
