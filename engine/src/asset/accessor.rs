//! Bounds-checked accessor decoding. Every byte range is computed with checked arithmetic and
//! compared with the buffer view and buffer before anything is read or allocated.

use std::borrow::Cow;

use gltf::accessor::{sparse::IndexType, DataType, Dimensions};

use super::limits::{MAX_ACCESSOR_COUNT, MAX_ACCESSOR_SCALARS};

/// All buffers of the document, loaded and length-checked.
pub(crate) struct Buffers<'a> {
    pub data: Vec<Cow<'a, [u8]>>,
}

fn comp_size(t: DataType) -> usize {
    match t {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

pub(crate) fn dims_name(d: Dimensions) -> &'static str {
    match d {
        Dimensions::Scalar => "SCALAR",
        Dimensions::Vec2 => "VEC2",
        Dimensions::Vec3 => "VEC3",
        Dimensions::Vec4 => "VEC4",
        Dimensions::Mat2 => "MAT2",
        Dimensions::Mat3 => "MAT3",
        Dimensions::Mat4 => "MAT4",
    }
}

fn comp_count(d: Dimensions) -> usize {
    match d {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 | Dimensions::Mat2 => 4,
        Dimensions::Mat3 => 9,
        Dimensions::Mat4 => 16,
    }
}

/// Where one accessor's (dense) elements lie.
struct Dense<'b> {
    bytes: &'b [u8],
    stride: usize,
}

fn bytes_at(b: &[u8], at: usize, n: usize) -> [u8; 4] {
    let mut out = [0u8; 4];
    if let Some(s) = b.get(at..at.saturating_add(n)) {
        out[..n].copy_from_slice(s);
    }
    out
}

fn comp_f32(b: &[u8], at: usize, t: DataType, normalized: bool) -> f32 {
    let r = bytes_at(b, at, comp_size(t));
    match t {
        DataType::F32 => f32::from_le_bytes(r),
        DataType::U32 => u32::from_le_bytes(r) as f32,
        DataType::I8 => {
            let v = r[0] as i8 as f32;
            if normalized {
                (v / 127.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U8 => {
            let v = r[0] as f32;
            if normalized {
                v / 255.0
            } else {
                v
            }
        }
        DataType::I16 => {
            let v = i16::from_le_bytes([r[0], r[1]]) as f32;
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U16 => {
            let v = u16::from_le_bytes([r[0], r[1]]) as f32;
            if normalized {
                v / 65535.0
            } else {
                v
            }
        }
    }
}

fn comp_u32(b: &[u8], at: usize, t: DataType) -> u32 {
    let r = bytes_at(b, at, comp_size(t));
    match t {
        DataType::U8 | DataType::I8 => r[0] as u32,
        DataType::U16 | DataType::I16 => u16::from_le_bytes([r[0], r[1]]) as u32,
        DataType::U32 | DataType::F32 => u32::from_le_bytes(r),
    }
}

/// Returns the bytes of a buffer view, checked against its buffer.
pub(crate) fn view_bytes<'b>(
    buffers: &'b Buffers<'_>,
    view: &gltf::buffer::View<'_>,
) -> Result<&'b [u8], String> {
    let bi = view.buffer().index();
    let buf = buffers
        .data
        .get(bi)
        .ok_or_else(|| format!("bufferView {} references missing buffer {bi}", view.index()))?;
    let start = view.offset();
    let end = start
        .checked_add(view.length())
        .filter(|&e| e <= buf.len())
        .ok_or_else(|| {
            format!(
                "bufferView {} out of bounds: bytes {start}+{} exceed buffer {bi} ({} bytes)",
                view.index(),
                view.length(),
                buf.len()
            )
        })?;
    Ok(&buf[start..end])
}

/// Checks `count` elements of `elem` bytes at `offset` with `stride` inside `bytes`.
fn check_range(
    what: &str,
    len: usize,
    offset: usize,
    stride: usize,
    elem: usize,
    count: usize,
) -> Result<(), String> {
    if count == 0 {
        return Ok(());
    }
    let need = stride
        .checked_mul(count - 1)
        .and_then(|v| v.checked_add(elem))
        .and_then(|v| v.checked_add(offset));
    match need {
        Some(n) if n <= len => Ok(()),
        _ => Err(format!(
            "{what} out of bounds: {count} elements of {elem} bytes (stride {stride}) at offset \
             {offset} exceed its bufferView ({len} bytes)"
        )),
    }
}

fn dense<'b>(
    buffers: &'b Buffers<'_>,
    acc: &gltf::Accessor<'_>,
    what: &str,
    elem: usize,
) -> Result<Option<Dense<'b>>, String> {
    let Some(view) = acc.view() else {
        return Ok(None);
    };
    let bytes = view_bytes(buffers, &view)?;
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(format!(
            "{what}: byteStride {stride} of bufferView {} is smaller than the element size {elem}",
            view.index()
        ));
    }
    if stride > 252 && view.stride().is_some() {
        return Err(format!(
            "{what}: byteStride {stride} above the glTF maximum 252"
        ));
    }
    check_range(what, bytes.len(), acc.offset(), stride, elem, acc.count())?;
    let start = acc.offset().min(bytes.len());
    Ok(Some(Dense {
        bytes: &bytes[start..],
        stride,
    }))
}

/// Validates the accessor's shape and returns (count, components, element bytes).
fn shape(acc: &gltf::Accessor<'_>, what: &str) -> Result<(usize, usize, usize), String> {
    let count = acc.count();
    let n = comp_count(acc.dimensions());
    let cs = comp_size(acc.data_type());
    if count > MAX_ACCESSOR_COUNT {
        return Err(format!(
            "{what}: count {count} above the limit {MAX_ACCESSOR_COUNT}"
        ));
    }
    if count.saturating_mul(n) > MAX_ACCESSOR_SCALARS {
        return Err(format!(
            "{what}: {count} × {n} components above the limit {MAX_ACCESSOR_SCALARS}"
        ));
    }
    if matches!(acc.dimensions(), Dimensions::Mat2 | Dimensions::Mat3) && cs < 4 {
        return Err(format!("{what}: padded matrix layouts are not supported"));
    }
    Ok((count, n, cs * n))
}

/// Applies a sparse substitution: calls `put(element, value_bytes, at)` per entry.
fn for_each_sparse(
    buffers: &Buffers<'_>,
    acc: &gltf::Accessor<'_>,
    what: &str,
    elem: usize,
    mut put: impl FnMut(usize, &[u8], usize),
) -> Result<(), String> {
    let Some(sparse) = acc.sparse() else {
        return Ok(());
    };
    let n = sparse.count();
    if n > acc.count() {
        return Err(format!(
            "{what}: sparse count {n} above accessor count {}",
            acc.count()
        ));
    }
    let idx = sparse.indices();
    let isz = match idx.index_type() {
        IndexType::U8 => 1,
        IndexType::U16 => 2,
        IndexType::U32 => 4,
    };
    let ib = view_bytes(buffers, &idx.view())?;
    check_range(
        &format!("{what} sparse indices"),
        ib.len(),
        idx.offset(),
        isz,
        isz,
        n,
    )?;
    let vals = sparse.values();
    let vb = view_bytes(buffers, &vals.view())?;
    check_range(
        &format!("{what} sparse values"),
        vb.len(),
        vals.offset(),
        elem,
        elem,
        n,
    )?;
    let it = match isz {
        1 => DataType::U8,
        2 => DataType::U16,
        _ => DataType::U32,
    };
    for k in 0..n {
        let i = comp_u32(ib, idx.offset() + k * isz, it) as usize;
        if i >= acc.count() {
            return Err(format!(
                "{what}: sparse index {i} out of range (count {})",
                acc.count()
            ));
        }
        put(i, vb, vals.offset() + k * elem);
    }
    Ok(())
}

/// Decodes an accessor to floats (normalised integers mapped to [0,1] / [-1,1]).
/// Returns `count × components` values.
pub(crate) fn read_f32(
    buffers: &Buffers<'_>,
    acc: &gltf::Accessor<'_>,
    what: &str,
) -> Result<Vec<f32>, String> {
    let what = format!("accessor {} ({what})", acc.index());
    let (count, n, elem) = shape(acc, &what)?;
    let t = acc.data_type();
    let norm = acc.normalized();
    if norm && matches!(t, DataType::U32 | DataType::F32) {
        return Err(format!(
            "{what}: normalized is invalid for this component type"
        ));
    }
    let cs = comp_size(t);
    let mut out = vec![0.0f32; count * n];
    if let Some(d) = dense(buffers, acc, &what, elem)? {
        for (i, e) in out.chunks_exact_mut(n).enumerate() {
            let base = i * d.stride;
            for (c, v) in e.iter_mut().enumerate() {
                *v = comp_f32(d.bytes, base + c * cs, t, norm);
            }
        }
    }
    for_each_sparse(buffers, acc, &what, elem, |i, vb, at| {
        for c in 0..n {
            out[i * n + c] = comp_f32(vb, at + c * cs, t, norm);
        }
    })?;
    Ok(out)
}

/// Decodes an unsigned-integer accessor (indices, joints). Float or signed data is an error.
pub(crate) fn read_u32(
    buffers: &Buffers<'_>,
    acc: &gltf::Accessor<'_>,
    what: &str,
    allowed: &[DataType],
) -> Result<Vec<u32>, String> {
    let what = format!("accessor {} ({what})", acc.index());
    let t = acc.data_type();
    if !allowed.contains(&t) {
        return Err(format!("{what}: component type {t:?} not allowed here"));
    }
    let (count, n, elem) = shape(acc, &what)?;
    let cs = comp_size(t);
    let mut out = vec![0u32; count * n];
    if let Some(d) = dense(buffers, acc, &what, elem)? {
        for (i, e) in out.chunks_exact_mut(n).enumerate() {
            let base = i * d.stride;
            for (c, v) in e.iter_mut().enumerate() {
                *v = comp_u32(d.bytes, base + c * cs, t);
            }
        }
    }
    for_each_sparse(buffers, acc, &what, elem, |i, vb, at| {
        for c in 0..n {
            out[i * n + c] = comp_u32(vb, at + c * cs, t);
        }
    })?;
    Ok(out)
}

/// Errors unless the accessor has the expected dimensions.
pub(crate) fn expect_dims(
    acc: &gltf::Accessor<'_>,
    what: &str,
    dims: Dimensions,
) -> Result<(), String> {
    if acc.dimensions() != dims {
        return Err(format!(
            "accessor {} ({what}) is {} but must be {}",
            acc.index(),
            dims_name(acc.dimensions()),
            dims_name(dims)
        ));
    }
    Ok(())
}
