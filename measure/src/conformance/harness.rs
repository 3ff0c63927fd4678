//! GPU conformance harness: runs **the WGSL functions the renderer uses** in a compute shader
//! on the real driver (lavapipe in CI), for comparison with the f64 references beside each
//! model (the parent module: what is compared, and the tolerances).
//!
//! # What runs
//! * **Shade kernel** (`shaders/conformance_shade.wgsl`), f32: composed, with a per-model
//!   `conformance_probe` and its input struct ([`ConformanceInput`], generated from Rust),
//!   after `shading_model` with `model.defs()` — the alias and flags of the renderer's
//!   character pipeline for that model, so the model's `shade(s: Surface)` and
//!   its sub-function (`ward_specular`, `dipole_profile`, `oss_colour`, `sss_oblique`) are
//!   the renderer's text. The Frame uniform ([`FrameUniform`]) is at `@group(0) @binding(0)`
//!   and [`ModelParams`] at `@group(1) @binding(0)`, as in the renderer; inputs and outputs
//!   are storage buffers at group 2.
//! * **Nondimensional kernel** (`shaders/conformance_nd.wgsl`): one [`NdFunction`] (`ward_nd`,
//!   `fresnel`, `dipole_nd`, `oss_nd` — modules the renderer imports) composed in
//!   f32, or with flag `REAL_F16` after `enable f16;` ([`Precision::F16`], only where the
//!   device has `SHADER_F16`), which makes the same text compute in half precision.

use std::collections::HashMap;

use glam::DVec3;
use wgpu::util::DeviceExt;

use dermis_engine::render::{read_buffer, FrameUniform, Gpu};
use dermis_engine::shader::{compose, compose_from, modules, structs, ShaderDefs};
use dermis_engine::shading::pixel::Pixel;
use dermis_engine::shading::{ModelParams, ShadingModel, Uniform};

use super::{NdFunction, Precision};

/// A uniform buffer at `binding`.
fn uniform(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// The f32 shade kernel (not a shared composer module: composed with the model's code by
/// [`shade_source`]).
pub const SHADE_KERNEL: &str = include_str!("../../../shaders/conformance_shade.wgsl");

dermis_engine::gpu_struct! {
    /// One input of the shade kernel (`conformance_shade.wgsl` reads an array of them; its
    /// WGSL is generated from this declaration).
    pub struct ConformanceInput {
        pub n: [f32; 4],
        pub t: [f32; 4],
        pub b: [f32; 4],
        pub l: [f32; 4],
        pub v: [f32; 4],
        /// rgb: light intensity × colour; w: light distance (m).
        pub light: [f32; 4],
        /// rgb: albedo; w: thickness (m).
        pub albedo: [f32; 4],
        /// x: the probe's argument (r or d in mm).
        pub probe: [f32; 4],
    }
}
/// The nondimensional kernel (not a composer module: appended after composition).
pub const ND_KERNEL: &str = include_str!("../../../shaders/conformance_nd.wgsl");

/// The per-model probe appended to the shade kernel: the model's `probe_wgsl` expression.
fn shade_probe(model: ShadingModel) -> String {
    format!(
        "fn conformance_probe(s: Surface, x: f32) -> vec3<f32> {{\n    return {};\n}}\n",
        model.descriptor().probe_wgsl
    )
}

/// The WGSL the shade harness compiles for `model`: the model's code as the renderer composes
/// it (`shading_model`, with its flags), its probe, and the kernel with its generated input
/// struct.
pub fn shade_source(model: ShadingModel) -> String {
    let input = structs::wgsl(&ConformanceInput::LAYOUT);
    let probe = shade_probe(model);
    let root = "#import shading_model\n#import conformance_probe\n#import conformance_shade\n";
    let mut set = modules().to_vec();
    set.extend([
        ("ConformanceInput", input.as_str()),
        ("conformance_probe", probe.as_str()),
        ("conformance_shade", SHADE_KERNEL),
        ("conformance", root),
    ]);
    compose_from(&set, "conformance", &model.defs()).expect("built-in shaders compose")
}

/// The WGSL body of `nd_probe(a, b)` calling `f` on the kernel's inputs.
fn nd_probe(f: NdFunction) -> &'static str {
    match f {
        NdFunction::WardLobe => {
            "let p = vec4<real>(a);\n    let q = vec4<real>(b);\n    \
             return vec4<f32>(f32(ward_lobe_nd(p.x, p.y, p.z, p.w, q.x, q.y, q.z, q.w)), 0.0, 0.0, 0.0);"
        }
        NdFunction::Fresnel => {
            "return vec4<f32>(f32(fresnel_transmittance(real(a.x), real(a.y))), 0.0, 0.0, 0.0);"
        }
        NdFunction::DipoleRd => {
            "let r = dipole_rd_nd(vec3<real>(real(a.x)), vec3<real>(real(a.y)), real(a.z), vec3<real>(real(a.w)));\n    \
             return vec4<f32>(f32(r.x), 0.0, 0.0, 0.0);"
        }
        NdFunction::OssFdStable => {
            "let r = oss_fd_stable_nd(vec3<real>(real(a.x)), vec3<real>(real(a.y)), real(a.z));\n    \
             return vec4<f32>(f32(r.x), 0.0, 0.0, 0.0);"
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
        nd_probe(f)
    )
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
    /// No shadow map (the frame's `shadow.x` is 0: every point lit), bound as the renderer
    /// binds its map.
    no_shadow: (wgpu::TextureView, wgpu::Sampler, wgpu::TextureView),
    model_layout: wgpu::BindGroupLayout,
    io_layout: wgpu::BindGroupLayout,
    shade_pipelines: HashMap<ShadingModel, wgpu::ComputePipeline>,
    nd_pipelines: HashMap<(NdFunction, Precision), wgpu::ComputePipeline>,
}

/// `size` bytes of `buffer` from `offset`, as a binding.
fn buffer_range(buffer: &wgpu::Buffer, offset: u64, size: u64) -> wgpu::BindingResource<'_> {
    wgpu::BindingResource::Buffer(wgpu::BufferBinding {
        buffer,
        offset,
        size: wgpu::BufferSize::new(size),
    })
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

/// Bytes of one [`ConformanceInput`].
const INPUT_BYTES: u64 = std::mem::size_of::<ConformanceInput>() as u64;
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
            frame_layout: make("conformance frame", &{
                let [map, sampler, penumbra] =
                    dermis_engine::render::shadow_map_entries(wgpu::ShaderStages::COMPUTE);
                [
                    uniform(0, wgpu::ShaderStages::COMPUTE),
                    map,
                    sampler,
                    penumbra,
                ]
            }),
            no_shadow: (
                dermis_engine::render::no_shadow_map(device, &gpu.queue),
                dermis_engine::render::comparison_sampler(device),
                dermis_engine::render::penumbra_grid_texture(device, 1, "no penumbra map"),
            ),
            model_layout: make(
                "conformance model",
                &[uniform(0, wgpu::ShaderStages::COMPUTE)],
            ),
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
        read_buffer(self.gpu, buffer, size, |data| {
            bytemuck::cast_slice::<u8, f32>(data).to_vec()
        })
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
        let mut inputs: Vec<ConformanceInput> = Vec::new();
        let mut slots = vec![0usize; items.len()];
        let mut groups: Vec<(usize, usize, usize)> = Vec::new(); // (params, first slot, count)
        let mut k = 0;
        while k < order.len() {
            let p = items[order[k]].params;
            assert!(p < params.len(), "item uses params {p} of {}", params.len());
            let first = inputs.len();
            let mut count = 0;
            while k < order.len() && items[order[k]].params == p {
                let it = &items[order[k]];
                slots[order[k]] = first + count;
                let px = &it.pixel;
                let v4 = |v: DVec3, w: f64| [v.x as f32, v.y as f32, v.z as f32, w as f32];
                inputs.push(ConformanceInput {
                    n: v4(px.n, 0.0),
                    t: v4(px.t, 0.0),
                    b: v4(px.b, 0.0),
                    l: v4(px.l, 0.0),
                    v: v4(px.v, 0.0),
                    light: v4(px.light, px.light_dist_m),
                    albedo: v4(px.albedo, px.thickness_m),
                    probe: [it.probe as f32, 0.0, 0.0, 0.0],
                });
                count += 1;
                k += 1;
            }
            groups.push((p, first, count));
            let padded = (first + count).div_ceil(chunk) * chunk;
            inputs.resize(padded, bytemuck::Zeroable::zeroed());
        }
        let slots_total = inputs.len().max(1);
        inputs.resize(slots_total, bytemuck::Zeroable::zeroed());
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
        // Identity view_proj, the ambient; the rest 0 (no shadow map: every point lit).
        let frame = FrameUniform {
            view_proj: glam::Mat4::IDENTITY,
            ambient: [ambient.x as f32, ambient.y as f32, ambient.z as f32],
            ..bytemuck::Zeroable::zeroed()
        };
        let frame_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("conformance frame"),
            contents: bytemuck::bytes_of(&frame),
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
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: frame_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&self.no_shadow.0),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::Sampler(&self.no_shadow.1),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&self.no_shadow.2),
                },
            ],
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
                        resource: buffer_range(
                            &params_buf,
                            p as u64 * ModelParams::SIZE,
                            ModelParams::SIZE,
                        ),
                    }],
                });
                let io_bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("conformance io"),
                    layout: &self.io_layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: buffer_range(
                                &input_buf,
                                first as u64 * INPUT_BYTES,
                                count as u64 * INPUT_BYTES,
                            ),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: buffer_range(
                                &output_buf,
                                first as u64 * OUTPUT_BYTES,
                                count as u64 * OUTPUT_BYTES,
                            ),
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
