//! [`BlockImage`] in its KTX2 file: read (every size, count and format checked before
//! anything is allocated), written, and decoded to RGBA8 for a device that cannot sample it.

use crate::{full_chain, level_size, BlockFormat, BlockImage, TextureRole};

/// The key/value entry naming the source image's hash (`fnv1a64:<16 hex digits>`).
pub const SOURCE_KEY: &str = "dermis.source";

/// The KTX2 file signature.
pub const KTX2_MAGIC: [u8; 12] = [
    0xab, 0x4b, 0x54, 0x58, 0x20, 0x32, 0x30, 0xbb, 0x0d, 0x0a, 0x1a, 0x0a,
];

impl BlockImage {
    /// Reads a KTX2 file, checking everything the renderer relies on, with at most
    /// `max_side` texels a side and `max_bytes` of levels; one line on failure.
    pub fn read(bytes: &[u8], (max_side, max_bytes): (u32, u64)) -> Result<Self, String> {
        let reader = ktx2::Reader::new(bytes).map_err(|e| format!("not a valid KTX2 file: {e}"))?;
        let h = reader.header();
        let vk = h
            .format
            .ok_or("KTX2 without a vkFormat (Basis Universal is not read)")?;
        let (format, srgb) = BlockFormat::from_vk(vk)
            .ok_or_else(|| format!("KTX2 format {vk:?} is not one dermis reads"))?;
        if let Some(s) = h.supercompression_scheme {
            return Err(format!("KTX2 supercompression {s:?} is not read"));
        }
        if h.pixel_depth != 0 || h.layer_count > 1 || h.face_count != 1 {
            return Err(format!(
                "KTX2 is not one 2D image (depth {}, layers {}, faces {})",
                h.pixel_depth, h.layer_count, h.face_count
            ));
        }
        let (width, height) = (h.pixel_width, h.pixel_height);
        if height == 0 || width > max_side || height > max_side {
            return Err(format!("KTX2 size {width}x{height} outside 1..={max_side}"));
        }
        let full = full_chain(width, height);
        let count = h.level_count as usize;
        if count == 0 || count > full {
            return Err(format!(
                "KTX2 has {count} mip levels; a {width}x{height} image has 1 to {full}"
            ));
        }
        let mut total: u64 = 0;
        let mut levels = Vec::with_capacity(count);
        for (i, level) in reader.levels().enumerate() {
            let (w, h) = level_size(width, height, i);
            let want = format.level_bytes(w, h);
            if level.data.len() != want || level.uncompressed_byte_length != want as u64 {
                return Err(format!(
                    "KTX2 level {i} ({w}x{h}) has {} bytes, {format:?} needs {want}",
                    level.data.len()
                ));
            }
            total += want as u64;
            if total > max_bytes {
                return Err(format!("KTX2 levels above {max_bytes} bytes"));
            }
            levels.push(level.data.to_vec());
        }
        let source_hash = reader
            .key_value_data()
            .find(|(k, _)| *k == SOURCE_KEY)
            .and_then(|(_, v)| std::str::from_utf8(v).ok())
            .and_then(|v| v.trim_end_matches('\0').strip_prefix("fnv1a64:"))
            .and_then(|hex| u64::from_str_radix(hex, 16).ok());
        Ok(Self {
            format,
            srgb,
            width,
            height,
            levels,
            source_hash,
        })
    }

    /// The KTX2 file of this image (deterministic: no time, no tool version).
    pub fn write(&self) -> Vec<u8> {
        let vk = self.format.vk_format(self.srgb);
        let (dfd, type_size) = ktx2::dfd::Basic::from_format(vk)
            .unwrap_or_else(|e| unreachable!("ktx2 describes every block format: {e:?}"));
        let dfd = ktx2::dfd::Block::Basic(dfd).to_vec();
        let mut kvd = Vec::new();
        let mut entry = |key: &str, value: &str| {
            let mut kv = key.as_bytes().to_vec();
            kv.push(0);
            kv.extend_from_slice(value.as_bytes());
            kv.push(0);
            kvd.extend_from_slice(&(kv.len() as u32).to_le_bytes());
            kvd.extend_from_slice(&kv);
            kvd.resize(kvd.len().next_multiple_of(4), 0);
        };
        entry("KTXwriter", "dermis");
        if let Some(hash) = self.source_hash {
            entry(SOURCE_KEY, &format!("fnv1a64:{hash:016x}"));
        }
        let n = self.levels.len();
        let index_end = ktx2::Header::LENGTH + n * ktx2::LevelIndex::LENGTH;
        let dfd_offset = index_end;
        let dfd_len = 4 + dfd.len();
        let kvd_offset = dfd_offset + dfd_len;
        let mut data_start = (kvd_offset + kvd.len()).next_multiple_of(16);
        // Smallest level first in the file (the KTX2 layout), each 16-byte aligned (a multiple
        // of the block size, as the format asks).
        let mut offsets = vec![0usize; n];
        for i in (0..n).rev() {
            offsets[i] = data_start;
            data_start = (data_start + self.levels[i].len()).next_multiple_of(16);
        }
        let header = ktx2::Header {
            format: Some(vk),
            type_size,
            pixel_width: self.width,
            pixel_height: self.height,
            pixel_depth: 0,
            layer_count: 0,
            face_count: 1,
            level_count: n as u32,
            supercompression_scheme: None,
            index: ktx2::Index {
                dfd_byte_offset: dfd_offset as u32,
                dfd_byte_length: dfd_len as u32,
                kvd_byte_offset: kvd_offset as u32,
                kvd_byte_length: kvd.len() as u32,
                sgd_byte_offset: 0,
                sgd_byte_length: 0,
            },
        };
        let mut out = header.as_bytes().to_vec();
        for (level, &offset) in self.levels.iter().zip(&offsets) {
            let index = ktx2::LevelIndex {
                byte_offset: offset as u64,
                byte_length: level.len() as u64,
                uncompressed_byte_length: level.len() as u64,
            };
            out.extend_from_slice(&index.as_bytes());
        }
        out.extend_from_slice(&(dfd_len as u32).to_le_bytes());
        out.extend_from_slice(&dfd);
        out.extend_from_slice(&kvd);
        for i in (0..n).rev() {
            out.resize(offsets[i], 0);
            out.extend_from_slice(&self.levels[i]);
        }
        out
    }

    /// Level `i` decoded to RGBA8 (row-major, tightly packed).
    pub fn decode_level(&self, i: usize) -> Result<Vec<u8>, String> {
        let data = self
            .levels
            .get(i)
            .ok_or_else(|| format!("no mip level {i}"))?;
        let (w, h) = level_size(self.width, self.height, i);
        let (w, h) = (w as usize, h as usize);
        let mut texels = vec![0u32; w * h];
        use texture2ddecoder as d;
        match self.format {
            BlockFormat::Bc1 => d::decode_bc1a(data, w, h, &mut texels),
            BlockFormat::Bc3 => d::decode_bc3(data, w, h, &mut texels),
            BlockFormat::Bc7 => d::decode_bc7(data, w, h, &mut texels),
            BlockFormat::Etc2Rgb8 => d::decode_etc2_rgb(data, w, h, &mut texels),
            BlockFormat::Etc2Rgba8 => d::decode_etc2_rgba8(data, w, h, &mut texels),
            BlockFormat::Astc4x4 => d::decode_astc(data, w, h, 4, 4, &mut texels),
        }
        .map_err(|e| format!("{:?} level {i}: {e}", self.format))?;
        // The decoder's texels are B, G, R, A bytes (little-endian u32).
        Ok(texels
            .iter()
            .flat_map(|t| {
                let [b, g, r, a] = t.to_le_bytes();
                [r, g, b, a]
            })
            .collect())
    }

    /// Bytes of every level together (what the GPU holds).
    pub fn bytes(&self) -> u64 {
        self.levels.iter().map(|l| l.len() as u64).sum()
    }

    /// Checks that this encoding can stand for `role`: its colour space. (Its alpha is the
    /// encoder's choice: kept where the image has any, else RGB reading 255, as the image.)
    pub fn check_role(&self, role: TextureRole) -> Result<(), String> {
        if self.srgb != role.srgb() {
            let (is, want) = match self.srgb {
                true => ("sRGB", "linear"),
                false => ("linear", "sRGB"),
            };
            return Err(format!(
                "{:?} is {is} but a {} texture is {want}",
                self.format,
                role.name()
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fnv1a64;

    const LIMITS: (u32, u64) = (8192, 1 << 28);

    fn sample(format: BlockFormat) -> BlockImage {
        let (w, h) = (8, 4);
        let levels = (0..full_chain(w, h))
            .map(|i| {
                let (lw, lh) = level_size(w, h, i);
                (0..format.level_bytes(lw, lh))
                    .map(|b| (b * 37 + i) as u8)
                    .collect()
            })
            .collect();
        BlockImage {
            format,
            srgb: true,
            width: w,
            height: h,
            levels,
            source_hash: Some(fnv1a64(b"source")),
        }
    }

    #[test]
    fn written_files_read_back_the_same() {
        for f in [
            BlockFormat::Bc1,
            BlockFormat::Etc2Rgba8,
            BlockFormat::Astc4x4,
        ] {
            let img = sample(f);
            let bytes = img.write();
            assert_eq!(BlockImage::read(&bytes, LIMITS).unwrap(), img);
            assert_eq!(bytes, img.write(), "deterministic");
        }
    }

    #[test]
    fn every_truncation_is_an_error_not_a_panic() {
        let bytes = sample(BlockFormat::Etc2Rgb8).write();
        for len in 0..bytes.len() {
            assert!(BlockImage::read(&bytes[..len], LIMITS).is_err(), "{len}");
        }
    }

    #[test]
    fn roles_and_colour_spaces() {
        let img = sample(BlockFormat::Etc2Rgb8);
        assert!(img.check_role(TextureRole::Colour).is_ok());
        assert!(img.check_role(TextureRole::Data).is_err());
        assert_eq!(TextureRole::of_srgb(true), TextureRole::Colour);
        assert!(TextureRole::ALL
            .iter()
            .all(|&r| TextureRole::of_srgb(r.srgb()) == r));
    }

    #[test]
    fn fnv_matches_the_published_vectors() {
        assert_eq!(fnv1a64(b""), 0xcbf29ce484222325);
        assert_eq!(fnv1a64(b"a"), 0xaf63dc4c8601ec8c);
    }
}
