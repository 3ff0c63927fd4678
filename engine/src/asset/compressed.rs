//! Textures in GPU block formats, as the loaders see them: [`encoded_texture`] picks an
//! image's usable block encodings (KTX2, made by `cargo xtask assets`) or decodes its source.
//! The formats themselves are `dermis-texture`'s, re-exported here.

pub use dermis_texture::*;

use super::limits::{MAX_IMAGE_ALLOC, MAX_IMAGE_SIDE};
use super::TextureImage;

/// The loader's image limits, for [`BlockImage::read`].
pub const LIMITS: (u32, u64) = (MAX_IMAGE_SIDE, MAX_IMAGE_ALLOC);

/// The texture for `role` from an image's `source` bytes (PNG, JPEG or KTX2; empty: the
/// source is not there, as in the APK, which carries the encodings only): its block
/// encodings where there are usable ones — the source itself if it is KTX2 in `role`'s
/// colour space, and every file
/// `sidecar(family)` names that `read` finds, of the source's size and (for a PNG/JPEG source)
/// made from these very bytes — else the source decoded. An encoding that cannot be used is
/// one logged line and is left out (`what` names the image).
pub fn encoded_texture(
    source: &[u8],
    role: TextureRole,
    sidecar: &dyn Fn(Family) -> String,
    read: &dyn Fn(&str) -> Result<Vec<u8>, String>,
    what: &str,
) -> Result<TextureImage, String> {
    let mut encodings = Vec::new();
    let (size, hash) = if source.is_empty() {
        (None, None)
    } else if source.starts_with(&KTX2_MAGIC) {
        let img = BlockImage::read(source, LIMITS).map_err(|e| format!("{what}: {e}"))?;
        let size = (img.width, img.height);
        // An image used in two roles points at one role's encoding (the APK's glbs); the
        // other role's is beside it.
        match img.check_role(role) {
            Ok(()) => encodings.push(std::sync::Arc::new(img)),
            Err(e) => log::debug!("{what}: {e}; its encodings are looked for"),
        }
        (Some(size), None)
    } else {
        // A source that cannot be read is decode_image's to report.
        let Ok(size) = super::images::image_dimensions(source, what) else {
            return super::images::decode_image(source, role.srgb(), what);
        };
        (Some(size), Some(fnv1a64(source)))
    };
    for family in Family::ALL {
        let path = sidecar(family);
        let Ok(bytes) = read(&path) else { continue };
        let usable = BlockImage::read(&bytes, LIMITS).and_then(|img| {
            img.check_role(role)?;
            if let Some((w, h)) = size.filter(|&s| s != (img.width, img.height)) {
                return Err(format!(
                    "{}x{}, the image is {w}x{h}",
                    img.width, img.height
                ));
            }
            if hash.is_some() && img.source_hash != hash {
                return Err("made from another image (run `cargo xtask assets`)".into());
            }
            Ok(img)
        });
        match usable {
            Ok(img)
                if !encodings
                    .iter()
                    .any(|e: &std::sync::Arc<BlockImage>| e.format == img.format) =>
            {
                encodings.push(std::sync::Arc::new(img))
            }
            Ok(_) => {}
            Err(e) => log::warn!("{what}: {path}: {e}; not used"),
        }
    }
    let Some(first) = encodings.first() else {
        if source.is_empty() || source.starts_with(&KTX2_MAGIC) {
            return Err(format!("{what}: no image and no usable encoding of it"));
        }
        return super::images::decode_image(source, role.srgb(), what);
    };
    Ok(TextureImage {
        width: first.width,
        height: first.height,
        texels: super::Texels::Blocks(encodings),
        srgb: role.srgb(),
        image: None,
    })
}

impl TextureImage {
    /// Level 0 as RGBA8: the decoded image, or the first block encoding decoded.
    pub fn rgba8(&self) -> Result<std::borrow::Cow<'_, [u8]>, String> {
        match &self.texels {
            super::Texels::Rgba8(px) => Ok(std::borrow::Cow::Borrowed(px)),
            super::Texels::Blocks(encodings) => encodings
                .first()
                .ok_or_else(|| "no encoding".to_string())?
                .decode_level(0)
                .map(std::borrow::Cow::Owned),
        }
    }

    /// Bytes held: decoded texels, or every level of every encoding.
    pub fn bytes(&self) -> u64 {
        match &self.texels {
            super::Texels::Rgba8(px) => px.len() as u64,
            super::Texels::Blocks(encodings) => encodings.iter().map(|e| e.bytes()).sum(),
        }
    }

    /// Level 0 as editable RGBA8 (block encodings are decoded and dropped).
    pub fn rgba8_mut(&mut self) -> Result<&mut Vec<u8>, String> {
        if let super::Texels::Blocks(_) = &self.texels {
            self.texels = super::Texels::Rgba8(self.rgba8()?.into_owned());
        }
        match &mut self.texels {
            super::Texels::Rgba8(px) => Ok(px),
            super::Texels::Blocks(_) => unreachable!("decoded above"),
        }
    }
}
