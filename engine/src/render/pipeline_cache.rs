//! wgpu's pipeline cache (the driver's compiled pipelines, `Features::PIPELINE_CACHE`: Vulkan)
//! kept in a file of the app's cache directory between launches.
//!
//! The file is dermis' own envelope around [`wgpu::PipelineCache::get_data`]: a magic, the key
//! of the adapter and driver that made it, the data's length and its FNV-1a 64 hash. A file
//! that is truncated, corrupt, or made by another adapter or driver is ignored with one logged
//! line (the driver would be handed bytes it never wrote otherwise); a missing one is the
//! first launch. The `Gpu` keeps it; every pipeline builder gets it with the device
//! ([`super::Gpu::pipelines`], the passes' `BuildCtx`, `CharacterPipelines`).

use std::path::{Path, PathBuf};

use crate::asset::compressed::fnv1a64;

const MAGIC: &[u8; 8] = b"DRMPCv01";
/// The cache's file name in the cache directory.
pub const FILE: &str = "pipelines.bin";

/// What the data must have been made by: wgpu's key for the adapter (vendor and device) plus
/// the adapter's and driver's names and versions. `None`: the backend keeps no cache.
pub fn cache_key(info: &wgpu::AdapterInfo) -> Option<String> {
    let key = wgpu::util::pipeline_cache_key(info)?;
    Some(format!(
        "{key}|{}|{}|{}|wgpu30",
        info.name, info.driver, info.driver_info
    ))
}

/// The cache data inside a file, if the file is whole and was made under `key`.
pub fn unwrap<'a>(file: &'a [u8], key: &str) -> Result<&'a [u8], String> {
    let rest = file
        .strip_prefix(MAGIC.as_slice())
        .ok_or("not a dermis pipeline cache")?;
    let take = |rest: &[u8], n: usize| -> Result<(Vec<u8>, usize), String> {
        rest.get(..n)
            .map(|b| (b.to_vec(), n))
            .ok_or_else(|| "truncated".to_string())
    };
    let (len, _) = take(rest, 4)?;
    let key_len = u32::from_le_bytes([len[0], len[1], len[2], len[3]]) as usize;
    let rest = &rest[4..];
    let (file_key, _) = take(rest, key_len)?;
    let rest = &rest[key_len..];
    if file_key != key.as_bytes() {
        return Err(format!(
            "made by another adapter or driver ({})",
            String::from_utf8_lossy(&file_key)
        ));
    }
    let (head, _) = take(rest, 16)?;
    let data_len = u64::from_le_bytes(head[..8].try_into().unwrap_or_default());
    let hash = u64::from_le_bytes(head[8..].try_into().unwrap_or_default());
    let data = &rest[16..];
    if data.len() as u64 != data_len {
        return Err(format!(
            "{} bytes of data, the header says {data_len}",
            data.len()
        ));
    }
    if fnv1a64(data) != hash {
        return Err("corrupt (its hash does not match)".into());
    }
    Ok(data)
}

/// The file holding `data` made under `key`.
pub fn wrap(data: &[u8], key: &str) -> Vec<u8> {
    let mut out = MAGIC.to_vec();
    out.extend_from_slice(&(key.len() as u32).to_le_bytes());
    out.extend_from_slice(key.as_bytes());
    out.extend_from_slice(&(data.len() as u64).to_le_bytes());
    out.extend_from_slice(&fnv1a64(data).to_le_bytes());
    out.extend_from_slice(data);
    out
}

/// A device's pipeline cache and the file it is kept in.
pub struct PipelineCacheFile {
    pub path: PathBuf,
    key: String,
    cache: wgpu::PipelineCache,
    /// Whether the cache started from the file's data.
    pub loaded: bool,
}

impl PipelineCacheFile {
    /// The cache of `device` in `dir` ([`FILE`]): the file's data where it is whole and this
    /// adapter's, else an empty cache (one logged line says why). `None` where the device
    /// keeps no pipeline cache.
    pub fn open(device: &wgpu::Device, info: &wgpu::AdapterInfo, dir: &Path) -> Option<Self> {
        if !device.features().contains(wgpu::Features::PIPELINE_CACHE) {
            log::info!("pipeline cache: {} offers none", info.name);
            return None;
        }
        let key = cache_key(info)?;
        let path = dir.join(FILE);
        let bytes = match std::fs::read(&path) {
            Ok(bytes) => Some(bytes),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                log::info!("pipeline cache: {} not there yet", path.display());
                None
            }
            Err(e) => {
                log::warn!("pipeline cache: {}: {e}; starting empty", path.display());
                None
            }
        };
        let data = bytes.as_deref().and_then(|b| match unwrap(b, &key) {
            Ok(data) => Some(data),
            Err(e) => {
                log::warn!("pipeline cache: {}: {e}; ignored", path.display());
                None
            }
        });
        // SAFETY: `data` is what `PipelineCache::get_data` returned on an adapter with this
        // very key (`save` wrote it; its hash and key are checked above), as wgpu requires;
        // `fallback` makes wgpu start empty where the driver still refuses it.
        let cache = unsafe {
            device.create_pipeline_cache(&wgpu::PipelineCacheDescriptor {
                label: Some("dermis pipelines"),
                data,
                fallback: true,
            })
        };
        let loaded = data.is_some();
        if loaded {
            log::info!("pipeline cache: {} loaded", path.display());
        }
        Some(Self {
            path,
            key,
            cache,
            loaded,
        })
    }

    /// The cache the device's pipelines pass through ([`super::Gpu::pipelines`]).
    pub fn cache(&self) -> &wgpu::PipelineCache {
        &self.cache
    }

    /// Writes the cache's data (atomically: a temporary file renamed); returns its size.
    pub fn save(&self) -> Result<usize, String> {
        let data = self
            .cache
            .get_data()
            .ok_or("the driver returned no pipeline cache data")?;
        let bytes = wrap(&data, &self.key);
        let err = |e: std::io::Error| format!("{}: {e}", self.path.display());
        if let Some(dir) = self.path.parent() {
            std::fs::create_dir_all(dir).map_err(err)?;
        }
        let tmp = self.path.with_extension("tmp");
        std::fs::write(&tmp, &bytes).map_err(err)?;
        std::fs::rename(&tmp, &self.path).map_err(err)?;
        Ok(bytes.len())
    }
}

impl Drop for PipelineCacheFile {
    /// Saves the cache (at exit: whatever was built since the last save).
    fn drop(&mut self) {
        if let Err(e) = self.save() {
            log::warn!("pipeline cache not saved at exit: {e}");
        }
    }
}

/// The desktop's cache directory: `$XDG_CACHE_HOME/dermis`, else `$HOME/.cache/dermis`.
pub fn desktop_dir() -> Option<PathBuf> {
    let base = std::env::var_os("XDG_CACHE_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))?;
    Some(base.join("dermis"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_wrapped_cache_unwraps_only_whole_and_under_its_key() {
        let data = b"driver bytes".repeat(10);
        let file = wrap(&data, "key A");
        assert_eq!(unwrap(&file, "key A").unwrap(), &data[..]);
        assert!(unwrap(&file, "key B")
            .unwrap_err()
            .contains("another adapter"));
        for len in 0..file.len() {
            assert!(unwrap(&file[..len], "key A").is_err(), "{len}");
        }
        let mut flipped = file.clone();
        *flipped.last_mut().unwrap() ^= 1;
        assert!(unwrap(&flipped, "key A").unwrap_err().contains("corrupt"));
        assert!(unwrap(b"garbage", "key A").is_err());
    }
}
