//! Hard limits the loader enforces *before* allocating, so that a hostile or corrupt file
//! fails fast with an [`AssetError`](super::AssetError) instead of exhausting memory.

/// Largest model file (.glb or .gltf) read from disk.
pub const MAX_FILE_BYTES: u64 = 320 << 20;
/// Sum of the declared `byteLength` of all buffers.
pub const MAX_TOTAL_BUFFER_BYTES: u64 = 256 << 20;
/// Largest `data:` URI payload (base64 characters).
pub const MAX_DATA_URI_BYTES: usize = 64 << 20;
/// Largest external file (buffer or image) referenced by a .gltf.
pub const MAX_EXTERNAL_FILE_BYTES: u64 = 256 << 20;
/// Most elements one accessor may have.
pub const MAX_ACCESSOR_COUNT: usize = 16 << 20;
/// Most scalar components one accessor may decode to (count × components).
pub const MAX_ACCESSOR_SCALARS: usize = 64 << 20;
/// Most vertices over all primitives of the model.
pub const MAX_TOTAL_VERTICES: usize = 16 << 20;
/// Most indices over all primitives of the model.
pub const MAX_TOTAL_INDICES: usize = 48 << 20;
/// Largest decoded image side (pixels).
pub const MAX_IMAGE_SIDE: u32 = 8192;
/// Most bytes the image decoder may allocate for one image.
pub const MAX_IMAGE_ALLOC: u64 = 256 << 20;
/// Most bytes of all decoded images together.
pub const MAX_TOTAL_IMAGE_BYTES: u64 = 512 << 20;
