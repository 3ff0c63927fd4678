//! The texture formats dermis ships, shared by the engine (`dermis-engine`, which reads them)
//! and `cargo xtask assets` (which makes them) without either building the other: the roles
//! a material reads an image in ([`TextureRole`]: colour, sRGB, or data, linear), the GPU block formats and their families ([`BlockFormat`], [`Family`]), one image
//! in a block format in its KTX2 file ([`BlockImage`]), where an image's encodings live
//! ([`sidecar_path`]), and the mip chain the renderer samples ([`mip_chain`]).
//!
//! What dermis stores: one 2D image, one layer, one face, no supercompression, its mip chain
//! (level 0 first in the index, as KTX2 has it), sRGB or linear as its role asks. The
//! key/value entry [`SOURCE_KEY`] holds the FNV-1a 64 hash of the PNG/JPEG bytes the file was
//! encoded from, so a loader that also has the source can tell a stale encoding from a
//! current one.

mod ktx2_file;
mod mips;

pub use ktx2_file::{KTX2_MAGIC, SOURCE_KEY};
pub use mips::mip_chain;

/// How a material reads an image: as colour (base colour, emissive, the multi-scatter and
/// diffuse-transmission colours: sRGB-encoded, as glTF has them) or as data (normal,
/// metallic-roughness, occlusion, thickness, diffuse-transmission strength: linear). The
/// loader reads an image once per role it is used in (an occlusion-roughness-metallic image
/// serves both its slots from one texture), and `cargo xtask assets` encodes it once per role.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TextureRole {
    Colour,
    Data,
}

impl TextureRole {
    pub const ALL: [TextureRole; 2] = [TextureRole::Colour, TextureRole::Data];

    /// The role of an image sampled as sRGB (`true`) or linear data.
    pub fn of_srgb(srgb: bool) -> Self {
        match srgb {
            true => TextureRole::Colour,
            false => TextureRole::Data,
        }
    }

    /// Colour is stored sRGB-encoded; data is linear.
    pub fn srgb(self) -> bool {
        self == TextureRole::Colour
    }

    /// The role's name in file names (`<image>-<name>.<family>.ktx2`).
    pub fn name(self) -> &'static str {
        match self {
            TextureRole::Colour => "colour",
            TextureRole::Data => "data",
        }
    }
}

/// A GPU family of block formats: a device reads all of a family or none of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Family {
    /// BC1–BC7 (desktop GPUs; lavapipe).
    Bc,
    /// ETC2 / EAC (every GLES 3 and Vulkan Android device).
    Etc2,
    /// ASTC LDR (nearly every Android GPU since 2015).
    Astc,
}

impl Family {
    pub const ALL: [Family; 3] = [Family::Bc, Family::Etc2, Family::Astc];

    /// The family's name in file names (`<image>-<role>.<name>.ktx2`).
    pub fn name(self) -> &'static str {
        match self {
            Family::Bc => "bc",
            Family::Etc2 => "etc2",
            Family::Astc => "astc",
        }
    }
}

/// The block formats dermis reads (4×4 texel blocks).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BlockFormat {
    /// BC1, 8 bytes a block: RGB (the encoder never uses its transparent texel).
    Bc1,
    /// BC3, 16 bytes: RGB as BC1 + interpolated alpha.
    Bc3,
    /// BC7, 16 bytes: RGBA.
    Bc7,
    /// ETC2 RGB8, 8 bytes.
    Etc2Rgb8,
    /// ETC2 RGB8 + EAC alpha, 16 bytes.
    Etc2Rgba8,
    /// ASTC 4×4 LDR, 16 bytes.
    Astc4x4,
}

impl BlockFormat {
    pub fn family(self) -> Family {
        match self {
            BlockFormat::Bc1 | BlockFormat::Bc3 | BlockFormat::Bc7 => Family::Bc,
            BlockFormat::Etc2Rgb8 | BlockFormat::Etc2Rgba8 => Family::Etc2,
            BlockFormat::Astc4x4 => Family::Astc,
        }
    }

    pub fn block_bytes(self) -> usize {
        match self {
            BlockFormat::Bc1 | BlockFormat::Etc2Rgb8 => 8,
            _ => 16,
        }
    }

    /// Whether the format stores an alpha channel.
    pub fn alpha(self) -> bool {
        !matches!(self, BlockFormat::Bc1 | BlockFormat::Etc2Rgb8)
    }

    /// The format for `family` that holds an image's channels — with its alpha where any
    /// texel's alpha is below 255 (a MASK or BLEND base colour, diffuse transmission's
    /// strength), else RGB, whose alpha reads 255 (`None`: dermis encodes none).
    pub fn for_image(family: Family, alpha: bool) -> Option<Self> {
        match (family, alpha) {
            (Family::Bc, false) => Some(BlockFormat::Bc1),
            (Family::Bc, true) => Some(BlockFormat::Bc3),
            (Family::Etc2, false) => Some(BlockFormat::Etc2Rgb8),
            (Family::Etc2, true) => Some(BlockFormat::Etc2Rgba8),
            (Family::Astc, _) => None,
        }
    }

    /// The Vulkan format (KTX2's `vkFormat`).
    pub fn vk_format(self, srgb: bool) -> ktx2::Format {
        use ktx2::Format as F;
        match (self, srgb) {
            (BlockFormat::Bc1, false) => F::BC1_RGBA_UNORM_BLOCK,
            (BlockFormat::Bc1, true) => F::BC1_RGBA_SRGB_BLOCK,
            (BlockFormat::Bc3, false) => F::BC3_UNORM_BLOCK,
            (BlockFormat::Bc3, true) => F::BC3_SRGB_BLOCK,
            (BlockFormat::Bc7, false) => F::BC7_UNORM_BLOCK,
            (BlockFormat::Bc7, true) => F::BC7_SRGB_BLOCK,
            (BlockFormat::Etc2Rgb8, false) => F::ETC2_R8G8B8_UNORM_BLOCK,
            (BlockFormat::Etc2Rgb8, true) => F::ETC2_R8G8B8_SRGB_BLOCK,
            (BlockFormat::Etc2Rgba8, false) => F::ETC2_R8G8B8A8_UNORM_BLOCK,
            (BlockFormat::Etc2Rgba8, true) => F::ETC2_R8G8B8A8_SRGB_BLOCK,
            (BlockFormat::Astc4x4, false) => F::ASTC_4x4_UNORM_BLOCK,
            (BlockFormat::Astc4x4, true) => F::ASTC_4x4_SRGB_BLOCK,
        }
    }

    /// The block format and colour space of a Vulkan format; `None`: not one dermis reads.
    /// BC1's RGB formats read as its RGBA ones (wgpu has only those; see [`BlockFormat::Bc1`]).
    pub fn from_vk(format: ktx2::Format) -> Option<(Self, bool)> {
        use ktx2::Format as F;
        Some(match format {
            F::BC1_RGB_UNORM_BLOCK | F::BC1_RGBA_UNORM_BLOCK => (BlockFormat::Bc1, false),
            F::BC1_RGB_SRGB_BLOCK | F::BC1_RGBA_SRGB_BLOCK => (BlockFormat::Bc1, true),
            F::BC3_UNORM_BLOCK => (BlockFormat::Bc3, false),
            F::BC3_SRGB_BLOCK => (BlockFormat::Bc3, true),
            F::BC7_UNORM_BLOCK => (BlockFormat::Bc7, false),
            F::BC7_SRGB_BLOCK => (BlockFormat::Bc7, true),
            F::ETC2_R8G8B8_UNORM_BLOCK => (BlockFormat::Etc2Rgb8, false),
            F::ETC2_R8G8B8_SRGB_BLOCK => (BlockFormat::Etc2Rgb8, true),
            F::ETC2_R8G8B8A8_UNORM_BLOCK => (BlockFormat::Etc2Rgba8, false),
            F::ETC2_R8G8B8A8_SRGB_BLOCK => (BlockFormat::Etc2Rgba8, true),
            F::ASTC_4x4_UNORM_BLOCK => (BlockFormat::Astc4x4, false),
            F::ASTC_4x4_SRGB_BLOCK => (BlockFormat::Astc4x4, true),
            _ => return None,
        })
    }

    /// Bytes of one level of `width × height` texels.
    pub fn level_bytes(self, width: u32, height: u32) -> usize {
        width.div_ceil(4) as usize * height.div_ceil(4) as usize * self.block_bytes()
    }
}

/// One image in a block format, with its mip chain (level 0 first).
#[derive(Clone, Debug, PartialEq)]
pub struct BlockImage {
    pub format: BlockFormat,
    pub srgb: bool,
    pub width: u32,
    pub height: u32,
    pub levels: Vec<Vec<u8>>,
    /// The hash of the image it was encoded from ([`SOURCE_KEY`]), where recorded.
    pub source_hash: Option<u64>,
}

/// FNV-1a, 64 bits: the source hash of [`SOURCE_KEY`].
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The size of mip level `level` of a `width × height` image.
pub fn level_size(width: u32, height: u32, level: usize) -> (u32, u32) {
    let shift = level.min(31) as u32;
    ((width >> shift).max(1), (height >> shift).max(1))
}

/// Levels in a full mip chain down to 1×1.
pub fn full_chain(width: u32, height: u32) -> usize {
    (32 - width.max(height).max(1).leading_zeros()) as usize
}

/// Where `cargo xtask assets` writes the block encoding in `family` of an image for `role`:
/// beside the file holding it (`file`, a path relative to the folder the loader reads),
/// `<file>.textures/[<image index>-]<role>.<family>.ktx2` (the index for a glTF file's images).
pub fn sidecar_path(file: &str, image: Option<usize>, role: TextureRole, family: Family) -> String {
    let index = image.map_or(String::new(), |i| format!("{i}-"));
    format!(
        "{file}.textures/{index}{}.{}.ktx2",
        role.name(),
        family.name()
    )
}
