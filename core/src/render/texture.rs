//! Texture upload with a full CPU-built mip chain (filtered in linear light for sRGB data).

use crate::asset::TextureImage;

/// Uploads `image` with all mip levels and returns its view.
pub fn upload(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    image: &TextureImage,
    label: &str,
) -> wgpu::TextureView {
    let levels = mip_count(image.width, image.height);
    let format = if image.srgb {
        wgpu::TextureFormat::Rgba8UnormSrgb
    } else {
        wgpu::TextureFormat::Rgba8Unorm
    };
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: image.width,
            height: image.height,
            depth_or_array_layers: 1,
        },
        mip_level_count: levels,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let (mut w, mut h) = (image.width, image.height);
    let mut level = image.rgba8.clone();
    for mip in 0..levels {
        write_level(queue, &texture, mip, &level, w, h);
        if mip + 1 < levels {
            level = downsample(&level, w, h, image.srgb);
            w = (w / 2).max(1);
            h = (h / 2).max(1);
        }
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
    let image = TextureImage {
        width: 1,
        height: 1,
        rgba8: rgba.to_vec(),
        srgb,
    };
    upload(device, queue, &image, "solid")
}

pub fn mip_count(width: u32, height: u32) -> u32 {
    32 - width.max(height).max(1).leading_zeros()
}

/// 2×2 box filter (edge texels repeat for odd sizes), in linear light when `srgb`.
fn downsample(src: &[u8], w: u32, h: u32, srgb: bool) -> Vec<u8> {
    let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
    let mut out = vec![0u8; (nw * nh * 4) as usize];
    let t = tables();
    let at = |x: u32, y: u32| ((y.min(h - 1) * w + x.min(w - 1)) * 4) as usize;
    for y in 0..nh {
        for x in 0..nw {
            let (x2, y2) = (x * 2, y * 2);
            let quad = [
                at(x2, y2),
                at(x2 + 1, y2),
                at(x2, y2 + 1),
                at(x2 + 1, y2 + 1),
            ];
            let texel = ((y * nw + x) * 4) as usize;
            for c in 0..4 {
                let linear = srgb && c < 3;
                let decode = &t.decode[usize::from(linear)];
                let sum: f32 = quad.iter().map(|&i| decode[src[i + c] as usize]).sum();
                let avg = sum * 0.25;
                out[texel + c] = if linear {
                    t.encode(avg)
                } else {
                    (avg * 255.0 + 0.5).clamp(0.0, 255.0) as u8
                };
            }
        }
    }
    out
}

/// Each byte's value (plain and sRGB-decoded), and the linear values where the sRGB-encoded
/// byte steps up: what a mip level costs is table lookups, not `powf` per texel.
struct Tables {
    decode: [[f32; 256]; 2],
    /// `steps[k]`: the least linear value encoded to byte `k + 1` (the sRGB curve's midpoint
    /// between `k` and `k + 1`, decoded).
    steps: [f32; 255],
}

impl Tables {
    /// The sRGB byte of a linear value in [0, 1]: the steps at or below it.
    fn encode(&self, linear: f32) -> u8 {
        self.steps.partition_point(|&s| s <= linear) as u8
    }
}

fn tables() -> &'static Tables {
    static TABLES: std::sync::OnceLock<Tables> = std::sync::OnceLock::new();
    TABLES.get_or_init(|| {
        let unit = |b: usize| b as f32 / 255.0;
        Tables {
            decode: [
                std::array::from_fn(unit),
                std::array::from_fn(|b| srgb_to_linear(unit(b))),
            ],
            steps: std::array::from_fn(|k| srgb_to_linear((k as f32 + 0.5) / 255.0)),
        }
    })
}

fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// The sRGB curve itself (what [`Tables::encode`] is checked against).
#[cfg(test)]
fn linear_to_srgb(v: f32) -> f32 {
    if v <= 0.0031308 {
        v * 12.92
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mip_chain_length() {
        assert_eq!(mip_count(1, 1), 1);
        assert_eq!(mip_count(512, 512), 10);
        assert_eq!(mip_count(640, 3), 10);
    }

    #[test]
    fn the_encode_table_rounds_as_the_srgb_curve_does() {
        let t = tables();
        let mut off = 0;
        let n = 200_000;
        for i in 0..=n {
            let v = i as f32 / n as f32;
            let exact = (linear_to_srgb(v) * 255.0 + 0.5).clamp(0.0, 255.0) as u8;
            let got = t.encode(v);
            assert!(exact.abs_diff(got) <= 1, "{v}: {exact} vs {got}");
            off += usize::from(exact != got);
        }
        // Only where float rounding lands exactly on a step.
        assert!(off <= 2, "{off} of {n} values off by one");
        assert_eq!((t.encode(0.0), t.encode(1.0)), (0, 255));
    }

    #[test]
    fn srgb_downsample_averages_in_linear_light() {
        // Black and white average to 50 % linear, which is sRGB 188, not 128.
        let src = [0, 0, 0, 255, 255, 255, 255, 255];
        let out = downsample(&src, 2, 1, true);
        assert!((out[0] as i32 - 188).abs() <= 1, "{}", out[0]);
        let lin = downsample(&src, 2, 1, false);
        assert!((lin[0] as i32 - 128).abs() <= 1);
    }
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
