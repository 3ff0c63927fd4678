//! Minimal, deterministic glTF 2.0 binary (GLB) writer.
//!
//! Collects buffer views and accessors into one binary chunk (every view 4-byte aligned) and
//! serialises the JSON chunk with object keys sorted, so the bytes never depend on map
//! iteration order or on serde_json's `preserve_order` feature.

use serde_json::{json, Value};

pub const ARRAY_BUFFER: u32 = 34962;
pub const ELEMENT_ARRAY_BUFFER: u32 = 34963;
pub const FLOAT: u32 = 5126;
pub const UNSIGNED_BYTE: u32 = 5121;
pub const UNSIGNED_SHORT: u32 = 5123;
pub const UNSIGNED_INT: u32 = 5125;

#[derive(Default)]
pub struct GlbBuilder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

fn f32_json(v: f32) -> Value {
    // f32 -> f64 is exact, so the printed value round-trips to the very same f32.
    json!(v as f64)
}

impl GlbBuilder {
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends raw bytes as a buffer view (4-byte aligned) and returns its index.
    pub fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut v = json!({ "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len() });
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        self.bin.extend_from_slice(bytes);
        self.views.push(v);
        self.views.len() - 1
    }

    /// Float accessor of `kind` ("SCALAR", "VEC2", "VEC3", "VEC4", "MAT4"), `comps` floats per element.
    pub fn floats(
        &mut self,
        data: &[f32],
        comps: usize,
        kind: &str,
        target: Option<u32>,
        with_bounds: bool,
    ) -> usize {
        assert!(comps > 0 && data.len().is_multiple_of(comps));
        let bytes: Vec<u8> = data.iter().flat_map(|f| f.to_le_bytes()).collect();
        let view = self.view(&bytes, target);
        let mut a = json!({
            "bufferView": view,
            "componentType": FLOAT,
            "count": data.len() / comps,
            "type": kind,
        });
        if with_bounds {
            let mut min = vec![f32::INFINITY; comps];
            let mut max = vec![f32::NEG_INFINITY; comps];
            for e in data.chunks(comps) {
                for c in 0..comps {
                    min[c] = min[c].min(e[c]);
                    max[c] = max[c].max(e[c]);
                }
            }
            a["min"] = Value::Array(min.into_iter().map(f32_json).collect());
            a["max"] = Value::Array(max.into_iter().map(f32_json).collect());
        }
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    /// Triangle indices (u16 when they fit, u32 otherwise).
    pub fn indices(&mut self, idx: &[u32]) -> usize {
        let max = idx.iter().copied().max().unwrap_or(0);
        let (bytes, ty): (Vec<u8>, u32) = if max < 65535 {
            (
                idx.iter().flat_map(|&i| (i as u16).to_le_bytes()).collect(),
                UNSIGNED_SHORT,
            )
        } else {
            (
                idx.iter().flat_map(|i| i.to_le_bytes()).collect(),
                UNSIGNED_INT,
            )
        };
        let view = self.view(&bytes, Some(ELEMENT_ARRAY_BUFFER));
        self.accessors.push(json!({
            "bufferView": view,
            "componentType": ty,
            "count": idx.len(),
            "type": "SCALAR",
        }));
        self.accessors.len() - 1
    }

    /// JOINTS_0 as UNSIGNED_BYTE VEC4.
    pub fn joints_u8(&mut self, joints: &[[u8; 4]]) -> usize {
        let bytes: Vec<u8> = joints.iter().flatten().copied().collect();
        let view = self.view(&bytes, Some(ARRAY_BUFFER));
        self.accessors.push(json!({
            "bufferView": view,
            "componentType": UNSIGNED_BYTE,
            "count": joints.len(),
            "type": "VEC4",
        }));
        self.accessors.len() - 1
    }

    /// Finishes the file: `doc` is the glTF JSON without `buffers`, `bufferViews`, `accessors`.
    pub fn finish(mut self, mut doc: Value) -> Vec<u8> {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        doc["buffers"] = json!([{ "byteLength": self.bin.len() }]);
        doc["bufferViews"] = Value::Array(self.views);
        doc["accessors"] = Value::Array(self.accessors);
        let mut text = String::new();
        write_canonical(&doc, &mut text);
        let mut json_bytes = text.into_bytes();
        while !json_bytes.len().is_multiple_of(4) {
            json_bytes.push(b' ');
        }
        let total = 12 + 8 + json_bytes.len() + 8 + self.bin.len();
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(json_bytes.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&json_bytes);
        out.extend_from_slice(&(self.bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&self.bin);
        out
    }
}

/// Compact JSON with object keys in sorted order.
pub fn write_canonical(v: &Value, out: &mut String) {
    match v {
        Value::Object(map) => {
            let mut keys: Vec<&String> = map.keys().collect();
            keys.sort();
            out.push('{');
            for (i, k) in keys.iter().enumerate() {
                if i > 0 {
                    out.push(',');
                }
                out.push_str(&Value::String((*k).clone()).to_string());
                out.push(':');
                write_canonical(&map[k.as_str()], out);
            }
            out.push('}');
        }
        Value::Array(items) => {
            out.push('[');
            for (i, item) in items.iter().enumerate() {
                if i > 0 {
                    out.push(',');
                }
                write_canonical(item, out);
            }
            out.push(']');
        }
        other => out.push_str(&other.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_and_alignment() {
        let mut b = GlbBuilder::new();
        b.floats(&[1.0, 2.0, 3.0], 3, "VEC3", Some(ARRAY_BUFFER), true);
        b.view(&[1, 2, 3], None);
        b.indices(&[0, 1, 2]);
        let glb = b.finish(json!({ "asset": { "version": "2.0" }, "z": 1, "a": 2 }));
        assert_eq!(&glb[0..4], b"glTF");
        assert_eq!(
            u32::from_le_bytes(glb[8..12].try_into().unwrap()) as usize,
            glb.len()
        );
        assert_eq!(glb.len() % 4, 0);
        let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
        let text = std::str::from_utf8(&glb[20..20 + json_len]).unwrap();
        assert!(text.starts_with("{\"a\":2,\"accessors\""), "{text}");
    }
}
