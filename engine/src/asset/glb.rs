//! The binary glTF (GLB) container: a 12-byte header and length-prefixed chunks, parsed with
//! checked arithmetic so that truncated or lying files fail with a clear message.

/// The chunks of a GLB file, borrowed from the input.
pub(crate) struct Glb<'a> {
    pub json: &'a [u8],
    pub bin: Option<&'a [u8]>,
}

const MAGIC: &[u8; 4] = b"glTF";
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

/// True when `bytes` starts like a GLB file (else it is treated as .gltf JSON).
pub(crate) fn is_glb(bytes: &[u8]) -> bool {
    bytes.len() >= 4 && &bytes[..4] == MAGIC
}

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Splits a GLB file into its JSON and BIN chunks. Errors are plain problem strings.
pub(crate) fn parse(bytes: &[u8]) -> Result<Glb<'_>, String> {
    if bytes.len() < 12 {
        return Err(format!(
            "truncated GLB header: {} bytes, need 12",
            bytes.len()
        ));
    }
    if !is_glb(bytes) {
        return Err("bad GLB magic (expected \"glTF\")".into());
    }
    let version = u32_at(bytes, 4).unwrap_or(0);
    if version != 2 {
        return Err(format!(
            "unsupported GLB version {version} (only 2 is supported)"
        ));
    }
    let declared = u32_at(bytes, 8).unwrap_or(0) as usize;
    if declared > bytes.len() {
        return Err(format!(
            "truncated GLB: header declares {declared} bytes but the file has {}",
            bytes.len()
        ));
    }
    if declared < 12 {
        return Err(format!(
            "corrupt GLB header: declared length {declared} is below 12"
        ));
    }
    let data = &bytes[..declared];

    let mut at = 12usize;
    let mut json: Option<&[u8]> = None;
    let mut bin: Option<&[u8]> = None;
    let mut index = 0usize;
    while at < data.len() {
        if data.len() - at < 8 {
            return Err(format!("truncated GLB chunk header at byte {at}"));
        }
        let len = u32_at(data, at).unwrap_or(0) as usize;
        let kind = u32_at(data, at + 4).unwrap_or(0);
        let start = at + 8;
        let end = start
            .checked_add(len)
            .filter(|&e| e <= data.len())
            .ok_or_else(|| {
                format!(
                    "truncated GLB chunk {index}: declares {len} bytes at byte {start} but only {} remain",
                    data.len() - start
                )
            })?;
        let chunk = &data[start..end];
        match (index, kind) {
            (0, CHUNK_JSON) => json = Some(chunk),
            (0, _) => return Err(format!("first GLB chunk is not JSON (type 0x{kind:08x})")),
            (_, CHUNK_JSON) => return Err("GLB has more than one JSON chunk".into()),
            (1, CHUNK_BIN) => bin = Some(chunk),
            (_, CHUNK_BIN) => return Err("GLB has more than one BIN chunk".into()),
            _ => log::debug!("skipping unknown GLB chunk type 0x{kind:08x}"),
        }
        // Chunks are 4-byte aligned; tolerate a missing final pad.
        at = end
            .checked_add(3)
            .map(|e| e & !3)
            .unwrap_or(usize::MAX)
            .min(data.len());
        index += 1;
    }
    let json = json.ok_or("GLB has no JSON chunk")?;
    Ok(Glb { json, bin })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glb(json: &[u8], bin: Option<&[u8]>) -> Vec<u8> {
        let mut out = Vec::new();
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&0u32.to_le_bytes());
        let mut push = |data: &[u8], kind: u32, pad: u8| {
            let padded = (data.len() + 3) & !3;
            out.extend_from_slice(&(padded as u32).to_le_bytes());
            out.extend_from_slice(&kind.to_le_bytes());
            out.extend_from_slice(data);
            out.resize(out.len() + padded - data.len(), pad);
        };
        push(json, CHUNK_JSON, b' ');
        if let Some(b) = bin {
            push(b, CHUNK_BIN, 0);
        }
        let n = out.len() as u32;
        out[8..12].copy_from_slice(&n.to_le_bytes());
        out
    }

    #[test]
    fn parses_json_and_bin() {
        let f = glb(b"{}", Some(&[1, 2, 3, 4, 5]));
        let g = parse(&f).unwrap();
        assert_eq!(g.json, b"{}  ");
        assert_eq!(&g.bin.unwrap()[..5], &[1, 2, 3, 4, 5]);
    }

    #[test]
    fn rejects_truncation_everywhere() {
        let f = glb(b"{\"asset\":{\"version\":\"2.0\"}}", Some(&[0; 16]));
        for n in 0..f.len() {
            assert!(parse(&f[..n]).is_err(), "prefix {n} accepted");
        }
    }

    #[test]
    fn rejects_huge_chunk_length() {
        let mut f = glb(b"{}", None);
        f[12..16].copy_from_slice(&u32::MAX.to_le_bytes());
        let e = parse(&f).err().unwrap();
        assert!(e.contains("truncated GLB chunk"), "{e}");
    }
}
