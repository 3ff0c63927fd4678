//! Texture upload: GPU block-compressed images as they are stored where the device samples
//! their format, else decoded to RGBA8; decoded images with a full CPU-built mip chain
//! (filtered in linear light for sRGB data). Every texture made here is counted
//! ([`uploaded_bytes`]).

use std::sync::atomic::{AtomicU64, Ordering};

use crate::asset::compressed::{full_chain, level_size, mip_chain};
use crate::asset::{BlockFormat, BlockImage, Family, Texels, TextureImage};

/// Bytes of every texture created through this module since the process started, all mip
/// levels counted at their size on the GPU (block formats at their block size).
static UPLOADED: AtomicU64 = AtomicU64::new(0);

/// What the renderer has uploaded as textures (bytes, all levels), process-wide: read it
/// before and after a load to know what that load put on the GPU.
pub fn uploaded_bytes() -> u64 {
    UPLOADED.load(Ordering::Relaxed)
}

fn count(bytes: u64) {
    UPLOADED.fetch_add(bytes, Ordering::Relaxed);
}

/// The device feature that lets it sample `family`.
pub fn family_feature(family: Family) -> wgpu::Features {
    match family {
        Family::Bc => wgpu::Features::TEXTURE_COMPRESSION_BC,
        Family::Etc2 => wgpu::Features::TEXTURE_COMPRESSION_ETC2,
        Family::Astc => wgpu::Features::TEXTURE_COMPRESSION_ASTC,
    }
}

/// wgpu's format for a block format.
pub fn block_format(format: BlockFormat, srgb: bool) -> wgpu::TextureFormat {
    use wgpu::TextureFormat as F;
    match (format, srgb) {
        (BlockFormat::Bc1, false) => F::Bc1RgbaUnorm,
        (BlockFormat::Bc1, true) => F::Bc1RgbaUnormSrgb,
        (BlockFormat::Bc3, false) => F::Bc3RgbaUnorm,
        (BlockFormat::Bc3, true) => F::Bc3RgbaUnormSrgb,
        (BlockFormat::Bc7, false) => F::Bc7RgbaUnorm,
        (BlockFormat::Bc7, true) => F::Bc7RgbaUnormSrgb,
        (BlockFormat::Etc2Rgb8, false) => F::Etc2Rgb8Unorm,
        (BlockFormat::Etc2Rgb8, true) => F::Etc2Rgb8UnormSrgb,
        (BlockFormat::Etc2Rgba8, false) => F::Etc2Rgba8Unorm,
        (BlockFormat::Etc2Rgba8, true) => F::Etc2Rgba8UnormSrgb,
        (BlockFormat::Astc4x4, srgb) => F::Astc {
            block: wgpu::AstcBlock::B4x4,
            channel: match srgb {
                true => wgpu::AstcChannel::UnormSrgb,
                false => wgpu::AstcChannel::Unorm,
            },
        },
    }
}

/// The encoding of `image` that `device` samples as it is stored, if any: the first of its
/// block encodings whose family the device has (and whose size is whole blocks).
pub fn native_encoding<'a>(
    device: &wgpu::Device,
    image: &'a TextureImage,
) -> Option<&'a BlockImage> {
    let Texels::Blocks(encodings) = &image.texels else {
        return None;
    };
    let features = device.features();
    encodings
        .iter()
        .find(|e| {
            features.contains(family_feature(e.format.family()))
                && e.width % 4 == 0
                && e.height % 4 == 0
        })
        .map(|e| &**e)
}

/// The bytes [`upload`] puts on `device`'s GPU for `image`, all levels: a native encoding's
/// blocks, else 4 a texel of the decoded chain (a block encoding's own levels, or the full
/// chain built from a decoded image).
pub fn upload_bytes(device: &wgpu::Device, image: &TextureImage) -> u64 {
    if let Some(native) = native_encoding(device, image) {
        return native.bytes();
    }
    let levels = match &image.texels {
        Texels::Blocks(e) => e.first().map_or(1, |e| e.levels.len()),
        Texels::Rgba8(_) => full_chain(image.width, image.height),
    };
    (0..levels)
        .map(|i| {
            let (w, h) = level_size(image.width, image.height, i);
            u64::from(w) * u64::from(h) * 4
        })
        .sum()
}

/// Uploads `image` with all mip levels and returns its view: a block encoding the device
/// samples as it is, else the image decoded to RGBA8 (a block encoding's own levels, or a
/// mip chain built from the decoded image).
pub fn upload(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    image: &TextureImage,
    label: &str,
) -> wgpu::TextureView {
    let encodings = match &image.texels {
        Texels::Rgba8(rgba) => return upload_rgba8(device, queue, image, rgba, label),
        Texels::Blocks(encodings) => encodings,
    };
    if let Some(native) = native_encoding(device, image) {
        return upload_blocks(device, queue, native, label);
    }
    let decoded = encodings
        .first()
        .map_or(Err("no encoding".to_string()), |e| {
            (0..e.levels.len())
                .map(|i| e.decode_level(i))
                .collect::<Result<Vec<_>, _>>()
        });
    let format = rgba8_format(image.srgb);
    match decoded {
        Ok(levels) => {
            log::debug!(
                "{label}: {:?} decoded to RGBA8 (the device does not sample it)",
                encodings[0].format
            );
            upload_levels(
                device,
                queue,
                &levels,
                (image.width, image.height),
                format,
                label,
            )
        }
        Err(e) => {
            log::warn!("{label}: cannot decode ({e}); drawn white");
            upload_levels(device, queue, &[vec![255; 4]], (1, 1), format, label)
        }
    }
}

fn rgba8_format(srgb: bool) -> wgpu::TextureFormat {
    match srgb {
        true => wgpu::TextureFormat::Rgba8UnormSrgb,
        false => wgpu::TextureFormat::Rgba8Unorm,
    }
}

/// A decoded image with the mip chain built here.
fn upload_rgba8(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    image: &TextureImage,
    rgba: &[u8],
    label: &str,
) -> wgpu::TextureView {
    let levels = mip_chain(rgba, image.width, image.height, image.srgb);
    let format = rgba8_format(image.srgb);
    upload_levels(
        device,
        queue,
        &levels,
        (image.width, image.height),
        format,
        label,
    )
}

fn new_texture(
    device: &wgpu::Device,
    (width, height): (u32, u32),
    levels: u32,
    format: wgpu::TextureFormat,
    label: &str,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: levels,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}

/// RGBA8 levels (level 0 of `size` first) as one texture.
fn upload_levels(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    levels: &[Vec<u8>],
    size: (u32, u32),
    format: wgpu::TextureFormat,
    label: &str,
) -> wgpu::TextureView {
    let texture = new_texture(device, size, levels.len() as u32, format, label);
    for (mip, data) in levels.iter().enumerate() {
        let (w, h) = level_size(size.0, size.1, mip);
        write_level(queue, &texture, mip as u32, data, w, h);
        count(data.len() as u64);
    }
    texture.create_view(&wgpu::TextureViewDescriptor::default())
}

/// A block encoding as it is stored, every level.
fn upload_blocks(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    image: &BlockImage,
    label: &str,
) -> wgpu::TextureView {
    let format = block_format(image.format, image.srgb);
    let size = (image.width, image.height);
    let texture = new_texture(device, size, image.levels.len() as u32, format, label);
    for (mip, data) in image.levels.iter().enumerate() {
        let (w, h) = level_size(size.0, size.1, mip);
        let (bw, bh) = (w.div_ceil(4), h.div_ceil(4));
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: mip as u32,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            data,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(bw * image.format.block_bytes() as u32),
                rows_per_image: Some(bh),
            },
            // Whole blocks: a level smaller than a block is copied as its physical size.
            wgpu::Extent3d {
                width: bw * 4,
                height: bh * 4,
                depth_or_array_layers: 1,
            },
        );
        count(data.len() as u64);
    }
    texture.create_view(&wgpu::TextureViewDescriptor::default())
}

/// A single-level RGBA8 texture of `format` (pixel-exact data such as the UI atlas).
pub fn upload_single(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    rgba: &[u8],
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    label: &str,
) -> wgpu::TextureView {
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    write_level(queue, &texture, 0, rgba, width, height);
    count(rgba.len() as u64);
    texture.create_view(&wgpu::TextureViewDescriptor::default())
}

/// Writes one tightly packed RGBA8 mip level.
fn write_level(
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    mip: u32,
    data: &[u8],
    w: u32,
    h: u32,
) {
    queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: mip,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        data,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(4 * w),
            rows_per_image: Some(h),
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
}

/// A 1×1 texture of one colour (the default base colour).
pub fn solid(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    rgba: [u8; 4],
    srgb: bool,
) -> wgpu::TextureView {
    upload_levels(
        device,
        queue,
        &[rgba.to_vec()],
        (1, 1),
        rgba8_format(srgb),
        "solid",
    )
}

/// IEEE binary16 bits of `x` (round to nearest even; overflow to ∞, underflow through the
/// subnormals to 0).
pub fn f32_to_f16(x: f32) -> u16 {
    let bits = x.to_bits();
    let sign = ((bits >> 16) & 0x8000) as u16;
    let exp = ((bits >> 23) & 0xff) as i32;
    let man = bits & 0x7f_ffff;
    if exp == 0xff {
        return sign | 0x7c00 | if man != 0 { 0x200 } else { 0 };
    }
    let e = exp - 127 + 15;
    if e >= 0x1f {
        return sign | 0x7c00;
    }
    if e <= 0 {
        if e < -10 {
            return sign;
        }
        let m = man | 0x80_0000;
        let shift = (14 - e) as u32;
        let half = 1u32 << (shift - 1);
        let rest = m & ((1 << shift) - 1);
        let mut v = m >> shift;
        if rest > half || (rest == half && v & 1 == 1) {
            v += 1;
        }
        return sign | v as u16;
    }
    let mut v = ((e as u32) << 10) | (man >> 13);
    let rest = man & 0x1fff;
    if rest > 0x1000 || (rest == 0x1000 && v & 1 == 1) {
        v += 1; // may carry into the exponent: still correct
    }
    sign | v as u16
}

/// An `Rgba16Float` texture of `width × height` texels (a LUT), written by [`write_rgba16f`].
pub fn rgba16f(device: &wgpu::Device, (width, height): (u32, u32), label: &str) -> wgpu::Texture {
    count(u64::from(width) * u64::from(height) * 8);
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba16Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}

/// Writes `texels` (row-major) into an `Rgba16Float` texture made by [`rgba16f`].
pub fn write_rgba16f(queue: &wgpu::Queue, texture: &wgpu::Texture, texels: &[[f32; 4]]) {
    let bytes: Vec<u8> = texels
        .iter()
        .flat_map(|t| t.iter().flat_map(|&v| f32_to_f16(v).to_le_bytes()))
        .collect();
    let (w, h) = (texture.width(), texture.height());
    queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        &bytes,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(w * 8),
            rows_per_image: Some(h),
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
}

#[cfg(test)]
mod f16_tests {
    use super::f32_to_f16;
    use crate::render::offscreen::f16_to_f32;

    #[test]
    fn f16_round_trips_and_rounds_to_nearest() {
        for x in [0.0f32, 1.0, -2.5, 0.333, 65504.0, 6.1e-5, 1e-7, 3.0e-6] {
            let y = f16_to_f32(f32_to_f16(x));
            assert!((y - x).abs() <= x.abs() * 1e-3 + 6e-8, "{x} → {y}");
        }
        assert_eq!(f32_to_f16(1e6), 0x7c00);
        assert_eq!(f32_to_f16(1.0 + 1.0 / 4096.0), f32_to_f16(1.0));
    }
}
