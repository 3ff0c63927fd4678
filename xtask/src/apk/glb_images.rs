//! The APK's copy of a `.glb`: each embedded image that has an ETC2 encoding among the staged
//! assets is dropped from the BIN chunk and the image points at that KTX2 file instead (`uri`,
//! `mimeType: image/ktx2`), which the engine's loader reads as the image itself. The phone
//! samples ETC2 as it is stored, so the PNG would be dead weight in the package.

use serde_json::Value;

const GLB_MAGIC: &[u8; 4] = b"glTF";
const JSON_CHUNK: u32 = 0x4E4F_534A;
const BIN_CHUNK: u32 = 0x004E_4942;

fn u32_at(b: &[u8], at: usize) -> Result<u32, String> {
    b.get(at..at + 4)
        .map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
        .ok_or_else(|| "truncated GLB".to_string())
}

/// The JSON and BIN chunks of a GLB.
fn chunks(glb: &[u8]) -> Result<(Value, Vec<u8>), String> {
    if glb.get(..4) != Some(GLB_MAGIC.as_slice()) {
        return Err("not a GLB".into());
    }
    let json_len = u32_at(glb, 12)? as usize;
    if u32_at(glb, 16)? != JSON_CHUNK {
        return Err("first chunk is not JSON".into());
    }
    let json = glb.get(20..20 + json_len).ok_or("truncated JSON chunk")?;
    let json: Value = serde_json::from_slice(json).map_err(|e| e.to_string())?;
    let at = 20 + json_len;
    let bin = if at + 8 <= glb.len() && u32_at(glb, at + 4)? == BIN_CHUNK {
        let len = u32_at(glb, at)? as usize;
        glb.get(at + 8..at + 8 + len)
            .ok_or("truncated BIN chunk")?
            .to_vec()
    } else {
        Vec::new()
    };
    Ok((json, bin))
}

fn glb_bytes(json: &Value, bin: &[u8]) -> Result<Vec<u8>, String> {
    let mut json = serde_json::to_vec(json).map_err(|e| e.to_string())?;
    json.resize(json.len().next_multiple_of(4), b' ');
    let mut bin = bin.to_vec();
    bin.resize(bin.len().next_multiple_of(4), 0);
    let total = 12 + 8 + json.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(GLB_MAGIC);
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(&JSON_CHUNK.to_le_bytes());
    out.extend_from_slice(&json);
    if !bin.is_empty() {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(&BIN_CHUNK.to_le_bytes());
        out.extend_from_slice(&bin);
    }
    Ok(out)
}

/// `glb` with every embedded image `encoding(index)` names (a URI relative to the file)
/// pointing at it instead, its bytes removed; the other buffer views keep their bytes, packed
/// in their order (4-byte aligned). Returns the new file and the bytes removed.
pub fn point_images_at(
    glb: &[u8],
    encoding: &dyn Fn(usize) -> Option<String>,
) -> Result<(Vec<u8>, usize), String> {
    let (mut json, bin) = chunks(glb)?;
    let views = json["bufferViews"].as_array().cloned().unwrap_or_default();
    let mut dropped = vec![false; views.len()];
    if let Some(images) = json["images"].as_array_mut() {
        for (i, image) in images.iter_mut().enumerate() {
            let (Some(view), Some(uri)) = (image["bufferView"].as_u64(), encoding(i)) else {
                continue;
            };
            let view = view as usize;
            if view >= views.len() {
                return Err(format!("image {i}: bufferView {view} out of range"));
            }
            dropped[view] = true;
            let mut pointed = serde_json::Map::new();
            if let Some(name) = image.get("name") {
                pointed.insert("name".into(), name.clone());
            }
            pointed.insert("uri".into(), Value::String(uri));
            pointed.insert("mimeType".into(), Value::String("image/ktx2".into()));
            *image = Value::Object(pointed);
        }
    }
    // New indices of the kept views, their bytes packed.
    let mut new_index = vec![None; views.len()];
    let mut kept = Vec::new();
    let mut new_bin = Vec::new();
    let mut removed = 0;
    for (i, view) in views.iter().enumerate() {
        let offset = view["byteOffset"].as_u64().unwrap_or(0) as usize;
        let len = view["byteLength"].as_u64().unwrap_or(0) as usize;
        if dropped[i] {
            removed += len;
            continue;
        }
        let bytes = bin
            .get(offset..offset + len)
            .ok_or_else(|| format!("bufferView {i} outside the BIN chunk"))?;
        new_bin.resize(new_bin.len().next_multiple_of(4), 0);
        let mut view = view.clone();
        view["byteOffset"] = Value::from(new_bin.len());
        new_bin.extend_from_slice(bytes);
        new_index[i] = Some(kept.len());
        kept.push(view);
    }
    let remap = |v: &mut Value| -> Result<(), String> {
        if let Some(old) = v.as_u64() {
            let new = new_index
                .get(old as usize)
                .copied()
                .flatten()
                .ok_or_else(|| format!("bufferView {old} is still used"))?;
            *v = Value::from(new);
        }
        Ok(())
    };
    if let Some(accessors) = json["accessors"].as_array_mut() {
        for a in accessors {
            remap(&mut a["bufferView"])?;
            if a.get("sparse").is_some() {
                remap(&mut a["sparse"]["indices"]["bufferView"])?;
                remap(&mut a["sparse"]["values"]["bufferView"])?;
            }
        }
    }
    if let Some(images) = json["images"].as_array_mut() {
        for image in images.iter_mut().filter(|i| i.get("bufferView").is_some()) {
            remap(&mut image["bufferView"])?;
        }
    }
    json["bufferViews"] = Value::Array(kept);
    if let Some(buffer) = json["buffers"].get_mut(0) {
        buffer["byteLength"] = Value::from(new_bin.len());
    }
    Ok((glb_bytes(&json, &new_bin)?, removed))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The project's character loses its PNG, keeps every other byte of geometry, and the
    /// engine's parser still reads it (the image now a reference).
    #[test]
    fn the_character_points_at_its_encoding() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/character.glb");
        let glb = std::fs::read(path).unwrap();
        let uri = "character.glb.textures/0-colour.etc2.ktx2";
        let (out, removed) = point_images_at(&glb, &|i| (i == 0).then(|| uri.to_string())).unwrap();
        assert!(removed > 100_000, "{removed}");
        assert!(out.len() + removed <= glb.len() + 64);
        let (json, bin) = chunks(&out).unwrap();
        assert_eq!(json["images"][0]["uri"], uri);
        assert_eq!(
            json["buffers"][0]["byteLength"].as_u64(),
            Some(bin.len() as u64)
        );
        let doc = gltf::Gltf::from_slice(&out).unwrap();
        for a in doc.document.accessors() {
            let view = a.view().unwrap();
            assert!(view.offset() + view.length() <= bin.len());
        }
        // Nothing to point at: the file is rebuilt with the same content.
        let (same, none) = point_images_at(&glb, &|_| None).unwrap();
        let (a, b) = (
            chunks(&same).unwrap().1.len(),
            chunks(&glb).unwrap().1.len(),
        );
        assert!(none == 0 && a.abs_diff(b) <= 16, "{a} vs {b}");
    }
}
