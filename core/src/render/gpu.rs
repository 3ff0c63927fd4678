//! Instance, adapter, device and queue.

use std::fmt;

/// The GPU context every other render object is created from.
pub struct Gpu {
    pub instance: wgpu::Instance,
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    /// Whether TIMESTAMP_QUERY was granted (GPU timings available).
    pub timestamps: bool,
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

/// Features dermis uses when the adapter has them.
const OPTIONAL_FEATURES: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
    .union(wgpu::Features::SHADER_F16);

impl Gpu {
    /// An instance honouring `WGPU_BACKEND` etc. (Vulkan and GL compiled in).
    pub fn instance() -> wgpu::Instance {
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle().with_env())
    }

    /// A context without a window (offscreen rendering, tests, benches).
    pub fn headless() -> Result<Self, GpuError> {
        let instance = Self::instance();
        pollster::block_on(Self::from_instance(instance, None))
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
        // Whatever the adapter offers; the renderer itself stays inside GLES3 limits
        // (16 KiB uniform blocks, no storage buffers in the render path).
        let limits = adapter.limits();
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
        })
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
