//! Rendering into a texture and reading it back (the `render` command, tests, benches).

use super::readback::read_mapped;
use super::targets::Targets;
use super::Gpu;

/// An 8-bit RGBA image (sRGB-encoded, as displayed).
#[derive(Clone, Debug, PartialEq)]
pub struct RgbaImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<u8>,
}

/// An offscreen colour target with its MSAA/depth targets and a readback buffer.
pub struct Offscreen {
    pub targets: Targets,
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
    readback: wgpu::Buffer,
    padded_row: u32,
    bytes_per_pixel: u32,
}

/// The offscreen format: sRGB, so shaders write linear values and the hardware encodes.
pub const OFFSCREEN_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

impl Offscreen {
    pub fn new(gpu: &Gpu, width: u32, height: u32) -> Self {
        Self::with_format(gpu, width, height, OFFSCREEN_FORMAT)
    }

    /// An offscreen target of `format` (`Rgba8UnormSrgb` for images, `Rgba16Float` for raw
    /// radiance in numerical checks).
    pub fn with_format(gpu: &Gpu, width: u32, height: u32, format: wgpu::TextureFormat) -> Self {
        let device = &gpu.device;
        let targets = Targets::new(device, format, width, height);
        let bytes_per_pixel = format.block_copy_size(None).unwrap_or(4);
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("offscreen"),
            size: wgpu::Extent3d {
                width: targets.width,
                height: targets.height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let padded_row = (targets.width * bytes_per_pixel)
            .div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
            * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("offscreen readback"),
            size: (padded_row * targets.height) as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            targets,
            texture,
            view,
            readback,
            padded_row,
            bytes_per_pixel,
        }
    }

    /// Records the copy of the rendered image into the readback buffer.
    pub fn copy_out(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.copy_texture_to_buffer(
            self.texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &self.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.padded_row),
                    rows_per_image: Some(self.targets.height),
                },
            },
            wgpu::Extent3d {
                width: self.targets.width,
                height: self.targets.height,
                depth_or_array_layers: 1,
            },
        );
    }

    /// Waits for the GPU and returns the image copied by [`Self::copy_out`] (8-bit formats).
    pub fn read(&self, gpu: &Gpu) -> RgbaImage {
        let (width, height) = (self.targets.width, self.targets.height);
        RgbaImage {
            width,
            height,
            pixels: self.read_bytes(gpu),
        }
    }

    /// Waits for the GPU and returns the tightly packed texel bytes.
    pub fn read_bytes(&self, gpu: &Gpu) -> Vec<u8> {
        let (w, h) = (self.targets.width, self.targets.height);
        let row_bytes = (w * self.bytes_per_pixel) as usize;
        read_mapped(&gpu.device, &self.readback, |data| {
            let mut bytes = Vec::with_capacity(row_bytes * h as usize);
            for row in 0..h {
                let start = (row * self.padded_row) as usize;
                bytes.extend_from_slice(&data[start..start + row_bytes]);
            }
            bytes
        })
        .expect("readback buffer was mapped above")
    }

    /// Raw RGBA16F radiance as f32 (for `Rgba16Float` targets).
    pub fn read_f16(&self, gpu: &Gpu) -> Vec<[f32; 4]> {
        self.read_bytes(gpu)
            .chunks_exact(8)
            .map(|t| {
                std::array::from_fn(|c| f16_to_f32(u16::from_le_bytes([t[2 * c], t[2 * c + 1]])))
            })
            .collect()
    }
}

/// IEEE half → single (NaN and ±Inf preserved).
pub fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = (h >> 10) & 0x1f;
    let frac = (h & 0x3ff) as f32;
    match exp {
        0 => sign * frac * 2f32.powi(-24),
        31 if frac == 0.0 => sign * f32::INFINITY,
        31 => f32::NAN,
        e => sign * (1.0 + frac / 1024.0) * 2f32.powi(e as i32 - 15),
    }
}

#[cfg(test)]
mod tests {
    use super::f16_to_f32;

    #[test]
    fn half_conversion() {
        assert_eq!(f16_to_f32(0x3c00), 1.0);
        assert_eq!(f16_to_f32(0xc000), -2.0);
        assert_eq!(f16_to_f32(0x7bff), 65504.0);
        assert!(f16_to_f32(0x7c00).is_infinite());
        assert!(f16_to_f32(0x7e00).is_nan());
        assert_eq!(f16_to_f32(0x0001), 2f32.powi(-24));
    }
}
