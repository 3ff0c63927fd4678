//! Instance, adapter, device and queue, and the pipeline cache kept with them.

use std::fmt;
use std::path::Path;

use super::pipeline_cache::PipelineCacheFile;

/// The GPU context every other render object is created from.
pub struct Gpu {
    pub instance: wgpu::Instance,
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    /// Whether TIMESTAMP_QUERY was granted (GPU timings available).
    pub timestamps: bool,
    /// The pipeline cache kept on disk, once [`Gpu::use_pipeline_cache`] has opened it.
    pub pipeline_cache: Option<PipelineCacheFile>,
}

#[derive(Debug)]
pub enum GpuError {
    NoAdapter(String),
    Device(String),
}

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoAdapter(e) => write!(
                f,
                "no GPU adapter found ({e}); on a machine without a GPU install Mesa's lavapipe \
                 (Debian: mesa-vulkan-drivers) or set WGPU_BACKEND=gl"
            ),
            Self::Device(e) => write!(f, "could not create the GPU device: {e}"),
        }
    }
}

impl std::error::Error for GpuError {}

/// Features dermis uses when the adapter has them: GPU timings, f16 (the stability suite),
/// the block-compressed texture families (textures are uploaded in the first family the
/// device samples, else decoded: `texture::upload`) and the pipeline cache.
const OPTIONAL_FEATURES: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
    .union(wgpu::Features::SHADER_F16)
    .union(wgpu::Features::TEXTURE_COMPRESSION_BC)
    .union(wgpu::Features::TEXTURE_COMPRESSION_ETC2)
    .union(wgpu::Features::TEXTURE_COMPRESSION_ASTC)
    .union(wgpu::Features::PIPELINE_CACHE);

impl Gpu {
    /// The limits of a mid-range Android phone: Khronos' Vulkan profile `VP_ANDROID_baseline_2022`
    /// (KhronosGroup/Vulkan-Profiles, `profiles/VP_ANDROID_baseline_2022.json`, commit 61aa0b2),
    /// mapped to wgpu's limits the way wgpu-hal 30's Vulkan backend maps a device reporting
    /// exactly those values (`to_wgpu_limits`), then intersected with
    /// [`wgpu::Limits::downlevel_defaults`] (GLES 3.1) wherever that is stricter.
    ///
    /// | wgpu limit | profile (Vulkan) | downlevel | chosen |
    /// |---|---|---|---|
    /// | texture 1D / 2D | maxImageDimension1D/2D/Cube, maxFramebufferWidth 4096 | 2048 | 4096 (1) |
    /// | texture 3D | maxImageDimension3D 512 | 256 | 256 |
    /// | texture array layers | maxImageArrayLayers 256 | 256 | 256 |
    /// | bind groups | maxBoundDescriptorSets 4 | 4 | 4 |
    /// | dynamic uniform / storage buffers | maxDescriptorSet…Dynamic 8 / 4 | 8 / 4 | 8 / 4 |
    /// | sampled textures per stage | maxPerStageDescriptorSampledImages 16 | 16 | 16 |
    /// | samplers per stage | maxPerStageDescriptorSamplers 16 | 16 | 16 |
    /// | storage buffers per stage | 4, capped by maxFragmentCombinedOutputResources 8 (2) | 4 | 3 |
    /// | storage textures per stage | 4, capped likewise (2) | 4 | 2 |
    /// | uniform buffers per stage | maxPerStageDescriptorUniformBuffers 12 | 12 | 12 |
    /// | uniform binding size | maxUniformBufferRange 16384 | 16 KiB | 16 KiB |
    /// | storage binding size | maxStorageBufferRange 128 MiB | 128 MiB | 128 MiB |
    /// | vertex buffers | maxVertexInputBindings 16 | 8 | 8 |
    /// | vertex attributes | maxVertexInputAttributes 16 | 16 | 16 |
    /// | vertex stride | maxVertexInputBindingStride 2048 | 2048 | 2048 |
    /// | inter-stage variables | maxVertexOutputComponents 64 / 4 − 1 | 15 | 15 |
    /// | uniform / storage offset alignment | 256 / 256 | 256 / 256 | 256 / 256 |
    /// | color attachments | maxColorAttachments 4, capped likewise (2) | 4 | 3 |
    /// | color bytes per sample | 3 attachments × 16 | 32 | 32 |
    /// | workgroup storage | maxComputeSharedMemorySize 16384 | 16352 | 16352 |
    /// | invocations per workgroup | maxComputeWorkGroupInvocations 128 | 256 | 128 |
    /// | workgroup size x / y / z | maxComputeWorkGroupSize 128 / 128 / 64 | 256 / 256 / 64 | 128 / 128 / 64 |
    /// | workgroups per dimension | maxComputeWorkGroupCount 65535 | 65535 | 65535 |
    /// | immediates (push constants) | maxPushConstantsSize 128 | 0 | 0 (3) |
    /// | buffer size | — (no maintenance3 in the profile) | 256 MiB | 256 MiB |
    ///
    /// (1) 2048 would refuse the swapchain of any phone screen (1080 × 2400 and up); the profile's
    ///     4096 is what `Limits::using_resolution` is for. (2) wgpu keeps storage textures +
    ///     storage buffers + color attachments within maxFragmentCombinedOutputResources (8) on
    ///     every vendor but Intel/NVIDIA/AMD/ImgTec: 2 + 3 + 3. (3) needs `Features::IMMEDIATES`,
    ///     which dermis does not request. Everything else is the downlevel value.
    pub const PHONE_LIMITS: wgpu::Limits = wgpu::Limits {
        max_texture_dimension_1d: 4096,
        max_texture_dimension_2d: 4096,
        max_storage_buffers_per_shader_stage: 3,
        max_storage_textures_per_shader_stage: 2,
        max_color_attachments: 3,
        max_compute_invocations_per_workgroup: 128,
        max_compute_workgroup_size_x: 128,
        max_compute_workgroup_size_y: 128,
        ..wgpu::Limits::downlevel_defaults()
    };

    /// The limits dermis requests from an adapter offering `adapter`: [`Self::PHONE_LIMITS`],
    /// lowered wherever the adapter has less (a GLES 3.0 phone without storage buffers still
    /// gets a device, and wgpu validates against what it really has).
    pub fn phone_limits(adapter: &wgpu::Limits) -> wgpu::Limits {
        Self::PHONE_LIMITS.or_worse_values_from(adapter)
    }

    /// The backends to try, in order: the platform's own API first (Vulkan; Metal, DX12
    /// where compiled in), then GL for a machine where none offers an adapter. Setting GL up
    /// (EGL, its driver) costs a start-up that uses Vulkan 15–25 ms for nothing, so its
    /// instance is only made when needed. A backend named in `WGPU_BACKEND` is the only one
    /// tried; wgpu's other variables are honoured too.
    fn instances() -> impl Iterator<Item = (wgpu::Backends, wgpu::Instance)> {
        let order = match wgpu::Backends::from_env() {
            Some(chosen) => vec![chosen],
            None => vec![wgpu::Backends::PRIMARY, wgpu::Backends::SECONDARY],
        };
        Self::instances_of(order)
    }

    /// An instance for each of `order`'s backend sets, made when the iterator reaches it.
    fn instances_of(
        order: Vec<wgpu::Backends>,
    ) -> impl Iterator<Item = (wgpu::Backends, wgpu::Instance)> {
        order.into_iter().map(|backends| {
            let mut desc = wgpu::InstanceDescriptor::new_without_display_handle().with_env();
            desc.backends = backends;
            (backends, wgpu::Instance::new(desc))
        })
    }

    /// A context without a window (offscreen rendering, tests, benches), on the first backend
    /// of [`Self::instances`] with an adapter.
    pub fn headless() -> Result<Self, GpuError> {
        Self::first_usable(Self::instances(), |instance| {
            pollster::block_on(Self::from_instance(instance, None)).map(|gpu| (gpu, ()))
        })
        .map(|(gpu, ())| gpu)
    }

    /// A context without a window on `backends` alone, whatever `WGPU_BACKEND` says (a test
    /// of the GL path beside others on Vulkan in one process).
    pub fn headless_on(backends: wgpu::Backends) -> Result<Self, GpuError> {
        Self::first_usable(Self::instances_of(vec![backends]), |instance| {
            pollster::block_on(Self::from_instance(instance, None)).map(|gpu| (gpu, ()))
        })
        .map(|(gpu, ())| gpu)
    }

    /// A context and a surface for the window `make` hands out (once per backend tried),
    /// on the first backend of [`Self::instances`] whose adapter can present to it.
    pub fn with_surface<W>(make: impl Fn() -> W) -> Result<(Self, wgpu::Surface<'static>), GpuError>
    where
        W: Into<wgpu::SurfaceTarget<'static>>,
    {
        Self::first_usable(Self::instances(), |instance| {
            let surface = instance
                .create_surface(make())
                .map_err(|e| GpuError::NoAdapter(format!("cannot make a surface: {e}")))?;
            let gpu = pollster::block_on(Self::from_instance(instance, Some(&surface)))?;
            Ok((gpu, surface))
        })
    }

    /// `try_one` on each backend in turn until one gives a device; otherwise every
    /// backend's reason (a device error if some backend had an adapter).
    fn first_usable<T>(
        instances: impl Iterator<Item = (wgpu::Backends, wgpu::Instance)>,
        try_one: impl Fn(wgpu::Instance) -> Result<(Self, T), GpuError>,
    ) -> Result<(Self, T), GpuError> {
        let (mut reasons, mut had_adapter) = (Vec::new(), false);
        for (backends, instance) in instances {
            match try_one(instance) {
                Ok(done) => return Ok(done),
                Err(GpuError::NoAdapter(e)) => reasons.push(format!("{backends:?}: {e}")),
                Err(GpuError::Device(e)) => {
                    had_adapter = true;
                    reasons.push(format!("{backends:?}: {e}"));
                }
            }
        }
        let reasons = reasons.join("; ");
        Err(match had_adapter {
            true => GpuError::Device(reasons),
            false => GpuError::NoAdapter(reasons),
        })
    }

    /// A context whose adapter can present to `surface`.
    pub async fn from_instance(
        instance: wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Self, GpuError> {
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: surface,
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        log::info!(
            "adapter: {} ({:?}, {})",
            info.name,
            info.backend,
            info.driver_info
        );
        let features = adapter.features() & OPTIONAL_FEATURES;
        // A mid-range phone's limits, not the machine's: what runs here runs on the phone.
        let limits = Self::phone_limits(&adapter.limits());
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("dermis"),
                required_features: features,
                required_limits: limits,
                experimental_features: wgpu::ExperimentalFeatures::disabled(),
                memory_hints: wgpu::MemoryHints::Performance,
                trace: wgpu::Trace::Off,
            })
            .await
            .map_err(|e| GpuError::Device(e.to_string()))?;
        let timestamps = features.contains(wgpu::Features::TIMESTAMP_QUERY);
        Ok(Self {
            instance,
            adapter,
            device,
            queue,
            timestamps,
            pipeline_cache: None,
        })
    }

    /// Keeps the device's pipelines in `dir` (the app's cache directory: the desktop's
    /// [`super::pipeline_cache::desktop_dir`], the activity's cache dir on Android): the cache
    /// there is loaded now (a bad or foreign file is one logged line and an empty cache) and
    /// every pipeline built from now on passes through it; [`Gpu::save_pipeline_cache`]
    /// writes it back. Nothing where the adapter keeps no cache (GL, lavapipe without
    /// `PIPELINE_CACHE`).
    pub fn use_pipeline_cache(&mut self, dir: &Path) {
        self.pipeline_cache = PipelineCacheFile::open(&self.device, &self.adapter.get_info(), dir);
    }

    /// What the renderer's pipelines are made with: the device and its pipeline cache.
    pub fn pipelines(&self) -> super::pipelines::PipelineDevice<'_> {
        super::pipelines::PipelineDevice {
            device: &self.device,
            cache: self.pipeline_cache.as_ref().map(PipelineCacheFile::cache),
        }
    }

    /// Writes the pipeline cache (after the pipelines are built, and at exit): its size in
    /// bytes, `None` without a cache; a failure is one logged line.
    pub fn save_pipeline_cache(&self) -> Option<usize> {
        let cache = self.pipeline_cache.as_ref()?;
        match cache.save() {
            Ok(n) => Some(n),
            Err(e) => {
                log::warn!("pipeline cache not saved: {e}");
                None
            }
        }
    }

    /// "name (backend)" of the adapter.
    pub fn adapter_name(&self) -> String {
        let info = self.adapter.get_info();
        format!("{} ({:?})", info.name, info.backend)
    }

    /// Whether the adapter is a software rasterizer (lavapipe, llvmpipe).
    pub fn is_cpu(&self) -> bool {
        self.adapter.get_info().device_type == wgpu::DeviceType::Cpu
    }

    /// Blocks until all submitted work is done.
    pub fn wait(&self) {
        let _ = self.device.poll(wgpu::PollType::wait_indefinitely());
    }
}
