//! The scene's assets read from the APK's `assets/` through the AAssetManager, all at start
//! (nothing is read during play): `character.glb` and `props/<PropKind::file()>`, parsed by
//! the same glTF loader as the desktop ([`load_gltf_slice`]).

use android_activity::ndk::asset::AssetManager;
use dermis_core::asset::{load_gltf_slice, Model};
use dermis_core::render::PropKind;
use dermis_core::scene::SceneAssets;
use std::ffi::CString;
use std::io::Read;

/// Reads one file of the APK's `assets/` (path relative to it, `/`-separated).
fn read(am: &AssetManager, path: &str) -> Result<Vec<u8>, String> {
    let name = CString::new(path).map_err(|_| format!("{path}: NUL in the name"))?;
    let mut asset = am
        .open(&name)
        .ok_or_else(|| format!("{path}: not in the APK's assets"))?;
    let mut bytes = Vec::with_capacity(asset.length());
    asset
        .read_to_end(&mut bytes)
        .map_err(|e| format!("{path}: {e}"))?;
    Ok(bytes)
}

/// Loads the model at `path`; external URIs resolve relative to its folder.
fn model(am: &AssetManager, path: &str) -> Result<Model, String> {
    let bytes = read(am, path)?;
    let dir = path.rsplit_once('/').map_or("", |(d, _)| d);
    let resolve = |uri: &str| -> Result<Vec<u8>, String> {
        if dir.is_empty() {
            read(am, uri)
        } else {
            read(am, &format!("{dir}/{uri}"))
        }
    };
    load_gltf_slice(&bytes, path, &resolve).map_err(|e| e.to_string())
}

/// The character and every prop.
pub fn load(am: &AssetManager) -> Result<SceneAssets, String> {
    let character = model(am, "character.glb")?;
    let mut props = Vec::with_capacity(PropKind::ALL.len());
    for kind in PropKind::ALL {
        props.push((kind, model(am, &format!("props/{}", kind.file()))?));
    }
    Ok(SceneAssets { character, props })
}
