//! The penumbra map: the distance from every point of the key light's shadow map to the
//! nearest caster edge, by jump flooding over a grid [`BLOCK`] times coarser than the map
//! (`shaders/penumbra.wgsl`). Models that declare the `penumbra` effect read it to filter
//! their shadow by the material's profile: a receiver at signed distance d from a straight
//! shadow edge receives the fraction ESF(d) of the light, the edge-spread function of
//! its diffusion kernel (a table in its LUT), so light bleeds into the shadow as far as the
//! material carries it — also far beyond what a few filter taps reach.
//!
//! Built only where the scene reaches such a model; run only in frames that draw one with a
//! shadow map. Cost: one seed pass (16 gathers and 72 slope tests per grid texel) and as
//! many jump passes (nine loads each) as the material's reach needs — [`reach_for`]: a dozen
//! diffusion lengths, at most [`REACH_MM`]; distances beyond are never read — over the part
//! of the grid the receivers read: the light's image of the subject's part inside the
//! camera's frustum ([`receivers`]), the seed pass grown by what the jumps carry and each
//! jump by what the later ones read ([`pass_regions`]; a scissor, the rest cleared: no
//! seed). The game's 1024² map has a 128² grid (skin1 over the whole runner: 2 jump passes;
//! the showroom's close-up: 3). Not run where even the subject's nearest pixels are wider
//! than the material's spread ([`subject_resolves`]: the runner at the follow camera).

use super::{Access, BuildCtx, Declared, Pass, Target};
use crate::render::layouts;
use crate::render::light_maps::{LightMaps, PenumbraGrid, PENUMBRA_FORMAT as FORMAT};
use crate::render::pipelines::{pipeline_layout, wgsl_module};
use crate::render::prepared::{per_frame, Drawn, PassFrame, PreparedFrame, FRAMES_PREPARED};
use crate::render::resources::Resources;
use crate::scene::{FramePacket, SubjectPose};
use crate::shader::uniforms::PenumbraUniform;
use glam::{Mat4, Vec2, Vec3};

/// Shadow-map texels per grid texel (per side), shared with the seed shader through `consts`.
pub use crate::shader::uniforms::PENUMBRA_BLOCK as BLOCK;
/// How far from an edge a distance is needed (mm): the edge-spread table's span.
pub const REACH_MM: f32 = crate::shading::edge_spread::SPAN_MM as f32;
/// The depth step that makes an edge, in metres along the light: at most 1 cm, and at most
/// [`EDGE_GAP_TEXELS`] texel widths, so a caster a few millimetres above a finely mapped
/// receiver (a blade over a measured medium, a finger over a palm) still has its edge. A step
/// is measured against the local slope (`edge` in `penumbra.wgsl`: how far it differs from
/// both neighbouring steps), so a smooth surface turned however far from the light, whose
/// steps are large but alike, makes no edge.
pub const EDGE_GAP_M: f32 = 0.01;
/// The same in the map's texel widths (what a surface turned 80° from the light spans over
/// ten texels: the bound of the seed pass's former min–max test, kept as the gap's scale).
pub const EDGE_GAP_TEXELS: f32 = 57.0;

/// The edge gap (m) for a shadow map of `texel_m` texels.
pub fn edge_gap_m(texel_m: f32) -> f32 {
    EDGE_GAP_M.min(EDGE_GAP_TEXELS * texel_m)
}
/// Uniform slot stride (the minimum uniform offset alignment).
const SLOT: u64 = 256;
/// The most passes a grid can need: the seed and one jump per halving of 2¹⁶ texels.
const MAX_PASSES: usize = 17;

/// The composed pass shader.
pub fn shader_source() -> String {
    crate::shader::compose("penumbra", &crate::shader::ShaderDefs::new())
        .expect("built-in shaders compose")
}

/// Steps of the jump passes for a grid of `size` texels: size/2, size/4, …, 1.
pub fn steps(size: u32) -> impl Iterator<Item = u32> {
    let first = size.next_power_of_two() / 2;
    std::iter::successors((first >= 1).then_some(first), |s| (*s > 1).then_some(s / 2))
}

/// The jump steps for a grid of `size` texels over a map `map_width_m` wide, for distances
/// up to `reach_mm` (at most [`REACH_MM`]): the halvings down to 1 from the first power of
/// two k whose passes carry a seed far enough (k + k/2 + … + 1 = 2k − 1 texels).
pub fn jump_steps(size: u32, map_width_m: f32, reach_mm: f32) -> impl Iterator<Item = u32> {
    let texel_mm = map_width_m * 1000.0 / size.max(1) as f32;
    let reach_mm = reach_mm.clamp(0.0, REACH_MM);
    let reach = (reach_mm / texel_mm.max(1e-6)).ceil().clamp(1.0, 1e6) as u32;
    let first = (reach + 1).div_ceil(2).next_power_of_two();
    steps(size).filter(move |&s| s <= first)
}

/// How far (mm) a material whose longest diffusion length is `diffusion_mm` needs the
/// distance to an edge ([`edge_spread::reach_mm`](crate::shading::edge_spread::reach_mm)).
pub fn reach_for(diffusion_mm: f32) -> f32 {
    (crate::shading::edge_spread::REACH_LENGTHS as f32 * diffusion_mm).min(REACH_MM)
}

/// The world size (mm) of one pixel of a `viewport` seen through `view_proj` from `eye`, at
/// `at` (across the line of sight); 0 where `at` is behind the eye or the view degenerate.
pub fn pixel_mm(view_proj: Mat4, eye: Vec3, viewport: (u32, u32), at: Vec3) -> f32 {
    let ray = at - eye;
    let d = ray.length();
    let across = ray
        .cross(Vec3::Y)
        .try_normalize()
        .or(ray.cross(Vec3::X).try_normalize());
    let Some(across) = across.filter(|_| d > 1e-6) else {
        return 0.0;
    };
    let ndc = |p: Vec3| {
        let c = view_proj * p.extend(1.0);
        (c.w > 1e-9).then(|| Vec2::new(c.x, c.y) / c.w)
    };
    let step = 0.01 * d;
    let half = 0.5 * Vec2::new(viewport.0 as f32, viewport.1 as f32);
    match (ndc(at), ndc(at + across * step)) {
        (Some(a), Some(b)) => {
            let px = ((b - a) * half).length();
            if px > 0.0 && px.is_finite() {
                step * 1000.0 / px
            } else {
                0.0
            }
        }
        _ => 0.0,
    }
}

/// Whether the penumbra shows at this frame's scale: the light a material carries past a
/// shadow's edge spreads over about its diffusion length; where a pixel at the subject is
/// wider than that, the spread lies within the pixel at the edge (which the shadow test's ramp
/// already blends), so the penumbra map would change nothing that can be seen.
pub fn resolvable(diffusion_mm: f32, pixel_mm: f32) -> bool {
    // (A pixel size that is not a number, or 0 behind the eye: drawn.)
    pixel_mm.is_nan() || pixel_mm <= diffusion_mm
}

/// The sphere around `subject`'s bind-pose bounds (its meshes' boxes), placed: centre, radius.
fn subject_sphere(subject: &SubjectPose) -> (Vec3, f32) {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for p in subject.model.meshes.iter().flat_map(|m| &m.primitives) {
        lo = lo.min(p.bounds.min);
        hi = hi.max(p.bounds.max);
    }
    if lo.x > hi.x {
        return (subject.world.transform_point3(Vec3::ZERO), 0.0);
    }
    let half = subject.world.transform_vector3(0.5 * (hi - lo)).length();
    (subject.world.transform_point3(0.5 * (lo + hi)), half)
}

/// Whether the subject's nearest part (its bounding sphere's point nearest the eye; the eye
/// inside it: yes) resolves the spread of a material whose longest diffusion length is
/// `diffusion_mm` ([`resolvable`]).
pub fn subject_resolves(packet: &FramePacket, subject: &SubjectPose, diffusion_mm: f32) -> bool {
    let (centre, radius) = subject_sphere(subject);
    let view = &packet.view;
    let to = centre - view.camera_pos;
    let d = to.length();
    if d <= radius || d <= 0.0 {
        return true;
    }
    let nearest = view.camera_pos + to * ((d - radius) / d);
    let px = pixel_mm(view.view_proj, view.camera_pos, packet.viewport, nearest);
    resolvable(diffusion_mm, px)
}

/// A rectangle of grid texels, `x0..x1` × `y0..y1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Region {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

impl Region {
    pub const EMPTY: Self = Self {
        x0: 0,
        y0: 0,
        x1: 0,
        y1: 0,
    };

    /// The whole grid of `size`² texels.
    pub fn full(size: u32) -> Self {
        Self {
            x1: size,
            y1: size,
            ..Self::EMPTY
        }
    }

    pub fn texels(&self) -> u64 {
        self.x1.saturating_sub(self.x0) as u64 * self.y1.saturating_sub(self.y0) as u64
    }

    /// Grown by `by` texels on every side, kept to a grid of `size`² texels.
    pub fn grown(self, by: u32, size: u32) -> Self {
        if self.texels() == 0 {
            return self;
        }
        Self {
            x0: self.x0.saturating_sub(by),
            y0: self.y0.saturating_sub(by),
            x1: self.x1.saturating_add(by).min(size),
            y1: self.y1.saturating_add(by).min(size),
        }
    }
}

/// The texels of a `size`² grid over a map of `map_size`² texels that receivers inside the
/// map's rectangle `uv` ([`ShadowView::seen_box_uv`](crate::render::ShadowView::seen_box_uv))
/// read: every texel the rectangle touches once grown by the ramp of the shadow test (more
/// than the receivers' normal offset moves their point); `None`: the whole grid. Empty where
/// the rectangle is.
pub fn receivers(uv: Option<(Vec2, Vec2)>, size: u32, map_size: u32) -> Region {
    let Some((lo, hi)) = uv.filter(|(lo, hi)| lo.is_finite() && hi.is_finite()) else {
        return Region::full(size);
    };
    if lo.x > hi.x || lo.y > hi.y {
        return Region::EMPTY;
    }
    let pad = crate::render::SHADOW_RAMP_TEXELS / map_size.max(1) as f32;
    let s = size as f32;
    let lo = ((lo - pad) * s).floor().clamp(Vec2::ZERO, Vec2::splat(s));
    let hi = ((hi + pad) * s).ceil().clamp(Vec2::ZERO, Vec2::splat(s));
    Region {
        x0: lo.x as u32,
        y0: lo.y as u32,
        x1: hi.x as u32,
        y1: hi.y as u32,
    }
}

/// The regions of a frame's passes for receivers in `region`, its jumps `steps` (in order):
/// the seed pass over every texel a seed can be carried from (as far as the steps carry), each
/// jump pass over every texel the passes after it read (as far as their steps reach): the last
/// over the receivers' texels alone.
pub fn pass_regions(region: Region, steps: &[u32], size: u32) -> impl Iterator<Item = Region> + '_ {
    let after = |k: usize| steps[k..].iter().sum::<u32>();
    (0..=steps.len()).map(move |k| region.grown(after(k), size))
}

/// The bind group layout of both passes.
fn layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let fragment = wgpu::ShaderStages::FRAGMENT;
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("penumbra"),
        entries: &[
            layouts::uniform(0, fragment),
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: fragment,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Depth,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 2,
                visibility: fragment,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::NonFiltering),
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 3,
                visibility: fragment,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
        ],
    })
}

pub struct PenumbraPass {
    /// The grid size it was built for (texels per side).
    size: u32,
    seed: wgpu::RenderPipeline,
    jump: wgpu::RenderPipeline,
    uniforms: wgpu::Buffer,
    /// Per prepared frame's copy, per pass (the seed, then one per possible jump): its bind
    /// groups reading grid target 0 and grid target 1.
    groups: [Vec<[wgpu::BindGroup; 2]>; FRAMES_PREPARED],
    /// The constants each copy holds (steps, edge gap): unchanged ones are not written again.
    written: [Option<(u32, f32)>; FRAMES_PREPARED],
    /// Per prepared frame's copy: the grid texels its receivers can read ([`receivers`]).
    regions: [Region; FRAMES_PREPARED],
    /// Passes per copy (the seed and every possible jump).
    passes: u64,
}

impl PenumbraPass {
    /// The pass over `grid`, reading the shadow map of `maps`.
    fn new(ctx: &BuildCtx, maps: &LightMaps, grid: &PenumbraGrid) -> Self {
        let device = ctx.device;
        let size = grid.size;
        let bind_layout = layout(device);
        let pipeline_layout = pipeline_layout(device, "penumbra", &[Some(&bind_layout)]);
        let module = wgsl_module(device, "penumbra", shader_source());
        let pipeline = |entry: &str| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(entry),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: Default::default(),
                depth_stencil: None,
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: FORMAT,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: ctx.cache,
            })
        };
        let passes = steps(size).count() + 1;
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("penumbra passes"),
            size: SLOT * (passes * FRAMES_PREPARED) as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("penumbra depth"),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            ..Default::default()
        });
        let group = |slot: u64, previous: &wgpu::TextureView| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("penumbra pass"),
                layout: &bind_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer: &uniforms,
                            offset: slot * SLOT,
                            size: wgpu::BufferSize::new(
                                std::mem::size_of::<PenumbraUniform>() as u64
                            ),
                        }),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&maps.shadow),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::Sampler(&sampler),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::TextureView(previous),
                    },
                ],
            })
        };
        let passes = passes as u64;
        let groups = per_frame(|copy| {
            (copy as u64 * passes..(copy as u64 + 1) * passes)
                .map(|k| [group(k, &grid.targets[0]), group(k, &grid.targets[1])])
                .collect()
        });
        Self {
            size,
            seed: pipeline("fs_seed"),
            jump: pipeline("fs_jump"),
            uniforms,
            groups,
            written: [None; FRAMES_PREPARED],
            regions: [Region::EMPTY; FRAMES_PREPARED],
            passes,
        }
    }
}

/// The seed and jump passes read the shadow map and write the penumbra map's grid.
impl Declared for PenumbraPass {
    const ACCESS: Access = Access {
        creates: &[],
        reads: &[Target::ShadowMap],
        writes: &[Target::PenumbraMap],
    };
}

impl Pass for PenumbraPass {
    fn build(ctx: &BuildCtx) -> Option<Self> {
        let maps = ctx.light_maps?;
        let grid = maps.penumbra.as_ref()?;
        ctx.set
            .models
            .iter()
            .any(|m| m.effects().penumbra)
            .then(|| Self::new(ctx, maps, grid))
    }

    /// Built for another grid (the light maps were made again at another size).
    fn stale(&self, ctx: &BuildCtx) -> bool {
        let grid = ctx.light_maps.and_then(|m| m.penumbra.as_ref());
        grid.map(|g| g.size) != Some(self.size)
    }

    /// Runs in frames with a shadow map that draw a model with the `penumbra` effect, where
    /// the subject's pixels resolve its material's spread ([`subject_resolves`]): as many jump
    /// passes as reach the material's [`reach_for`] over the map's width this frame.
    fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        packet: &FramePacket,
        frame: &mut PreparedFrame,
        res: &Resources,
    ) -> PassFrame {
        let reads = frame.draw.character
            && frame.subject.is_some()
            && frame.draw.shading.is_some_and(|m| m.effects().penumbra);
        let diffusion = res.models.diffusion_mm();
        // Where the subject's pixels are wider than its material's spread, nothing to draw.
        let shows = packet
            .subject
            .as_ref()
            .is_none_or(|s| subject_resolves(packet, s, diffusion));
        if !(frame.shadow.drawn && reads && shows) {
            return PassFrame::default();
        }
        let shadow = &frame.shadow;
        let gap = edge_gap_m(shadow.texel_m) * shadow.depth_per_m;
        let reach = reach_for(diffusion);
        let jumps = jump_steps(self.size, shadow.width_m(), reach).count() as u32;
        let copy = frame.copy;
        // Only the texels the subject's seen part can read (the map is fitted to more: the
        // floor its shadow falls on, the parts of it out of the frame).
        let posed = frame
            .subject
            .and_then(|d| res.subjects.get(d.slot))
            .and_then(|s| s.gpu.posed);
        let uv = posed.and_then(|b| shadow.seen_box_uv(packet.view.view_proj, b));
        let region = receivers(uv, self.size, shadow.size);
        if region.texels() == 0 {
            return PassFrame::default();
        }
        self.regions[copy] = region;
        if self.written[copy] != Some((jumps, gap)) {
            // Every pass's constants in one write (each write stages a buffer of its own).
            let mut slots = [0u8; SLOT as usize * MAX_PASSES];
            let first = std::iter::once(0);
            let all = first.chain(jump_steps(self.size, shadow.width_m(), reach));
            let mut passes = 0;
            for (k, step) in all.enumerate().take(MAX_PASSES) {
                let jump = PenumbraUniform {
                    step: step as f32,
                    grid: self.size as f32,
                    edge_gap: gap,
                    _pad0: 0.0,
                };
                let at = k * SLOT as usize;
                let bytes = bytemuck::bytes_of(&jump);
                slots[at..at + bytes.len()].copy_from_slice(bytes);
                passes = k + 1;
            }
            let at = copy as u64 * self.passes * SLOT;
            queue.write_buffer(&self.uniforms, at, &slots[..passes * SLOT as usize]);
            frame.uploads += 1;
            self.written[copy] = Some((jumps, gap));
        }
        let u = &mut frame.uniform;
        u.penumbra_drawn = 1;
        u.penumbra_grid = self.size as f32;
        u.edge_gap = gap;
        PassFrame {
            runs: true,
            steps: jumps,
        }
    }

    /// The seed pass and this frame's jump passes (one full-screen draw each); the last writes
    /// grid target 0 (the one receivers bind), so the seed goes where the parity puts it.
    fn encode(
        &self,
        frame: &PreparedFrame,
        res: &Resources,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Drawn {
        let Some(grid) = res.light_maps.as_ref().and_then(|m| m.penumbra.as_ref()) else {
            return Drawn::default();
        };
        let jumps = frame.pass(<Self as super::Slot>::SLOT).steps as usize;
        // The jump steps halve down to 1 ([`jump_steps`]).
        let steps: Vec<u32> = (0..jumps).rev().map(|k| 1 << k).collect();
        let regions = pass_regions(self.regions[frame.copy], &steps, self.size);
        let mut target = jumps % 2;
        let mut texels = [0u64; 2];
        let passes = self.groups[frame.copy].iter().take(jumps + 1);
        for (k, (groups, region)) in passes.zip(regions).enumerate() {
            let seed = k == 0;
            if !seed {
                target = 1 - target;
            }
            texels[usize::from(!seed)] += region.texels();
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(if seed {
                    "penumbra seed"
                } else {
                    "penumbra jump"
                }),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &grid.targets[target],
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(if seed { &self.seed } else { &self.jump });
            // Jumps read the other target; the seed reads none (bound: the other one).
            pass.set_bind_group(0, &groups[1 - target], &[]);
            // Only the texels later passes or the receivers read (the rest: cleared, no seed).
            let (w, h) = (region.x1 - region.x0, region.y1 - region.y0);
            pass.set_scissor_rect(region.x0, region.y0, w, h);
            pass.draw(0..3, 0..1);
        }
        Drawn {
            texels,
            ..Drawn::calls(jumps as u32 + 1)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jump_steps_halve_down_to_one() {
        let steps_of = |s: u32| steps(s).collect::<Vec<_>>();
        assert_eq!(steps_of(256), vec![128, 64, 32, 16, 8, 4, 2, 1]);
        assert_eq!(steps_of(1), Vec::<u32>::new());
        assert_eq!(steps_of(5), vec![4, 2, 1]);
        // The game's grid: 128 texels over ~2.1 m (16.4 mm each) need 8 texels of the
        // table's reach (steps 8 + 4 + 2 + 1 carry a seed 15 texels), 1.9 m 9 of them.
        let jumps = |s: u32, w: f32| jump_steps(s, w, REACH_MM).collect::<Vec<_>>();
        assert_eq!(jumps(128, 2.1), vec![8, 4, 2, 1]);
        assert_eq!(jumps(128, 1.9), vec![8, 4, 2, 1]);
        assert_eq!(jumps(128, 0.9), vec![16, 8, 4, 2, 1]);
        // A fine map reaches as far as its grid allows.
        assert_eq!(jumps(16, 0.01), steps_of(16));
        // A material that carries light 40 mm needs 3 of the 16.4 mm texels: steps 2, 1.
        assert_eq!(jump_steps(128, 2.1, 40.0).collect::<Vec<_>>(), vec![2, 1]);
        // Every seed within the reach is carried: the steps sum to at least it.
        for reach in [1.0, 10.0, 40.0, 100.0, 128.0] {
            let texels = (reach / (2100.0 / 128.0) as f32).ceil() as u32;
            let sum: u32 = jump_steps(128, 2.1, reach).sum();
            assert!(sum >= texels, "{reach} mm: {sum} < {texels}");
        }
        // Never beyond the table's span.
        assert_eq!(jump_steps(128, 2.1, 1e4).count(), jumps(128, 2.1).len());
        assert!(steps_of(1 << 16).len() < MAX_PASSES);
    }

    #[test]
    fn the_passes_cover_what_the_receivers_read_and_what_reaches_them() {
        // No rectangle known: the whole grid; an empty one: nothing.
        assert_eq!(receivers(None, 128, 1024), Region::full(128));
        let empty = Some((Vec2::new(0.6, 0.2), Vec2::new(0.4, 0.3)));
        assert_eq!(receivers(empty, 128, 1024).texels(), 0);
        // Every grid texel the rectangle touches, once grown by the test's ramp.
        let r = receivers(
            Some((Vec2::new(0.25, 0.5), Vec2::new(0.5, 0.75))),
            128,
            1024,
        );
        assert_eq!(
            r,
            Region {
                x0: 31,
                y0: 63,
                x1: 65,
                y1: 97
            }
        );
        // Kept to the grid.
        let all = receivers(Some((Vec2::splat(-1.0), Vec2::splat(2.0))), 128, 1024);
        assert_eq!(all, Region::full(128));
        // The seed pass over what the jumps 4 + 2 + 1 carry, each jump over what the later
        // ones read, the last over the receivers' texels alone.
        let passes: Vec<Region> = pass_regions(r, &[4, 2, 1], 128).collect();
        let grown = |by: u32| Region {
            x0: r.x0 - by,
            y0: r.y0 - by,
            x1: r.x1 + by,
            y1: r.y1 + by,
        };
        assert_eq!(passes, vec![grown(7), grown(3), grown(1), r]);
        // At the grid's edge the growth stops there.
        let corner = Region {
            x0: 0,
            y0: 2,
            x1: 10,
            y1: 128,
        };
        assert_eq!(
            corner.grown(3, 128),
            Region {
                x0: 0,
                y0: 0,
                x1: 13,
                y1: 128
            }
        );
        assert_eq!(Region::EMPTY.grown(3, 128).texels(), 0);
    }

    #[test]
    fn a_pixel_is_measured_where_the_subject_stands() {
        let eye = Vec3::new(0.0, 1.0, 4.0);
        let view_proj = crate::camera::look_at(eye, Vec3::Y, 1.0, 16.0 / 9.0);
        let near = pixel_mm(view_proj, eye, (1280, 720), Vec3::new(0.0, 1.0, 2.0));
        let far = pixel_mm(view_proj, eye, (1280, 720), Vec3::new(0.0, 1.0, 0.0));
        // Twice as far, twice as wide; halving the frame doubles it too.
        assert!((far / near - 2.0).abs() < 0.01, "{near} {far}");
        let small = pixel_mm(view_proj, eye, (640, 360), Vec3::new(0.0, 1.0, 0.0));
        assert!((small / far - 2.0).abs() < 0.01, "{small} {far}");
        // Behind the eye: no size (the penumbra is drawn).
        assert_eq!(
            pixel_mm(view_proj, eye, (1280, 720), Vec3::new(0.0, 1.0, 9.0)),
            0.0
        );
        assert!(resolvable(3.7, 0.0) && resolvable(3.7, 2.0) && !resolvable(3.7, 6.0));
        assert!(resolvable(3.7, f32::NAN));
    }
}
