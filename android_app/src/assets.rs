//! The scene's assets (and the scanned head) read from the APK's `assets/` through the
//! AAssetManager, all at start
//! (nothing is read during play), by the core's loader ([`SceneAssets::load_with`]): this
//! file only says how to read one asset.

use android_activity::ndk::asset::AssetManager;
use dermis_engine::scene::{HeadLoad, SceneAssets};
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

/// The character, every prop and the showroom's scanned head (its textures' ETC2 encodings
/// only: the APK has no JPEG decoder; a head that does not load is one logged line and no
/// subject option, as on the desktop).
pub fn load(am: &AssetManager) -> Result<SceneAssets, String> {
    let read = |path: &str| read(am, path);
    let mut assets = SceneAssets::load_with(&read).map_err(|e| e.to_string())?;
    let head = HeadLoad::pending();
    head.finish_with(&read);
    assets.head = head;
    Ok(assets)
}
