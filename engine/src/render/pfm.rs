//! Portable Float Map (`PF`, RGB f32): linear images the engine writes (`render --hdr`) and the
//! path tracer's cached references are stored in. Rows in memory run top to bottom; the file
//! stores them bottom to top, little-endian (negative scale).

use std::path::Path;

/// A linear RGB image, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct FloatImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 3]>,
}

impl FloatImage {
    pub fn new(width: u32, height: u32, pixels: Vec<[f32; 3]>) -> Result<Self, String> {
        if pixels.len() != (width as usize) * (height as usize) {
            return Err(format!(
                "{} pixels for a {width}x{height} image",
                pixels.len()
            ));
        }
        Ok(Self {
            width,
            height,
            pixels,
        })
    }

    pub fn encode(&self) -> Vec<u8> {
        let mut out = format!("PF\n{} {}\n-1.0\n", self.width, self.height).into_bytes();
        for row in self.pixels.chunks_exact(self.width as usize).rev() {
            for p in row {
                for c in p {
                    out.extend_from_slice(&c.to_le_bytes());
                }
            }
        }
        out
    }

    pub fn decode(bytes: &[u8]) -> Result<Self, String> {
        // Three whitespace-terminated header tokens after the magic.
        let mut tokens = Vec::new();
        let mut at = 0;
        while tokens.len() < 4 {
            while at < bytes.len() && bytes[at].is_ascii_whitespace() {
                at += 1;
            }
            let start = at;
            while at < bytes.len() && !bytes[at].is_ascii_whitespace() {
                at += 1;
            }
            if start == at || at - start > 32 {
                return Err("PFM: truncated header".into());
            }
            tokens.push(String::from_utf8_lossy(&bytes[start..at]).into_owned());
        }
        at += 1; // the single whitespace byte after the scale
        if tokens[0] != "PF" {
            return Err(format!("PFM: `{}` is not an RGB float map", tokens[0]));
        }
        let dim = |s: &str| -> Result<u32, String> {
            s.parse::<u32>()
                .ok()
                .filter(|d| (1..=16384).contains(d))
                .ok_or(format!("PFM: bad size `{s}`"))
        };
        let (w, h) = (dim(&tokens[1])?, dim(&tokens[2])?);
        let scale: f32 = tokens[3].parse().map_err(|_| "PFM: bad scale")?;
        if scale == 0.0 || !scale.is_finite() {
            return Err("PFM: bad scale".into());
        }
        let n = w as usize * h as usize;
        let body = bytes.get(at..).unwrap_or(&[]);
        if body.len() != n * 12 {
            return Err(format!("PFM: {} data bytes for {w}x{h}", body.len()));
        }
        let read = |c: &[u8]| {
            let b = [c[0], c[1], c[2], c[3]];
            if scale < 0.0 {
                f32::from_le_bytes(b)
            } else {
                f32::from_be_bytes(b)
            }
        };
        let mut rows: Vec<Vec<[f32; 3]>> = body
            .chunks_exact(12 * w as usize)
            .map(|row| {
                row.chunks_exact(12)
                    .map(|p| [read(&p[0..4]), read(&p[4..8]), read(&p[8..12])])
                    .collect()
            })
            .collect();
        rows.reverse();
        Self::new(w, h, rows.concat())
    }

    pub fn save(&self, path: &Path) -> Result<(), String> {
        std::fs::write(path, self.encode()).map_err(|e| format!("{}: {e}", path.display()))
    }

    pub fn load(path: &Path) -> Result<Self, String> {
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Self::decode(&bytes).map_err(|e| format!("{}: {e}", path.display()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_with_rows_top_to_bottom() {
        let img = FloatImage::new(2, 3, (0..6).map(|i| [i as f32, 0.5, -1.0]).collect()).unwrap();
        let bytes = img.encode();
        assert!(bytes.starts_with(b"PF\n2 3\n-1.0\n"));
        // The file's first row is the image's last.
        assert_eq!(f32::from_le_bytes(bytes[12..16].try_into().unwrap()), 4.0);
        assert_eq!(FloatImage::decode(&bytes).unwrap(), img);
        assert!(FloatImage::decode(&bytes[..bytes.len() - 1]).is_err());
        assert!(FloatImage::decode(b"P6\n1 1\n255\n").is_err());
    }
}
