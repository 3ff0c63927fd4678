//! Image decoding (PNG/JPEG via `image`) under hard size limits, to RGBA8, and a glTF
//! file's images read in a role (their block encodings where there are usable ones).

use std::io::Cursor;

use super::accessor::{view_bytes, Buffers};
use super::compressed::{encoded_texture, sidecar_path};
use super::limits::{MAX_IMAGE_ALLOC, MAX_IMAGE_SIDE};
use super::uri::{resolve_uri, UriRef};
use super::{Family, TextureImage, TextureRole};

/// Decodes an encoded image to RGBA8, refusing images above the size limits before decoding.
pub(crate) fn decode_image(bytes: &[u8], srgb: bool, what: &str) -> Result<TextureImage, String> {
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_IMAGE_SIDE);
    limits.max_image_height = Some(MAX_IMAGE_SIDE);
    limits.max_alloc = Some(MAX_IMAGE_ALLOC);
    let mut reader = image::ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| format!("{what}: cannot read image: {e}"))?;
    if reader.format().is_none() {
        return Err(format!(
            "{what}: unknown image format (PNG and JPEG are supported)"
        ));
    }
    reader.limits(limits);
    let img = reader
        .decode()
        .map_err(|e| format!("{what}: cannot decode image: {e}"))?;
    let rgba = img.into_rgba8();
    let (width, height) = rgba.dimensions();
    Ok(TextureImage::rgba(width, height, rgba.into_raw(), srgb))
}

/// An encoded image's size from its header, without decoding it.
pub(crate) fn image_dimensions(bytes: &[u8], what: &str) -> Result<(u32, u32), String> {
    image::ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| format!("{what}: cannot read image: {e}"))?
        .into_dimensions()
        .map_err(|e| format!("{what}: cannot read image: {e}"))
}

/// Image `index`'s bytes as the file holds them (PNG, JPEG or KTX2).
fn gltf_image_source(
    doc: &gltf::Document,
    buffers: &Buffers<'_>,
    resolve: &dyn Fn(&str) -> Result<Vec<u8>, String>,
    index: usize,
) -> Result<Vec<u8>, String> {
    let what = format!("image {index}");
    let image = doc
        .images()
        .nth(index)
        .ok_or_else(|| format!("missing {what}"))?;
    match image.source() {
        gltf::image::Source::View { view, .. } => view_bytes(buffers, &view)
            .map(<[u8]>::to_vec)
            .map_err(|e| format!("{what}: {e}")),
        gltf::image::Source::Uri { uri, .. } => {
            match resolve_uri(uri).map_err(|e| format!("{what}: {e}"))? {
                UriRef::Data(d) => Ok(d),
                UriRef::Relative(p) => resolve(&p).map_err(|e| format!("{what}: {e}")),
            }
        }
    }
}

/// Image `index` of the glTF file `file` read in `role`: its block encodings where `cargo
/// xtask assets` made them beside the file (`<file>.textures/<index>-<role>.<family>.ktx2`,
/// checked against the source's hash and size) or the image is a KTX2 file itself, else the
/// image decoded. See [`encoded_texture`].
pub(super) fn gltf_image(
    doc: &gltf::Document,
    buffers: &Buffers<'_>,
    resolve: &dyn Fn(&str) -> Result<Vec<u8>, String>,
    (index, role): (usize, TextureRole),
    file: &str,
) -> Result<TextureImage, String> {
    let what = format!("image {index}");
    let source = gltf_image_source(doc, buffers, resolve, index)?;
    let sidecar = |family: Family| sidecar_path(file, Some(index), role, family);
    let mut tex = encoded_texture(&source, role, &sidecar, resolve, &what)?;
    tex.image = Some(index);
    Ok(tex)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_garbage() {
        assert!(decode_image(b"not an image", true, "image 0").is_err());
    }

    #[test]
    fn decodes_png_to_rgba8() {
        let mut png = Vec::new();
        let img = image::RgbImage::from_pixel(3, 2, image::Rgb([10, 20, 30]));
        img.write_to(&mut Cursor::new(&mut png), image::ImageFormat::Png)
            .unwrap();
        let t = decode_image(&png, true, "image 0").unwrap();
        let px = t.rgba8().unwrap();
        assert_eq!((t.width, t.height, px.len()), (3, 2, 24));
        assert_eq!(&px[..4], &[10, 20, 30, 255]);
        assert!(t.srgb);
    }
}
