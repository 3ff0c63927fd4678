//! The scene's assets read from the APK's `assets/` through the AAssetManager, all at start
//! (nothing is read during play), by the core's loader ([`SceneAssets::load_with`]): this
//! file only says how to read one asset.

use android_activity::ndk::asset::AssetManager;
use dermis_core::scene::SceneAssets;
use std::ffi::CString;
use std::io::Read;

/// Reads one file of the APK's `assets/` (path relative to it, `/`-separated).
fn read(am: &AssetManager, path: &str) -> Result<Vec<u8>, String> {
    let name = CString::new(path).map_err(|_| "NUL in the name".to_string())?;
    let mut asset = am
        .open(&name)
        .ok_or_else(|| "not in the APK's assets".to_string())?;
    let mut bytes = Vec::with_capacity(asset.length());
    asset.read_to_end(&mut bytes).map_err(|e| e.to_string())?;
    Ok(bytes)
}

/// The character and every prop.
pub fn load(am: &AssetManager) -> Result<SceneAssets, String> {
    SceneAssets::load_with(&|path| read(am, path)).map_err(|e| e.to_string())
}
