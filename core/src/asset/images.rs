//! Image decoding (PNG/JPEG via `image`) under hard size limits, to RGBA8.

use std::io::Cursor;

use super::limits::{MAX_IMAGE_ALLOC, MAX_IMAGE_SIDE};
use super::TextureImage;

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
